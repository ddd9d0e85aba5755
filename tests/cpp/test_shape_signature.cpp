// Shape signature (features/shape_signature, thesis 3.5.3): the histogram's
// definition on cases with a known stretch, invariances, the earth mover's
// distance on synthetic histograms, resolution independence, errors.
#include <gtest/gtest.h>

#include <iostream>
#include <random>

#include "common/errors.h"
#include "features/shape_signature.h"
#include "param/spherical/sphere_map.h"
#include "test_meshes.h"

using namespace paramorph;
using namespace paramorph::features;

namespace {

VectorXd delta(int bins, int at) {
  VectorXd h = VectorXd::Zero(bins);
  h[at] = 1.0;
  return h;
}

std::pair<MatrixX3d, MatrixX3i> ellipsoid(int levels, const Eigen::Vector3d& axes) {
  auto [V, F] = test_meshes::icosphere(levels);
  V = V * axes.asDiagonal();
  return {V, F};
}

}  // namespace

TEST(ShapeSignature, AMapThatKeepsEveryAreaShareIsSplitBetweenTheCentralBins) {
  // The unit icosphere is its own sphere map: every face has stretch 1, so
  // ln s = 0 sits half-way between the centres of the two central bins.
  auto [V, F] = test_meshes::icosphere(2);
  SignatureOptions options;
  options.sphere = V;
  for (int bins : {8, 32}) {
    options.bins = bins;
    const VectorXd h = shape_signature(2.5 * V, F, options);  // a uniform scale changes no share
    ASSERT_EQ(h.size(), bins);
    EXPECT_NEAR(h[bins / 2 - 1], 0.5, 1e-9);
    EXPECT_NEAR(h[bins / 2], 0.5, 1e-9);
    EXPECT_NEAR(h.sum(), 1.0, 1e-12);
  }
  // An odd bin count has a bin centred on 0.
  options.bins = 9;
  EXPECT_NEAR(shape_signature(V, F, options)[4], 1.0, 1e-9);
}

TEST(ShapeSignature, StretchBeyondTheRangeLandsInTheEndBins) {
  // A "map" that shrinks the upper hemisphere 1000 times towards the centre:
  // faces with all corners above keep 1e-6 of their share (ln s ~ +13, far
  // beyond the range: last bin); faces with all corners below keep their
  // shape, so their ln s is ln(a / A) with a, A the mapped and surface totals.
  auto [V, F] = test_meshes::icosphere(3);
  MatrixX3d X = V;
  for (Index v = 0; v < V.rows(); ++v)
    if (V(v, 2) > 0.0) X.row(v) *= 1e-3;
  auto area = [](const MatrixX3d& P, const Eigen::Vector3i& f) {
    const Eigen::Vector3d a = P.row(f[0]), b = P.row(f[1]), c = P.row(f[2]);
    return 0.5 * (b - a).cross(c - a).norm();
  };
  double above = 0.0, below = 0.0, A = 0.0, a = 0.0;
  for (Index f = 0; f < F.rows(); ++f) {
    const Eigen::Vector3i face = F.row(f).transpose();
    A += area(V, face), a += area(X, face);
    const int up = (V(face[0], 2) > 0) + (V(face[1], 2) > 0) + (V(face[2], 2) > 0);
    if (up == 3) above += area(V, face);
    if (up == 0) below += area(V, face);
  }
  SignatureOptions options;
  options.sphere = X;
  options.log_range = 2.0;
  options.bins = 16;
  const VectorXd h = shape_signature(V, F, options);
  EXPECT_NEAR(h.sum(), 1.0, 1e-12);
  EXPECT_GE(h[15], above / A - 1e-12) << "every shrunk face is in the last bin";
  EXPECT_LE(h[15], 1.0 - below / A + 1e-12) << "no unshrunk face is";
  // The unshrunk faces' weight sits in the two bins whose centres bracket ln(a / A).
  const double t = (std::log(a / A) + 2.0) / 0.25 - 0.5;
  ASSERT_GT(t, 0.0);
  const int k = int(t);
  EXPECT_GE(h[k] + h[k + 1], below / A - 1e-12) << "ln(a/A) = " << std::log(a / A);
  EXPECT_GT(below / A, 0.3);
  EXPECT_GT(above / A, 0.3);
}

TEST(ShapeSignature, GivenSphereEqualsComputedAndScaleDoesNotMatter) {
  auto [V, F] = test_meshes::lumpy_blob(3);
  const VectorXd computed = shape_signature(V, F);
  SignatureOptions options;
  options.sphere = spherical::sphere_map(V, F).positions;
  EXPECT_LT((shape_signature(V, F, options) - computed).cwiseAbs().maxCoeff(), 1e-12);
  for (double s : {1e-6, 1e6}) {
    const MatrixX3d scaled = s * V;
    EXPECT_LT(signature_distance(shape_signature(scaled, F), computed), 1e-6) << "scale " << s;
  }
  EXPECT_GT((computed.array() > 1e-3).count(), 4) << "a blob spreads over several bins";
}

