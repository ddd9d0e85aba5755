// The pieces of the morph's correspondence (native/morph, issue 16): the
// sphere warp and its checked flow (pins exact, fold-free), the pins' order
// test, tip assignments, the distortion score, the correspondence frame and
// the shared Kabsch rotation.
#include <gtest/gtest.h>

#include <cmath>

#include <Eigen/Geometry>

#include "common/best_rotation.h"
#include "common/errors.h"
#include "morph/correspondence_frame.h"
#include "morph/flow_sphere_map.h"
#include "morph/map_distortion.h"
#include "morph/pin_order.h"
#include "morph/sphere_warp.h"
#include "morph/tip_assignments.h"
#include "test_meshes.h"

using namespace paramorph;
using namespace paramorph::morph;

namespace {

Eigen::Matrix3d turn(double angle, const Eigen::Vector3d& axis) {
  return Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix();
}

MatrixX3d unit_rows(std::initializer_list<Eigen::RowVector3d> rows) {
  MatrixX3d out(Index(rows.size()), 3);
  Index k = 0;
  for (const auto& r : rows) out.row(k++) = r.normalized();
  return out;
}

}  // namespace

TEST(BestRotation, RecoversARotationAndNeverReflects) {
  auto [V, F] = test_meshes::lumpy_blob(1);
  const Eigen::Matrix3d R = turn(0.7, {1, 2, 3});
  EXPECT_LT((best_rotation(V, V * R) - R).norm(), 1e-12);
  // A mirrored copy gets the best proper rotation, never the mirror.
  MatrixX3d mirrored = V;
  mirrored.col(0) *= -1;
  EXPECT_NEAR(best_rotation(V, mirrored).determinant(), 1.0, 1e-12);
  // One pair: the shortest turn.
  const MatrixX3d a = unit_rows({{1, 0, 0}}), b = unit_rows({{0, 1, 0}});
  EXPECT_LT((a * best_rotation(a, b) - b).norm(), 1e-12);
  EXPECT_TRUE(best_rotation(MatrixX3d(0, 3), MatrixX3d(0, 3)).isIdentity());
}

