#include "param/spherical/tangent_newton.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include "common/errors.h"
#include "common/parallel.h"
#include "common/report_while.h"
#include "common/supernodal_cholesky.h"

namespace paramorph::spherical {

using SparseMatrix = Eigen::SparseMatrix<double>;

Mat32 tangent_basis(const Eigen::Vector3d& v) {
  const Eigen::Vector3d axis = std::abs(v.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  const Eigen::Vector3d e1 = (axis - axis.dot(v) * v).normalized();
  Mat32 T;
  T << e1, v.cross(e1);
  return T;
}

Mat6 project_psd(const Mat6& H) {
  const Eigen::SelfAdjointEigenSolver<Mat6> eigen(H);
  return eigen.eigenvectors() * eigen.eigenvalues().cwiseMax(0.0).asDiagonal() * eigen.eigenvectors().transpose();
}

/// The fixed sparsity (lower triangle of the 2#V by 2#V matrix), each face
/// block's slots, the fixed vertices' slots, and the factorisation.
struct TangentNewton::Solver {
  SparseMatrix A;
  std::vector<Index> face_slot;      ///< 36 per face, row-major over the local 6 by 6 (-1: upper triangle)
  std::vector<Index> diagonal_slot;  ///< 3 per vertex: (2i,2i), (2i+1,2i), (2i+1,2i+1)
  std::vector<Index> fixed_off_diagonal, fixed_diagonal;
  VectorXd scale, scaled;
  SupernodalCholesky<SparseMatrix> llt;
};

TangentNewton::TangentNewton(const MatrixX3i& F, Index vertices, const std::vector<Index>& fixed,
                             std::function<void()> tick)
    : F_(F), fixed_(std::size_t(vertices), 0), bases_(std::size_t(vertices)), gradient_(VectorXd::Zero(2 * vertices)),
      solver_(std::make_shared<Solver>()), tick_(std::move(tick)) {
  for (const Index v : fixed) {
    PM_REQUIRE(v >= 0 && v < vertices, InvalidInputError, "fixed vertex ", v, " out of range");
    fixed_[std::size_t(v)] = 1;
  }
  Solver& s = *solver_;
  const Index faces = Index(F.rows());
  auto global = [&](Index f, int local) { return 2 * F(f, local / 2) + local % 2; };
  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(std::size_t(faces) * 21 + std::size_t(vertices) * 3);
  for (Index f = 0; f < faces; ++f)
    for (int r = 0; r < 6; ++r)
      for (int c = 0; c < 6; ++c)
        if (global(f, r) >= global(f, c)) entries.emplace_back(global(f, r), global(f, c), 0.0);
  for (Index v = 0; v < vertices; ++v)
    for (auto [r, c] : {std::pair{0, 0}, {1, 0}, {1, 1}}) entries.emplace_back(2 * v + r, 2 * v + c, 0.0);
  s.A.resize(2 * vertices, 2 * vertices);
  s.A.setFromTriplets(entries.begin(), entries.end());
  s.A.makeCompressed();
  const Index* outer = s.A.outerIndexPtr();
  const Index* inner = s.A.innerIndexPtr();
  auto slot = [&](Index r, Index c) {
    return Index(std::lower_bound(inner + outer[c], inner + outer[c + 1], r) - inner);
  };
  s.face_slot.resize(std::size_t(faces) * 36);
  for (Index f = 0; f < faces; ++f)
    for (int r = 0; r < 6; ++r)
      for (int c = 0; c < 6; ++c)
        s.face_slot[36 * std::size_t(f) + 6 * r + c] = global(f, r) >= global(f, c) ? slot(global(f, r), global(f, c)) : -1;
  s.diagonal_slot.resize(std::size_t(vertices) * 3);
  for (Index v = 0; v < vertices; ++v) {
    s.diagonal_slot[3 * v] = slot(2 * v, 2 * v);
    s.diagonal_slot[3 * v + 1] = slot(2 * v + 1, 2 * v);
    s.diagonal_slot[3 * v + 2] = slot(2 * v + 1, 2 * v + 1);
  }
  for (Index c = 0; c < 2 * vertices; ++c)
    for (Index k = outer[c]; k < outer[c + 1]; ++k) {
      if (!fixed_[std::size_t(c / 2)] && !fixed_[std::size_t(inner[k] / 2)]) continue;
      (inner[k] == c ? s.fixed_diagonal : s.fixed_off_diagonal).push_back(k);
    }
  s.llt.cholmod().print = 0;  // a singular try is handled (shifted), not news
  // Fill-reducing ordering: the one of AMD and METIS with the smaller factor
  // (CHOLMOD compares them). pair20k's Suzanne: METIS 1.10M nonzeros and
  // 1.4e8 flops per factorization against AMD's 1.23M and 2.3e8 (58 against
  // 69 ms); spot: AMD's 0.24M against METIS's 0.26M.
  s.llt.cholmod().nmethods = 2;
  s.llt.cholmod().method[0].ordering = CHOLMOD_AMD;
  s.llt.cholmod().method[1].ordering = CHOLMOD_METIS;
  s.llt.cholmod().postorder = 1;
  report_while([solver = solver_] { solver->llt.analyze(solver->A); }, tick_);
  s.scale.resize(2 * vertices);
  s.scaled.resize(s.A.nonZeros());
}

TangentNewton::~TangentNewton() = default;

void TangentNewton::begin(const MatrixX3d& X) {
  const Index vertices = Index(fixed_.size());
#pragma omp parallel for schedule(static) if (worth_parallel(vertices))
  for (Index v = 0; v < vertices; ++v) bases_[std::size_t(v)] = tangent_basis(X.row(v).transpose());
  std::fill(solver_->A.valuePtr(), solver_->A.valuePtr() + solver_->A.nonZeros(), 0.0);
  gradient_.setZero();
}

void TangentNewton::add_face(Index f, const Vec6& gradient, const Mat6& hessian) {
  for (int k = 0; k < 3; ++k) gradient_.segment<2>(2 * F_(f, k)) += gradient.segment<2>(2 * k);
  const Index* slot = solver_->face_slot.data() + 36 * std::size_t(f);
  double* values = solver_->A.valuePtr();
  for (int k = 0; k < 36; ++k)
    if (slot[k] >= 0) values[slot[k]] += hessian(k / 6, k % 6);
}

void TangentNewton::add_vertex(Index v, const Eigen::Vector2d& gradient, const Eigen::Matrix2d& hessian) {
  gradient_.segment<2>(2 * v) += gradient;
  double* values = solver_->A.valuePtr();
  values[solver_->diagonal_slot[3 * v]] += hessian(0, 0);
  values[solver_->diagonal_slot[3 * v + 1]] += hessian(1, 0);
  values[solver_->diagonal_slot[3 * v + 2]] += hessian(1, 1);
}

VectorXd TangentNewton::solve() {
  Solver& s = *solver_;
  double* values = s.A.valuePtr();
  const Index* outer = s.A.outerIndexPtr();
  const Index* inner = s.A.innerIndexPtr();
  const Index n = Index(gradient_.size()), nonzeros = Index(s.A.nonZeros());
  for (const Index k : s.fixed_off_diagonal) values[k] = 0.0;
  for (const Index k : s.fixed_diagonal) values[k] = 1.0;
  for (Index v = 0; v < Index(fixed_.size()); ++v)
    if (fixed_[std::size_t(v)]) gradient_.segment<2>(2 * v).setZero();
  // Symmetric diagonal scaling first (squeezed faces put 1/gap^2 ~ 1e26
  // beside entries of 1); a diagonal shift only for a singular system.
  for (Index c = 0; c < n; ++c) s.scale[c] = values[outer[c]] != 0 ? 1.0 / std::sqrt(std::abs(values[outer[c]])) : 1.0;
  for (Index c = 0; c < n; ++c)
    for (Index k = outer[c]; k < outer[c + 1]; ++k) values[k] *= s.scale[c] * s.scale[inner[k]];
  std::copy(values, values + nonzeros, s.scaled.data());
  // Factored beside a reporting thread, which owns the solver with this
  // object (a cancel leaves it to finish alone).
  factorizations_ += report_while(
      [solver = solver_, n, nonzeros] {
        Solver& s = *solver;
        double* values = s.A.valuePtr();
        const Index* outer = s.A.outerIndexPtr();
        int tries = 0;
        for (double tau = 0;;) {
          if (tau > 0) {
            std::copy(s.scaled.data(), s.scaled.data() + nonzeros, values);
            for (Index c = 0; c < n; ++c) values[outer[c]] += tau;
          }
          s.llt.factorize(s.A);
          ++tries;
          if (s.llt.info() == Eigen::Success) return tries;
          PM_REQUIRE(tau < 1e8, ComputeError, "no positive definite Newton system on the sphere");
          tau = tau == 0 ? 1e-10 : 8 * tau;
        }
      },
      tick_);
  return -s.scale.cwiseProduct(s.llt.solve(s.scale.cwiseProduct(gradient_)));
}

void TangentNewton::move(const MatrixX3d& X, const VectorXd& step, double t, MatrixX3d& out) const {
  for (Index v = 0; v < X.rows(); ++v) {
    if (fixed_[std::size_t(v)]) out.row(v) = X.row(v);
    else out.row(v) = (X.row(v).transpose() + t * bases_[std::size_t(v)] * step.segment<2>(2 * v)).normalized().transpose();
  }
}

}  // namespace paramorph::spherical
