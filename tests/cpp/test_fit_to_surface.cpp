// morph/fit_to_surface: a kept topology drawn onto the target's surface both
// ways (issue 31): a coarse sphere whose vertices miss a horn of the target.
#include <gtest/gtest.h>

#include <cmath>
#include <utility>

#include <Eigen/Geometry>

#include "common/errors.h"
#include "mesh/surface_distance.h"
#include "morph/fit_to_surface.h"
#include "test_meshes.h"

using namespace paramorph;

namespace {

/// Radius of the target along unit direction d: a unit sphere with a horn
/// (height 0.8, narrow) towards `horn`. Both meshes are then stretched into
/// an ellipsoid, so that the shape has a frame of its own.
double horned_radius(const Eigen::RowVector3d& d, const Eigen::RowVector3d& horn) {
  const double angle = std::acos(std::clamp(d.dot(horn), -1.0, 1.0));
  return 1.0 + 0.8 * std::exp(-angle * angle / 0.06);
}

struct Case {
  MatrixX3d VB, X;
  MatrixX3i FB, F;
};

/// B: a fine sphere with a horn towards the centre of one of A's faces, so
/// no vertex of A starts on its tip; X: a coarse sphere's vertices put on B
/// along their directions (as a correspondence through sphere maps does).
Case horned_case() {
  Case c;
  auto [S, FS] = test_meshes::icosphere(1);
  c.F = FS;
  const Eigen::RowVector3d horn = ((S.row(FS(0, 0)) + S.row(FS(0, 1)) + S.row(FS(0, 2))) / 3.0).normalized();
  auto [B, FB] = test_meshes::icosphere(5);
  for (Index i = 0; i < Index(B.rows()); ++i) B.row(i) *= horned_radius(B.row(i), horn);
  c.VB = B;
  c.FB = FB;
  c.X = S;
  for (Index i = 0; i < Index(S.rows()); ++i) c.X.row(i) *= horned_radius(S.row(i), horn);
  const Eigen::RowVector3d stretch(1.0, 0.8, 0.65);
  c.VB = c.VB.array().rowwise() * stretch.array();
  c.X = c.X.array().rowwise() * stretch.array();
  return c;
}

double two_sided(const MatrixX3d& X, const MatrixX3i& F, const MatrixX3d& VB, const MatrixX3i& FB) {
  return surface_distance(X, F, VB, FB).hausdorff();
}

}  // namespace

TEST(FitToSurface, ReachesTheHornTheVerticesMissed) {
  const Case c = horned_case();
  const morph::FitToSurface fit = morph::fit_to_surface(c.X, c.F, c.VB, c.FB, VectorXi());
  const double before = two_sided(c.X, c.F, c.VB, c.FB), after = two_sided(fit.positions, c.F, c.VB, c.FB);
  EXPECT_GT(fit.rounds, 0);
  EXPECT_GT(before, 0.3);  // the horn's tip is far from A's triangles
  EXPECT_LT(after, 0.6 * before) << before << " -> " << after;
  EXPECT_LE(fit.distance_after, fit.distance_before);
  // No face turned over against where it started.
  for (Index f = 0; f < Index(c.F.rows()); ++f) {
    auto normal = [&](const MatrixX3d& V) {
      return Eigen::RowVector3d((V.row(c.F(f, 1)) - V.row(c.F(f, 0))).cross(V.row(c.F(f, 2)) - V.row(c.F(f, 0))));
    };
    EXPECT_GT(normal(fit.positions).dot(normal(c.X)), 0) << "face " << f;
  }
}

TEST(FitToSurface, HeldVerticesStayExactly) {
  const Case c = horned_case();
  VectorXi held(3);
  held << c.F(0, 0), c.F(0, 1), 7;
  const morph::FitToSurface fit = morph::fit_to_surface(c.X, c.F, c.VB, c.FB, held);
  EXPECT_GT(fit.rounds, 0);
  for (Index k = 0; k < Index(held.size()); ++k) EXPECT_EQ(fit.positions.row(held(k)), c.X.row(held(k)));
  EXPECT_GT((fit.positions - c.X).rowwise().norm().maxCoeff(), 0.05);  // the others moved
}

