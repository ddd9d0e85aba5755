// Segmentations (native/features/): Segmentation, area_stretch,
// segment_extremities (features/segment_extremities.h), extremity_tips
// (features/extremity_tips.h), feature_regions
// (features/feature_regions.h), feature_points (features/feature_points.h).
#include <pybind11/stl.h>

#include "features/extremity_tips.h"
#include "features/protrusion_tips.h"
#include "features/feature_points.h"
#include "features/feature_regions.h"
#include "features/segment_extremities.h"
#include "mesh/validate.h"
#include "param/spherical/sphere_quality.h"
#include "python/arrays.h"
#include "python/bindings.h"
#include "python/progress.h"

namespace paramorph::python {

namespace {

using features::Segmentation;

void def_segmentation(py::module_& m) {
  py::class_<Segmentation>(m, "Segmentation",
                           "Regions of a mesh's faces: labels, seeds, areas, centroids, adjacency.")
      .def_property_readonly("face_labels", [](const Segmentation& s) { return to_numpy(s.face_labels); },
                             "(m,) int32, the region of each face, 0 .. regions - 1")
      .def_property_readonly("seeds", [](const Segmentation& s) { return s.seeds; },
                             "per region, the vertex it grew from")
      .def_property_readonly("area", [](const Segmentation& s) { return to_numpy(s.area); },
                             "(regions,) float64 surface area of each region")
      .def_property_readonly("centroid", [](const Segmentation& s) { return to_numpy(s.centroid); },
                             "(regions, 3) float64 area-weighted centroid of each region")
      .def_property_readonly(
          "adjacency",
          [](const Segmentation& s) {
            MatrixX2i pairs(s.adjacency.size(), 2);
            for (std::size_t i = 0; i < s.adjacency.size(); ++i)
              pairs.row(i) << s.adjacency[i].first, s.adjacency[i].second;
            return to_numpy(pairs);
          },
          "(k, 2) int32 pairs (a < b) of regions sharing an edge, sorted")
      .def_property_readonly("regions", &Segmentation::regions)
      .def("__repr__", [](const Segmentation& s) {
        return "<Segmentation regions=" + std::to_string(s.regions()) +
               " faces=" + std::to_string(s.face_labels.size()) + ">";
      });
}

void def_area_stretch(py::module_& m) {
  m.def(
      "area_stretch",
      [](const py::object& V, const py::object& F, const py::object& sphere) {
        const MatrixX3d v = to_vertices(V);
        const MatrixX3i f = to_faces(F);
        const MatrixX3d x = to_vertices(sphere, "sphere_positions");
        validate_arrays(v, f);
        PM_REQUIRE(x.rows() == v.rows(), InvalidInputError, "sphere_positions must be (",
                   v.rows(), ", 3), one point per vertex; got ", x.rows(), " rows");
        VectorXd stretch;
        {
          py::gil_scoped_release release;
          stretch = spherical::area_stretch(TriMesh(v, f), x);
        }
        return to_numpy(stretch);
      },
      py::arg("V"), py::arg("F"), py::arg("sphere_positions"),
      R"doc(Area stretch factor of every vertex (thesis Def. 3.1): the mean over its
faces of (face area / surface area) / (mapped face area / sphere area).

V: (n, 3) float64/float32; F: (m, 3) int32/int64; sphere_positions: (n, 3) unit
vectors, e.g. sphere_map(V, F).positions. Returns (n,) float64, > 0 for a
fold-free map; high on parts the map squeezes (limbs, ears).
Raises InvalidInputError for malformed or mismatched arrays.)doc");
}

void def_segment_extremities(py::module_& m) {
  m.def(
      "segment_extremities",
      [](const py::object& V, const py::object& F, double threshold, double min_area,
         const py::object& sphere, py::object progress) {
        features::ExtremityOptions o;
        o.threshold = threshold;
        o.min_area = min_area;
        if (!sphere.is_none()) o.sphere = to_vertices(sphere, "sphere");
        const MatrixX3d v = to_vertices(V);
        const MatrixX3i f = to_faces(F);
        PythonProgress bridge(std::move(progress));
        return run_without_gil(bridge,
                               [&] { return features::segment_extremities(v, f, o, bridge.get()); });
      },
      py::arg("V"), py::arg("F"), py::kw_only(), py::arg("threshold") = 1.5,
      py::arg("min_area") = 0.01, py::arg("sphere") = py::none(), py::arg("progress") = py::none(),
      R"doc(Segmentation into extremities (limbs, ears) and body by the area stretch
of a conformal sphere map (thesis 3.5.1, Defs. 3.1, 3.2).

The body's level is the median log area stretch over the sphere; the surface
more than `threshold` (in log A) above it is swept from the local maxima of
the stretch downwards, a part whose stretch varied by at least `threshold`
before meeting another being an extremity of its own; the rest is the body.
Regions under `min_area` (share of the surface) are merged into the neighbour
of nearest mean stretch, smallest first.

V: (n, 3) float64/float32; F: (m, 3) int32/int64, counter-clockwise outside.
sphere: (n, 3) unit vectors of a fold-free map; when None the conformal
sphere_map is computed and the mesh must be closed, connected, manifold and
genus 0. progress: callable(fraction, stage) -> bool; False raises Cancelled.
Returns a Segmentation. Raises the MeshError subclasses of sphere_map,
InvalidInputError for bad options, Cancelled.)doc");
}

void def_feature_regions(py::module_& m) {
  m.def(
      "feature_regions",
      [](const py::object& V, const py::object& F, double normal_angle, double concavity_threshold,
         double min_area, const py::object& concavity, py::object progress) {
        features::FeatureRegionOptions o;
        o.normal_angle = normal_angle;
        o.concavity_threshold = concavity_threshold;
        o.min_area = min_area;
        if (!concavity.is_none()) o.concavity = to_vector(concavity, "concavity");
        const MatrixX3d v = to_vertices(V);
        const MatrixX3i f = to_faces(F);
        PythonProgress bridge(std::move(progress));
        return run_without_gil(bridge,
                               [&] { return features::feature_regions(v, f, o, bridge.get()); });
      },
      py::arg("V"), py::arg("F"), py::kw_only(), py::arg("normal_angle") = 40.0,
      py::arg("concavity_threshold") = 0.02, py::arg("min_area") = 0.005,
      py::arg("concavity") = py::none(), py::arg("progress") = py::none(),
      R"doc(Feature regions by concavity and creases (thesis 4.5, Def. 4.1).

Pockets deeper than `concavity_threshold` (share of the bounding-box
diagonal) below the convex hull become regions (two pockets that meet stay
two); regions never cross an edge whose faces' normals differ by more than
`normal_angle` degrees; regions under `min_area` (share of the surface) are
merged into the most similar neighbour (mean normal and depth), smallest
first. Any manifold mesh, open or closed, any genus.

V: (n, 3) float64/float32; F: (m, 3) int32/int64. concavity: (n,) from
concavity(V, F) when already computed. progress: callable(fraction, stage) ->
bool. Returns a Segmentation. Raises DegenerateFaceError (faces with no
normal), NonManifoldError, InvalidInputError, Cancelled.)doc");
}

void def_feature_points(py::module_& m) {
  py::class_<features::FeaturePoints>(m, "FeaturePoints",
                                      "Feature points (Def. 4.2) with their regions and kinds.")
      .def_readonly("vertices", &features::FeaturePoints::vertices,
                    "vertex indices, most extreme first within each region")
      .def_readonly("regions", &features::FeaturePoints::regions, "per point, its region")
      .def_readonly("kinds", &features::FeaturePoints::kinds,
                    "per point, +1 concave (a pocket's bottom) or -1 convex (a tip)")
      .def("__len__", [](const features::FeaturePoints& p) { return p.vertices.size(); });
  m.def(
      "feature_points",
      [](const py::object& V, const py::object& F, const py::object& face_labels,
         const py::object& concavity, double spacing) {
        const MatrixX3d v = to_vertices(V);
        const MatrixX3i f = to_faces(F);
        auto labels = py::array_t<Index, py::array::c_style | py::array::forcecast>::ensure(face_labels);
        PM_REQUIRE(labels && labels.ndim() == 1, InvalidInputError,
                   "face_labels must be an (m,) integer array");
        const VectorXi l = Eigen::Map<const VectorXi>(labels.data(), labels.shape(0));
        const VectorXd c = to_vector(concavity, "concavity");
        features::FeaturePointOptions o;
        o.spacing = spacing;
        py::gil_scoped_release release;
        return features::feature_points(v, f, l, c, o);
      },
      py::arg("V"), py::arg("F"), py::arg("face_labels"), py::arg("concavity"), py::kw_only(),
      py::arg("spacing") = 0.05,
      R"doc(Feature points inside regions (thesis Def. 4.2): local extrema of the
concavity intensity. Concave points: vertices deeper below the hull than
their 1-ring (pocket bottoms). Convex points: hull vertices farther from the
centroid than every hull neighbour (tips). Within a region, points of one kind
closer than `spacing` (share of the bounding-box diagonal) to a more extreme
one are dropped.

V, F: the mesh; face_labels: (m,) regions (Segmentation.face_labels);
concavity: (n,) from concavity(V, F). Returns FeaturePoints.
Raises InvalidInputError for mismatched arrays.)doc");
}

}  // namespace

void def_extremity_tips(py::module_& m) {
  py::class_<features::ExtremityTips>(m, "ExtremityTips", "Result of extremity_tips().")
      .def_readonly("body", &features::ExtremityTips::body, "the body region (largest area)")
      .def_readonly("vertices", &features::ExtremityTips::vertices, "per extremity, its tip vertex (longest first)")
      .def_readonly("regions", &features::ExtremityTips::regions, "the extremity's region")
      .def_readonly("lengths", &features::ExtremityTips::lengths, "edge-path distance from the body to the tip");
  m.def(
      "extremity_tips",
      [](const py::object& V, const py::object& F, const Segmentation& segmentation, double prominence) {
        const MatrixX3d v = to_vertices(V);
        const MatrixX3i f = to_faces(F);
        require_mesh(v, f);
        py::gil_scoped_release release;
        return features::extremity_tips(v, f, segmentation, prominence);
      },
      py::arg("V"), py::arg("F"), py::arg("segmentation"), py::kw_only(), py::arg("prominence") = 0.0,
      R"doc(The tips of the extremities of a segmentation (segment_extremities): the
peaks of the distance along edges from the body (the largest region) that
rise at least `prominence` (units of V) above where they meet a higher one,
and in every extremity at least its farthest vertex. Returns ExtremityTips
(body, vertices, regions, lengths), farthest first.)doc");
}

void def_protrusion_tips(py::module_& m) {
  py::class_<features::ProtrusionTips>(m, "ProtrusionTips", "Result of protrusion_tips().")
      .def_property_readonly(
          "average_distance", [](const features::ProtrusionTips& t) { return to_numpy(t.average_distance); },
          "per vertex: mean edge-path distance to the samples")
      .def_readonly("core", &features::ProtrusionTips::core, "the vertex of least average distance")
      .def_readonly("vertices", &features::ProtrusionTips::vertices, "the tips, highest average distance first")
      .def_readonly("paths", &features::ProtrusionTips::paths, "per tip: vertices of a shortest edge path from the core");
  m.def(
      "protrusion_tips",
      [](const py::object& V, const py::object& F, double radius, std::size_t samples, std::size_t max_tips) {
        const MatrixX3d v = to_vertices(V);
        const MatrixX3i f = to_faces(F);
        require_mesh(v, f);
        py::gil_scoped_release release;
        return features::protrusion_tips(v, f, {radius, samples, max_tips});
      },
      py::arg("V"), py::arg("F"), py::kw_only(), py::arg("radius") = 0.15, py::arg("samples") = 100,
      py::arg("max_tips") = 24,
      R"doc(The tips of a mesh's protrusions (limbs, tail, muzzle, horns, ears): the
vertices highest in average edge-path distance (to `samples` farthest-point
samples) within `radius` (units of V) of themselves, above the median, at
most `max_tips`, highest first; with the core (least average distance) and
the edge path from the core to each tip. Meant for proxies of a few thousand
faces: one Dijkstra per sample. Returns ProtrusionTips.)doc");
}

void bind_segmentation(py::module_& m) {
  def_segmentation(m);
  def_area_stretch(m);
  def_segment_extremities(m);
  def_extremity_tips(m);
  def_protrusion_tips(m);
  def_feature_regions(m);
  def_feature_points(m);
}

}  // namespace paramorph::python
