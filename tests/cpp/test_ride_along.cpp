// morph/ride_along: separate parts (eyes, buttons) carried by the motion of
// the body around where they sit, never sinking into it (issue 31).
#include <gtest/gtest.h>

#include <cmath>

#include <Eigen/Geometry>

#include "common/errors.h"
#include "morph/ride_along.h"
#include "test_meshes.h"

using namespace paramorph;

namespace {

/// A small sphere of `radius` centred at `centre` (an eye, a button).
std::pair<MatrixX3d, MatrixX3i> ball(const Eigen::RowVector3d& centre, double radius) {
  auto [V, F] = test_meshes::icosphere(2);
  V *= radius;
  V.rowwise() += centre;
  return {V, F};
}

/// Two eyes: one at the unit sphere's +x pole sunk `sunk` into it, one at
/// the -x pole just outside; labels 0 and 1.
struct Eyes {
  MatrixX3d V;
  VectorXi part_of;
};
Eyes two_eyes(double radius, double sunk) {
  const auto [a, fa] = ball(Eigen::RowVector3d(1.0 + radius - sunk, 0, 0), radius);
  const auto [b, fb] = ball(Eigen::RowVector3d(-1.0 - radius - 0.01, 0, 0), radius);
  Eyes eyes;
  eyes.V.resize(a.rows() + b.rows(), 3);
  eyes.V << a, b;
  eyes.part_of.resize(eyes.V.rows());
  eyes.part_of << VectorXi::Zero(a.rows()), VectorXi::Ones(b.rows());
  return eyes;
}

double deepest(const MatrixX3d& V, const MatrixX3i& F, const MatrixX3d& points) {
  return std::max(0.0, -morph::signed_distance(V, F, points).minCoeff());
}

}  // namespace

TEST(RideAlong, SignedDistanceIsNegativeInsideAndMeasuresTheGap) {
  const auto [V, F] = test_meshes::icosphere(4);
  MatrixX3d points(4, 3);
  points << 0.5, 0, 0,  0, 0, 0,  0, 1.5, 0,  0.1, -0.2, 2.0;
  const VectorXd d = morph::signed_distance(V, F, points);
  EXPECT_NEAR(d(0), -0.5, 2e-3);
  EXPECT_NEAR(d(1), -1.0, 2e-3);
  EXPECT_NEAR(d(2), 0.5, 2e-3);
  EXPECT_GT(d(3), 0.9);
  // On a vertex and across an edge of a cube, where face normals alone mislead.
  const auto [C, G] = test_meshes::box_grid(2, Eigen::Vector3d(1, 1, 1));
  MatrixX3d corner(2, 3);
  corner << 1.2, 1.1, 1.3,  0.9, 0.95, 0.0;
  const VectorXd c = morph::signed_distance(C, G, corner);
  EXPECT_GT(c(0), 0.0);
  EXPECT_NEAR(c(1), -0.05, 1e-9);
}