TEST(FitToSurface, MovesWithATurnedScaledShiftedScene) {
  const Case c = horned_case();
  const Eigen::Matrix3d R = Eigen::AngleAxisd(2.3, Eigen::Vector3d(1, -2, 0.5).normalized()).toRotationMatrix();
  const double scale = 37.0;
  const Eigen::RowVector3d shift(-120.0, 4.5, 900.0);
  auto moved = [&](const MatrixX3d& V) {
    MatrixX3d out = scale * V * R.transpose();
    out.rowwise() += shift;
    return out;
  };
  const morph::FitToSurface plain = morph::fit_to_surface(c.X, c.F, c.VB, c.FB, VectorXi());
  const morph::FitToSurface turned = morph::fit_to_surface(moved(c.X), c.F, moved(c.VB), c.FB, VectorXi());
  // Computed in B's own frame: the same numbers up to rounding, which a
  // near-tie (a step halved or not, which of two equally close rounds is
  // kept) can turn into a small difference; a fit that depended on the
  // placement would differ by a share of the model.
  EXPECT_EQ(plain.rounds, turned.rounds);
  EXPECT_LT((turned.positions - moved(plain.positions)).cwiseAbs().maxCoeff(), 1e-3 * scale);
  EXPECT_NEAR(turned.distance_after, scale * plain.distance_after, 1e-5 * scale);
}

TEST(FitToSurface, NoRoundsOrAllHeldLeavesTheMeshAsItWas) {
  const Case c = horned_case();
  morph::FitToSurfaceOptions none;
  none.rounds = 0;
  none.smooth_pleats = 0;
  const morph::FitToSurface zero = morph::fit_to_surface(c.X, c.F, c.VB, c.FB, VectorXi(), none);
  EXPECT_EQ(zero.positions, c.X);
  EXPECT_EQ(zero.rounds, 0);
  EXPECT_EQ(zero.distance_after, zero.distance_before);
  VectorXi all(c.X.rows());
  for (Index i = 0; i < Index(all.size()); ++i) all(i) = i;
  const morph::FitToSurface held = morph::fit_to_surface(c.X, c.F, c.VB, c.FB, all);
  EXPECT_EQ(held.positions, c.X);
}

TEST(FitToSurface, GoesOnPastTheScheduleWhileItComesCloser) {
  // A schedule of 10 rounds ends short of the horn: with patience the fit
  // goes on (up to twice the schedule) and ends closer; without, it stops.
  const Case c = horned_case();
  morph::FitToSurfaceOptions short_schedule;
  short_schedule.rounds = 10;
  short_schedule.patience = 0;
  short_schedule.even_out_passes = 0;  // one run: its rounds alone
  const morph::FitToSurface plain = morph::fit_to_surface(c.X, c.F, c.VB, c.FB, VectorXi(), short_schedule);
  short_schedule.patience = 5;
  const morph::FitToSurface patient = morph::fit_to_surface(c.X, c.F, c.VB, c.FB, VectorXi(), short_schedule);
  EXPECT_LE(plain.rounds, 10);
  EXPECT_GT(patient.rounds, 10);
  EXPECT_LE(patient.rounds, 20);
  EXPECT_LT(patient.distance_after, plain.distance_after);
}

