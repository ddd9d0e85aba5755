// Concavity intensity (features/concavity, thesis Def. 4.1): zero on convex
// meshes, analytic distances inside a dented box, an independent bound from
// the support function, pruning equal to brute force, rigid/scale
// invariance, flat input rejected without Qhull printing anything.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <iostream>
#include <random>

#include "common/errors.h"
#include "features/concavity.h"
#include "mesh/validate.h"
#include "test_meshes.h"

using namespace paramorph;
using namespace paramorph::features;

namespace {

double diameter(const MatrixX3d& V) {
  return (V.colwise().maxCoeff() - V.colwise().minCoeff()).norm();
}

/// Unit directions spread evenly over the sphere (Fibonacci lattice).
MatrixX3d fibonacci_directions(int count) {
  MatrixX3d U(count, 3);
  const double golden = M_PI * (3.0 - std::sqrt(5.0));
  for (int k = 0; k < count; ++k) {
    const double z = 1.0 - 2.0 * (k + 0.5) / count, r = std::sqrt(1.0 - z * z);
    U.row(k) << r * std::cos(golden * k), r * std::sin(golden * k), z;
  }
  return U;
}

}  // namespace

TEST(Concavity, ConvexMeshesAreZeroEverywhere) {
  {
    auto [V, F] = test_meshes::icosphere(3);
    const VectorXd I = concavity(V, F);
    ASSERT_EQ(I.size(), V.rows());
    EXPECT_LT(I.maxCoeff(), 1e-12) << "icosphere";
    EXPECT_GE(I.minCoeff(), 0.0);
  }
  {
    // Most vertices lie inside the flat sides, not at the hull's corners.
    auto [V, F] = test_meshes::box_grid(6, {1.0, 1.5, 2.0});
    const VectorXd I = concavity(V, F);
    EXPECT_LT(I.maxCoeff(), 1e-12) << "box_grid";
    EXPECT_EQ(convex_hull(V).offsets.size(), 6)
        << "coplanar facets should merge into the box's sides";
  }
}

TEST(Concavity, DentsInABoxAreAtTheDistanceOfTheNearestSide) {
  const Eigen::Vector3d half(1.0, 1.5, 2.0);
  auto [V, F] = test_meshes::box_grid(8, half);
  // Push non-corner vertices inward along their side's normal by different
  // depths; the corners keep the hull the box, so the distance of a point
  // inside is min over axes of (half_a - |p_a|).
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> depth(0.05, 2.5);
  std::vector<std::pair<Index, double>> dents;
  for (Index v = 0; v < V.rows(); ++v) {
    const Eigen::Vector3d p = V.row(v).transpose();
    int on_side = -1, sides = 0;
    for (int a = 0; a < 3; ++a)
      if (std::abs(std::abs(p[a]) - half[a]) < 1e-12) on_side = a, ++sides;
    if (sides != 1 || v % 3 != 0) continue;  // face-interior vertices, every third
    const double d = std::min(depth(rng), half[on_side]);
    V(v, on_side) -= std::copysign(d, p[on_side]);
    dents.push_back({v, d});
  }
  ASSERT_GT(dents.size(), 50u);
  const VectorXd I = concavity(V, F);
  for (Index v = 0; v < V.rows(); ++v) {
    const Eigen::Vector3d p = V.row(v).transpose();
    EXPECT_NEAR(I[v], (half - p.cwiseAbs()).minCoeff(), 1e-12)
        << "vertex " << v << " at " << p.transpose();
  }
  // Both cases occur: the dent's own side is the nearest, and another side is.
  int own = 0, other = 0;
  for (const auto& [v, d] : dents) (std::abs(I[v] - d) < 1e-9 ? own : other) += 1;
  EXPECT_GT(own, 10);
  EXPECT_GT(other, 10);
}

