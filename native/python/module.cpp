// paramorph_native: thin pybind11 bindings over the C++ core (numpy in, numpy out).
#include "morph/ipopt_polish.h"
#include "python/bindings.h"

PYBIND11_MODULE(paramorph_native, m) {
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
        return info;
      },
      "What this build has: {'version': str, 'ipopt': bool (optimize_sphere_map's Ipopt polish; the\n"
      "released wheel leaves Ipopt out, see README)}.");
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