TEST(SphereWarp, InterpolatesTheMovesExactlyAndStaysTangent) {
  const MatrixX3d from = unit_rows({{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {-1, -1, 0.2}, {0.3, -1, -1}});
  const MatrixX3d to = unit_rows({{1, 0.1, 0}, {0.05, 1, 0.1}, {0, -0.1, 1}, {-1, -1.1, 0.3}, {0.3, -1, -0.8}});
  const MatrixX3d moved = warp_points(from, from, to, 16);
  EXPECT_LT((moved - to).cwiseAbs().maxCoeff(), 1e-9);  // the points land where they must
  MatrixX3d moves(from.rows(), 3);
  for (Index j = 0; j < from.rows(); ++j) moves.row(j) = log_map(from.row(j), to.row(j));
  const SphereWarpField field(from, moves);
  const Eigen::RowVector3d x = Eigen::RowVector3d(0.4, 0.5, -0.6).normalized();
  EXPECT_NEAR(field(x).dot(x), 0.0, 1e-12);
  for (Index j = 0; j < from.rows(); ++j) EXPECT_LT((field(from.row(j)) - moves.row(j)).norm(), 1e-9);
}

TEST(FlowSphereMap, PinnedVerticesEndExactlyOnTheirPointsAndNothingFolds) {
  auto [V, F] = test_meshes::icosphere(3);
  const MatrixX3d X = V.rowwise().normalized();
  const std::vector<Index> pinned = {0, 40, 200, 500};
  MatrixX3d from(4, 3), to(4, 3);
  const Eigen::Matrix3d small = turn(0.25, {0, 0, 1});
  for (Index k = 0; k < 4; ++k) {
    from.row(k) = X.row(pinned[std::size_t(k)]);
    const Eigen::RowVector3d moved = k % 2 ? Eigen::RowVector3d(from.row(k) * small) : Eigen::RowVector3d(from.row(k) * small.transpose());
    to.row(k) = moved.normalized();
  }
  std::vector<std::pair<Index, Index>> riders;
  for (Index k = 0; k < 4; ++k) riders.emplace_back(pinned[std::size_t(k)], k);
  const SphereFlowResult r = flow_sphere_map(F, X, from, to, riders);
  ASSERT_EQ(r.reached, 1.0);
  for (Index k = 0; k < 4; ++k)
    EXPECT_TRUE((r.positions.row(pinned[std::size_t(k)]).array() == to.row(k).array()).all()) << "pin " << k;
  VectorXd det(F.rows());
  for (Index f = 0; f < F.rows(); ++f)
    det[f] = r.positions.row(F(f, 0)).dot(r.positions.row(F(f, 1)).cross(r.positions.row(F(f, 2))));
  EXPECT_GT(det.minCoeff(), 0);
}

TEST(FlowSphereMap, ReportsWhereItStallsInsteadOfFolding) {
  // Two neighbouring vertices pinned to swap places: no fold-free map does
  // that, and the flow says which points block it.
  auto [V, F] = test_meshes::icosphere(2);
  const MatrixX3d X = V.rowwise().normalized();
  const Index a = F(0, 0), b = F(0, 1);
  MatrixX3d from(2, 3), to(2, 3);
  from << X.row(a), X.row(b);
  to << X.row(b), X.row(a);
  const SphereFlowResult r = flow_sphere_map(F, X, from, to, {{a, 0}, {b, 1}});
  EXPECT_LT(r.reached, 1.0);
  EXPECT_FALSE(r.blocking.empty());
  VectorXd det(F.rows());
  for (Index f = 0; f < F.rows(); ++f)
    det[f] = r.positions.row(F(f, 0)).dot(r.positions.row(F(f, 1)).cross(r.positions.row(F(f, 2))));
  EXPECT_GT(det.minCoeff(), -1e-13);  // what it returns is still fold-free
}

TEST(PinOrder, AMirrorImageIsToldFromAMildDistortion) {
  const MatrixX3d on_a = unit_rows({{1, 0, 0.1}, {0, 1, 0.1}, {-1, 0, 0.1}, {0, -1, 0.1}, {0, 0, 1}});
  MatrixX3d distorted = on_a * turn(0.4, {1, 1, 0});
  distorted.row(0) = (distorted.row(0) + Eigen::RowVector3d(0, 0.1, 0)).normalized();
  EXPECT_FALSE(pin_order(distorted, on_a).mirrored());
  MatrixX3d mirrored = on_a;
  mirrored.col(1) *= -1;  // left and right swapped
  const PinOrder order = pin_order(mirrored, on_a);
  EXPECT_TRUE(order.mirrored());
  EXPECT_FALSE(order.pins.empty());
  EXPECT_NE(mirrored_pins_message(order).find("mirrored order"), std::string::npos);
}

TEST(PinOrder, ThousandsOfPointsAreSampledNotCountedPastOverflow) {
  // 3000 points: k^3 overflows 32 bits; the triples are drawn instead.
  MatrixX3d on_a = MatrixX3d::Random(3000, 3);
  on_a.rowwise().normalize();
  const PinOrder same = pin_order(on_a * turn(0.7, {0, 1, 1}), on_a);
  EXPECT_GT(same.oriented, 10000);
  EXPECT_EQ(same.disagreeing, 0);
  MatrixX3d mirrored = on_a;
  mirrored.col(0) *= -1;
  const PinOrder order = pin_order(mirrored, on_a);
  EXPECT_TRUE(order.mirrored());
  EXPECT_EQ(order.disagreeing, order.oriented);
}

TEST(TipAssignments, FindTheRotationThatPairsEveryTip) {
  const MatrixX3d tips_a = unit_rows({{1, 0, -1}, {1, 0.3, -1}, {-1, 0, -1}, {-1, 0.3, -1}, {1.5, 0.2, 0.6}, {-1.5, 0.1, 0.3}});
  const Eigen::Matrix3d R = turn(1.1, {0.3, 1, 0.2});
  // B: A's tips turned, shuffled.
  const std::vector<Index> order = {3, 0, 5, 1, 4, 2};
  MatrixX3d tips_b(6, 3);
  for (Index k = 0; k < 6; ++k) tips_b.row(k) = tips_a.row(order[std::size_t(k)]) * R;
  const std::vector<TipAssignment> found = tip_assignments(tips_a, tips_b, 0.2, 8);
  ASSERT_FALSE(found.empty());
  ASSERT_EQ(found.front().pairs.size(), 6u);
  EXPECT_LT(found.front().mean_angle, 1e-6);
  for (const auto& [a, b] : found.front().pairs) EXPECT_EQ(a, order[std::size_t(b)]);
}

TEST(MapDistortion, ZeroForAnIsometryUpToScaleAndTheCapForAMirror) {
  auto [V, F] = test_meshes::lumpy_blob(2);
  const MatrixX3d X = V.rowwise().normalized();
  // B: A turned and scaled, the same sphere map (turned alike).
  const Eigen::Matrix3d R = turn(0.9, {1, 0, 1});
  const MapDistortion same = map_distortion(V, F, X, 3.0 * V * R, F, X * R * R.transpose());
  // Not exactly 0: images are measured in the plane of A's smoothed normal.
  EXPECT_LT(same.mean, 1e-3);
  EXPECT_EQ(same.folded_share, 0.0);
  // A mirror image: every face turned over.
  MatrixX3d mirrored = V;
  mirrored.col(0) *= -1;
  MatrixX3i turned = F;
  turned.col(1).swap(turned.col(2));
  const MapDistortion mirror = map_distortion(V, F, X, mirrored, turned, X);
  EXPECT_GT(mirror.folded_share, 0.99);
  EXPECT_NEAR(mirror.mean, 10.6, 1e-9);
}

TEST(CorrespondenceFrame, TurnsAnInsideOutFileAndNormalises) {
  auto [V, F] = test_meshes::lumpy_blob(2);
  MatrixX3i turned = F;
  turned.col(1).swap(turned.col(2));
  const MatrixX3d placed = (0.1 * V).rowwise() + Eigen::RowVector3d(5, -3, 2);
  const CorrespondenceFrame frame = correspondence_frame(placed, turned);
  EXPECT_TRUE(frame.inside_out);
  EXPECT_TRUE(frame.F == F);
  const CorrespondenceFrame original = correspondence_frame(V, F);
  EXPECT_FALSE(original.inside_out);
  EXPECT_LT((frame.V - original.V).cwiseAbs().maxCoeff(), 1e-9);  // one frame whatever the placement
}