TEST(RideAlong, AtRestThePartsStayAndASimilarityCarriesThemExactly) {
  const auto [V, F] = test_meshes::icosphere(3);
  const Eyes eyes = two_eyes(0.15, 0.05);
  const morph::PartRider rider(V, F, eyes.V, eyes.part_of);
  ASSERT_EQ(rider.parts(), 2);
  EXPECT_NEAR(rider.rest_depth()(0), 0.05, 0.01);  // sunk into its socket
  EXPECT_EQ(rider.rest_depth()(1), 0.0);
  for (Index p = 0; p < 2; ++p) EXPECT_GE(Index(rider.patches()[p].size()), 12);

  const morph::CarriedParts rest = rider.at(V);
  EXPECT_LT((rest.positions - eyes.V).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_EQ(rest.pushed.maxCoeff(), 0.0);

  // Turned, scaled 3x and moved as a whole: the parts follow exactly.
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  const Eigen::RowVector3d shift(5, -2, 9);
  const MatrixX3d moved = ((3.0 * V * R).rowwise() + shift).eval();
  const morph::CarriedParts carried = rider.at(moved);
  const MatrixX3d expected = ((3.0 * eyes.V * R).rowwise() + shift).eval();
  EXPECT_LT((carried.positions - expected).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_EQ(carried.pushed.maxCoeff(), 0.0);
}

TEST(RideAlong, EachPartFollowsItsOwnSideOfTheBody) {
  // The +x half of the body stretches to twice its length; the -x half stays.
  const auto [V, F] = test_meshes::icosphere(3);
  const Eyes eyes = two_eyes(0.15, 0.0);
  const morph::PartRider rider(V, F, eyes.V, eyes.part_of);
  MatrixX3d now = V;
  for (Index i = 0; i < now.rows(); ++i)
    if (now(i, 0) > 0) now(i, 0) *= 2.0;
  const morph::CarriedParts carried = rider.at(now);
  const auto centre = [&](int part) {
    Eigen::RowVector3d sum = Eigen::RowVector3d::Zero();
    int n = 0;
    for (Index i = 0; i < eyes.V.rows(); ++i)
      if (eyes.part_of(i) == part) sum += carried.positions.row(i), ++n;
    return Eigen::RowVector3d(sum / n);
  };
  EXPECT_NEAR(centre(0).x(), 2.0 + 0.15, 0.15);  // went out with the tip
  EXPECT_NEAR(centre(1).x(), -1.0 - 0.16, 0.02);  // stayed
  // Rigid: the carried eye keeps its shape up to one uniform scale.
  const double before = (eyes.V.row(0) - eyes.V.row(5)).norm(), after =
      (carried.positions.row(0) - carried.positions.row(5)).norm();
  const double before2 = (eyes.V.row(3) - eyes.V.row(9)).norm(), after2 =
      (carried.positions.row(3) - carried.positions.row(9)).norm();
  EXPECT_NEAR(after / before, after2 / before2, 1e-9);
  EXPECT_LE(deepest(now, F, carried.positions.topRows(eyes.V.rows() / 2)), 1e-3);
}

TEST(RideAlong, APartIsPushedOutRatherThanSinkIntoABulge) {
  // A bump narrower than the eye's patch rises right under the eye: the
  // patch's average motion lags the bump, so the eye is pushed out along
  // the patch's normal, to no deeper than it sat at rest.
  const auto [V, F] = test_meshes::icosphere(4);
  for (double sunk : {0.0, 0.04}) {
    const Eyes eyes = two_eyes(0.2, sunk);
    morph::RideAlongOptions options;
    options.patch_scale = 3.0;
    const morph::PartRider rider(V, F, eyes.V, eyes.part_of, options);
    MatrixX3d now = V;
    for (Index i = 0; i < now.rows(); ++i) {
      const double off = (now.row(i) - Eigen::RowVector3d(1, 0, 0)).squaredNorm();
      now.row(i) *= 1.0 + 0.3 * std::exp(-off / (2 * 0.15 * 0.15));
    }
    const morph::CarriedParts carried = rider.at(now);
    EXPECT_GT(carried.pushed(0), 0.05) << "sunk " << sunk;
    EXPECT_EQ(carried.pushed(1), 0.0);
    const Index half = eyes.V.rows() / 2;
    EXPECT_LE(deepest(now, F, carried.positions.topRows(half)), rider.rest_depth()(0) + 2e-3) << "sunk " << sunk;
  }
}

TEST(RideAlong, BadInputIsRefused) {
  const auto [V, F] = test_meshes::icosphere(2);
  const Eyes eyes = two_eyes(0.1, 0.0);
  VectorXi short_labels = eyes.part_of.head(3);
  EXPECT_THROW(morph::PartRider(V, F, eyes.V, short_labels), InvalidInputError);
  VectorXi gap = eyes.part_of;
  gap.setConstant(1);  // part 0 has no vertex
  EXPECT_THROW(morph::PartRider(V, F, eyes.V, gap), InvalidInputError);
  const morph::PartRider rider(V, F, eyes.V, eyes.part_of);
  EXPECT_THROW(rider.at(V.topRows(5)), InvalidInputError);
  MatrixX3d nan = V;
  nan(0, 0) = std::nan("");
  EXPECT_THROW(rider.at(nan), InvalidInputError);
}

TEST(RideAlong, APartFarFromTheBodyStaysWhereItWas) {
  const auto [V, F] = test_meshes::icosphere(3);
  const auto [near_ball, nf] = ball(Eigen::RowVector3d(0, 1.2, 0), 0.15);   // gap 0.05: rides
  const auto [far_ball, ff] = ball(Eigen::RowVector3d(0, 0, 4.0), 0.15);    // gap 2.85: another object
  MatrixX3d parts(near_ball.rows() + far_ball.rows(), 3);
  parts << near_ball, far_ball;
  VectorXi part_of(parts.rows());
  part_of << VectorXi::Zero(near_ball.rows()), VectorXi::Ones(far_ball.rows());
  const morph::PartRider rider(V, F, parts, part_of);
  EXPECT_TRUE(rider.riding()[0]);
  EXPECT_FALSE(rider.riding()[1]);
  EXPECT_NEAR(rider.rest_gap()(0), 0.05, 0.01);
  EXPECT_NEAR(rider.rest_gap()(1), 2.85, 0.01);
  const MatrixX3d moved = (2.0 * V).rowwise() + Eigen::RowVector3d(1, 0, 0);
  const morph::CarriedParts carried = rider.at(moved);
  const Index n = near_ball.rows();
  EXPECT_LT((carried.positions.topRows(n) - ((2.0 * near_ball).rowwise() + Eigen::RowVector3d(1, 0, 0)))
                .cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_EQ((carried.positions.bottomRows(far_ball.rows()) - far_ball).cwiseAbs().maxCoeff(), 0.0);
}
