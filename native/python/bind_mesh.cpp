// validate() and require_closed_genus0() (mesh/validate.h): numpy in, a
// read-only MeshReport or a typed MeshError out; simplify() (mesh/simplify.h);
// repair() (mesh/repair.h).
#include <cmath>
#include <string>

#include "mesh/repair.h"
#include "mesh/simplify.h"
#include "mesh/validate.h"
#include <pybind11/stl.h>

#include "python/arrays.h"
#include "python/bindings.h"
#include "python/progress.h"

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

  py::class_<RepairReport>(m, "RepairReport", "Every change repair() made, counted on the input.")
      .def_readonly("welded_vertices", &RepairReport::welded_vertices)
      .def_readonly("degenerate_faces_removed", &RepairReport::degenerate_faces_removed)
      .def_readonly("duplicate_faces_removed", &RepairReport::duplicate_faces_removed)
      .def_readonly("isolated_vertices_removed", &RepairReport::isolated_vertices_removed)
      .def_readonly("faces_reversed", &RepairReport::faces_reversed,
                    "faces turned to agree with their neighbours")
      .def_readonly("parts_turned_outward", &RepairReport::parts_turned_outward)
      .def_readonly("non_manifold_vertices_split", &RepairReport::non_manifold_vertices_split)
      .def_readonly("non_manifold_edges", &RepairReport::non_manifold_edges)
      .def_readonly("holes_filled", &RepairReport::holes_filled)
      .def_readonly("holes_not_filled", &RepairReport::holes_not_filled)
      .def_readonly("single_faces_left_open", &RepairReport::single_faces_left_open)
      .def_readonly("fill_faces_added", &RepairReport::fill_faces_added)
      .def_readonly("fill_vertices_added", &RepairReport::fill_vertices_added)
      .def_readonly("fairing_failed", &RepairReport::fairing_failed)
      .def_readonly("components", &RepairReport::components, "parts in the result")
      .def_readonly("components_removed", &RepairReport::components_removed)
      .def_readonly("faces_removed_with_components", &RepairReport::faces_removed_with_components)
      .def_property_readonly("changes", &RepairReport::changes,
                             "one plain-word sentence per kind of change; empty when nothing changed")
      .def_property_readonly("changed", &RepairReport::changed)
      .def("__repr__", [](const RepairReport& r) {
        std::string s = "<RepairReport";
        for (const auto& change : r.changes()) s += "; " + change;
        return s + (r.changed() ? ">" : " nothing changed>");
      });
  py::class_<RepairResult>(m, "RepairResult", "repair()'s mesh, its map back to the input and the report.")
      .def_property_readonly("V", [](const RepairResult& r) { return to_numpy(r.V); })
      .def_property_readonly("F", [](const RepairResult& r) { return to_numpy(r.F); })
      .def_property_readonly("vertex_source", [](const RepairResult& r) { return to_numpy(r.vertex_source); },
                             "(n,) int32: the input vertex of each vertex, -1 for a vertex a hole fill added")
      .def_property_readonly("face_source", [](const RepairResult& r) { return to_numpy(r.face_source); },
                             "(m,) int32: the input face of each face, -1 for a face a hole fill added")
      .def_property_readonly(
          "input_vertex_target", [](const RepairResult& r) { return to_numpy(r.input_vertex_target); },
          "(n_in,) int32: the vertex each input vertex became, -1 when it was dropped\n"
          "(loose, only in removed faces, or in a removed part)")
      .def_readonly("report", &RepairResult::report);
  m.def(
      "repair",
      [](const py::object& V, const py::object& F, double weld_tolerance, bool fill_holes, bool orient_outward,
         bool keep_largest_component, py::object progress) {
        const MatrixX3d v = to_vertices(V, "V");
        const MatrixX3i f = to_faces(F, "F");
        RepairOptions options;
        options.weld_tolerance = weld_tolerance;
        options.fill_holes = fill_holes;
        options.orient_outward = orient_outward;
        options.keep_largest_component = keep_largest_component;
        PythonProgress bridge(std::move(progress));
        return run_without_gil(bridge, [&] { return repair(v, f, options, bridge.get()); });
      },
      py::arg("V"), py::arg("F"), py::kw_only(), py::arg("weld_tolerance") = 1e-6, py::arg("fill_holes") = true,
      py::arg("orient_outward") = true, py::arg("keep_largest_component") = false,
      py::arg("progress") = py::none(),
      R"doc(Repairs a messy triangle mesh into a manifold, consistently oriented one.

In order: welds vertices closer than weld_tolerance times the bounding-box
diagonal (0: exact duplicates only; unwelded UV/normal seams), drops faces
with a repeated corner and duplicate faces, orients every part consistently
and cuts non-manifold vertices and edges apart (CGAL orient_polygon_soup),
removes zero-area faces (CGAL), fills every hole with a refined and faired
patch (CGAL, Liepa) when fill_holes, keeps only the part with the largest
area when keep_largest_component, and turns every part enclosing a negative
volume outward when orient_outward. Kept vertices keep their positions.

Returns a RepairResult: V, F, vertex_source (input vertex per vertex, -1 for
fill vertices), face_source (input face per face, -1 for fill faces),
input_vertex_target (output vertex per input vertex, -1 when dropped) and
report (counts, and report.changes: one plain sentence per kind of change).
Handles (genus > 0) are not removed: validate() the result for that.
Raises InvalidInputError for malformed arrays, a bad weld_tolerance or a
mesh whose faces are all degenerate.)doc");
}

}  // namespace paramorph::python
