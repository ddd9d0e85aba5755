// Morphing (native/morph/): optimize_sphere_map (morph/optimize_sphere_map.h),
// align_sphere_map (morph/align_sphere_map.h), morph (morph/morph.h),
// morph_correspondence (morph/morph.h), map_distortion, flow_sphere_map and the
// sphere-map tools the morph is built from.

#include <pybind11/stl.h>

#include <limits>

#include "morph/align_sphere_map.h"
#include "morph/flow_sphere_map.h"
#include "morph/map_distortion.h"
#include "param/spherical/map_through_proxy.h"
#include "morph/morph.h"
#include "morph/optimization_start.h"
#include "morph/optimize_sphere_map.h"
#include "morph/sphere_warp.h"
#include "param/spherical/untangle_sphere_map.h"
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

morph::SphereSolver to_solver(const std::string& name) {
  if (name == "auto") return morph::SphereSolver::Auto;
  if (name == "barrier") return morph::SphereSolver::Barrier;
  if (name == "ipopt") return morph::SphereSolver::Ipopt;
  throw InvalidInputError("solver must be \"auto\", \"barrier\" or \"ipopt\", got \"" + name + "\"");
}

void def_optimize_sphere_map(py::module_& m) {
  using morph::OptimizeSphereResult;
  py::class_<OptimizeSphereResult>(m, "OptimizedSphereMap", "Result of optimize_sphere_map().")
      .def_property_readonly("positions", [](const OptimizeSphereResult& r) { return to_numpy(r.positions); },
                             "(n, 3) float64 unit vectors, fold-free")
      .def_readonly("iterations", &OptimizeSphereResult::iterations, "Ipopt's iterations")
      .def_readonly("used_ipopt", &OptimizeSphereResult::used_ipopt, "whether Ipopt ran")
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
         const std::string& solver, py::object progress) {
        morph::OptimizeSphereOptions o;
        o.solver = to_solver(solver);
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
      py::arg("weights") = py::none(), py::arg("solver") = "auto", py::arg("progress") = py::none(),
      R"doc(Optimized sphere map for morphing (thesis 4.3.3): from a fold-free map
`sphere` (None: the start morph uses, the conformal sphere_map or, where that
squeezes faces under 1e-6 of the mean triple product, the radial projection
relaxed until fold-free, thesis 4.3.2), every vertex moves as close as the
fold constraints allow to its radial projection from the centroid (or to
`target`): maximise sum w_i v_i^0 . v_i subject to |v_i| = 1 (4.9) and, per
face, det(v_a, v_b, v_c) >= epsilon x (mean start triple product) (4.10;
lowered to half the start's smallest when the start is tighter). weights: (n,)
non-negative per-vertex w_i (all 1 when None; thesis (4.12) weighs feature
points). A log-barrier Newton path on the spheres; every accepted iterate is
fold-free. solver: "auto" (Ipopt's polish from the path where this build has
Ipopt, build_info()["ipopt"], else the path followed 8 decades of mu down),
"barrier" (the path alone), "ipopt" (InvalidInputError without Ipopt). status
is Ipopt's; without Ipopt "Barrier_Converged"; "Barrier_Point" where the path's
last round stopped at its step cap (every face above epsilon).

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
         double feature_weight, double warp_width, const py::object& target, const std::string& solver,
         py::object progress) {
        morph::AlignSphereOptions o;
        o.solver = to_solver(solver);
        o.epsilon = epsilon;
        o.max_iterations = max_iterations;
        o.tol = tol;
        o.feature_weight = feature_weight;
        o.warp_width = warp_width;
        if (!target.is_none()) o.target = to_vertices(target, "target");
        const MatrixX3d v = to_vertices(V);
        const MatrixX3i f = to_faces(F);
        require_mesh(v, f);  // before the radial projection reads V through F
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
      py::arg("warp_width") = 0.0, py::arg("target") = py::none(), py::arg("solver") = "auto",
      py::arg("progress") = py::none(),
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

void def_map_distortion(py::module_& m) {
  using morph::MapDistortion;
  py::class_<MapDistortion>(m, "MapDistortion", "Result of map_distortion().")
      .def_readonly("mean", &MapDistortion::mean, "area-weighted mean of the capped per-face distortion")
      .def_readonly("folded_share", &MapDistortion::folded_share, "share of B's area whose image is turned over")
      .def_readonly("capped_share", &MapDistortion::capped_share, "share of B's area at the cap")
      .def_property_readonly("per_face", [](const MapDistortion& r) { return to_numpy(r.per_face); });
  m.def(
      "map_distortion",
      [](const py::object& VA, const py::object& FA, const py::object& sphere_a, const py::object& VB,
         const py::object& FB, const py::object& sphere_b, double cap) {
        const MatrixX3d va = to_vertices(VA, "VA"), vb = to_vertices(VB, "VB");
        const MatrixX3i fa = to_faces(FA, "FA"), fb = to_faces(FB, "FB");
        const MatrixX3d sa = to_vertices(sphere_a, "sphere_a"), sb = to_vertices(sphere_b, "sphere_b");
        require_mesh(va, fa, "A");
        require_mesh(vb, fb, "B");
        require_directions(sa, "sphere_a", va.rows(), "A");
        require_directions(sb, "sphere_b", vb.rows(), "B");
        py::gil_scoped_release release;
        return morph::map_distortion(va, fa, sa, vb, fb, sb, cap);
      },
      py::arg("VA"), py::arg("FA"), py::arg("sphere_a"), py::arg("VB"), py::arg("FB"), py::arg("sphere_b"),
      py::kw_only(), py::arg("cap") = 10.6,
      R"doc(Distortion of the correspondence two sphere maps make, without ground
truth: every vertex of B read on A through the maps, every face of B compared
with its image (both surfaces scaled to one area): (ln s1)^2 + (ln s2)^2 per
face, capped at `cap`, turned-over images at the cap; the area-weighted mean.)doc");
  py::class_<morph::SphereFlowResult>(m, "SphereFlow", "Result of flow_sphere_map().")
      .def_property_readonly("positions", [](const morph::SphereFlowResult& r) { return to_numpy(r.positions); })
      .def_readonly("reached", &morph::SphereFlowResult::reached, "share of the way travelled (1: all)")
      .def_readonly("steps", &morph::SphereFlowResult::steps)
      .def_readonly("halved", &morph::SphereFlowResult::halved)
      .def_readonly("repairs", &morph::SphereFlowResult::repairs)
      .def_readonly("blocking", &morph::SphereFlowResult::blocking,
                    "when stalled: the points nearest the faces the smallest step would fold");
  m.def(
      "flow_sphere_map",
      [](const py::object& F, const py::object& X, const py::object& from, const py::object& to,
         const py::object& pinned_vertices) {
        const MatrixX3i f = to_faces(F, "F");
        const MatrixX3d x = to_vertices(X, "X"), a = to_vertices(from, "from"), b = to_vertices(to, "to");
        std::vector<std::pair<Index, Index>> riders;
        const std::vector<Index> pinned = to_indices(pinned_vertices, "pinned_vertices");
        for (std::size_t k = 0; k < pinned.size(); ++k) riders.emplace_back(pinned[k], Index(k));
        py::gil_scoped_release release;
        return morph::flow_sphere_map(f, x, a, b, riders);
      },
      py::arg("F"), py::arg("X"), py::arg("from_points"), py::arg("to_points"), py::arg("pinned_vertices"),
      R"doc(A fold-free sphere map X carried by the smooth flow taking from_points to
to_points, in checked steps; pinned_vertices[k] rides on point k (the first
len(pinned_vertices) points) and ends exactly on to_points[k].)doc");
  m.def(
      "warp_sphere_points",
      [](const py::object& points, const py::object& from, const py::object& to, int steps) {
        const MatrixX3d p = to_vertices(points, "points"), a = to_vertices(from, "from"), b = to_vertices(to, "to");
        MatrixX3d out;
        {
          py::gil_scoped_release release;
          out = morph::warp_points(p, a, b, steps);
        }
        return to_numpy(out);
      },
      py::arg("points"), py::arg("from"), py::arg("to"), py::kw_only(), py::arg("steps") = 16,
      "Unit vectors moved by the smooth flow of the sphere that takes `from` to `to` along great circles.");
  m.def(
      "map_through_proxy",
      [](const py::object& V, const py::object& proxy_V, const py::object& proxy_F, const py::object& proxy_map) {
        const MatrixX3d v = to_vertices(V, "V"), pv = to_vertices(proxy_V, "proxy_V"), pm_ = to_vertices(proxy_map, "proxy_map");
        const MatrixX3i pf = to_faces(proxy_F, "proxy_F");
        require_points(v, "V");
        require_mesh(pv, pf, "proxy");
        require_directions(pm_, "proxy_map", pv.rows(), "the proxy");
        MatrixX3d out;
        {
          py::gil_scoped_release release;
          out = spherical::map_through_proxy(v, pv, pf, pm_);
        }
        return to_numpy(out);
      },
      py::arg("V"), py::arg("proxy_V"), py::arg("proxy_F"), py::arg("proxy_map"),
      "A sphere map of a fine mesh read off a coarse proxy's map at each vertex's closest point on the proxy.");
  m.def(
      "untangle_sphere_map",
      [](const py::object& V, const py::object& F, const py::object& X, const py::object& fixed, int max_rings) {
        const MatrixX3d v = to_vertices(V, "V");
        const MatrixX3i f = to_faces(F, "F");
        MatrixX3d x = to_vertices(X, "X");
        std::vector<char> flags(std::size_t(v.rows()), 0);
        for (const Index i : to_indices(fixed, "fixed")) {
          PM_REQUIRE(i >= 0 && i < v.rows(), InvalidInputError, "fixed vertex ", i, " is out of range (", v.rows(),
                     " vertices)");
          flags[std::size_t(i)] = 1;
        }
        spherical::SphereUntangleOptions o;
        o.max_rings = max_rings;
        spherical::SphereUntangleResult r;
        {
          py::gil_scoped_release release;
          r = spherical::untangle_sphere_map(v, f, x, flags, o);
        }
        return py::make_tuple(to_numpy(x), r.folded_before, r.folded, r.patches, r.largest_rings);
      },
      py::arg("V"), py::arg("F"), py::arg("X"), py::arg("fixed"), py::kw_only(), py::arg("max_rings") = 10,
      "Untangles the few folded spots of a sphere map patch by patch: (X, folded before, folded after, patches, rings).");
  m.def(
      "carry_through_maps",
      [](const py::object& VA, const py::object& FA, const py::object& sphere_a, const py::object& points) {
        const MatrixX3d va = to_vertices(VA, "VA");
        const MatrixX3i fa = to_faces(FA, "FA");
        const MatrixX3d sa = to_vertices(sphere_a, "sphere_a"), sb = to_vertices(points, "points");
        require_mesh(va, fa, "A");
        require_directions(sa, "sphere_a", va.rows(), "A");
        require_directions(sb, "points");
        MatrixX3d carried;
        {
          py::gil_scoped_release release;
          carried = morph::carry_through_maps(va, fa, sa, sb);
        }
        return to_numpy(carried);
      },
      py::arg("VA"), py::arg("FA"), py::arg("sphere_a"), py::arg("points"),
      "Points of the sphere read on A through its sphere map: (p, 3) positions on A.");
}

/// Parses morph()'s keyword options (shared by morph and morph_correspondence).
morph::MorphOptions morph_options(bool automatic, const py::object& pairs, const py::object& pins, Index proxy_faces,
                                  bool extremities, bool registration, bool features, double merge_tolerance) {
  morph::MorphOptions o;
  o.automatic = automatic;
  auto to_pairs = [](const py::object& obj, const char* name) {
    std::vector<std::array<Index, 2>> out;
    const py::array_t<long long, py::array::c_style | py::array::forcecast> a(obj);
    // An empty list arrives as shape (0,): no pairs, not a wrong shape.
    if (a.size() == 0) return out;
    PM_REQUIRE(a.ndim() == 2 && a.shape(1) == 2, InvalidInputError, name, " must be a (k, 2) integer array");
    constexpr long long kLargest = std::numeric_limits<Index>::max();
    for (py::ssize_t i = 0; i < a.shape(0); ++i) {
      // Out of Index's range must not wrap round into a valid vertex.
      const long long va = a.at(i, 0), vb = a.at(i, 1);
      PM_REQUIRE(va >= -kLargest && va <= kLargest && vb >= -kLargest && vb <= kLargest, InvalidInputError, name, " ", i,
                 " (", va, ", ", vb, ") is out of range");
      out.push_back({Index(va), Index(vb)});
    }
    return out;
  };
  if (!pairs.is_none()) o.pairs = to_pairs(pairs, "pairs");
  if (!pins.is_none()) o.pins = to_pairs(pins, "pins");
  o.correspondence.proxy_faces = proxy_faces;
  o.correspondence.extremities = extremities;
  o.correspondence.registration = registration;
  o.correspondence.features = features;
  o.overlay.merge_tolerance = merge_tolerance;
  return o;
}

py::list candidates_to_list(const std::vector<morph::CorrespondenceCandidate>& candidates) {
  py::list out;
  for (const auto& c : candidates) out.append(c);
  return out;
}

void def_correspondence(py::module_& m) {
  using morph::CorrespondenceCandidate;
  py::class_<CorrespondenceCandidate>(m, "CorrespondenceCandidate",
                                      "One automatic correspondence the morph weighed, and its score.")
      .def_readonly("kind", &CorrespondenceCandidate::kind,
                    "'none', 'extremities', 'registration', 'features' or 'given'")
      .def_readonly("detail", &CorrespondenceCandidate::detail)
      .def_property_readonly("proxy_pairs", [](const CorrespondenceCandidate& c) { return pairs_to_numpy(c.proxy_pairs); },
                             "(k, 2) its automatic pairs on the proxies")
      .def_readonly("score", &CorrespondenceCandidate::score,
                    "(distortion + 0.5 curvature_mismatch) x (1 + 0.25 turn / pi) x (1 + 0.5 tip_disagreement): lower is "
                    "better; inf when rejected before scoring")
      .def_readonly("distortion", &CorrespondenceCandidate::distortion,
                    "mean isometric distortion of its correspondence (0 for an isometry)")
      .def_readonly("curvature_mismatch", &CorrespondenceCandidate::curvature_mismatch,
                    "mean difference of smoothed Gaussian curvature at corresponding points, over its spread")
      .def_readonly("turn", &CorrespondenceCandidate::turn, "radians it turns B from where it is placed")
      .def_readonly("tip_disagreement", &CorrespondenceCandidate::tip_disagreement,
                    "0 to 1: how far it puts B's protrusion tips from the partners their paths chose as placed")
      .def_readonly("rejected", &CorrespondenceCandidate::rejected, "why it could not be used: before scoring (score inf) or, by morph, on the models ('' otherwise)")
      .def("__repr__", [](const CorrespondenceCandidate& c) {
        return "<CorrespondenceCandidate " + c.kind + " (" + c.detail + ") score=" + std::to_string(c.score) +
               (c.rejected.empty() ? "" : " rejected: " + c.rejected) + ">";
      });
  using morph::MorphCorrespondence;
  py::class_<MorphCorrespondence>(m, "MorphCorrespondence", "Result of morph_correspondence().")
      .def_property_readonly("candidates", [](const MorphCorrespondence& r) { return candidates_to_list(r.correspondence.candidates); })
      .def_property_readonly("chosen", [](const MorphCorrespondence& r) { return r.correspondence.chosen; },
                             "index of the candidate morph() would use")
      .def_property_readonly("pairs", [](const MorphCorrespondence& r) { return pairs_to_numpy(r.correspondence.pairs); },
                             "(k, 2) the chosen candidate's pairs on the models (vertex of A, of B), pins not included")
      .def_property_readonly("proxy_a", [](const MorphCorrespondence& r) {
        return py::make_tuple(to_numpy(r.correspondence.proxy_a), to_numpy(r.correspondence.proxy_faces_a));
      }, "(V, F) of A's proxy, in A's correspondence frame (outward, centred, unit area)")
      .def_property_readonly("proxy_b", [](const MorphCorrespondence& r) {
        return py::make_tuple(to_numpy(r.correspondence.proxy_b), to_numpy(r.correspondence.proxy_faces_b));
      }, "(V, F) of B's proxy, in B's correspondence frame")
      .def_property_readonly("map_a", [](const MorphCorrespondence& r) { return to_numpy(r.correspondence.map_a); },
                             "balanced sphere map of A's proxy")
      .def_property_readonly("map_b", [](const MorphCorrespondence& r) { return to_numpy(r.correspondence.map_b); },
                             "balanced sphere map of B's proxy")
      .def_property_readonly("warped_b", [](const MorphCorrespondence& r) { return to_numpy(r.correspondence.warped_b); },
                             "the chosen candidate's map of B's proxy, on A's proxy map")
      .def_readonly("inside_out_a", &MorphCorrespondence::inside_out_a)
      .def_readonly("inside_out_b", &MorphCorrespondence::inside_out_b)
      .def_property_readonly("placement_turn", [](const MorphCorrespondence& r) { return r.correspondence.placement_turn; },
                             "radians B's placement was straightened by its tips before matching (0: as placed)")
      .def_property_readonly("timings", [](const MorphCorrespondence& r) { return r.correspondence.timings; });
}

void def_morph(py::module_& m) {
  using morph::Morph;
  py::class_<morph::WeldStats>(m, "WeldStats")
      .def_readonly("faces_before", &morph::WeldStats::faces_before)
      .def_readonly("faces_after", &morph::WeldStats::faces_after)
      .def_readonly("collapsed_edges", &morph::WeldStats::collapsed_edges, "short edges collapsed (vertices welded)")
      .def_readonly("flipped_edges", &morph::WeldStats::flipped_edges, "edges flipped inside a cell")
      .def_readonly("slivers_before", &morph::WeldStats::slivers_before,
                    "faces of area under 1e-12 of the squared diagonal at either end, before")
      .def_readonly("slivers_after", &morph::WeldStats::slivers_after)
      .def("__repr__", [](const morph::WeldStats& w) {
        return "<WeldStats faces " + std::to_string(w.faces_before) + " -> " + std::to_string(w.faces_after) +
               ", collapsed " + std::to_string(w.collapsed_edges) + ", flipped " + std::to_string(w.flipped_edges) +
               ", slivers " + std::to_string(w.slivers_before) + " -> " + std::to_string(w.slivers_after) + ">";
      });
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
                             "(P, 2) int32 (vertex of A, vertex of B) that hold exactly, pins first")
      .def_property_readonly("pair_is_pin", [](const Morph& r) {
        py::array_t<bool> out(py::ssize_t(r.pair_is_pin.size()));
        for (std::size_t i = 0; i < r.pair_is_pin.size(); ++i) out.mutable_at(py::ssize_t(i)) = r.pair_is_pin[i];
        return out;
      })
      .def_property_readonly("candidates", [](const Morph& r) { return candidates_to_list(r.candidates); },
                             "every CorrespondenceCandidate weighed, with its score")
      .def_readonly("chosen", &Morph::chosen, "index of the candidate used")
      .def_readonly("distortion", &Morph::distortion,
                    "isometric distortion of the final correspondence (0 for an isometry)")
      .def_readonly("inside_out_a", &Morph::inside_out_a, "A's file was inside-out (turned for the morph)")
      .def_readonly("inside_out_b", &Morph::inside_out_b, "B's file was inside-out (turned for the morph)")
      .def_readonly("placement_turn", &Morph::placement_turn,
                    "radians B's placement beside A was straightened by its tips for the correspondence "
                    "(0: matched as placed); the output keeps the models as placed")
      .def_property_readonly("sphere_a", [](const Morph& r) { return to_numpy(r.sphere_a); })
      .def_property_readonly("sphere_b", [](const Morph& r) { return to_numpy(r.sphere_b); })
      .def_readonly("timings", &Morph::timings)
      .def_readonly("weld", &Morph::weld, "WeldStats: faces before and after, edges collapsed and flipped, slivers")
      .def_readonly("fallbacks", &Morph::fallbacks,
                    "what the morph fell back on, in words for a report (empty: everything went the first way)")
      .def(
          "carry",
          [](const Morph& r, int side, const py::object& values) {
            py::array arr = py::array::ensure(values);
            PM_REQUIRE(arr && (arr.ndim() == 1 || arr.ndim() == 2), InvalidInputError,
                       "values must be a (3 * faces,) or (3 * faces, d) array");
            auto data = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(arr);
            const py::ssize_t cols = arr.ndim() == 2 ? arr.shape(1) : 1;
            Eigen::MatrixXd in(arr.shape(0), cols);
            for (py::ssize_t i = 0; i < arr.shape(0); ++i)
              for (py::ssize_t j = 0; j < cols; ++j) in(i, j) = data.data()[i * cols + j];
            return to_numpy(Eigen::MatrixXd(morph::carry_corner_values(r, side, in)));
          },
          py::arg("side"), py::arg("corner_values"),
          "Per-corner values of A (side 0) or B (side 1), rows 3f + c, carried to the merged faces "
          "(rows 3k + c).");
  m.def(
      "morph",
      [](const py::object& VA, const py::object& FA, const py::object& VB, const py::object& FB, bool automatic,
         const py::object& pairs, const py::object& pins, Index proxy_faces, bool extremities, bool registration,
         bool features, double merge_tolerance, double weld_tolerance, py::object progress) {
        morph::MorphOptions o =
            morph_options(automatic, pairs, pins, proxy_faces, extremities, registration, features, merge_tolerance);
        PM_REQUIRE(weld_tolerance >= 0 && weld_tolerance < 1e-2, InvalidInputError,
                   "weld_tolerance is a share of the diagonal in [0, 0.01) (0: no welding), got ", weld_tolerance);
        o.weld_tolerance = weld_tolerance;
        const MatrixX3d va = to_vertices(VA, "VA"), vb = to_vertices(VB, "VB");
        const MatrixX3i fa = to_faces(FA, "FA"), fb = to_faces(FB, "FB");
        PythonProgress bridge(std::move(progress));
        return run_without_gil(bridge, [&] { return morph::morph(va, fa, vb, fb, o, bridge.get()); });
      },
      py::arg("VA"), py::arg("FA"), py::arg("VB"), py::arg("FB"), py::kw_only(), py::arg("automatic") = true,
      py::arg("pairs") = py::none(), py::arg("pins") = py::none(), py::arg("proxy_faces") = 3000,
      py::arg("extremities") = true, py::arg("registration") = true, py::arg("features") = true,
      py::arg("merge_tolerance") = 1e-6, py::arg("weld_tolerance") = 1e-6, py::arg("progress") = py::none(),
      R"doc(Morph of closed genus-0 mesh A into B (thesis ch. 4; issue 16).

Both models are turned outward when their files are inside-out, centred and
scaled for the correspondence, and both turned by one rotation taken from A's
shape (a common turn, scale or shift of the scene gives the same answer). On proxies of about `proxy_faces` faces with
balanced (isometric) sphere maps, candidate correspondences are scored by the
distortion they make, no ground truth needed: none (the models as placed),
pairings of extremity tips (segment_extremities), with 3+ pins tips paired by
their distances to the pins, 3D registrations from the
principal axes, the thesis' feature points (match_features); the lowest
wins, so automatic pairs are used only when they beat no pairs
(automatic=False: the pins and any given pairs alone). pins: (k, 2) (vertex of A, vertex of B),
hard: the pinned vertex of A lands exactly on its partner at t = 1. pairs:
(k, 2) to use instead of the automatic candidates (e.g. an edited preview).
The maps are overlaid (4.4) into one merged topology, which is then welded
(edges under 1e-4 of the diagonal at either end collapsed where every face
stays inside one face of each input within weld_tolerance of the diagonal,
faces of nearly zero area flipped inside their cells; both ends move by at
most weld_tolerance; 0: off; morph.weld says what it did).

Returns Morph: faces, sphere, source (A as placed), target (B as placed),
vertex_of_a/b, source_face_a/b, merged, pairs, pair_is_pin, candidates,
chosen, distortion, inside_out_a/b, placement_turn (radians B's placement was straightened by
its tips for the correspondence, set down a little askew), sphere_a/b, timings, weld, fallbacks (what it fell back on,
in words: a model's own sphere map where its proxy's keeps folds), carry(side, values).
Errors name the mesh ("mesh A: ..."), keep their MeshError type; pins out of
range: InvalidInputError; a vertex pinned twice or mirrored pins:
ConstraintError naming them; Cancelled.)doc");
  m.def(
      "morph_correspondence",
      [](const py::object& VA, const py::object& FA, const py::object& VB, const py::object& FB, bool automatic,
         const py::object& pairs, const py::object& pins, Index proxy_faces, bool extremities, bool registration,
         bool features, py::object progress) {
        const morph::MorphOptions o =
            morph_options(automatic, pairs, pins, proxy_faces, extremities, registration, features, 1e-6);
        const MatrixX3d va = to_vertices(VA, "VA"), vb = to_vertices(VB, "VB");
        const MatrixX3i fa = to_faces(FA, "FA"), fb = to_faces(FB, "FB");
        PythonProgress bridge(std::move(progress));
        return run_without_gil(bridge, [&] { return morph::morph_correspondence(va, fa, vb, fb, o, bridge.get()); });
      },
      py::arg("VA"), py::arg("FA"), py::arg("VB"), py::arg("FB"), py::kw_only(), py::arg("automatic") = true,
      py::arg("pairs") = py::none(), py::arg("pins") = py::none(), py::arg("proxy_faces") = 3000,
      py::arg("extremities") = true, py::arg("registration") = true, py::arg("features") = true,
      py::arg("progress") = py::none(),
      R"doc(The correspondence morph() would choose with the same options, for a
preview: every candidate with its score, the chosen one, and its pairs on the
models. Same checks and errors as morph().)doc");
}

void bind_morph(py::module_& m) {
  def_optimize_sphere_map(m);
  def_align_sphere_map(m);
  def_map_distortion(m);
  def_correspondence(m);
  def_morph(m);
}

}  // namespace paramorph::python
