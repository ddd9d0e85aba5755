// features/mirror_plane: a shape's mirror plane from the shape alone, and how
// alone points are under it (issue 29: a muzzle or a tail against ears and feet).
#include <gtest/gtest.h>

#include <cmath>

#include <Eigen/Geometry>

#include "common/errors.h"
#include "features/mirror_plane.h"
#include "test_meshes.h"

using namespace paramorph;

namespace {

/// A lumpy body symmetric only under x -> -x (its lumps depend on x through
/// x squared), longest along y, so the mirror normal is the middle principal
/// axis, not the first or the last.
std::pair<MatrixX3d, MatrixX3i> mirrored_blob() {
  auto [V, F] = test_meshes::icosphere(4);
  for (Index i = 0; i < V.rows(); ++i) {
    const Eigen::Vector3d p = V.row(i).transpose();
    const double r = 1.0 + 0.3 * std::sin(3.0 * p.y()) * std::cos(2.0 * p.z()) + 0.4 * p.x() * p.x() + 0.2 * p.z();
    V.row(i) = (r * p.cwiseProduct(Eigen::Vector3d(1.0, 1.8, 0.7))).transpose();
  }
  return {V, F};
}

VectorXd ones(Index n) { return VectorXd::Ones(n); }

}  // namespace

TEST(MirrorPlane, FindsTheMirrorOfATurnedAndMovedBody) {
  auto [V, F] = mirrored_blob();
  const Eigen::Matrix3d turn =
      (Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()) * Eigen::AngleAxisd(2.1, Eigen::Vector3d::UnitX()))
          .toRotationMatrix();
  const Eigen::RowVector3d shift(3.0, -1.0, 0.5);
  const MatrixX3d moved = (V * turn.transpose()).rowwise() + shift;
  const features::MirrorPlane plane = features::mirror_plane(moved, F, ones(V.rows()));
  const Eigen::RowVector3d expected = (turn * Eigen::Vector3d::UnitX()).transpose();
  EXPECT_GT(std::abs(plane.normal.dot(expected)), 1 - 1e-6);
  EXPECT_NEAR(plane.normal.norm(), 1.0, 1e-12);
  EXPECT_NEAR(plane.offset, shift.dot(plane.normal), 1e-6);
  EXPECT_LT(plane.mean_distance, 1e-6);
}

TEST(MirrorPlane, ANonSymmetricBodyMapsFarFromItself) {
  auto [V, F] = test_meshes::icosphere(4);
  for (Index i = 0; i < V.rows(); ++i) {  // lumps with no mirror: odd and shifted in every coordinate
    const Eigen::Vector3d p = V.row(i).transpose();
    const double r = 1.0 + 0.3 * std::sin(3.0 * p.x() + 1.0) * std::cos(2.0 * p.y() + 0.5) + 0.3 * std::sin(2.0 * p.z() + 0.3) * p.x();
    V.row(i) = (r * p.cwiseProduct(Eigen::Vector3d(1.0, 1.8, 0.7))).transpose();
  }
  const features::MirrorPlane plane = features::mirror_plane(V, F, ones(V.rows()));
  EXPECT_GT(plane.mean_distance, 0.01);
}

TEST(MirrorPlane, LonelinessTellsSinglesFromTwins) {
  features::MirrorPlane plane;  // x = 0
  MatrixX3d points(5, 3);
  points << 0.0, 0.0, 2.0,    // a muzzle on the plane
      1.0, -1.0, 0.0,         // a pair of feet
      -1.02, -1.0, 0.05,      //
      0.3, 1.0, -1.5,         // a tail swung to one side, no twin
      0.01, 0.5, -2.0;        // near the plane
  const VectorXd alone = features::mirror_loneliness(points, plane);
  EXPECT_GT(alone[0], 0.95);
  EXPECT_LT(alone[1], 0.1);
  EXPECT_LT(alone[2], 0.1);
  EXPECT_GT(alone[3], 0.5);
  EXPECT_GT(alone[4], 0.95);
  EXPECT_EQ(features::mirror_loneliness(points.topRows(1), plane)[0], 1.0);
}

TEST(MirrorPlane, RefusesMismatchedWeights) {
  auto [V, F] = test_meshes::icosphere(2);
  EXPECT_THROW(features::mirror_plane(V, F, ones(3)), InvalidInputError);
  EXPECT_THROW(features::mirror_plane(V, F, VectorXd::Zero(V.rows())), InvalidInputError);
  EXPECT_THROW(features::mirror_plane(V, F, ones(V.rows()), 0), InvalidInputError);
}
