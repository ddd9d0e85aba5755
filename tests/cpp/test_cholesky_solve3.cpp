#include <gtest/gtest.h>

#include "common/cholesky_solve3.h"
#include "mesh/tri_mesh.h"
#include "param/spherical/initial_map.h"
#include "param/spherical/spring_graph.h"
#include "test_meshes.h"

using namespace paramorph;

TEST(CholeskySolve3, MatchesEigensSolveOnAPuncturedLaplacian) {
  auto [V, F] = test_meshes::lumpy_blob(3);
  const TriMesh mesh(V, F);
  const auto graph = spherical::build_spring_graph(
      mesh, spherical::edge_weights(mesh, spherical::Weights::Conformal));
  const auto laplacian = spherical::factor_punctured_laplacian(mesh, graph);
  const Index n = laplacian->interior_count;
  MatrixX3d B = MatrixX3d::Random(n, 3), X;
  cholesky_solve3(*laplacian->factor, B, X);
  const Eigen::MatrixXd reference = laplacian->factor->solve(Eigen::MatrixXd(B));
  EXPECT_LT((X - reference).cwiseAbs().maxCoeff(), 1e-10 * reference.cwiseAbs().maxCoeff());
  // In-place use (B and X the same object) is what the PCG does.
  cholesky_solve3(*laplacian->factor, B, B);
  EXPECT_LT((B - reference).cwiseAbs().maxCoeff(), 1e-10 * reference.cwiseAbs().maxCoeff());
}