TEST(Concavity, OneVertexPushedInByDHasConcavityD) {
  auto [V, F] = test_meshes::box_grid(4, {1.0, 1.0, 1.0});
  Index top = -1;  // the centre of the +z side
  for (Index v = 0; v < V.rows(); ++v)
    if ((V.row(v) - Eigen::RowVector3d(0, 0, 1)).norm() < 1e-12) top = v;
  ASSERT_GE(top, 0);
  for (double d : {0.01, 0.3, 0.9}) {
    MatrixX3d W = V;
    W(top, 2) -= d;
    VectorXd I = concavity(W, F);
    EXPECT_NEAR(I[top], d, 1e-12);
    I[top] = 0.0;
    EXPECT_LT(I.maxCoeff(), 1e-12) << "only the pushed vertex is inside the hull";
  }
}

TEST(Concavity, HullPlanesSupportThePointsAndBoundTheDistanceFromAbove) {
  // Independent of Qhull: for any unit u, h(u) = max_j u · v_j is a
  // supporting plane, so I(p) <= h(u) - u · p, with equality at the nearest
  // facet's normal; over many directions the bound is tight to about
  // (angular spacing) x (distance to the farthest vertex).
  auto [V, F] = test_meshes::lumpy_blob(3);
  const VectorXd I = concavity(V, F);
  const double D = diameter(V);
  ASSERT_GT(I.maxCoeff(), 0.01 * D) << "the blob should be clearly non-convex";

  const ConvexHull hull = convex_hull(V);
  const MatrixX3d centred = V.rowwise() - hull.origin.transpose();
  const Eigen::MatrixXd plane_values =
      (centred * hull.normals.transpose()).rowwise() + hull.offsets.transpose();
  EXPECT_LT(plane_values.maxCoeff(), 1e-9 * D) << "a facet plane cuts through the points";
  for (Index f = 0; f < plane_values.cols(); ++f) {
    const int touching = int((plane_values.col(f).array() > -1e-9 * D).count());
    EXPECT_GE(touching, 3) << "facet " << f << " touches no face of the point set";
  }

  // Global directions, then a finer cap around each vertex's best one; any
  // direction gives an upper bound, the cap only makes it tighter.
  const int count = 20000, cap_count = 600;
  const MatrixX3d U = fibonacci_directions(count);
  const Eigen::MatrixXd proj = V * U.transpose();  // #V by count
  const Eigen::RowVectorXd support = proj.colwise().maxCoeff();
  const double cap_radius = 3.0 * std::sqrt(4.0 * M_PI / count);
  const MatrixX3d cap_unit = fibonacci_directions(cap_count);  // rescaled into a cap around +z
  double worst_gap = 0.0;
  for (Index v = 0; v < V.rows(); ++v) {
    Index best = 0;
    double bound = (support - proj.row(v)).minCoeff(&best);
    const Eigen::Vector3d u0 = U.row(best).transpose();
    const Eigen::Matrix3d frame =
        Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), u0).toRotationMatrix();
    for (int k = 0; k < cap_count; ++k) {
      // Map the sphere's polar angle [0, pi] onto [0, cap_radius].
      const Eigen::Vector3d w = cap_unit.row(k).transpose();
      const double polar = std::acos(std::clamp(w.z(), -1.0, 1.0)) * cap_radius / M_PI;
      const Eigen::Vector2d around = w.head<2>().normalized();
      const Eigen::Vector3d u =
          frame * Eigen::Vector3d(std::sin(polar) * around.x(), std::sin(polar) * around.y(),
                                  std::cos(polar));
      bound = std::min(bound, (V * u).maxCoeff() - V.row(v).dot(u));
    }
    EXPECT_LE(I[v], bound + 1e-12 * D) << "vertex " << v;
    worst_gap = std::max(worst_gap, bound - I[v]);
  }
  std::cout << "concavity max " << I.maxCoeff() << ", worst gap to the support bound " << worst_gap
            << "\n";
  EXPECT_LT(worst_gap, 0.05 * I.maxCoeff());
}

