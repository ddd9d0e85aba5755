// The free-vertex Laplacian and its use as L-BFGS's H0 (param/planar/laplacian_preconditioner).
#include <gtest/gtest.h>

#include "mesh/cotangent_weights.h"
#include "param/planar/laplacian_preconditioner.h"
#include "test_meshes.h"

using namespace paramorph;
using namespace paramorph::planar;

namespace {
TriMesh grid_patch(int n) {
  auto [V, F] = test_meshes::bumpy_grid(n);
  return TriMesh(V, F);
}
}  // namespace

TEST(FreeLaplacian, RowSumsAreTheWeightsToPinnedNeighbours) {
  const TriMesh mesh = grid_patch(6);
  std::vector<char> fixed(mesh.num_vertices(), 0);
  for (Index v = 0; v < mesh.num_vertices(); v += 5) fixed[v] = 1;
  const FreeVertices free = free_vertices(fixed);
  ASSERT_EQ(Index(free.vertices.size()) + (mesh.num_vertices() + 4) / 5, mesh.num_vertices());
  const VectorXd w = clamped_cotangent_weights(mesh);
  const Eigen::SparseMatrix<double> lower = free_laplacian(mesh, w, free);
  const Eigen::SparseMatrix<double> L = lower.selfadjointView<Eigen::Lower>();
  // L_ff · 1 = Σ of the weights to pinned neighbours, per row.
  const VectorXd row_sums = L * VectorXd::Ones(L.cols());
  const Csr& nbr = mesh.vertex_neighbors();
  for (Index v : free.vertices) {
    double to_pinned = 0.0;
    for (Index k = nbr.begin(v); k < nbr.end(v); ++k)
      if (fixed[nbr.items[k]]) to_pinned += w[mesh.vertex_neighbor_edges().items[k]];
    EXPECT_NEAR(row_sums[free.slot[v]], to_pinned, 1e-12) << v;
  }
}

TEST(LaplacianPreconditioner, ApplyInvertsTheQuadraticForm) {
  const TriMesh mesh = grid_patch(8);
  for (bool pinned : {false, true}) {  // free boundary (shifted) and with pins
    std::vector<char> fixed(mesh.num_vertices(), 0);
    if (pinned) fixed[0] = fixed[40] = 1;
    const FreeVertices free = free_vertices(fixed);
    VectorXd soft = VectorXd::Zero(mesh.num_vertices());
    if (pinned) soft[7] = 3.0;  // a soft pin's penalty on the diagonal
    const LaplacianPreconditioner P(mesh, free, soft);
    const Index m = 2 * Index(free.vertices.size());
    VectorXd s = VectorXd::LinSpaced(m, -1.0, 2.0).array().cos();
    if (!pinned) {  // the shifted free-boundary P is near singular on translations: test off them
      for (int c = 0; c < 2; ++c) {
        double mean = 0.0;
        for (Index i = c; i < m; i += 2) mean += s[i];
        for (Index i = c; i < m; i += 2) s[i] -= 2.0 * mean / m;
      }
    }
    EXPECT_GT(P.quadratic(s), 0.0);
    // sᵀ P (P⁻¹ s) = sᵀ s.
    VectorXd q = s;
    P.apply(q);
    EXPECT_NEAR(0.5 * (P.quadratic(q + s) - P.quadratic(q) - P.quadratic(s)), s.squaredNorm(),
                1e-6 * s.squaredNorm()) << pinned;
  }
}
