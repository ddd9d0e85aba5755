// morph/correspondence_frame: shape_rotation, the one turn a morph applies
// to both models so that a turned scene gives the same correspondence
// (issue 29).
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include "common/errors.h"
#include "morph/correspondence_frame.h"
#include "test_meshes.h"

using namespace paramorph;

namespace {

/// An icosphere stretched differently along each axis and pushed out on
/// one side of two of them: distinct spreads and skews, so the frame is
/// fixed by the shape.
std::pair<MatrixX3d, MatrixX3i> lopsided_egg() {
  auto [V, F] = test_meshes::icosphere(3);
  for (Index v = 0; v < V.rows(); ++v) {
    V(v, 0) *= 3.0 + 0.8 * V(v, 0);
    V(v, 1) *= 1.8 + 0.5 * V(v, 1);
    V(v, 2) *= 1.0;
  }
  return {V, F};
}

}  // namespace

TEST(ShapeRotation, TurnsWithTheShapeAndIsAProperRotation) {
  const auto [V, F] = lopsided_egg();
  const Eigen::Matrix3d R = morph::shape_rotation(V, F);
  EXPECT_NEAR(R.determinant(), 1.0, 1e-12);
  EXPECT_LT((R * R.transpose() - Eigen::Matrix3d::Identity()).norm(), 1e-12);
  for (const Eigen::Vector3d axis : {Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(0.3, 0.8, -0.5), Eigen::Vector3d(0, 0, 1)}) {
    for (const double angle : {0.7, 2.5, -1.9}) {
      const Eigen::Matrix3d Q = Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix();
      const MatrixX3d turned = V * Q.transpose();
      // The frame of the turned shape undoes the turn: R' Q = R.
      EXPECT_LT((morph::shape_rotation(turned, F) * Q - R).norm(), 1e-9) << "angle " << angle;
    }
  }
}

TEST(ShapeRotation, LargestSpreadFirst) {
  const auto [V, F] = lopsided_egg();
  const Eigen::Matrix3d R = morph::shape_rotation(V, F);
  // The egg is longest along x, then y: the frame's first row is +-x, the second +-y.
  EXPECT_GT(std::abs(R(0, 0)), 0.99);
  EXPECT_GT(std::abs(R(1, 1)), 0.99);
}

TEST(ShapeRotation, RefusesAMeshWithNoArea) {
  MatrixX3d V(3, 3);
  V << 0, 0, 0, 1, 0, 0, 2, 0, 0;
  MatrixX3i F(1, 3);
  F << 0, 1, 2;
  EXPECT_THROW(morph::shape_rotation(V, F), InvalidInputError);
}
