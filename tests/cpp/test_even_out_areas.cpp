// morph/even_out_areas: a kept topology's faces evened out along its own
// surface before the fit (issue 31): a sphere whose vertices are crowded
// towards one pole, as a decimated source's are where it had detail.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "mesh/vertex_normals.h"
#include "morph/even_out_areas.h"
#include "test_meshes.h"

using namespace paramorph;

namespace {

/// Standard deviation of the face areas over their mean.
double area_spread(const MatrixX3d& V, const MatrixX3i& F) {
  VectorXd area(F.rows());
  for (Index f = 0; f < Index(F.rows()); ++f) area(f) = face_normal(V, F, f).norm();
  const double mean = area.mean();
  return std::sqrt((area.array() - mean).square().mean()) / mean;
}

/// A unit icosphere's vertices drawn towards +z (d -> d + 0.8 z, back onto
/// the sphere: a bijection of the sphere, so no face turns over): its faces
/// near +z are a small fraction of those near -z.
std::pair<MatrixX3d, MatrixX3i> crowded_sphere() {
  auto [V, F] = test_meshes::icosphere(3);
  for (Index v = 0; v < Index(V.rows()); ++v) {
    Eigen::RowVector3d d = V.row(v).normalized();
    d.z() += 0.8;
    V.row(v) = d.normalized();
  }
  return {V, F};
}

}  // namespace

TEST(EvenOutAreas, EvensTheFacesTurnsNoneAndKeepsTheHeldVertices) {
  const auto [X, F] = crowded_sphere();
  std::vector<char> movable(X.rows(), 1);
  for (Index v = 0; v < 6; ++v) movable[v] = 0;
  const MatrixX3d P = morph::even_out_areas(X, F, movable, 30, 0.5);
  for (Index v = 0; v < 6; ++v) EXPECT_EQ(P.row(v), X.row(v)) << v;
  for (Index f = 0; f < Index(F.rows()); ++f) EXPECT_GT(face_normal(P, F, f).dot(face_normal(X, F, f)), 0.0) << f;
  const double before = area_spread(X, F), after = area_spread(P, F);
  EXPECT_GT(before, 1.0);
  EXPECT_LT(after, 0.7 * before) << before << " -> " << after;
}

TEST(EvenOutAreas, NoPassesLeaveTheMeshAsItWas) {
  const auto [X, F] = crowded_sphere();
  const MatrixX3d P = morph::even_out_areas(X, F, std::vector<char>(X.rows(), 1), 0, 0.5);
  EXPECT_EQ(P, X);
}
