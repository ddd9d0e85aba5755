// Spherical overlay (morph/spherical_overlay.h): pm.overlay -> MergedTopology.
#include "morph/spherical_overlay.h"
#include "python/arrays.h"
#include "python/bindings.h"
#include "python/progress.h"

namespace paramorph::python {

namespace {

void def_overlay(py::module_& m) {
  using morph::MergedTopology;
  using morph::OverlayStats;
  py::class_<OverlayStats>(m, "OverlayStats", "What overlay() did and how long each step took.")
      .def_readonly("merge_tolerance", &OverlayStats::merge_tolerance,
                    "the tolerance used: the option, at most a quarter of the thinnest face's "
                    "altitude of either map, at least 1e-15")
      .def_readonly("cells", &OverlayStats::cells, "cells of the exact arrangement")
      .def_readonly("crossings", &OverlayStats::crossings, "arc crossings of the exact arrangement")
      .def_readonly("merged_vertices", &OverlayStats::merged_vertices,
                    "arrangement vertices merged into another (within merge_tolerance)")
      .def_readonly(
          "max_merge_distance", &OverlayStats::max_merge_distance,
          "largest distance (radians) from a merged vertex to the input vertices and arcs it "
          "stands for (<= merge_tolerance unless a turned-over tiny cell was repaired)")
      .def_readonly("degenerate_cells", &OverlayStats::degenerate_cells,
                    "cell pieces with no positive triangulation (0 expected)")
      .def_readonly("folded", &OverlayStats::folded, "merged triangles with det <= 0 (checked: 0)")
      .def_readonly("open_edges", &OverlayStats::open_edges,
                    "half-edges without one opposite twin (checked: 0)")
      .def_readonly("min_altitude", &OverlayStats::min_altitude,
                    "smallest altitude (radians: twice the flat area over the longest side) of "
                    "the merged triangles on the sphere")
      .def_readonly("thin_triangles", &OverlayStats::thin_triangles,
                    "merged triangles thinner than half the tolerance used, left after the "
                    "sliver repair (0 unless a map's own faces are that thin)")
      .def_readonly("seconds_validate", &OverlayStats::seconds_validate)
      .def_readonly("seconds_arrangement", &OverlayStats::seconds_arrangement)
      .def_readonly("seconds_merge", &OverlayStats::seconds_merge)
      .def_readonly("seconds_triangulate", &OverlayStats::seconds_triangulate)
      .def_readonly("seconds_attributes", &OverlayStats::seconds_attributes)
      .def_readonly("seconds", &OverlayStats::seconds);
  py::class_<MergedTopology>(m, "MergedTopology",
                             "Result of overlay(): the merged topology of two sphere maps.")
      .def_property_readonly(
          "V", [](const MergedTopology& r) { return to_numpy(r.V); },
          "(M, 3) float64 merged vertices on the unit sphere")
      .def_property_readonly(
          "F", [](const MergedTopology& r) { return to_numpy(r.F); },
          "(K, 3) int32 merged triangles, det > 0, closed genus 0")
      .def_property_readonly(
          "face_a", [](const MergedTopology& r) { return to_numpy(r.face_a); },
          "(M,) int32: a face of A holding each merged vertex")
      .def_property_readonly(
          "bary_a", [](const MergedTopology& r) { return to_numpy(r.bary_a); },
          "(M, 3) float64 barycentric coordinates in face_a (central projection)")
      .def_property_readonly(
          "face_b", [](const MergedTopology& r) { return to_numpy(r.face_b); },
          "(M,) int32: a face of B holding each merged vertex")
      .def_property_readonly(
          "bary_b", [](const MergedTopology& r) { return to_numpy(r.bary_b); },
          "(M, 3) float64 barycentric coordinates in face_b")
      .def_property_readonly(
          "source_face_a", [](const MergedTopology& r) { return to_numpy(r.source_face_a); },
          "(K,) int32: the face of A each merged triangle lies in")
      .def_property_readonly(
          "source_face_b", [](const MergedTopology& r) { return to_numpy(r.source_face_b); },
          "(K,) int32: the face of B each merged triangle lies in")
      .def_property_readonly(
          "corner_bary_a", [](const MergedTopology& r) { return to_numpy(r.corner_bary_a); },
          "(K, 9) float64: per triangle corner, its coordinates in source_face_a")
      .def_property_readonly(
          "corner_bary_b", [](const MergedTopology& r) { return to_numpy(r.corner_bary_b); },
          "(K, 9) float64: per triangle corner, its coordinates in source_face_b")
      .def_property_readonly(
          "vertex_kind", [](const MergedTopology& r) { return to_numpy(r.vertex_kind); },
          "(M,) int32: 0 vertex of A, 1 of B, 2 of both, 3 edge-edge crossing")
      .def_property_readonly(
          "vertex_of_a", [](const MergedTopology& r) { return to_numpy(r.vertex_of_a); },
          "(VA,) int32: the merged vertex of each vertex of A")
      .def_property_readonly(
          "vertex_of_b", [](const MergedTopology& r) { return to_numpy(r.vertex_of_b); },
          "(VB,) int32: the merged vertex of each vertex of B")
      .def_readonly("stats", &MergedTopology::stats)
      .def("__repr__", [](const MergedTopology& r) {
        return "<MergedTopology vertices=" + std::to_string(r.V.rows()) +
               " faces=" + std::to_string(r.F.rows()) +
               " crossings=" + std::to_string(r.stats.crossings) + ">";
      });
  m.def(
      "overlay",
      [](const py::object& sphere_a, const py::object& FA, const py::object& sphere_b,
         const py::object& FB, double merge_tolerance, py::object progress) {
        morph::OverlayOptions o;
        o.merge_tolerance = merge_tolerance;
        const MatrixX3d sa = to_vertices(sphere_a, "sphere_a"),
                        sb = to_vertices(sphere_b, "sphere_b");
        const MatrixX3i fa = to_faces(FA, "FA"), fb = to_faces(FB, "FB");
        PythonProgress bridge(std::move(progress));
        return run_without_gil(bridge,
                               [&] { return morph::overlay(sa, fa, sb, fb, o, bridge.get()); });
      },
      py::arg("sphere_a"), py::arg("FA"), py::arg("sphere_b"), py::arg("FB"), py::kw_only(),
      py::arg("merge_tolerance") = 1e-6, py::arg("progress") = py::none(),
      R"doc(Spherical overlay of two sphere maps into one merged topology (thesis 4.4).

The great-circle arcs of A's edges are intersected with B's by walking face to
face (O(E + K)), every sign test an exact orientation predicate (CGAL) with
ties broken by symbolic perturbation; each cell (face of A ∩ face of B) is
triangulated. Vertices closer than merge_tolerance (radians) to one point are
one merged vertex (coincident vertices, vertices on the other map's edges,
overlapping edges); input vertices of one map are never merged together.
No slivers: a merged triangle thinner than merge_tolerance / 2 on the sphere
has its two closest corners merged (stats.thin_triangles: those left, 0 unless
a map's own faces are that thin; stats.min_altitude: the thinnest).

sphere_a: (VA, 3) unit vectors (within 1e-9); FA: (FA, 3) int faces of a
closed genus-0 mesh, every face det > 0, covering the sphere once; the same
for sphere_b, FB. progress: callable(fraction, stage) -> bool; False raises
Cancelled.

Returns MergedTopology: V (M, 3), F (K, 3) int32 (det > 0, closed, genus 0),
face_a/bary_a and face_b/bary_b (each merged vertex located in A and B by
central projection), source_face_a/b (K,), corner_bary_a/b (K, 9),
vertex_kind (M,) (0 A, 1 B, 2 both, 3 crossing), vertex_of_a (VA,),
vertex_of_b (VB,), stats (tolerance used, counts, checks and timings).
The tolerance used is at most a quarter of the thinnest face's altitude of
either map (vertices of one map are never merged together). Raises
InvalidInputError (shapes, non-unit points, folded faces, a map covering the
sphere more than once, or maps that nearly coincide below what double
precision resolves for their thinnest faces: the result is checked, never
returned broken), the MeshError subclasses of a mesh that is not closed genus
0, Cancelled.)doc");
}

}  // namespace

void bind_overlay(py::module_& m) {
  def_overlay(m);
}

}  // namespace paramorph::python