TEST(ShapeSignature, SameShapeAtTwoResolutionsIsCloserThanAnotherShape) {
  auto [V3, F3] = test_meshes::lumpy_blob(3);
  auto [V4, F4] = test_meshes::lumpy_blob(4);
  auto [E, FE] = ellipsoid(4, {1.0, 1.6, 0.8});
  const VectorXd coarse = shape_signature(V3, F3), fine = shape_signature(V4, F4);
  const VectorXd other = shape_signature(E, FE);
  const double same = signature_distance(coarse, fine);
  const double different =
      std::min(signature_distance(coarse, other), signature_distance(fine, other));
  std::cout << "lumpy blob level 3 vs 4: " << same << "; blob vs ellipsoid: " << different << "\n";
  EXPECT_LT(same, 0.5 * different) << "same " << same << ", different " << different;
}

TEST(SignatureDistance, IsTheEarthMoversDistanceInLogStretchUnits) {
  const int bins = 16;
  const double L = 4.0, w = 2.0 * L / bins;
  EXPECT_DOUBLE_EQ(signature_distance(delta(bins, 3), delta(bins, 3)), 0.0);
  EXPECT_NEAR(signature_distance(delta(bins, 3), delta(bins, 4)), w, 1e-15);
  EXPECT_NEAR(signature_distance(delta(bins, 2), delta(bins, 9)), 7 * w, 1e-14);
  EXPECT_NEAR(signature_distance(delta(bins, 0), delta(bins, bins - 1), 2.0), (bins - 1) * 0.25,
              1e-14);
  // A shape shifted by one bin is one bin width away, however spread it is.
  VectorXd spread = VectorXd::Zero(bins);
  spread.segment(2, 6) << 0.1, 0.3, 0.2, 0.25, 0.05, 0.1;
  VectorXd shifted = VectorXd::Zero(bins);
  shifted.segment(3, 6) = spread.segment(2, 6);
  EXPECT_NEAR(signature_distance(spread, shifted), w, 1e-14);
  // Unnormalised input is normalised.
  EXPECT_NEAR(signature_distance(7.0 * spread, shifted), w, 1e-14);

  std::mt19937 rng(3);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  auto random_histogram = [&] {
    VectorXd h(bins);
    for (int k = 0; k < bins; ++k) h[k] = unit(rng);
    return h;
  };
  for (int trial = 0; trial < 50; ++trial) {
    const VectorXd a = random_histogram(), b = random_histogram(), c = random_histogram();
    const double ab = signature_distance(a, b), ba = signature_distance(b, a);
    EXPECT_DOUBLE_EQ(ab, ba);
    EXPECT_LE(signature_distance(a, c), ab + signature_distance(b, c) + 1e-12);
    EXPECT_LE(ab, 2.0 * L);
  }
}

TEST(SignatureDistance, RejectsMismatchedOrInvalidHistograms) {
  EXPECT_THROW(signature_distance(delta(8, 1), delta(9, 1)), InvalidInputError);
  EXPECT_THROW(signature_distance(VectorXd(), VectorXd()), InvalidInputError);
  EXPECT_THROW(signature_distance(VectorXd::Zero(8), delta(8, 1)), InvalidInputError);
  VectorXd negative = delta(8, 1);
  negative[3] = -0.5;
  EXPECT_THROW(signature_distance(negative, delta(8, 1)), InvalidInputError);
  VectorXd nan = delta(8, 1);
  nan[0] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(signature_distance(delta(8, 1), nan), InvalidInputError);
  EXPECT_THROW(signature_distance(delta(8, 1), delta(8, 2), 0.0), InvalidInputError);
}

TEST(ShapeSignature, RejectsBadOptionsAndMeshesAndHonoursCancel) {
  auto [V, F] = test_meshes::icosphere(2);
  SignatureOptions options;
  options.bins = 0;
  EXPECT_THROW(shape_signature(V, F, options), InvalidInputError);
  options = {};
  options.log_range = -1.0;
  EXPECT_THROW(shape_signature(V, F, options), InvalidInputError);
  options.log_range = std::numeric_limits<double>::infinity();
  EXPECT_THROW(shape_signature(V, F, options), InvalidInputError);
  options = {};
  options.sphere = MatrixX3d(V.topRows(V.rows() - 1));
  EXPECT_THROW(shape_signature(V, F, options), InvalidInputError);
  options.sphere = MatrixX3d::Zero(V.rows(), 3);
  EXPECT_THROW(shape_signature(V, F, options), InvalidInputError) << "sphere of zero area";

  auto [G, FG] = test_meshes::bumpy_grid(4);
  EXPECT_THROW(shape_signature(G, FG), NotClosedError) << "no sphere given: needs a closed mesh";

  std::vector<double> seen;
  Progress record(
      [&](double fraction, const std::string&) {
        seen.push_back(fraction);
        return true;
      },
      0.0);
  shape_signature(V, F, {}, &record);
  ASSERT_GE(seen.size(), 3u);
  EXPECT_EQ(seen.front(), 0.0);
  EXPECT_EQ(seen.back(), 1.0);
  for (std::size_t k = 1; k < seen.size(); ++k) EXPECT_GE(seen[k], seen[k - 1]);

  Progress cancel([](double, const std::string&) { return false; }, 0.0);
  EXPECT_THROW(shape_signature(V, F, {}, &cancel), Cancelled);
}
