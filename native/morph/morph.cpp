#include "morph/morph.h"

#include <chrono>
#include <cmath>

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <Eigen/SVD>
#include <map>
#include <optional>
#include <utility>

#include "common/best_rotation.h"
#include "common/errors.h"
#include "mesh/validate.h"
#include "morph/correspondence_frame.h"
#include "morph/map_distortion.h"
#include "morph/flow_sphere_map.h"
#include "morph/sphere_predicates.h"
#include "param/spherical/balanced_sphere_map.h"
#include "param/spherical/map_through_proxy.h"
#include "param/spherical/relax_sphere_map.h"
#include "param/spherical/untangle_sphere_map.h"

namespace paramorph::morph {

namespace {

using Pairs = std::vector<std::array<Index, 2>>;

/// Position on the mesh of every merged vertex from its face and central
/// barycentric coordinates.
MatrixX3d positions_on(const MatrixX3d& V, const MatrixX3i& F, const VectorXi& face, const MatrixX3d& bary) {
  MatrixX3d out(face.size(), 3);
  for (Index i = 0; i < face.size(); ++i) {
    const auto f = F.row(face[i]);
    out.row(i) = bary(i, 0) * V.row(f[0]) + bary(i, 1) * V.row(f[1]) + bary(i, 2) * V.row(f[2]);
  }
  return out;
}

/// Range and uniqueness: a vertex of A or of B in two pins (or pairs) is a
/// contradiction, not a typo to guess about.
void check_pairs(const Pairs& pairs, Index na, Index nb, const char* what) {
  std::map<Index, std::size_t> of_a, of_b;
  for (std::size_t k = 0; k < pairs.size(); ++k) {
    const auto& p = pairs[k];
    PM_REQUIRE(p[0] >= 0 && p[0] < na && p[1] >= 0 && p[1] < nb, InvalidInputError, what, " ", k, " (", p[0],
               ", ", p[1], ") is out of range: A has ", na, " vertices, B ", nb);
    const auto [a, new_a] = of_a.emplace(p[0], k);
    PM_REQUIRE(new_a, ConstraintError, what, "s ", a->second, " and ", k, " both pin vertex ", p[0], " of A");
    const auto [b, new_b] = of_b.emplace(p[1], k);
    PM_REQUIRE(new_b, ConstraintError, what, "s ", b->second, " and ", k, " both pin vertex ", p[1], " of B");
  }
}

/// Whether every face of a sphere map turns the right way by the exact
/// orientation test the overlay applies (a face squeezed to exactly flat by
/// rounding counts as folded there).
bool exactly_fold_free(const MatrixX3d& X, const MatrixX3i& F) {
  const MatrixX3d unit = X.rowwise().normalized();
  for (Index f = 0; f < F.rows(); ++f) {
    const Eigen::Vector3d a = unit.row(F(f, 0)), b = unit.row(F(f, 1)), c = unit.row(F(f, 2));
    if (orientation(a.data(), b.data(), c.data()) <= 0) return false;
  }
  return true;
}

/// A model's map read off its proxy's map (the proxy's map itself when the
/// model was small enough to be its own proxy), untangled; nothing when
/// folds remain (the caller decides whether that is an error or a reason to
/// try another way).
std::optional<MatrixX3d> read_through_proxy(const MatrixX3d& V, const MatrixX3i& F, const MatrixX3d& proxy_V,
                                            const MatrixX3i& proxy_F, const MatrixX3d& proxy_map) {
  const bool own = proxy_V.rows() == V.rows() && proxy_F.rows() == F.rows() && proxy_F == F;
  MatrixX3d X = own ? proxy_map : spherical::map_through_proxy(V, proxy_V, proxy_F, proxy_map);
  const spherical::SphereUntangleResult untangled =
      spherical::untangle_sphere_map(V, F, X, std::vector<char>(std::size_t(V.rows()), 0));
  if (untangled.folded > 0) return std::nullopt;
  // Where the model turns against its proxy (thin tips) the map can keep
  // hair-thin faces spanning a sixth of the sphere: relax them.
  if (!own || untangled.folded_before > 0) spherical::relax_poor_regions(V, F, X, {});
  if (!exactly_fold_free(X, F)) return std::nullopt;
  return X;
}

/// A model's map read off its proxy's map; where that keeps folds (a thin
/// part the proxy simplified away turns against it), the model's own
/// balanced map, fold-free by construction (issue 28), turned to face the
/// proxy's map as closely as it can, and a note saying so.
MatrixX3d model_map(const char* name, const MatrixX3d& V, const MatrixX3i& F, const MatrixX3d& proxy_V,
                    const MatrixX3i& proxy_F, const MatrixX3d& proxy_map, std::vector<std::string>& fallbacks,
                    Progress* progress) {
  if (std::optional<MatrixX3d> read = read_through_proxy(V, F, proxy_V, proxy_F, proxy_map)) return *read;
  const MatrixX3d read_folded = spherical::map_through_proxy(V, proxy_V, proxy_F, proxy_map);
  const MatrixX3d own = spherical::balanced_sphere_map(V, F, {}, progress).positions;
  fallbacks.push_back(detail::concat("mesh ", name, ": its own sphere map (", F.rows(),
                                     " faces) instead of its proxy's, which kept folds where the model "
                                     "turns against the simplified proxy"));
  return own * best_rotation(own, read_folded);
}

struct Prepared {
  CorrespondenceFrame a, b;
  Pairs pins;
};

Prepared prepare(const MatrixX3d& VA, const MatrixX3i& FA, const MatrixX3d& VB, const MatrixX3i& FB,
                 const MorphOptions& o) {
  for_mesh("A", [&] { validate_arrays(VA, FA); require_closed_genus0(validate(TriMesh(VA, FA))); return 0; });
  for_mesh("B", [&] { validate_arrays(VB, FB); require_closed_genus0(validate(TriMesh(VB, FB))); return 0; });
  check_overlay_options(o.overlay);  // an InvalidInputError of the overlay is then about the maps
  check_pairs(o.pins, VA.rows(), VB.rows(), "pin");
  if (o.pairs) check_pairs(*o.pairs, VA.rows(), VB.rows(), "pair");
  Prepared p{correspondence_frame(VA, FA), correspondence_frame(VB, FB), o.pins};
  // One turn for both, from A's shape: the same correspondence however the
  // scene is turned (issue 29), the models' relative placement kept.
  const Eigen::Matrix3d turn = shape_rotation(p.a.V, p.a.F);
  // Snapped to a grid of 2^-kGridBits (the models have unit area here):
  // turned copies of a scene then give the same bits, not numbers a rounding
  // apart that send a simplification's tie or a tip's peak the other way.
  // The turn itself is computed a few ulps differently in each scene, so
  // the grid must be coarse enough that no coordinate of 100k vertices is
  // likely to fall that near a rounding boundary (2^-32 let one through on
  // a 23k-vertex scan: a landmark moved 0.6 %).
  constexpr int kGridBits = 24;
  auto snap = [](MatrixX3d V) { return MatrixX3d(V.unaryExpr([](double x) { return std::ldexp(std::nearbyint(std::ldexp(x, kGridBits)), -kGridBits); })); };
  p.a.V = snap(p.a.V * turn.transpose());
  p.b.V = snap(p.b.V * turn.transpose());
  return p;
}

CorrespondenceOptions candidate_options(const MorphOptions& o) {
  CorrespondenceOptions c = o.correspondence;
  if (!o.automatic) c.extremities = c.registration = c.features = false;
  return c;
}

}  // namespace

MorphCorrespondence morph_correspondence(const MatrixX3d& VA, const MatrixX3i& FA, const MatrixX3d& VB,
                                         const MatrixX3i& FB, const MorphOptions& o, Progress* progress) {
  const Prepared p = prepare(VA, FA, VB, FB, o);
  MorphCorrespondence out;
  out.inside_out_a = p.a.inside_out;
  out.inside_out_b = p.b.inside_out;
  out.correspondence = correspondence(p.a.V, p.a.F, p.b.V, p.b.F, p.pins, o.pairs, candidate_options(o), progress);
  return out;
}

namespace {

/// The overlay refused the two maps (their thinnest faces nearly coincide).
struct OverlayRefused : ComputeError {
  using ComputeError::ComputeError;
};

/// No ranked candidate's pairs, nor the pins alone, could be met on the
/// model (a ConstraintError to the caller when trying more does not help).
struct CandidatesUnmet : ConstraintError {
  using ConstraintError::ConstraintError;
};

/// Candidates tried after the ranked ones all failed: four hooves pinned
/// on a lion and a scanned cow, the pins alone and the three best stalled,
/// the fifth (tips paired by their distances to the pins) held (issue 29).
constexpr int kMoreFallbacks = 10;

Morph morph_once(const MatrixX3d& VA, const MatrixX3i& FA, const MatrixX3d& VB, const MatrixX3i& FB,
                 const MorphOptions& o, Progress* progress) {
  if (progress) progress->report(0.0, "morph");
  const auto started = std::chrono::steady_clock::now();
  const Prepared p = prepare(VA, FA, VB, FB, o);
  Morph m;
  m.inside_out_a = p.a.inside_out;
  m.inside_out_b = p.b.inside_out;

  // 2. The correspondence.
  Correspondence c = run_stage("correspondence", 0.0, 0.7, progress, [&](Progress* window) {
    return correspondence(p.a.V, p.a.F, p.b.V, p.b.F, p.pins, o.pairs, candidate_options(o), window);
  });
  m.timings = c.timings;
  m.candidates = c.candidates;
  m.placement_turn = c.placement_turn;

  // 3. The two maps. A's is its proxy's map read at its vertices; B's is its
  // own map carried by the chosen correspondence's flow, from where its
  // pinned vertices (and the winner's samples) are on it to where their
  // partners are on A's map. Riding on their points, the pinned vertices end
  // exactly on their partners. Where B's map cannot meet the best candidate
  // without folding, the next best is tried.
  auto clock = std::chrono::steady_clock::now();
  auto mark = [&](const char* stage) {
    m.timings.emplace_back(stage, std::chrono::duration<double>(std::chrono::steady_clock::now() - clock).count());
    clock = std::chrono::steady_clock::now();
  };
  m.sphere_a = for_mesh("A", [&] {
    return run_stage("sphere map of A", 0.7, 0.75, progress, [&](Progress* window) {
      return model_map("A", p.a.V, p.a.F, c.proxy_a, c.proxy_faces_a, c.map_a, m.fallbacks, window);
    });
  });
  if (progress) progress->report(0.75, "sphere map of B");
  std::optional<MatrixX3d> own_b;  // B's own map, read only if a short flow stalls
  std::string first_failure;
  int attempt = 0;
  for (const Realization& real : c.ranked) {
    // Attempt i reports in [a_i, a_i+1], a_i = 0.85 - 0.1 / 2^i: forward
    // only, however many candidates are tried.
    const double lo = 0.85 - 0.1 * std::pow(0.5, attempt), mid = 0.85 - 0.075 * std::pow(0.5, attempt),
                 hi = 0.85 - 0.05 * std::pow(0.5, attempt);
    ++attempt;
    if (progress) progress->report(lo, "sphere map of B");
    std::vector<std::array<Index, 2>> held = p.pins;
    held.insert(held.end(), real.pairs.begin(), real.pairs.end());
    const Index count = Index(held.size());
    std::vector<std::pair<Index, Index>> riders;
    MatrixX3d to(count, 3);
    for (Index k = 0; k < count; ++k) {
      to.row(k) = m.sphere_a.row(held[std::size_t(k)][0]);
      riders.emplace_back(held[std::size_t(k)][1], k);
    }
    // First the winner's own proxy map read at B's vertices (its pins and
    // pairs already at their exact points, up to the proxy's interpolation),
    // nudged the last stretch by a short flow; where that folds or stalls,
    // B's own map carried the whole way.
    SphereFlowResult carried;
    SphereFlowOptions flow;
    flow.model = &p.b.V;
    const std::optional<MatrixX3d> read = for_mesh("B", [&] {
      return read_through_proxy(p.b.V, p.b.F, c.proxy_b, c.proxy_faces_b, real.warped_b);
    });
    if (read) {
      MatrixX3d from(count, 3);
      for (Index k = 0; k < count; ++k) from.row(k) = read->row(held[std::size_t(k)][1]);
      carried = run_stage("carrying B's map", lo, mid, progress, [&](Progress* window) {
        return flow_sphere_map(p.b.F, *read, from, to, riders, flow, ProgressWindow(window));
      });
    }
    if (carried.reached < 1) {
      if (!own_b) own_b = for_mesh("B", [&] {
        return run_stage("sphere map of B", lo, mid, progress, [&](Progress* window) {
          return model_map("B", p.b.V, p.b.F, c.proxy_b, c.proxy_faces_b, c.map_b, m.fallbacks, window);
        });
      });
      const Index shaped = real.shape_a.rows();
      MatrixX3d all_from(count + shaped, 3), all_to(count + shaped, 3);
      for (Index k = 0; k < count; ++k) all_from.row(k) = own_b->row(held[std::size_t(k)][1]);
      all_to.topRows(count) = to;
      all_from.bottomRows(shaped) = real.shape_b;
      all_to.bottomRows(shaped) = real.shape_a;
      const Eigen::Matrix3d turn = all_from.rows() ? best_rotation(all_from, all_to) : real.rotation;
      carried = run_stage("carrying B's map", mid, hi, progress, [&](Progress* window) {
        return flow_sphere_map(p.b.F, *own_b * turn, all_from * turn, all_to, riders, flow, ProgressWindow(window));
      });
    }
    bool squeezed = false;
    if (carried.reached >= 1) {
      // The pinned vertices sit exactly on their partners; a face squeezed
      // flat by rounding there would stop the overlay: the next candidate.
      MatrixX3d placed = carried.positions;
      for (Index k = 0; k < count; ++k) placed.row(held[std::size_t(k)][1]) = m.sphere_a.row(held[std::size_t(k)][0]);
      squeezed = !exactly_fold_free(placed, p.b.F);
    }
    if (carried.reached < 1 || squeezed) {
      std::vector<Index> named;
      for (const Index j : carried.blocking)
        if (j < Index(p.pins.size())) named.push_back(j);
      const std::string why = squeezed ? std::string("its map squeezes a face flat where its pins and pairs sit on "
                                                     "their partners") : detail::concat(
          "its pins and pairs cannot all be met on the model without folding its map (stalled ",
          int(100 * carried.reached), "% of the way", named.empty() ? std::string() : ", near pins " + format_indices(named),
          ")");
      if (first_failure.empty()) first_failure = why;
      m.candidates[std::size_t(real.candidate)].rejected = why;
      continue;
    }
    m.chosen = real.candidate;
    m.sphere_b = carried.positions;
    for (Index k = 0; k < count; ++k) m.sphere_b.row(held[std::size_t(k)][1]) = m.sphere_a.row(held[std::size_t(k)][0]);
    for (const auto& pin : p.pins) m.pairs.push_back(pin), m.pair_is_pin.push_back(true);
    for (const auto& pair : real.pairs) m.pairs.push_back(pair), m.pair_is_pin.push_back(false);
    break;
  }
  PM_REQUIRE(m.sphere_b.rows() == p.b.V.rows(), CandidatesUnmet, "mesh B: ", first_failure,
             "; pins very close together on one mesh and further apart on the other, or crossing each other's "
             "way, are the usual cause");
  mark("sphere maps of the models");

  // 4. Overlay, 5. positions on both meshes as placed.
  try {
    m.merged = run_stage("overlay", 0.85, 0.97, progress, [&](Progress* window) {
      return overlay(m.sphere_a, p.a.F, m.sphere_b, p.b.F, o.overlay, window);
    });
  } catch (const InvalidInputError& refused) {
    // Both maps are fold-free here: the overlay refuses only maps whose
    // thinnest faces nearly coincide below what doubles resolve (a dancer's
    // fingers into a cat: altitude 4e-7 rad). morph() tries other proxies.
    throw OverlayRefused(refused.what());
  }
  mark("overlay");
  m.source = positions_on(VA, p.a.F, m.merged.face_a, m.merged.bary_a);
  m.target = positions_on(VB, p.b.F, m.merged.face_b, m.merged.bary_b);
  if (progress) progress->report(0.98, "morph");  // the last steps took 0.5 s at 100k faces
  m.distortion = map_distortion(p.a.V, p.a.F, m.sphere_a, p.b.V, p.b.F, m.sphere_b).mean;
  mark("positions");
  if (progress) progress->report(0.99, "morph");
  if (o.weld_tolerance > 0) {
    m.weld = run_stage("morph", 0.99, 1.0, progress, [&](Progress* window) {
      return weld_merged(m.merged, m.source, m.target, VA, p.a.F, VB, p.b.F, o.weld_tolerance, window);
    });
    mark("weld");
  }
  m.timings.emplace_back("total", std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count());
  if (progress) progress->report(1.0, "morph");
  return m;
}

/// morph_once, and where none of the ranked candidates could be met, again
/// with more of them (reporting in the last stretch, 0.97 to 1).
Morph morph_trying_more(const MatrixX3d& VA, const MatrixX3i& FA, const MatrixX3d& VB, const MatrixX3i& FB,
                        const MorphOptions& o, Progress* progress) {
  try {
    return morph_once(VA, FA, VB, FB, o, progress);
  } catch (const CandidatesUnmet&) {
    if (o.pairs || !o.automatic || o.correspondence.fallbacks >= kMoreFallbacks) throw;
    MorphOptions more = o;
    more.correspondence.fallbacks = kMoreFallbacks;
    Morph m = run_stage("morph trying more candidates", 0.97, 1.0, progress,
                        [&](Progress* window) { return morph_once(VA, FA, VB, FB, more, window); });
    const CorrespondenceCandidate& used = m.candidates[std::size_t(m.chosen)];
    m.fallbacks.push_back(detail::concat("candidate '", used.kind, ": ", used.detail, "', ranked below the best ",
                                         o.correspondence.fallbacks + 1,
                                         ": their pairs and the pins alone could not all be met on the model"));
    return m;
  }
}

}  // namespace

Morph morph(const MatrixX3d& VA, const MatrixX3i& FA, const MatrixX3d& VB, const MatrixX3i& FB,
            const MorphOptions& o, Progress* progress) {
  try {
    return morph_trying_more(VA, FA, VB, FB, o, progress);
  } catch (const OverlayRefused& refused) {
    // Other proxies give other maps: the same correspondence problem, other
    // thin faces. The redo reports in the last stretch (0.97 to 1) so
    // progress never goes back; Esc still stops it.
    MorphOptions finer = o;
    finer.correspondence.proxy_faces = o.correspondence.proxy_faces * 3 / 2;
    try {
      Morph m = run_stage("morph with finer proxies", 0.97, 1.0, progress,
                          [&](Progress* window) { return morph_trying_more(VA, FA, VB, FB, finer, window); });
      m.fallbacks.push_back(detail::concat("proxies of ", finer.correspondence.proxy_faces, " faces instead of ",
                                           o.correspondence.proxy_faces,
                                           ": the overlay refused the first maps, whose thinnest faces nearly "
                                           "coincided below what doubles resolve"));
      return m;
    } catch (const OverlayRefused& again) {
      throw ComputeError(detail::concat("the overlay of the two maps failed with proxies of ",
                                        o.correspondence.proxy_faces, " and ", finer.correspondence.proxy_faces,
                                        " faces (", again.what(), "): try a few pins or another proxy size"));
    }
  }
}

Eigen::MatrixXd carry_corner_values(const Morph& morph, int side, const Eigen::MatrixXd& values) {
  PM_REQUIRE(side == 0 || side == 1, InvalidInputError, "side is 0 (A) or 1 (B), got ", side);
  const MergedTopology& merged = morph.merged;
  const VectorXi& source = side == 0 ? merged.source_face_a : merged.source_face_b;
  const auto& bary = side == 0 ? merged.corner_bary_a : merged.corner_bary_b;
  const bool turned = side == 0 ? morph.inside_out_a : morph.inside_out_b;
  const Index faces_in = source.size() ? source.maxCoeff() + 1 : 0;
  PM_REQUIRE(values.rows() % 3 == 0 && values.rows() / 3 >= faces_in && values.allFinite(),
             InvalidInputError, "corner values need 3 finite rows per face of the mesh (",
             values.rows(), " rows given)");
  // The faces of an inside-out file were turned (corners 1 and 2 swapped).
  auto row = [&](Index f, int c) { return values.row(3 * f + (turned && c ? 3 - c : c)); };
  Eigen::MatrixXd out(3 * source.size(), values.cols());
  for (Index k = 0; k < source.size(); ++k)
    for (int c = 0; c < 3; ++c)
      out.row(3 * k + c) = bary(k, 3 * c) * row(source[k], 0) + bary(k, 3 * c + 1) * row(source[k], 1) +
                           bary(k, 3 * c + 2) * row(source[k], 2);
  return out;
}

}  // namespace paramorph::morph
