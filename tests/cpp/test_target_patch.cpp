#include <gtest/gtest.h>

#include <cmath>

#include <Eigen/Geometry>

#include "common/errors.h"
#include "paste/target_patch.h"
#include "test_meshes.h"

using namespace paramorph;

namespace {

std::pair<MatrixX3d, MatrixX3i> flat_grid(int n) {
  MatrixX3d V((n + 1) * (n + 1), 3);
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j <= n; ++j) V.row(i * (n + 1) + j) << double(i) / n, double(j) / n, 0.0;
  return {V, test_meshes::grid_faces(n)};
}

/// A torus (tube radius r around a circle of radius R), faces outward.
std::pair<MatrixX3d, MatrixX3i> torus(int around, int tube, double R, double r) {
  MatrixX3d V(around * tube, 3);
  MatrixX3i F(2 * around * tube, 3);
  for (int i = 0; i < around; ++i)
    for (int j = 0; j < tube; ++j) {
      const double a = 2 * M_PI * i / around, b = 2 * M_PI * j / tube;
      V.row(i * tube + j) << (R + r * std::cos(b)) * std::cos(a), (R + r * std::cos(b)) * std::sin(a),
          r * std::sin(b);
      const int p = i * tube + j, q = ((i + 1) % around) * tube + j, s = i * tube + (j + 1) % tube,
                t = ((i + 1) % around) * tube + (j + 1) % tube;
      F.row(2 * p) << p, q, t;
      F.row(2 * p + 1) << p, t, s;
    }
  return {V, F};
}

}  // namespace

TEST(TargetPatch, AFlatPatchMapsToItselfTurnedToTheReference) {
  auto [V, F] = flat_grid(40);
  const TriMesh mesh(V, F);
  const Index face = 2 * (20 * 40 + 20);  // a face at the middle of the grid
  const Eigen::Vector3d bary(0.2, 0.3, 0.5);
  const Eigen::Vector3d reference(1.0, 1.0, 0.7);  // not in the plane: projected
  const paste::TargetPatch p = paste::target_patch(mesh, face, bary, reference, 0.3);
  EXPECT_NEAR(p.normal.z(), 1.0, 1e-12);
  const Eigen::Vector3d t = p.tangent, s = p.normal.cross(t);
  EXPECT_NEAR(t.dot(Eigen::Vector3d(1, -1, 0)), 0.0, 1e-12);
  for (Index k = 0; k < p.vertices.size(); ++k) {
    const Eigen::Vector3d d = V.row(p.vertices[k]).transpose() - p.anchor_point;
    EXPECT_NEAR(p.uv(k, 0), d.dot(t), 1e-9) << k;
    EXPECT_NEAR(p.uv(k, 1), d.dot(s), 1e-9) << k;
  }
  // The disc of radius 0.3 fits, without taking much more than it needs.
  EXPECT_GE(p.reach, 0.3);
  EXPECT_LT(p.reach, 0.3 * 1.25 * 1.25);
  for (Index i = 0; i < p.faces.size(); ++i)
    for (int k = 0; k < 3; ++k) EXPECT_EQ(p.vertices[p.local_faces(i, k)], F(p.faces[i], k));
}

TEST(TargetPatch, OnASphereTheMapIsNearlyIsometricAtTheAnchor) {
  auto [V, F] = test_meshes::icosphere(4);
  const TriMesh mesh(V, F);
  const paste::TargetPatch p = paste::target_patch(mesh, 7, Eigen::Vector3d(1, 1, 1) / 3, Eigen::Vector3d::UnitZ(), 0.6);
  EXPECT_GT(p.normal.dot(p.anchor_point.normalized()), 0.999);
  EXPECT_NEAR(p.tangent.dot(p.normal), 0.0, 1e-12);
  // Edge lengths near the anchor are kept (scale 1 there), and uv is
  // counter-clockwise where the sphere's faces are.
  double worst = 0;
  for (Index i = 0; i < p.local_faces.rows(); ++i) {
    const Eigen::Vector2d a = p.uv.row(p.local_faces(i, 0)), b = p.uv.row(p.local_faces(i, 1)),
                          c = p.uv.row(p.local_faces(i, 2));
    EXPECT_GT((b - a).x() * (c - a).y() - (b - a).y() * (c - a).x(), 0.0) << i;
    if ((a + b + c).norm() / 3 > 0.15) continue;
    const double length3d = (V.row(F(p.faces[i], 0)) - V.row(F(p.faces[i], 1))).norm();
    worst = std::max(worst, std::abs((a - b).norm() / length3d - 1));
  }
  EXPECT_LT(worst, 0.03);
  EXPECT_GT(p.reach, 0.4);
}

TEST(TargetPatch, TooLargeARegionIsATypedError) {
  auto [V, F] = test_meshes::icosphere(2);
  const TriMesh sphere(V, F);
  EXPECT_THROW(paste::target_patch(sphere, 0, Eigen::Vector3d(1, 0, 0), Eigen::Vector3d::UnitX(), 10.0),
               TargetTooSmallError);
  // Around a thin tube the region wraps into a band: not a disc.
  auto [TV, TF] = torus(48, 16, 1.0, 0.15);
  const TriMesh ring(TV, TF);
  EXPECT_THROW(paste::target_patch(ring, 0, Eigen::Vector3d(1, 0, 0), Eigen::Vector3d::UnitZ(), 0.7),
               TargetTooSmallError);
  EXPECT_NO_THROW(paste::target_patch(ring, 0, Eigen::Vector3d(1, 0, 0), Eigen::Vector3d::UnitZ(), 0.2));
  EXPECT_THROW(paste::target_patch(sphere, -1, Eigen::Vector3d(1, 0, 0), Eigen::Vector3d::UnitX(), 0.5),
               InvalidInputError);
  EXPECT_THROW(paste::target_patch(sphere, 0, Eigen::Vector3d(1, 0, 0), Eigen::Vector3d::UnitX(), -1.0),
               InvalidInputError);
}