TEST(FitToSurface, EndingFarItRunsAgainFromEvenedFacesAndKeepsTheCloser) {
  // 10 rounds end short of the horn (over 2 % of the diagonal): the rounds
  // run again from A's faces evened out, and the closer end is kept.
  const Case c = horned_case();
  morph::FitToSurfaceOptions once;
  once.rounds = 10;
  once.patience = 0;
  once.even_out_passes = 0;
  const morph::FitToSurface plain = morph::fit_to_surface(c.X, c.F, c.VB, c.FB, VectorXi(), once);
  const double diagonal = (c.VB.colwise().maxCoeff() - c.VB.colwise().minCoeff()).norm();
  ASSERT_GT(plain.distance_after, 0.02 * diagonal);
  morph::FitToSurfaceOptions again = once;
  again.even_out_passes = 30;
  const morph::FitToSurface evened = morph::fit_to_surface(c.X, c.F, c.VB, c.FB, VectorXi(), again);
  EXPECT_EQ(evened.rounds, 3 * plain.rounds);  // its second run's schedule is twice the first's
  EXPECT_LE(evened.distance_after, plain.distance_after);
}

TEST(FitToSurface, CountsTheFacesThatPointAgainstTheTarget) {
  // A lying on B itself faces the way B does; turning 7 of its faces (a
  // pleat, as it were) is counted, whichever way A's file faces as a whole.
  const Case c = horned_case();
  morph::FitToSurfaceOptions none;
  none.rounds = 0;
  none.smooth_pleats = 0;  // the count alone
  const morph::FitToSurface same = morph::fit_to_surface(c.VB, c.FB, c.VB, c.FB, VectorXi(), none);
  EXPECT_EQ(same.facing_away_before, 0.0);
  MatrixX3i pleated = c.FB;
  for (Index f = 0; f < 7; ++f) std::swap(pleated(100 * f, 1), pleated(100 * f, 2));
  const double share = 7.0 / double(c.FB.rows());
  EXPECT_DOUBLE_EQ(morph::fit_to_surface(c.VB, pleated, c.VB, c.FB, VectorXi(), none).facing_away_before, share);
  MatrixX3i inside_out = pleated;
  inside_out.col(1).swap(inside_out.col(2));
  const morph::FitToSurface turned = morph::fit_to_surface(c.VB, inside_out, c.VB, c.FB, VectorXi(), none);
  EXPECT_DOUBLE_EQ(turned.facing_away_before, share);
  EXPECT_EQ(turned.facing_away_after, turned.facing_away_before);  // no rounds: the same mesh
}

TEST(FitToSurface, SmoothsAPleatAlongTheTargetNeverFarther) {
  // A finer sphere on the horned target, one vertex on the side away from
  // the horn pushed along the surface past the far edge of one of its faces:
  // that face and its neighbours fold over (a pleat). With no rounds, the
  // smoothing alone unfolds it, moving along B (no farther from B than
  // before: the horn, which A does not reach, bounds the distance), and the
  // held vertex beside the pleat stays exactly where it was.
  const Case horned = horned_case();
  auto [S, F] = test_meshes::icosphere(3);
  const Eigen::RowVector3d stretch(1.0, 0.8, 0.65);
  // The horn's direction, as horned_case puts it (the centre of the coarse sphere's face 0).
  auto [C, FC] = test_meshes::icosphere(1);
  const Eigen::RowVector3d towards = ((C.row(FC(0, 0)) + C.row(FC(0, 1)) + C.row(FC(0, 2))) / 3.0).normalized();
  auto on_target = [&](const Eigen::RowVector3d& d) {
    const Eigen::RowVector3d u = d.normalized();
    return Eigen::RowVector3d((u * horned_radius(u, towards)).array() * stretch.array());
  };
  MatrixX3d X(S.rows(), 3);
  for (Index i = 0; i < Index(S.rows()); ++i) X.row(i) = on_target(S.row(i));
  Index away_from_horn = 0;
  (S * towards.transpose()).minCoeff(&away_from_horn);
  Index face = 0;
  while (F(face, 0) != away_from_horn && F(face, 1) != away_from_horn && F(face, 2) != away_from_horn) ++face;
  Index a = -1, b = -1;
  for (int k = 0; k < 3; ++k)
    if (F(face, k) != away_from_horn) (a < 0 ? a : b) = F(face, k);
  const Eigen::RowVector3d middle = 0.5 * (S.row(a) + S.row(b));
  X.row(away_from_horn) = on_target(S.row(away_from_horn) + 1.4 * (middle - S.row(away_from_horn)));
  VectorXi held(1);
  held << a;

  morph::FitToSurfaceOptions smoothing_only;
  smoothing_only.rounds = 0;
  smoothing_only.smooth_pleats = 0;
  const morph::FitToSurface off = morph::fit_to_surface(X, F, horned.VB, horned.FB, held, smoothing_only);
  ASSERT_GT(off.facing_away_before, 0.0);  // the pleat is there
  EXPECT_EQ(off.facing_away_after, off.facing_away_before);
  EXPECT_EQ(off.pleat_moves, 0);
  EXPECT_EQ(off.positions, X);

  smoothing_only.smooth_pleats = 20;
  const morph::FitToSurface on = morph::fit_to_surface(X, F, horned.VB, horned.FB, held, smoothing_only);
  EXPECT_GT(on.pleat_moves, 0);
  EXPECT_EQ(on.facing_away_after, 0.0) << "from " << on.facing_away_before;
  EXPECT_LE(on.distance_after, on.distance_before);
  EXPECT_EQ(on.positions.row(a), X.row(a));
  // The exact two-sided distance (not only the fit's sampled one) no larger.
  EXPECT_LE(two_sided(on.positions, F, horned.VB, horned.FB), two_sided(X, F, horned.VB, horned.FB) * (1 + 1e-9));
}

