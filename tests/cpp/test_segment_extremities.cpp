// Extremity segmentation by area stretch (features/segment_extremities, thesis 3.5.1).
#include <gtest/gtest.h>

#include <set>

#include "common/errors.h"
#include "features/segment_extremities.h"
#include "param/spherical/sphere_quality.h"
#include "test_meshes.h"

using namespace paramorph;
using namespace paramorph::features;

namespace {
/// Every face labelled in 0..R-1, region areas summing to the surface area,
/// adjacency pairs ordered, distinct, and each backed by a shared edge.
void expect_consistent(const TriMesh& mesh, const Segmentation& s) {
  ASSERT_EQ(Index(s.face_labels.size()), mesh.num_faces());
  EXPECT_EQ(s.face_labels.minCoeff(), 0);
  EXPECT_EQ(s.face_labels.maxCoeff(), s.regions() - 1);
  std::set<int> used(s.face_labels.data(), s.face_labels.data() + s.face_labels.size());
  EXPECT_EQ(Index(used.size()), s.regions());  // no empty region
  const double total = spherical::face_areas(mesh.V(), mesh.F()).sum();
  EXPECT_NEAR(s.area.sum(), total, 1e-9 * total);
  for (std::size_t i = 0; i < s.adjacency.size(); ++i) {
    EXPECT_LT(s.adjacency[i].first, s.adjacency[i].second);
    if (i) EXPECT_LT(s.adjacency[i - 1], s.adjacency[i]);
  }
}

/// An icosphere with four limbs pulled out along ±x and ±y.
std::pair<MatrixX3d, MatrixX3i> four_limbed_blob() {
  auto [V, F] = test_meshes::icosphere(3);
  const Eigen::Vector3d dirs[4] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}};
  for (Index v = 0; v < V.rows(); ++v) {
    const Eigen::Vector3d p = V.row(v).normalized();
    double pull = 0;
    for (const auto& d : dirs) pull = std::max(pull, std::max(0.0, p.dot(d) - 0.85) / 0.15);
    V.row(v) = (p * (1.0 + 2.5 * pull)).transpose();
  }
  return {V, F};
}
}  // namespace

TEST(SegmentExtremities, GrowsTwoRegionsAcrossAStretchStep) {
  auto [V, F] = test_meshes::bumpy_grid(12);
  const TriMesh mesh(V, F);
  VectorXd stretch(V.rows());
  for (Index v = 0; v < V.rows(); ++v) stretch[v] = V(v, 0) > 0.5 ? 10.0 : 1.0;
  const Segmentation s = grow_stretch_regions(mesh, stretch, 0.5);
  expect_consistent(mesh, s);
  ASSERT_EQ(s.regions(), 2);
  EXPECT_GT(V(s.seeds[0], 0), 0.5);  // the higher stretch seeds first
  EXPECT_EQ(s.adjacency.size(), 1u);
  for (Index f = 0; f < mesh.num_faces(); ++f) {
    int high = 0;
    for (int k = 0; k < 3; ++k) high += V(F(f, k), 0) > 0.5;
    if (high == 3) EXPECT_EQ(s.face_labels[f], 0) << f;
    if (high == 0) EXPECT_EQ(s.face_labels[f], 1) << f;
  }
}

TEST(SegmentExtremities, EachLimbOfABlobIsItsOwnRegion) {
  auto [V, F] = four_limbed_blob();
  const Segmentation s = segment_extremities(V, F);
  const TriMesh mesh(V, F);
  expect_consistent(mesh, s);
  // The tip of each limb (farthest vertex along its axis) and the top of the body.
  const Eigen::Vector3d dirs[5] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}};
  std::set<int> regions;
  for (const auto& d : dirs) {
    Index tip = 0;
    (V * d).maxCoeff(&tip);
    const Csr& corners = mesh.vertex_corners();
    regions.insert(s.face_labels[corners.items[corners.begin(tip)] / 3]);
  }
  EXPECT_EQ(regions.size(), 5u) << s.regions() << " regions";
  EXPECT_LE(s.regions(), 40);  // regions, not noise
}

TEST(SegmentExtremities, BadInputRaisesTheMatchingError) {
  auto [V, F] = test_meshes::bumpy_grid(6);
  EXPECT_THROW(segment_extremities(V, F), NotClosedError);
  const TriMesh mesh(V, F);
  EXPECT_THROW(grow_stretch_regions(mesh, VectorXd::Ones(V.rows()), 0.0), InvalidInputError);
  VectorXd stretch = VectorXd::Ones(V.rows());
  stretch[3] = -1.0;
  EXPECT_THROW(grow_stretch_regions(mesh, stretch, 0.5), InvalidInputError);
  ExtremityOptions o;
  o.sphere = MatrixX3d::Zero(2, 3);
  EXPECT_THROW(segment_extremities(V, F, o), InvalidInputError);
}
