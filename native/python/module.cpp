// paramorph_native: thin pybind11 bindings over the C++ core (numpy in, numpy out).
#include "morph/ipopt_polish.h"
#include "python/bindings.h"

#include <cstdlib>
#include <string>

#define PARAMORPH_STR2(x) #x
#define PARAMORPH_STR(x) PARAMORPH_STR2(x)
#define PARAMORPH_PYBIND11_VERSION \
  PARAMORPH_STR(PYBIND11_VERSION_MAJOR) "." PARAMORPH_STR(PYBIND11_VERSION_MINOR) "." PARAMORPH_STR(PYBIND11_VERSION_PATCH)

namespace {

/// pybind11 before 2.12 reads NumPy 2's array descriptors with NumPy 1's
/// layout: with NumPy 2.4 every int32 array the module returns came back
/// as zeros (a morph's vertex_of_a) and landmarks landed 48 % of the
/// diagonal off, without an error. Refuse to load rather than answer wrong.
/// Decided when compiling: a build with pybind11 >= 2.12 (PyPI's, for
/// CPython 3.13 and Blender 5.x) reads NumPy 1 and 2 alike.
void require_numpy_this_build_reads() {
#if PYBIND11_VERSION_HEX < 0x020C0000
  const std::string version = pybind11::module_::import("numpy").attr("__version__").cast<std::string>();
  const int major = std::atoi(version.c_str());
  if (major >= 2)
    throw pybind11::import_error("paramorph_native was built with pybind11 " PARAMORPH_PYBIND11_VERSION
                                 ", which reads NumPy 2 arrays wrongly, and this Python has NumPy " +
                                 version + ": use NumPy < 2, or rebuild with pybind11 >= 2.12");
#endif
}

}  // namespace

PYBIND11_MODULE(paramorph_native, m) {
  require_numpy_this_build_reads();
  m.doc() =
      "paramorph native core: mesh validation, OpenCL devices, spherical and planar "
      "parameterization, feature measures and matching, feature cut-and-paste";
  m.attr("__version__") = PARAMORPH_VERSION;
  m.def(
      "build_info",
      [] {
        pybind11::dict info;
        info["version"] = PARAMORPH_VERSION;
        info["ipopt"] = paramorph::morph::ipopt_available();
        info["pybind11"] = PARAMORPH_PYBIND11_VERSION;
        return info;
      },
      "What this build has: {'version': str, 'ipopt': bool (optimize_sphere_map's Ipopt polish; the\n"
      "released wheel leaves Ipopt out, see README), 'pybind11': str (the pybind11 it was built with;\n"
      "before 2.12 the module refuses NumPy 2)}.");
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
  paramorph::python::bind_ride_along(m);
  paramorph::python::bind_fit_to_surface(m);
}
