// validate() and require_closed_genus0() (mesh/validate.h): numpy in, a
// read-only MeshReport or a typed MeshError out; simplify() (mesh/simplify.h).
#include <cmath>
#include <string>

#include "mesh/simplify.h"
#include "mesh/validate.h"
#include "python/arrays.h"
#include "python/bindings.h"

namespace paramorph::python {

namespace {

/// Converts under the GIL (numpy access), then checks and builds the topology
/// without it so other Python threads (Blender's UI) keep running.
MeshReport report_of(const py::object& V, const py::object& F, double relative_area_tolerance) {
  MatrixX3d v = to_vertices(V, "V");
  MatrixX3i f = to_faces(F, "F");
  PM_REQUIRE(std::isfinite(relative_area_tolerance) && relative_area_tolerance >= 0,
             InvalidInputError, "relative_area_tolerance must be finite and >= 0, got ",
             relative_area_tolerance);
  py::gil_scoped_release release;
  validate_arrays(v, f);
  return validate(TriMesh(std::move(v), std::move(f)), relative_area_tolerance);
}

std::string repr(const MeshReport& r) {
  std::string s = "<MeshReport V=" + std::to_string(r.vertices) + " F=" + std::to_string(r.faces) +
                  " E=" + std::to_string(r.edges) + " components=" + std::to_string(r.components) +
                  " boundary_loops=" + std::to_string(r.boundary_loops) +
                  " chi=" + std::to_string(r.euler_characteristic) + " genus=" + std::to_string(r.genus);
  auto add = [&](const char* name, std::size_t n) {
    if (n) s += std::string(" ") + name + "=" + std::to_string(n);
  };
  add("non_manifold_edges", r.non_manifold_edges.size());
  add("non_manifold_vertices", r.non_manifold_vertices.size());
  add("degenerate_faces", r.degenerate_faces.size());
  add("duplicate_faces", r.duplicate_faces.size());
  add("isolated_vertices", r.isolated_vertices.size());
  add("inconsistent_orientation_edges", r.inconsistent_orientation_edges.size());
  return s + " is_closed_genus0=" + (r.is_closed_genus0 ? "True" : "False") + ">";
}

}  // namespace

void bind_mesh(py::module_& m) {
  py::class_<MeshReport>(m, "MeshReport",
                         "Everything validate() finds. Index arrays are int32, 0-based and sorted;\n"
                         "edges are numbered as in the sorted (a < b) edge list of the mesh.")
      .def_readonly("vertices", &MeshReport::vertices, "number of vertices")
      .def_readonly("faces", &MeshReport::faces, "number of faces")
      .def_readonly("edges", &MeshReport::edges, "number of undirected edges")
      .def_readonly("components", &MeshReport::components,
                    "connected components, each isolated vertex counting as one")
      .def_readonly("boundary_loops", &MeshReport::boundary_loops, "number of holes")
      .def_readonly("boundary_edges", &MeshReport::boundary_edges, "edges with exactly one face")
      .def_readonly("euler_characteristic", &MeshReport::euler_characteristic, "V - E + F")
      .def_readonly("genus", &MeshReport::genus,
                    "genus from chi = 2 - 2g - b of the one surface; -1 when undefined\n"
                    "(several surfaces or non-manifold)")
      .def_property_readonly(
          "non_manifold_edges", [](const MeshReport& r) { return to_numpy(r.non_manifold_edges); },
          "edge indices with more than two faces")
      .def_property_readonly(
          "non_manifold_edge_vertices",
          [](const MeshReport& r) { return to_numpy(r.non_manifold_edge_vertices); },
          "(k, 2) vertex pairs (a < b) of non_manifold_edges")
      .def_property_readonly(
          "non_manifold_vertices", [](const MeshReport& r) { return to_numpy(r.non_manifold_vertices); },
          "vertices whose faces do not form a single fan (bow-ties)")
      .def_property_readonly(
          "degenerate_faces", [](const MeshReport& r) { return to_numpy(r.degenerate_faces); },
          "faces with a repeated vertex or (near) zero area")
      .def_property_readonly(
          "repeated_vertex_faces", [](const MeshReport& r) { return to_numpy(r.repeated_vertex_faces); },
          "faces naming one vertex twice (also in degenerate_faces)")
      .def_property_readonly(
          "duplicate_faces", [](const MeshReport& r) { return to_numpy(r.duplicate_faces); },
          "faces on the same three vertices as an earlier face")
      .def_property_readonly(
          "isolated_vertices", [](const MeshReport& r) { return to_numpy(r.isolated_vertices); },
          "vertices in no face")
      .def_property_readonly(
          "inconsistent_orientation_edges",
          [](const MeshReport& r) { return to_numpy(r.inconsistent_orientation_edges); },
          "interior edges that both faces run in the same direction")
      .def_property_readonly(
          "inconsistent_orientation_edge_vertices",
          [](const MeshReport& r) { return to_numpy(r.inconsistent_orientation_edge_vertices); },
          "(k, 2) vertex pairs (a < b) of inconsistent_orientation_edges")
      .def_readonly("is_closed_genus0", &MeshReport::is_closed_genus0,
                    "closed, connected, manifold, consistently oriented, genus 0, no degenerate\n"
                    "faces and no isolated vertices")
      .def("__repr__", &repr);

  m.def("validate", &report_of, py::arg("V"), py::arg("F"), py::kw_only(),
        py::arg("relative_area_tolerance") = 1e-14,
        R"doc(Topology and validity report of a triangle mesh.

V: (n, 3) float64 or float32 vertex positions.
F: (m, 3) int32 or int64 vertex indices, 0-based.

Raises InvalidInputError for malformed arrays (wrong shape or dtype, NaN/inf
coordinates, index out of range, empty mesh), naming the offending entries.
Everything else (holes, handles, non-manifold or degenerate elements,
orientation) is reported in the returned MeshReport, not raised. A face is
degenerate when two indices repeat or its area is at most
relative_area_tolerance times the squared bounding-box diagonal. The default
(1e-14) catches exact zero areas in float64; coordinates rounded to float32
(Blender's own precision) leave "zero" areas near 1e-9 relative, so raise it
(e.g. 1e-8) to catch those.)doc");
  m.def(
      "require_closed_genus0",
      [](const py::object& V, const py::object& F, double relative_area_tolerance) {
        require_closed_genus0(report_of(V, F, relative_area_tolerance));
      },
      py::arg("V"), py::arg("F"), py::kw_only(), py::arg("relative_area_tolerance") = 1e-14,
      R"doc(Raises the matching MeshError subclass unless (V, F) is a closed, connected,
manifold, consistently oriented genus-0 surface without degenerate faces or
loose vertices. Checks in this order: InvalidInputError (malformed arrays),
NonManifoldError (edges with > 2 faces, bow-tie vertices), DegenerateFaceError,
DisconnectedError (several surfaces), NotClosedError (says how many holes),
DisconnectedError (loose vertices), NonManifoldError (inconsistent
orientation), NotGenusZeroError (says the genus). Messages name the vertices,
edges (as vertex pairs) or faces to fix.)doc");
  m.def(
      "simplify",
      [](const py::object& V, const py::object& F, Index target_faces) {
        const MatrixX3d v = to_vertices(V, "V");
        const MatrixX3i f = to_faces(F, "F");
        require_mesh(v, f);
        SimplifiedMesh out;
        {
          py::gil_scoped_release release;
          out = simplify(v, f, target_faces);
        }
        return py::make_tuple(to_numpy(out.V), to_numpy(out.F), to_numpy(out.proxy_of));
      },
      py::arg("V"), py::arg("F"), py::arg("target_faces"),
      R"doc(A coarser copy with the same topology (CGAL edge collapse, Lindstrom-Turk):
returns (V, F, proxy_of), proxy_of[i] the proxy vertex input vertex i was
collapsed into. The input must be a closed, manifold, oriented mesh.)doc");
}

}  // namespace paramorph::python
