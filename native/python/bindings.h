// One bind_<topic> per file; module.cpp only calls them.
#pragma once

#include <pybind11/pybind11.h>

namespace paramorph::python {
void bind_errors(pybind11::module_& m);
void bind_mesh(pybind11::module_& m);
void bind_compute(pybind11::module_& m);
void bind_sphere(pybind11::module_& m);
void bind_planar(pybind11::module_& m);
void bind_segmentation(pybind11::module_& m);
void bind_features(pybind11::module_& m);
void bind_matching(pybind11::module_& m);
void bind_morph(pybind11::module_& m);
void bind_overlay(pybind11::module_& m);
void bind_paste(pybind11::module_& m);
void bind_in_betweens(pybind11::module_& m);
void bind_ride_along(pybind11::module_& m);
void bind_fit_to_surface(pybind11::module_& m);
}  // namespace paramorph::python
