// Feature matching (native/features/): region_graph (features/region_graph.h)
// and match_features (features/match_features.h), thesis 4.5.
#include <pybind11/stl.h>

#include "features/match_features.h"
#include "features/region_graph.h"
#include "python/arrays.h"
#include "python/bindings.h"
#include "python/progress.h"

namespace paramorph::python {

namespace {

using features::FeatureMatch;
using features::RegionGraph;

MatrixX2i to_pairs(const std::vector<std::pair<Index, Index>>& pairs) {
  MatrixX2i out(pairs.size(), 2);
  for (std::size_t k = 0; k < pairs.size(); ++k) out.row(k) << pairs[k].first, pairs[k].second;
  return out;
}

MatrixX2i to_pairs(const std::vector<std::array<Index, 2>>& pairs) {
  MatrixX2i out(pairs.size(), 2);
  for (std::size_t k = 0; k < pairs.size(); ++k) out.row(k) << pairs[k][0], pairs[k][1];
  return out;
}

/// A numpy array even when empty ((0, 2) stays two columns).
py::array pairs_to_numpy(const MatrixX2i& m) {
  return py::array_t<Index>({py::ssize_t(m.rows()), py::ssize_t(2)}, m.data());
}

void def_region_graph(py::module_& m) {
  py::class_<RegionGraph>(
      m, "RegionGraph", "Region adjacency graph with geodesic edge lengths, reduced (thesis 4.5).")
      .def_property_readonly(
          "edges", [](const RegionGraph& g) { return pairs_to_numpy(to_pairs(g.edges)); },
          "(e, 2) int32 region pairs (a < b) of the reduced graph, sorted")
      .def_property_readonly(
          "lengths", [](const RegionGraph& g) { return to_numpy(g.lengths); },
          "(e,) float64 geodesic distance between the regions' anchors")
      .def_property_readonly(
          "degree", [](const RegionGraph& g) { return to_numpy(g.degree); },
          "(regions,) int32 degree in the reduced graph")
      .def_property_readonly(
          "dropped", [](const RegionGraph& g) { return pairs_to_numpy(to_pairs(g.dropped)); },
          "(k, 2) int32 long edges removed by the reduction")
      .def_property_readonly("dropped_lengths",
                             [](const RegionGraph& g) { return to_numpy(g.dropped_lengths); })
      .def_property_readonly(
          "anchors", [](const RegionGraph& g) { return to_numpy(g.anchors); },
          "(regions,) int32 vertex standing for each region's centroid")
      .def("__repr__", [](const RegionGraph& g) {
        return "<RegionGraph regions=" + std::to_string(g.degree.size()) +
               " edges=" + std::to_string(g.edges.size()) +
               " dropped=" + std::to_string(g.dropped.size()) + ">";
      });
  m.def(
      "region_graph",
      [](const py::object& V, const py::object& F, const features::Segmentation& regions,
         double long_edge_factor) {
        const MatrixX3d v = to_vertices(V);
        const MatrixX3i f = to_faces(F);
        features::RegionGraphOptions o;
        o.long_edge_factor = long_edge_factor;
        py::gil_scoped_release release;
        return features::region_graph(v, f, regions, o);
      },
      py::arg("V"), py::arg("F"), py::arg("regions"), py::kw_only(),
      py::arg("long_edge_factor") = 2.0,
      R"doc(Region adjacency graph of a segmentation (thesis 4.5, Fig. 4.5).

Nodes are regions; edges join regions sharing a mesh edge, with the geodesic
distance (shortest path along mesh edges) between the regions' anchors (each
region's vertex nearest its centroid). Reduction: an edge longer than
`long_edge_factor` times the median edge length is dropped, unless it is the
shortest edge of one of its regions (no region is isolated by it).

V: (n, 3); F: (m, 3); regions: a Segmentation of F (e.g. feature_regions(V, F)).
Returns RegionGraph. Raises InvalidInputError for malformed arrays, a
segmentation of another mesh or long_edge_factor <= 0.)doc");
}

void def_match_features(py::module_& m) {
  py::class_<FeatureMatch>(m, "FeatureMatch", "Result of match_features().")
      .def_property_readonly(
          "labels_a", [](const FeatureMatch& r) { return to_numpy(r.regions_a.face_labels); },
          "(mA,) int32 feature region of each face of A")
      .def_property_readonly(
          "labels_b", [](const FeatureMatch& r) { return to_numpy(r.regions_b.face_labels); },
          "(mB,) int32 feature region of each face of B")
      .def_readonly("regions_a", &FeatureMatch::regions_a, "Segmentation of A")
      .def_readonly("regions_b", &FeatureMatch::regions_b, "Segmentation of B")
      .def_readonly("graph_a", &FeatureMatch::graph_a, "reduced RegionGraph of A")
      .def_readonly("graph_b", &FeatureMatch::graph_b, "reduced RegionGraph of B")
      .def_property_readonly(
          "region_pairs",
          [](const FeatureMatch& r) { return pairs_to_numpy(to_pairs(r.region_pairs)); },
          "(k, 2) int32 (region of A, region of B), one-to-one, sorted by A's region")
      .def_property_readonly(
          "region_scores", [](const FeatureMatch& r) { return to_numpy(r.region_scores); },
          "(k,) float64 score s_ij (4.11) of each region pair, lower is better")
      .def_property_readonly(
          "point_pairs",
          [](const FeatureMatch& r) { return pairs_to_numpy(to_pairs(r.point_pairs)); },
          "(p, 2) int32 (vertex of A, vertex of B), one-to-one, sorted by A's vertex")
      .def_property_readonly(
          "point_scores", [](const FeatureMatch& r) { return to_numpy(r.point_scores); },
          "(p,) float64 distance of each point pair after centroid alignment, "
          "share of A's bounding-box diagonal")
      .def_property_readonly(
          "rotation", [](const FeatureMatch& r) { return to_numpy(r.rotation); },
          "(3, 3) float64 rotation turning B (centred, normalised) onto A")
      .def_property_readonly(
          "centre_a", [](const FeatureMatch& r) { return to_numpy(r.centre_a); },
          "(3,) area-weighted centroid of A")
      .def_property_readonly("centre_b", [](const FeatureMatch& r) { return to_numpy(r.centre_b); })
      .def_readonly("scale_a", &FeatureMatch::scale_a, "RMS radius of A about centre_a")
      .def_readonly("scale_b", &FeatureMatch::scale_b)
      .def_property_readonly(
          "graph_edges_a",
          [](const FeatureMatch& r) { return pairs_to_numpy(to_pairs(r.graph_a.edges)); },
          "(e, 2) int32 edges of A's reduced region graph")
      .def_property_readonly(
          "graph_edges_b",
          [](const FeatureMatch& r) { return pairs_to_numpy(to_pairs(r.graph_b.edges)); })
      .def_property_readonly(
          "centroids_a", [](const FeatureMatch& r) { return to_numpy(r.regions_a.centroid); },
          "(regions of A, 3) float64 region centroids in A's coordinates")
      .def_property_readonly("centroids_b",
                             [](const FeatureMatch& r) { return to_numpy(r.regions_b.centroid); })
      .def_property_readonly(
          "points_a", [](const FeatureMatch& r) { return to_numpy(r.points_a.vertices); },
          "(pA,) int32 feature point vertices of A")
      .def_property_readonly("points_b",
                             [](const FeatureMatch& r) { return to_numpy(r.points_b.vertices); })
      .def_property_readonly(
          "kinds_a", [](const FeatureMatch& r) { return to_numpy(r.points_a.kinds); },
          "(pA,) int32 +1 concave, -1 convex")
      .def_property_readonly("kinds_b",
                             [](const FeatureMatch& r) { return to_numpy(r.points_b.kinds); })
      .def(
          "transform_b",
          [](const FeatureMatch& r, const py::object& X) {
            const MatrixX3d x = to_vertices(X, "X");
            const MatrixX3d y = ((x.rowwise() - r.centre_b.transpose()) * (r.scale_a / r.scale_b) *
                                 r.rotation.transpose())
                                    .rowwise() +
                                r.centre_a.transpose();
            return to_numpy(y);
          },
          py::arg("X"),
          "Points of B, (n, 3), placed in A's frame: centre_a + scale_a / scale_b * rotation (x - "
          "centre_b).")
      .def("__repr__", [](const FeatureMatch& r) {
        return "<FeatureMatch regions=" + std::to_string(r.regions_a.regions()) + "/" +
               std::to_string(r.regions_b.regions()) +
               " region_pairs=" + std::to_string(r.region_pairs.size()) +
               " point_pairs=" + std::to_string(r.point_pairs.size()) + ">";
      });
  m.def(
      "match_features",
      [](const py::object& VA, const py::object& FA, const py::object& VB, const py::object& FB,
         double normal_angle, double concavity_threshold, double min_area, double spacing,
         double long_edge_factor, int alignment_nodes, double max_region_score,
         double outlier_factor, double max_point_distance, py::object progress) {
        features::MatchOptions o;
        o.regions.normal_angle = normal_angle;
        o.regions.concavity_threshold = concavity_threshold;
        o.regions.min_area = min_area;
        o.points.spacing = spacing;
        o.graph.long_edge_factor = long_edge_factor;
        o.alignment_nodes = alignment_nodes;
        o.max_region_score = max_region_score;
        o.outlier_factor = outlier_factor;
        o.max_point_distance = max_point_distance;
        const MatrixX3d va = to_vertices(VA, "VA"), vb = to_vertices(VB, "VB");
        const MatrixX3i fa = to_faces(FA, "FA"), fb = to_faces(FB, "FB");
        PythonProgress bridge(std::move(progress));
        return run_without_gil(
            bridge, [&] { return features::match_features(va, fa, vb, fb, o, bridge.get()); });
      },
      py::arg("VA"), py::arg("FA"), py::arg("VB"), py::arg("FB"), py::kw_only(),
      py::arg("normal_angle") = 40.0, py::arg("concavity_threshold") = 0.02,
      py::arg("min_area") = 0.005, py::arg("spacing") = 0.05, py::arg("long_edge_factor") = 2.0,
      py::arg("alignment_nodes") = 6, py::arg("max_region_score") = 0.5,
      py::arg("outlier_factor") = 4.0, py::arg("max_point_distance") = 0.05,
      py::arg("progress") = py::none(),
      R"doc(Automatic feature matching between two meshes (thesis 4.5).

Per mesh: feature regions (normal_angle, concavity_threshold, min_area as in
feature_regions; shares of the bounding-box diagonal taken in the mesh's
principal axes, so a turned mesh segments the same), feature points (spacing)
and the reduced region graph (long_edge_factor as in region_graph). Both
meshes are centred on their area-weighted centroid and scaled to unit RMS
radius. The rotation B -> A: candidates from two region correspondences
each (a top region of each graph by degree, among the alignment_nodes
highest, and a neighbour or another top region of each; Procrustes), the 24
principal-axes alignments and the identity, ranked by the least total score
of a one-to-one region pairing and refined by ICP on the region centroids;
the identity-started one is kept unless another is 5% cheaper. Region
pairs: s_ij = |c_i - R c_j| * max/min area share * max/min degree (4.11),
pairs at max_region_score or above, or above outlier_factor x the median
score (and 0.1 x max_region_score), dropped. Point pairs: within each region
pair, B's region moved so the centroids coincide, points of one kind that are
mutually nearest within max_point_distance (share of A's bounding-box
diagonal). Deterministic.

VA, VB: (n, 3) float64/float32; FA, FB: (m, 3) int32/int64, manifold, with
volume (open or closed, any genus). progress: callable(fraction, stage) ->
bool; False raises Cancelled.
Returns FeatureMatch (labels_a/b, region_pairs, region_scores, point_pairs
(vertex indices), point_scores, rotation, graph_edges_a/b, centroids_a/b,
points_a/b, kinds_a/b, regions_a/b, graph_a/b, centre_a/b, scale_a/b,
transform_b()). Raises DegenerateFaceError, NonManifoldError,
InvalidInputError (malformed arrays, a flat mesh, bad options; messages say
"mesh A" or "mesh B"), Cancelled.)doc");
}

}  // namespace

void bind_matching(py::module_& m) {
  def_region_graph(m);
  def_match_features(m);
}

}  // namespace paramorph::python
