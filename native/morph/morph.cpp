#include "morph/morph.h"

#include <chrono>
#include <cmath>
#include <exception>
#include <functional>
#include <utility>

#include <Eigen/Geometry>

#include "common/errors.h"
#include "morph/optimization_start.h"
#include "morph/radial_projection.h"
#include "morph/registered_pairs.h"
#include "param/spherical/sphere_map.h"

namespace paramorph::morph {

namespace {

/// One stage: its own 0..1 progress inside [lo, hi] of the caller's, and
/// its wall time in `timings`.
template <typename Work>
auto stage(const std::string& name, double lo, double hi, Progress* parent,
           std::vector<std::pair<std::string, double>>& timings, Work&& work) {
  const auto started = std::chrono::steady_clock::now();
  auto result = run_stage(name, lo, hi, parent, std::forward<Work>(work));
  timings.emplace_back(name, std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count());
  return result;
}

double angle(const Eigen::RowVector3d& a, const Eigen::RowVector3d& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

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

void check_pairs(const std::vector<std::array<Index, 2>>& pairs, Index na, Index nb, const char* what) {
  for (const auto& p : pairs)
    PM_REQUIRE(p[0] >= 0 && p[0] < na && p[1] >= 0 && p[1] < nb, InvalidInputError, what, " (", p[0],
               ", ", p[1], ") is out of range: A has ", na, " vertices, B ", nb);
}

}  // namespace

Morph morph(const MatrixX3d& VA, const MatrixX3i& FA, const MatrixX3d& VB, const MatrixX3i& FB,
            const MorphOptions& o, Progress* progress) {
  check_pairs(o.pins, VA.rows(), VB.rows(), "pin");
  if (o.pairs) check_pairs(*o.pairs, VA.rows(), VB.rows(), "pair");
  PM_REQUIRE(std::isfinite(o.pin_weight) && o.pin_weight > 0 && std::isfinite(o.pin_radius) &&
                 o.pin_radius >= 0, InvalidInputError, "pin_weight must be positive and pin_radius >= 0");
  PM_REQUIRE(std::isfinite(o.pair_distance) && o.pair_distance >= 0 && std::isfinite(o.registered_warp_width) &&
                 o.registered_warp_width >= 0 && o.registered_warp_width < M_PI,
             InvalidInputError, "pair_distance must be >= 0 and registered_warp_width in [0, pi)");
  Morph m;
  if (progress) progress->report(0.0, "morph");

  // 1. Sphere maps; A's optimized for morphing, from optimization_start
  // (the conformal map, or the relaxed radial projection where that squeezes).
  auto sphere_of = [&](const MatrixX3d& V, const MatrixX3i& F, const std::optional<MatrixX3d>& given,
                       const char* which, bool for_optimization, double lo, double hi) {
    if (given) return *given;
    return for_mesh(which, [&] {
      return stage(std::string("sphere map ") + which, lo, hi, progress, m.timings, [&](Progress* p) {
        return for_optimization ? optimization_start(V, F, p) : spherical::sphere_map(V, F, {}, p).positions;
      });
    });
  };
  const MatrixX3d start_a = sphere_of(VA, FA, o.sphere_a, "A", true, 0.0, 0.08);
  const MatrixX3d start_b = sphere_of(VB, FB, o.sphere_b, "B", false, 0.08, 0.16);

  OptimizeSphereOptions optimize;
  optimize.epsilon = o.epsilon;
  optimize.max_iterations = o.max_iterations;
  m.sphere_a = for_mesh("A", [&] {
    return stage("optimize A", 0.16, 0.45, progress, m.timings, [&](Progress* p) {
      return optimize_sphere_map(VA, FA, start_a, optimize, p).positions;
    });
  });

  // 2. Pairs: pins, then the automatic (or given) pairs away from them.
  for (const auto& pin : o.pins) {
    m.pairs.push_back(pin);
    m.pair_is_pin.push_back(true);
    m.pair_scores.push_back(0.0);
  }
  std::vector<std::array<Index, 2>> automatic;
  std::vector<double> scores;
  std::optional<MatrixX3d> registered_target;  // B's targets from the registration
  if (o.features) {
    MorphPairs matched = stage("match features", 0.45, 0.58, progress, m.timings, [&](Progress* p) {
      return morph_pairs(VA, FA, VB, FB, o.match, o.register_surfaces, o.registration, o.pair_distance,
                         o.max_fold_share, p);
    });
    m.match = std::move(matched.match);
    m.registration = std::move(matched.registration);
    automatic = std::move(matched.pairs.pairs);
    scores = std::move(matched.pairs.scores);
    m.registration_fold_share = matched.fold_share;
    if (m.registration) {
      // 3. B's targets: A's optimized map at the closest points of A to the registered B.
      registered_target =
          positions_on(m.sphere_a, FA, matched.on_a.face, matched.on_a.bary).rowwise().normalized();
    }
  }
  // Pairs given (e.g. edited in Preview Matches) replace the automatic ones;
  // the registration's targets still apply.
  if (o.pairs) {
    automatic = *o.pairs;
    scores.assign(automatic.size(), 0.0);
  }
  for (std::size_t i = 0; i < automatic.size(); ++i) {
    bool clashes = false;
    for (const auto& pin : o.pins)
      clashes = clashes || pin[0] == automatic[i][0] || pin[1] == automatic[i][1] ||
                angle(m.sphere_a.row(pin[0]), m.sphere_a.row(automatic[i][0])) < o.pin_radius ||
                angle(start_b.row(pin[1]), start_b.row(automatic[i][1])) < o.pin_radius;
    if (clashes) continue;
    m.pairs.push_back(automatic[i]);
    m.pair_is_pin.push_back(false);
    m.pair_scores.push_back(scores[i]);
  }

  // 4. B's map: its registered targets, or its own radial projection
  // (turned by the feature match's rotation when there is one), bent
  // towards A's paired features.
  std::vector<Index> paired_b;
  MatrixX3d targets(Index(m.pairs.size()), 3);
  VectorXd weights(Index(m.pairs.size()));
  for (std::size_t i = 0; i < m.pairs.size(); ++i) {
    paired_b.push_back(m.pairs[i][1]);
    targets.row(Index(i)) = m.sphere_a.row(m.pairs[i][0]);
    weights[Index(i)] = m.pair_is_pin[i] ? o.pin_weight : 1.0;
  }
  AlignSphereOptions align = o.align;
  align.epsilon = o.epsilon;
  align.max_iterations = o.max_iterations;
  if (registered_target) {
    align.target = *registered_target;
    if (align.warp_width == 0) align.warp_width = o.registered_warp_width;
  } else if (m.match) {
    align.target = radial_projection(VB, FB) * m.match->rotation.transpose();
  }
  const AlignSphereResult aligned = for_mesh("B", [&] {
    return stage("align B", 0.55, 0.88, progress, m.timings, [&](Progress* p) {
      return align_sphere_map(VB, FB, start_b, paired_b, targets, weights, align, p);
    });
  });
  m.sphere_b = aligned.positions;
  m.mean_pair_error = aligned.mean_error;

  // 5. Overlay, 6. positions on both meshes.
  m.merged = stage("overlay", 0.88, 0.98, progress, m.timings, [&](Progress* p) {
    return overlay(m.sphere_a, FA, m.sphere_b, FB, o.overlay, p);
  });
  m.source = positions_on(VA, FA, m.merged.face_a, m.merged.bary_a);
  m.target = positions_on(VB, FB, m.merged.face_b, m.merged.bary_b);
  if (progress) progress->report(1.0, "morph");
  return m;
}

Eigen::MatrixXd carry_corner_values(const MergedTopology& merged, int side, const Eigen::MatrixXd& values) {
  PM_REQUIRE(side == 0 || side == 1, InvalidInputError, "side is 0 (A) or 1 (B), got ", side);
  const VectorXi& source = side == 0 ? merged.source_face_a : merged.source_face_b;
  const auto& bary = side == 0 ? merged.corner_bary_a : merged.corner_bary_b;
  const Index faces_in = source.size() ? source.maxCoeff() + 1 : 0;
  PM_REQUIRE(values.rows() % 3 == 0 && values.rows() / 3 >= faces_in && values.allFinite(),
             InvalidInputError, "corner values need 3 finite rows per face of the mesh (",
             values.rows(), " rows given)");
  Eigen::MatrixXd out(3 * source.size(), values.cols());
  for (Index k = 0; k < source.size(); ++k)
    for (int c = 0; c < 3; ++c)
      out.row(3 * k + c) = bary(k, 3 * c) * values.row(3 * source[k]) +
                           bary(k, 3 * c + 1) * values.row(3 * source[k] + 1) +
                           bary(k, 3 * c + 2) * values.row(3 * source[k] + 2);
  return out;
}

}  // namespace paramorph::morph
