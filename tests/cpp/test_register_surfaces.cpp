// The morph's 3D registration (morph/register_surfaces, thesis ch. 4) and
// closest points on a mesh (mesh/closest_points).

#include <gtest/gtest.h>

#include <cmath>

#include <Eigen/Geometry>

#include "common/errors.h"
#include "mesh/closest_points.h"
#include "morph/register_surfaces.h"
#include "test_meshes.h"

using namespace paramorph;
using namespace paramorph::morph;

namespace {

double diagonal(const MatrixX3d& V) { return (V.colwise().maxCoeff() - V.colwise().minCoeff()).norm(); }

/// A smooth non-rigid map: rotation, anisotropic scale, a quadratic bend, a shift.
MatrixX3d deform(const MatrixX3d& X) {
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  MatrixX3d Y = X * R.transpose();
  Y.col(0) = 1.2 * Y.col(0) + 0.1 * Y.col(2).cwiseAbs2();
  Y.col(1) *= 0.9;
  return Y.rowwise() + Eigen::RowVector3d(0.3, -0.2, 0.1);
}

}  // namespace

TEST(ClosestPoints, PointsOffTheSurfaceLandOnTheirFaceAndHintsAgree) {
  const auto [V, F] = test_meshes::lumpy_blob(2);
  // Face centroids pushed out a little along their face normal: their closest
  // point is the centroid itself (the blob is smooth at this scale).
  MatrixX3d centroids(F.rows(), 3), Q(F.rows(), 3);
  for (Index f = 0; f < Index(F.rows()); ++f) {
    const Eigen::RowVector3d a = V.row(F(f, 0)), b = V.row(F(f, 1)), c = V.row(F(f, 2));
    centroids.row(f) = (a + b + c) / 3.0;
    Q.row(f) = centroids.row(f) + 1e-3 * (b - a).cross(c - a).normalized();
  }
  const ClosestPointTree tree(V, F);
  const ClosestPoints c = tree.query(Q);
  int on_own_face = 0;
  for (Index f = 0; f < Index(F.rows()); ++f) {
    on_own_face += c.face[f] == f;
    EXPECT_LE(c.distance[f], 1e-3 + 1e-12);
    EXPECT_NEAR(c.bary.row(f).sum(), 1.0, 1e-12);
    EXPECT_GE(c.bary.row(f).minCoeff(), 0.0);
    // The barycentrics reproduce the point.
    const Eigen::RowVector3d x = c.bary(f, 0) * V.row(F(c.face[f], 0)) + c.bary(f, 1) * V.row(F(c.face[f], 1)) +
                                 c.bary(f, 2) * V.row(F(c.face[f], 2));
    EXPECT_LT((x - c.points.row(f)).norm(), 1e-9);
  }
  EXPECT_GT(on_own_face, 0.95 * F.rows());
  // A hint (here: the answers for slightly different queries) changes nothing.
  const ClosestPoints again = tree.query(Q, &c);
  const ClosestPoints moved = tree.query(Q.array() * 1.001, &c);
  const ClosestPoints fresh = tree.query(Q.array() * 1.001);
  EXPECT_LT((again.points - c.points).norm(), 1e-12);
  EXPECT_LT((moved.distance - fresh.distance).cwiseAbs().maxCoeff(), 1e-12);
}

TEST(RegisterSurfaces, RecoversASmoothDeformationAcrossTessellations) {
  const auto [VA, FA] = test_meshes::lumpy_blob(3);
  const auto [V2, FB] = test_meshes::lumpy_blob(2);  // same shape, another tessellation
  const MatrixX3d VB = deform(V2);
  const Eigen::RowVector3d ca = VA.colwise().mean(), cb = VB.colwise().mean();
  const PolynomialWarp identity = PolynomialWarp::similarity(cb, 1.0, Eigen::Matrix3d::Identity(), ca, 1.0);
  const PolynomialWarp wrong = PolynomialWarp::similarity(
      cb, 1.0, Eigen::AngleAxisd(2.0, Eigen::Vector3d::UnitZ()).toRotationMatrix(), ca, 1.0);
  const double before = (identity(VB) - V2).rowwise().norm().mean() / diagonal(VA);
  for (const auto& starts : {std::vector<PolynomialWarp>{identity, wrong}, std::vector<PolynomialWarp>{wrong, identity}}) {
    const Registration r = register_surfaces(VA, FA, VB, FB, starts);
    // The start near the truth wins, whichever place it has.
    EXPECT_EQ(r.start, starts[0].coefficients.isApprox(identity.coefficients) ? 0u : 1u);
    ASSERT_EQ(r.start_costs.size(), 2u);
    EXPECT_EQ(r.warp.degree, 3);
    // Every vertex of B goes back near where it came from on A.
    const double after = (r.warp(VB) - V2).rowwise().norm().mean() / diagonal(VA);
    EXPECT_LT(after, 0.01) << "before: " << before;
    EXPECT_LT(after, 0.2 * before);
    EXPECT_LT(r.cost, 0.005);
  }
}

TEST(RegisterSurfaces, RejectsBadInput) {
  const auto [V, F] = test_meshes::icosphere(1);
  EXPECT_THROW(register_surfaces(V, F, V, F, {}), InvalidInputError);
  const PolynomialWarp start =
      PolynomialWarp::similarity(Eigen::RowVector3d::Zero(), 1.0, Eigen::Matrix3d::Identity(), Eigen::RowVector3d::Zero(), 1.0);
  RegisterOptions o;
  o.max_degree = 4;
  EXPECT_THROW(register_surfaces(V, F, V, F, {start}, o), InvalidInputError);
  o = {};
  o.max_distance = 0;
  EXPECT_THROW(register_surfaces(V, F, V, F, {start}, o), InvalidInputError);
}

