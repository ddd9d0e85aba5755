#include <gtest/gtest.h>

#include "common/cholesky_solve_rows.h"
#include "mesh/tri_mesh.h"
#include "param/spherical/initial_map.h"
#include "param/spherical/spring_graph.h"
#include "test_meshes.h"

using namespace paramorph;

namespace {

template <int K>
void expect_matches_eigen(const spherical::PuncturedLaplacian& laplacian) {
  const Index n = laplacian.interior_count;
  RowsK<K> B = RowsK<K>::Random(n, K), X;
  cholesky_solve_rows<spherical::PuncturedLaplacian::Factor, K>(*laplacian.factor, B, X);
  const Eigen::MatrixXd reference = laplacian.factor->solve(Eigen::MatrixXd(B));
  EXPECT_LT((X - reference).cwiseAbs().maxCoeff(), 1e-10 * reference.cwiseAbs().maxCoeff());
  // In-place use (B and X the same object) is what the solvers do.
  cholesky_solve_rows<spherical::PuncturedLaplacian::Factor, K>(*laplacian.factor, B, B);
  EXPECT_LT((B - reference).cwiseAbs().maxCoeff(), 1e-10 * reference.cwiseAbs().maxCoeff());
}

}  // namespace

TEST(CholeskySolveRows, MatchesEigensSolveOnAPuncturedLaplacian) {
  auto [V, F] = test_meshes::lumpy_blob(3);
  const TriMesh mesh(V, F);
  const auto graph = spherical::build_spring_graph(
      mesh, spherical::edge_weights(mesh, spherical::Weights::Conformal));
  const auto laplacian = spherical::factor_punctured_laplacian(mesh, graph);
  expect_matches_eigen<3>(*laplacian);
  expect_matches_eigen<2>(*laplacian);
  expect_matches_eigen<1>(*laplacian);
}
