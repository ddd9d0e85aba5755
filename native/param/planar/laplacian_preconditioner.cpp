#include "param/planar/laplacian_preconditioner.h"

#include <Eigen/SparseCholesky>

#include "common/fill_reducing_ordering.h"
#include "common/cholesky_solve_rows.h"
#include "common/errors.h"
#include "mesh/cotangent_weights.h"

namespace paramorph::planar {

struct LaplacianPreconditioner::Factor {
  Eigen::SimplicialLLT<Eigen::SparseMatrix<double>, Eigen::Lower, FillReducingOrdering<int>> llt;
};

FreeVertices free_vertices(const std::vector<char>& fixed) {
  FreeVertices out;
  out.slot.assign(fixed.size(), -1);
  for (std::size_t v = 0; v < fixed.size(); ++v)
    if (!fixed[v]) {
      out.slot[v] = Index(out.vertices.size());
      out.vertices.push_back(Index(v));
    }
  return out;
}

Eigen::SparseMatrix<double> free_laplacian(const TriMesh& mesh, const VectorXd& w,
                                           const FreeVertices& free) {
  const Csr& nbr = mesh.vertex_neighbors();
  const Csr& nbr_edges = mesh.vertex_neighbor_edges();
  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(nbr.items.size() / 2 + free.vertices.size());
  for (Index v : free.vertices) {
    const Index row = free.slot[v];
    double degree = 0.0;
    for (Index k = nbr.begin(v); k < nbr.end(v); ++k) {
      const double wk = w[nbr_edges.items[k]];
      degree += wk;
      const Index col = free.slot[nbr.items[k]];
      if (col >= 0 && col < row) triplets.emplace_back(row, col, -wk);
    }
    triplets.emplace_back(row, row, degree);
  }
  const Index n = Index(free.vertices.size());
  Eigen::SparseMatrix<double> L(n, n);
  L.setFromTriplets(triplets.begin(), triplets.end());
  return L;
}

LaplacianPreconditioner::LaplacianPreconditioner(const TriMesh& mesh, const FreeVertices& free,
                                                 const VectorXd& diagonal)
    : factor_(std::make_unique<Factor>()) {
  lower_ = free_laplacian(mesh, clamped_cotangent_weights(mesh), free);
  const Index n = lower_.rows();
  const bool pinned = Index(free.slot.size()) != n;
  double shift = 0.0, mean_degree = lower_.diagonal().sum() / std::max<Index>(1, n);
  for (Index r = 0; r < n; ++r) {
    const double extra = diagonal.size() ? diagonal[free.vertices[r]] : 0.0;
    shift += extra;
    lower_.coeffRef(r, r) += extra;
  }
  // Nothing holds the map in place: shift by a hair so P is definite. The
  // energy's gradient has no translation part, so the shift barely matters.
  if (!pinned && shift == 0.0)
    for (Index r = 0; r < n; ++r) lower_.coeffRef(r, r) += 1e-8 * mean_degree;
  factor_->llt.compute(lower_);
  PM_REQUIRE(factor_->llt.info() == Eigen::Success, DegenerateFaceError,
             "the Laplacian of the free vertices could not be factored (degenerate weights)");
}

LaplacianPreconditioner::~LaplacianPreconditioner() = default;

namespace {
using Interleaved = Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, 2, Eigen::RowMajor>>;
}

void LaplacianPreconditioner::apply(VectorXd& x) const {
  // Interleaved (u, v) is already the #free by 2 row-major layout.
  RowsK<2> X = Interleaved(x.data(), x.size() / 2, 2);
  cholesky_solve_rows<decltype(factor_->llt), 2>(factor_->llt, X, X);
  Interleaved(x.data(), x.size() / 2, 2) = X;
}

double LaplacianPreconditioner::quadratic(const VectorXd& s) const {
  const Eigen::MatrixX2d S = Interleaved(const_cast<double*>(s.data()), s.size() / 2, 2);
  const Eigen::MatrixX2d PS = lower_.selfadjointView<Eigen::Lower>() * S;
  return (S.array() * PS.array()).sum();
}

LbfgsPreconditioner laplacian_lbfgs_preconditioner(const LaplacianPreconditioner& laplacian) {
  return {[&laplacian](VectorXd& q) { laplacian.apply(q); },
          [&laplacian](const VectorXd& s) { return laplacian.quadratic(s); }};
}

}  // namespace paramorph::planar