TEST(Concavity, PrunedMinimumEqualsBruteForce) {
  auto [V, F] = test_meshes::lumpy_blob(4);
  const ConvexHull hull = convex_hull(V);
  ASSERT_GT(hull.offsets.size(), 500);
  // Points near the surface (inside and outside) interleaved with points spread
  // through a box twice the blob's size.
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  // Plus degenerate nodes: 300 copies of one point, 300 points on a segment.
  MatrixX3d P(20600, 3);
  for (Index k = 20000; k < 20300; ++k) P.row(k) << 0.1, -0.2, 0.3;
  for (Index k = 20300; k < 20600; ++k)
    P.row(k) = (k - 20300) / 300.0 * Eigen::RowVector3d(1, 0.5, -0.2);
  for (Index k = 0; k < 20000; ++k) {
    const Eigen::RowVector3d q(unit(rng), unit(rng), unit(rng));
    P.row(k) = k % 2 ? Eigen::RowVector3d(V.row(k % V.rows()) * (0.9 + 0.2 * (unit(rng) + 1) / 2))
                     : Eigen::RowVector3d(2.0 * q);
  }
  const VectorXd fast = depth_below_planes(P, hull);
  VectorXd brute(P.rows());
  for (Index k = 0; k < P.rows(); ++k) {
    const Eigen::Vector3d p = (P.row(k) - hull.origin.transpose()).transpose();
    brute[k] = (-(hull.normals * p + hull.offsets)).minCoeff();
  }
  EXPECT_LT((fast - brute).cwiseAbs().maxCoeff(), 1e-13 * diameter(P));
  EXPECT_LT(brute.minCoeff(), 0.0) << "some test points should be outside";
  EXPECT_GT(brute.maxCoeff(), 0.0) << "some test points should be inside";
}

TEST(Concavity, InvariantUnderRigidMotionAndLinearInScale) {
  auto [V, F] = test_meshes::lumpy_blob(3);
  const VectorXd I = concavity(V, F);
  const double size = I.maxCoeff();
  ASSERT_GT(size, 0.0);
  const Eigen::Matrix3d R =
      Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, -0.5).normalized()).toRotationMatrix();
  const MatrixX3d moved = (V * R.transpose()).rowwise() + Eigen::RowVector3d(1e3, -2e3, 5e2);
  EXPECT_LT((concavity(moved, F) - I).cwiseAbs().maxCoeff(), 1e-9 * size);
  for (double s : {1e-6, 1e6}) {
    const MatrixX3d scaled = s * V;
    EXPECT_LT((concavity(scaled, F) / s - I).cwiseAbs().maxCoeff(), 1e-12 * size) << "scale " << s;
  }
}

TEST(Concavity, FlatOrMalformedInputIsInvalidAndQhullStaysQuiet) {
  auto [Vg, Fg] = test_meshes::bumpy_grid(6);
  MatrixX3d flat = Vg;
  flat.col(2) = 0.3 * flat.col(0) + 0.2 * flat.col(1) + Eigen::VectorXd::Constant(flat.rows(), 5.0);
  testing::internal::CaptureStdout();
  testing::internal::CaptureStderr();
  EXPECT_THROW(concavity(flat, Fg), InvalidInputError) << "tilted plane";
  MatrixX3d line = Vg;
  line.col(1) = 2.0 * line.col(0);
  line.col(2) = -line.col(0);
  EXPECT_THROW(concavity(line, Fg), InvalidInputError) << "points on a line";
  EXPECT_THROW(concavity(MatrixX3d::Zero(Vg.rows(), 3), Fg), InvalidInputError) << "one point";
  const std::string out = testing::internal::GetCapturedStdout();
  const std::string err = testing::internal::GetCapturedStderr();
  EXPECT_EQ(out, "");
  EXPECT_EQ(err, "");

  try {
    concavity(flat, Fg);
    FAIL() << "expected InvalidInputError";
  } catch (const InvalidInputError& e) {
    EXPECT_NE(std::string(e.what()).find("plane"), std::string::npos) << e.what();
  }

  MatrixX3d tri(3, 3);
  tri << 0, 0, 0, 1, 0, 0, 0, 1, 0;
  MatrixX3i one(1, 3);
  one << 0, 1, 2;
  EXPECT_THROW(concavity(tri, one), InvalidInputError) << "one triangle";

  auto [V, F] = test_meshes::icosphere(1);
  MatrixX3d nan = V;
  nan(4, 1) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(concavity(nan, F), InvalidInputError);
  MatrixX3i bad = F;
  bad(2, 1) = Index(V.rows());
  EXPECT_THROW(concavity(V, bad), InvalidInputError);
}
