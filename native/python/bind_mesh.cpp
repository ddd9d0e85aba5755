// validate() and require_closed_genus0() (mesh/validate.h).
#include "mesh/validate.h"
#include "python/arrays.h"
#include "python/bindings.h"

namespace paramorph::python {

namespace {
MeshReport report_of(const py::object& V, const py::object& F) {
  const MatrixX3d v = to_vertices(V);
  const MatrixX3i f = to_faces(F);
  py::gil_scoped_release release;
  validate_arrays(v, f);
  return validate(TriMesh(v, f));
}
}  // namespace

void bind_mesh(py::module_& m) {
  py::class_<MeshReport>(m, "MeshReport", "What validate() found; index arrays are 0-based, sorted.")
      .def_readonly("vertices", &MeshReport::vertices)
      .def_readonly("faces", &MeshReport::faces)
      .def_readonly("edges", &MeshReport::edges)
      .def_readonly("components", &MeshReport::components)
      .def_readonly("boundary_loops", &MeshReport::boundary_loops)
      .def_readonly("euler_characteristic", &MeshReport::euler_characteristic)
      .def_readonly("genus", &MeshReport::genus, "-1 when undefined (disconnected or non-manifold)")
      .def_property_readonly("non_manifold_edges", [](const MeshReport& r) { return to_numpy(r.non_manifold_edges); })
      .def_property_readonly("non_manifold_vertices", [](const MeshReport& r) { return to_numpy(r.non_manifold_vertices); })
      .def_property_readonly("degenerate_faces", [](const MeshReport& r) { return to_numpy(r.degenerate_faces); })
      .def_property_readonly("isolated_vertices", [](const MeshReport& r) { return to_numpy(r.isolated_vertices); })
      .def_property_readonly("inconsistent_orientation_edges",
                             [](const MeshReport& r) { return to_numpy(r.inconsistent_orientation_edges); })
      .def_readonly("is_closed_genus0", &MeshReport::is_closed_genus0)
      .def("__repr__", [](const MeshReport& r) {
        return "<MeshReport V=" + std::to_string(r.vertices) + " F=" + std::to_string(r.faces) +
               " components=" + std::to_string(r.components) +
               " boundary_loops=" + std::to_string(r.boundary_loops) + " genus=" +
               std::to_string(r.genus) + " closed_genus0=" + (r.is_closed_genus0 ? "True" : "False") + ">";
      });

  m.def("validate", &report_of, py::arg("V"), py::arg("F"),
        "Topology and validity report of a triangle mesh. V: (n, 3) float64/float32; F: (m, 3)\n"
        "int32/int64. Raises InvalidInputError for malformed arrays (NaN/inf, index out of range,\n"
        "wrong shape or dtype); everything else is reported, not raised.");
  m.def(
      "require_closed_genus0",
      [](const py::object& V, const py::object& F) { require_closed_genus0(report_of(V, F)); },
      py::arg("V"), py::arg("F"),
      "Raises the matching MeshError subclass unless the mesh is a closed, connected, manifold,\n"
      "consistently oriented genus-0 surface without degenerate faces.");
}

}  // namespace paramorph::python