TEST(FitToSurface, RefusesBadInput) {
  const Case c = horned_case();
  auto with = [](auto set) {
    morph::FitToSurfaceOptions o;
    set(o);
    return o;
  };
  const VectorXi none;
  EXPECT_THROW(morph::fit_to_surface(c.X, c.F, c.VB, c.FB, none, with([](auto& o) { o.rounds = -1; })),
               InvalidInputError);
  EXPECT_THROW(morph::fit_to_surface(c.X, c.F, c.VB, c.FB, none, with([](auto& o) { o.patience = -1; })),
               InvalidInputError);
  EXPECT_THROW(morph::fit_to_surface(c.X, c.F, c.VB, c.FB, none, with([](auto& o) { o.smooth_pleats = -1; })),
               InvalidInputError);
  EXPECT_THROW(morph::fit_to_surface(c.X, c.F, c.VB, c.FB, none, with([](auto& o) { o.even_out_passes = -1; })),
               InvalidInputError);
  EXPECT_THROW(morph::fit_to_surface(c.X, c.F, c.VB, c.FB, none, with([](auto& o) { o.even_out_step = 0; })),
               InvalidInputError);
  EXPECT_THROW(morph::fit_to_surface(c.X, c.F, c.VB, c.FB, none, with([](auto& o) { o.even_out_step = 1.5; })),
               InvalidInputError);
  EXPECT_THROW(morph::fit_to_surface(c.X, c.F, c.VB, c.FB, none, with([](auto& o) { o.stiffness = NAN; })),
               InvalidInputError);
  EXPECT_THROW(morph::fit_to_surface(c.X, c.F, c.VB, c.FB, none, with([](auto& o) { o.stiffness_decay = 0; })),
               InvalidInputError);
  VectorXi outside(1);
  outside << Index(c.X.rows());
  EXPECT_THROW(morph::fit_to_surface(c.X, c.F, c.VB, c.FB, outside), InvalidInputError);
  EXPECT_THROW(morph::fit_to_surface(c.X, MatrixX3i(0, 3), c.VB, c.FB, none), InvalidInputError);
  MatrixX3d bad = c.X;
  bad(0, 0) = NAN;
  EXPECT_THROW(morph::fit_to_surface(bad, c.F, c.VB, c.FB, none), InvalidInputError);
}
