// Morphing (native/morph/): optimize_sphere_map (morph/optimize_sphere_map.h),
// align_sphere_map (morph/align_sphere_map.h), morph (morph/morph.h),
// morph_pairs (morph/registered_pairs.h).

#include <pybind11/stl.h>

#include "morph/align_sphere_map.h"
#include "morph/morph.h"
#include "morph/optimization_start.h"
#include "morph/optimize_sphere_map.h"
#include "morph/registered_pairs.h"
#include "python/arrays.h"
#include "python/bindings.h"
#include "python/progress.h"

namespace paramorph::python {

namespace {

py::array pairs_to_numpy(const std::vector<std::array<Index, 2>>& pairs) {
  py::array_t<Index> out({py::ssize_t(pairs.size()), py::ssize_t(2)});
  auto w = out.mutable_unchecked<2>();
  for (std::size_t k = 0; k < pairs.size(); ++k) {
    w(py::ssize_t(k), 0) = pairs[k][0];
    w(py::ssize_t(k), 1) = pairs[k][1];
  }
  return out;
}

void def_optimize_sphere_map(py::module_& m) {
  using morph::OptimizeSphereResult;
  py::class_<OptimizeSphereResult>(m, "OptimizedSphereMap", "Result of optimize_sphere_map().")
      .def_property_readonly("positions", [](const OptimizeSphereResult& r) { return to_numpy(r.positions); },
                             "(n, 3) float64 unit vectors, fold-free")
      .def_readonly("iterations", &OptimizeSphereResult::iterations, "Ipopt's iterations")
      .def_readonly("barrier_steps", &OptimizeSphereResult::barrier_steps,
                    "Newton steps of the log-barrier warm start (0: Ipopt alone)")
      .def_readonly("objective", &OptimizeSphereResult::objective,
                    "sum of w_i v_i^0 . v_i at the end (sum of w_i at best)")
      .def_readonly("start_objective", &OptimizeSphereResult::start_objective)
      .def_readonly("epsilon", &OptimizeSphereResult::epsilon, "the absolute triple-product bound used")
      .def_readonly("min_triple", &OptimizeSphereResult::min_triple)
      .def_readonly("flipped", &OptimizeSphereResult::flipped)
      .def_readonly("status", &OptimizeSphereResult::status, "Ipopt's return status")
      .def_readonly("seconds", &OptimizeSphereResult::seconds)
      .def("__repr__", [](const OptimizeSphereResult& r) {
        return "<OptimizedSphereMap n=" + std::to_string(r.positions.rows()) +
               " iterations=" + std::to_string(r.iterations) + " flipped=" + std::to_string(r.flipped) +
               " status=" + r.status + ">";
      });
  m.def(
      "optimize_sphere_map",
      [](const py::object& V, const py::object& F, const py::object& sphere, double epsilon,
         int max_iterations, double tol, const py::object& target, const py::object& weights,
         py::object progress) {
        morph::OptimizeSphereOptions o;
        o.epsilon = epsilon;
        o.max_iterations = max_iterations;
        o.tol = tol;
        if (!target.is_none()) o.target = to_vertices(target, "target");
        if (!weights.is_none()) o.weights = to_vector(weights, "weights");
        const MatrixX3d v = to_vertices(V);
        const MatrixX3i f = to_faces(F);
        std::optional<MatrixX3d> given;
        if (!sphere.is_none()) given = to_vertices(sphere, "sphere");
        PythonProgress bridge(std::move(progress));
        return run_without_gil(bridge, [&] {
          const MatrixX3d start = given ? *given : morph::optimization_start(v, f, bridge.get());
          return morph::optimize_sphere_map(v, f, start, o, bridge.get());
        });
      },
      py::arg("V"), py::arg("F"), py::arg("sphere") = py::none(), py::kw_only(), py::arg("epsilon") = 0.05,
      py::arg("max_iterations") = 200, py::arg("tol") = 1e-6, py::arg("target") = py::none(),
      py::arg("weights") = py::none(), py::arg("progress") = py::none(),
      R"doc(Optimized sphere map for morphing (thesis 4.3.3): from a fold-free map
`sphere` (None: the start morph uses, the conformal sphere_map or, where that
squeezes faces under 1e-6 of the mean triple product, the radial projection
relaxed until fold-free, thesis 4.3.2), every vertex moves as close as the
fold constraints allow to its radial projection from the centroid (or to
`target`): maximise sum w_i v_i^0 . v_i subject to |v_i| = 1 (4.9) and, per
face, det(v_a, v_b, v_c) >= epsilon x (mean start triple product) (4.10;
lowered to half the start's smallest when the start is tighter). weights: (n,)
non-negative per-vertex w_i (all 1 when None; thesis (4.12) weighs feature
points). Ipopt (MUMPS) with exact sparse derivatives, warm-started from a
log-barrier Newton path on the spheres; every accepted iterate is fold-free.
status is Ipopt's, or "Barrier_Point" where the path's last round stopped at
its step cap and its point (every face above epsilon) is returned unpolished.

V: (n, 3) float64/float32; F: (m, 3) int32/int64, closed genus 0; sphere:
(n, 3). progress: callable(fraction, stage) -> bool; False raises Cancelled.
Returns OptimizedSphereMap (positions, iterations, barrier_steps, objective,
start_objective, epsilon, min_triple, flipped, status, seconds). Raises the MeshError
subclasses of a non-closed / non-genus-0 mesh, InvalidInputError for a folded
or mis-shaped start or bad weights, Cancelled.)doc");
}

}  // namespace

void def_align_sphere_map(py::module_& m) {
  using morph::AlignSphereResult;
  py::class_<AlignSphereResult>(m, "AlignedSphereMap", "Result of align_sphere_map().")
      .def_property_readonly("positions", [](const AlignSphereResult& r) { return to_numpy(r.positions); },
                             "(n, 3) float64 unit vectors, fold-free")
      .def_property_readonly("rotation", [](const AlignSphereResult& r) { return to_numpy(r.rotation); },
                             "(3, 3): the rotation applied to the targets first (row vectors: p @ R)")
      .def_readonly("mean_error_rotated", &AlignSphereResult::mean_error_rotated,
                    "mean angle (radians) from a paired vertex to its target after the rotation alone")
      .def_readonly("mean_error", &AlignSphereResult::mean_error, "mean angle at the end")
      .def_readonly("max_error", &AlignSphereResult::max_error, "largest angle at the end")
      .def_readonly("solve", &AlignSphereResult::solve, "the Ipopt run (OptimizedSphereMap)");
  m.def(
      "align_sphere_map",
      [](const py::object& V, const py::object& F, const py::object& sphere, const py::object& vertices,
         const py::object& targets, const py::object& weights, double epsilon, int max_iterations, double tol,
         double feature_weight, double warp_width, const py::object& target, py::object progress) {
        morph::AlignSphereOptions o;
        o.epsilon = epsilon;
        o.max_iterations = max_iterations;
        o.tol = tol;
        o.feature_weight = feature_weight;
        o.warp_width = warp_width;
        if (!target.is_none()) o.target = to_vertices(target, "target");
        const MatrixX3d v = to_vertices(V);
        const MatrixX3i f = to_faces(F);
        const MatrixX3d s = to_vertices(sphere, "sphere");
        const std::vector<Index> paired = to_indices(vertices, "vertices");
        const MatrixX3d t = to_vertices(targets, "targets");
        const VectorXd w = weights.is_none() ? VectorXd() : to_vector(weights, "weights");
        PythonProgress bridge(std::move(progress));
        return run_without_gil(bridge, [&] {
          return morph::align_sphere_map(v, f, s, paired, t, w, o, bridge.get());
        });
      },
      py::arg("V"), py::arg("F"), py::arg("sphere"), py::arg("vertices"), py::arg("targets"),
      py::arg("weights") = py::none(), py::kw_only(), py::arg("epsilon") = 0.05,
      py::arg("max_iterations") = 200, py::arg("tol") = 1e-6, py::arg("feature_weight") = 50.0,
      py::arg("warp_width") = 0.0, py::arg("target") = py::none(), py::arg("progress") = py::none(),
      R"doc(Feature-aligned sphere map (thesis 4.5, (4.12)): B's map moved so its
paired vertices land on their targets (e.g. where their partners are on A's
map), fold-free. The targets of every vertex (B's radial projection, or
`target`) are turned by the best rotation of the pairs, bent by a smooth warp
that carries the pairs onto their targets, then optimize_sphere_map keeps the
map fold-free while pulling each vertex to its bent target and each paired
vertex to its pair's target with `feature_weight` x its pair weight.

vertices: (k,) ints; targets: (k, 3) unit vectors; weights: (k,) > 0 or None.
Returns AlignedSphereMap (positions, rotation, mean_error_rotated, mean_error,
max_error, solve).)doc");
}

void def_morph(py::module_& m) {
  using morph::Morph;
  py::class_<Morph>(m, "Morph", "Result of morph(): the merged topology and both shapes on it.")
      .def_property_readonly("faces", [](const Morph& r) { return to_numpy(r.merged.F); },
                             "(K, 3) int32 merged triangles")
      .def_property_readonly("sphere", [](const Morph& r) { return to_numpy(r.merged.V); },
                             "(M, 3) merged vertices on the unit sphere")
      .def_property_readonly("source", [](const Morph& r) { return to_numpy(r.source); },
                             "(M, 3) each merged vertex on A (the Basis shape)")
      .def_property_readonly("target", [](const Morph& r) { return to_numpy(r.target); },
                             "(M, 3) each merged vertex on B (the target shape)")
      .def_property_readonly("vertex_of_a", [](const Morph& r) { return to_numpy(r.merged.vertex_of_a); })
      .def_property_readonly("vertex_of_b", [](const Morph& r) { return to_numpy(r.merged.vertex_of_b); })
      .def_property_readonly("source_face_a", [](const Morph& r) { return to_numpy(r.merged.source_face_a); })
      .def_property_readonly("source_face_b", [](const Morph& r) { return to_numpy(r.merged.source_face_b); })
      .def_property_readonly("merged", [](const Morph& r) { return r.merged; },
                             "the MergedTopology (barycentric coordinates in A and B, stats)")
      .def_property_readonly("pairs", [](const Morph& r) { return pairs_to_numpy(r.pairs); },
                             "(P, 2) int32 (vertex of A, vertex of B) used, pins first")
      .def_property_readonly("pair_is_pin", [](const Morph& r) {
        py::array_t<bool> out(py::ssize_t(r.pair_is_pin.size()));
        for (std::size_t i = 0; i < r.pair_is_pin.size(); ++i) out.mutable_at(py::ssize_t(i)) = r.pair_is_pin[i];
        return out;
      })
      .def_property_readonly("pair_scores", [](const Morph& r) { return to_numpy(r.pair_scores); })
      .def_readonly("mean_pair_error", &Morph::mean_pair_error,
                    "mean angle (radians) between paired points on the two maps")
      .def_property_readonly("registration_cost", [](const Morph& r) -> py::object {
        return r.registration ? py::cast(r.registration->cost) : py::none();
      }, "mean distance of the registered B from A (share of A's diagonal), or None")
      .def_readonly("registration_fold_share", &Morph::registration_fold_share,
                    "share of B's area folded when carried onto A by the registration tried "
                    "(over max_fold_share: the registration was not used)")
      .def_property_readonly("sphere_a", [](const Morph& r) { return to_numpy(r.sphere_a); })
      .def_property_readonly("sphere_b", [](const Morph& r) { return to_numpy(r.sphere_b); })
      .def_property_readonly("match", [](const Morph& r) -> py::object {
        return r.match ? py::cast(*r.match) : py::none();
      }, "the FeatureMatch when features were matched, else None")
      .def_readonly("timings", &Morph::timings, "[(stage, seconds)]")
      .def("carry", [](const Morph& r, int side, const py::object& values) {
             py::array arr = py::array::ensure(values);
             PM_REQUIRE(arr && (arr.ndim() == 1 || arr.ndim() == 2), InvalidInputError,
                        "values must be a (3 * faces,) or (3 * faces, d) array");
             auto data = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(arr);
             const py::ssize_t cols = arr.ndim() == 2 ? arr.shape(1) : 1;
             Eigen::MatrixXd in(arr.shape(0), cols);
             for (py::ssize_t i = 0; i < arr.shape(0); ++i)
               for (py::ssize_t j = 0; j < cols; ++j) in(i, j) = data.data()[i * cols + j];
             const Eigen::MatrixXd out = morph::carry_corner_values(r.merged, side, in);
             return to_numpy(out);
           },
           py::arg("side"), py::arg("values"),
           R"doc(Per-corner values of A (side 0) or B (side 1) -- UVs, colours: row
3f + c for corner c of face f -- carried to the merged triangles (row 3k + c)
through the corner barycentric coordinates.)doc")
      .def("__repr__", [](const Morph& r) {
        return "<Morph faces=" + std::to_string(r.merged.F.rows()) + " vertices=" +
               std::to_string(r.merged.V.rows()) + " pairs=" + std::to_string(r.pairs.size()) + ">";
      });
  m.def(
      "morph",
      [](const py::object& VA, const py::object& FA, const py::object& VB, const py::object& FB, bool features,
         const py::object& pairs, const py::object& pins, double epsilon, int max_iterations, double pin_weight,
         double pin_radius, double feature_weight, double normal_angle, double concavity_threshold,
         double min_area, double spacing, double merge_tolerance, const py::object& sphere_a,
         const py::object& sphere_b, bool register_surfaces, double pair_distance, double max_fold_share,
         py::object progress) {
        morph::MorphOptions o;
        o.max_fold_share = max_fold_share;
        o.features = features;
        o.register_surfaces = register_surfaces;
        o.pair_distance = pair_distance;
        if (!pairs.is_none()) o.pairs = to_index_pairs(pairs, "pairs");
        if (!pins.is_none()) o.pins = to_index_pairs(pins, "pins");
        o.epsilon = epsilon;
        o.max_iterations = max_iterations;
        o.pin_weight = pin_weight;
        o.pin_radius = pin_radius;
        o.align.feature_weight = feature_weight;
        o.match.regions.normal_angle = normal_angle;
        o.match.regions.concavity_threshold = concavity_threshold;
        o.match.regions.min_area = min_area;
        o.match.points.spacing = spacing;
        o.overlay.merge_tolerance = merge_tolerance;
        if (!sphere_a.is_none()) o.sphere_a = to_vertices(sphere_a, "sphere_a");
        if (!sphere_b.is_none()) o.sphere_b = to_vertices(sphere_b, "sphere_b");
        const MatrixX3d va = to_vertices(VA, "VA"), vb = to_vertices(VB, "VB");
        const MatrixX3i fa = to_faces(FA, "FA"), fb = to_faces(FB, "FB");
        PythonProgress bridge(std::move(progress));
        return run_without_gil(bridge, [&] { return morph::morph(va, fa, vb, fb, o, bridge.get()); });
      },
      py::arg("VA"), py::arg("FA"), py::arg("VB"), py::arg("FB"), py::kw_only(), py::arg("features") = true,
      py::arg("pairs") = py::none(), py::arg("pins") = py::none(), py::arg("epsilon") = 0.05,
      py::arg("max_iterations") = 200, py::arg("pin_weight") = 4.0, py::arg("pin_radius") = 0.15,
      py::arg("feature_weight") = 50.0, py::arg("normal_angle") = 40.0, py::arg("concavity_threshold") = 0.02,
      py::arg("min_area") = 0.005, py::arg("spacing") = 0.05, py::arg("merge_tolerance") = 1e-6,
      py::arg("sphere_a") = py::none(), py::arg("sphere_b") = py::none(),
      py::arg("register_surfaces") = true, py::arg("pair_distance") = 0.03, py::arg("max_fold_share") = 0.01,
      py::arg("progress") = py::none(),
      R"doc(Feature-based morph of closed genus-0 mesh A into B (thesis ch. 4): both
sphere-mapped, A's map optimized (4.3.3), features matched (4.5; off with
features=False, or `pairs` (k, 2) given instead), B's map aligned to A's
paired features ((4.12), fold constraints), the maps overlaid (4.4).
With features, B is first registered onto A in 3D (register_surfaces=True:
polynomial point-to-plane ICP); B's targets are then A's map at the closest
points of A, and the pairs are the feature points mutually nearest after
registration, within pair_distance (share of A's bounding-box diagonal);
when more than max_fold_share of B's area folds when carried onto A by the
registration (shapes too unlike for a 3D fit), it is not used.
pins: (k, 2) user pairs, always used and winning over automatic pairs on or
within pin_radius (radians) of their vertices. sphere_a / sphere_b: fold-free
sphere maps already at hand.

Returns Morph: faces, sphere, source (A's shape), target (B's shape),
vertex_of_a/b, source_face_a/b, merged, pairs, pair_is_pin, pair_scores,
mean_pair_error, registration_cost, sphere_a/b, match, timings, carry(side, values). Errors name
the mesh ("mesh A: ..."), keep their MeshError type; Cancelled.)doc");
}

void def_morph_pairs(py::module_& m) {
  using morph::MorphPairs;
  py::class_<MorphPairs>(m, "MorphPairs", "Result of morph_pairs().")
      .def_readonly("match", &MorphPairs::match, "the FeatureMatch (regions, points, region pairs)")
      .def_property_readonly("pairs", [](const MorphPairs& r) { return pairs_to_numpy(r.pairs.pairs); },
                             "(P, 2) int32 (vertex of A, vertex of B): the pairs morph() would use")
      .def_property_readonly("scores", [](const MorphPairs& r) { return to_numpy(r.pairs.scores); })
      .def_property_readonly("registration_cost", [](const MorphPairs& r) -> py::object {
        return r.registration ? py::cast(r.registration->cost) : py::none();
      }, "mean distance of the registered B from A (share of A's diagonal), or None")
      .def_readonly("fold_share", &MorphPairs::fold_share,
                    "share of B's area folded when carried onto A by the registration tried");
  m.def(
      "morph_pairs",
      [](const py::object& VA, const py::object& FA, const py::object& VB, const py::object& FB,
         double normal_angle, double concavity_threshold, double min_area, double spacing,
         bool register_surfaces, double pair_distance, double max_fold_share, py::object progress) {
        features::MatchOptions o;
        o.regions.normal_angle = normal_angle;
        o.regions.concavity_threshold = concavity_threshold;
        o.regions.min_area = min_area;
        o.points.spacing = spacing;
        const MatrixX3d va = to_vertices(VA, "VA"), vb = to_vertices(VB, "VB");
        const MatrixX3i fa = to_faces(FA, "FA"), fb = to_faces(FB, "FB");
        PythonProgress bridge(std::move(progress));
        return run_without_gil(bridge, [&] {
          return morph::morph_pairs(va, fa, vb, fb, o, register_surfaces, {}, pair_distance, max_fold_share,
                                    bridge.get());
        });
      },
      py::arg("VA"), py::arg("FA"), py::arg("VB"), py::arg("FB"), py::kw_only(), py::arg("normal_angle") = 40.0,
      py::arg("concavity_threshold") = 0.02, py::arg("min_area") = 0.005, py::arg("spacing") = 0.05,
      py::arg("register_surfaces") = true, py::arg("pair_distance") = 0.03, py::arg("max_fold_share") = 0.01,
      py::arg("progress") = py::none(),
      R"doc(The feature pairs morph() makes with the same options, for a preview:
match_features, then B registered onto A in 3D and the feature points of one
kind mutually nearest after registration (within pair_distance, share of A's
bounding-box diagonal); without register_surfaces, or when more than
max_fold_share of B's area folds when carried onto A (shapes too unlike for
a 3D fit), the match's own point pairs. Returns MorphPairs: match, pairs,
scores, registration_cost (None when not used), fold_share. Errors as
match_features; Cancelled.)doc");
}

void bind_morph(py::module_& m) {
  def_optimize_sphere_map(m);
  def_align_sphere_map(m);
  def_morph(m);
  def_morph_pairs(m);
}

}  // namespace paramorph::python
