// paramorph_native: thin pybind11 bindings over the C++ core (numpy in, numpy out).
#include "python/bindings.h"

PYBIND11_MODULE(paramorph_native, m) {
  m.doc() =
      "paramorph native core: mesh validation, OpenCL devices, spherical and planar "
      "parameterization, feature measures and matching, feature cut-and-paste";
  m.attr("__version__") = "0.1.0";
  paramorph::python::bind_errors(m);
  paramorph::python::bind_mesh(m);
  paramorph::python::bind_compute(m);
  paramorph::python::bind_sphere(m);
  paramorph::python::bind_planar(m);
  paramorph::python::bind_segmentation(m);
  paramorph::python::bind_features(m);
  paramorph::python::bind_matching(m);
  paramorph::python::bind_morph(m);
  paramorph::python::bind_overlay(m);
  paramorph::python::bind_paste(m);
  paramorph::python::bind_in_betweens(m);
}
