// RBF interpolation of (5.1)/(5.2), factored once (paste/rbf_interpolator.h).
#include "paste/rbf_interpolator.h"

#include <Eigen/QR>
#include <algorithm>
#include <cmath>

#include "common/errors.h"

namespace paramorph::paste {

namespace {

Index polynomial_term_count(int degree, Index d) {
  switch (degree) {
    case -1: return 0;
    case 0: return 1;
    case 1: return d + 1;
    default: return (d + 1) * (d + 2) / 2;
  }
}

/// Monomials of degree <= `degree` at x (normalized): 1, x_k, x_k x_l (k <= l).
void monomials(const double* x, Index d, int degree, double* out, Index stride) {
  if (degree < 0) return;
  Index t = 0;
  out[stride * t++] = 1.0;
  if (degree >= 1)
    for (Index k = 0; k < d; ++k) out[stride * t++] = x[k];
  if (degree >= 2)
    for (Index k = 0; k < d; ++k)
      for (Index l = k; l < d; ++l) out[stride * t++] = x[k] * x[l];
}

bool all_finite(const Eigen::MatrixXd& m) { return m.allFinite(); }

}  // namespace

RbfBasis parse_rbf_basis(const std::string& name) {
  if (name == "polyharmonic") return RbfBasis::Polyharmonic;
  if (name == "wendland") return RbfBasis::Wendland;
  throw InvalidInputError("basis must be \"polyharmonic\" or \"wendland\", got \"" + name + "\"");
}

RbfInterpolator::RbfInterpolator(const Eigen::MatrixXd& centres, const RbfOptions& options)
    : options_(options) {
  const Index n = Index(centres.rows()), d = Index(centres.cols());
  PM_REQUIRE(d == 2 || d == 3, InvalidInputError, "RBF centres must be N by 2 or N by 3, got ", n,
             " by ", d);
  PM_REQUIRE(all_finite(centres), InvalidInputError, "RBF centres have non-finite coordinates");
  const int degree = options.polynomial_degree;
  if (options.basis == RbfBasis::Polyharmonic) {
    PM_REQUIRE(degree == 1 || degree == 2, InvalidInputError,
               "the polyharmonic basis r^3 needs a polynomial of degree 1 or 2, got ", degree);
  } else {
    PM_REQUIRE(degree >= -1 && degree <= 2, InvalidInputError,
               "polynomial_degree must be -1 (none), 0, 1 or 2, got ", degree);
    PM_REQUIRE(std::isfinite(options.support_radius) && options.support_radius > 0.0,
               InvalidInputError, "the Wendland basis needs a support_radius > 0, got ",
               options.support_radius);
  }
  polynomial_terms_ = polynomial_term_count(degree, d);
  PM_REQUIRE(n >= std::max<Index>(1, polynomial_terms_), InvalidInputError, "RBF needs at least ",
             std::max<Index>(1, polynomial_terms_), " centres for a polynomial of degree ", degree,
             ", got ", n);

  // Map the centres into the unit ball around their centroid: r^3 + p and
  // Wendland(r/h) span the same functions in any units, and the conditioning
  // test below then does not depend on them.
  shift_ = centres.colwise().mean();
  scale_ = (centres.rowwise() - shift_).rowwise().norm().maxCoeff();
  if (!(scale_ > 0.0)) scale_ = 1.0;  // one centre (or all equal: caught below)
  centres_ = normalized(centres);
  support_ = options.support_radius / scale_;

  // Coincident centres make two equal rows: name them rather than report a
  // singular matrix. O(N^2), the same as filling Phi.
  const double tiny = 1e-12;
  for (Index i = 0; i < n; ++i)
    for (Index j = i + 1; j < n; ++j)
      PM_REQUIRE((centres_.row(i) - centres_.row(j)).norm() > tiny, InvalidInputError,
                 "RBF centres ", i, " and ", j, " coincide");

  const Index size = n + polynomial_terms_;
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(size, size);
  for (Index i = 0; i < n; ++i) fill_row(centres_.row(i).data(), &A(i, 0), size);
  // fill_row wrote row i of [Phi P] (column-major: stride = size); mirror P.
  A.bottomLeftCorner(polynomial_terms_, n) = A.topRightCorner(n, polynomial_terms_).transpose();

  if (polynomial_terms_ > 0) {
    // Unisolvent: only the zero polynomial of this degree vanishes at every centre.
    Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(A.topRightCorner(n, polynomial_terms_));
    qr.setThreshold(1e-10);
    PM_REQUIRE(qr.rank() == polynomial_terms_, InvalidInputError,
               "RBF centres are not unisolvent for a polynomial of degree ", degree,
               " (P has rank ", qr.rank(), " of ", polynomial_terms_,
               "; e.g. all on one line for a linear polynomial)");
  }
  lu_.compute(A);
  rcond_ = lu_.rcond();
  PM_REQUIRE(rcond_ > 1e-13 && std::isfinite(rcond_), InvalidInputError,
             "RBF system is numerically singular (reciprocal condition ", rcond_,
             "): centres nearly coincide or are nearly not unisolvent");
}

RbfInterpolator::RowMajorXd RbfInterpolator::normalized(const Eigen::MatrixXd& points) const {
  return (points.rowwise() - shift_) / scale_;
}

void RbfInterpolator::fill_row(const double* x, double* row, Index stride) const {
  const Index n = num_centres(), d = dimension();
  for (Index j = 0; j < n; ++j) {
    double r2 = 0.0;
    for (Index k = 0; k < d; ++k) {
      const double t = x[k] - centres_(j, k);
      r2 += t * t;
    }
    const double r = std::sqrt(r2);
    double phi;
    if (options_.basis == RbfBasis::Polyharmonic) {
      phi = r2 * r;
    } else {
      const double q = r / support_;
      const double t = 1.0 - q, t2 = t * t;
      phi = q < 1.0 ? t2 * t2 * (4.0 * q + 1.0) : 0.0;
    }
    row[stride * j] = phi;
  }
  monomials(x, d, options_.polynomial_degree, row + stride * n, stride);
}

Eigen::MatrixXd RbfInterpolator::solve(const Eigen::MatrixXd& values) const {
  const Index n = num_centres();
  PM_REQUIRE(values.rows() == n, InvalidInputError, "RBF values must have one row per centre (",
             n, "), got ", values.rows());
  PM_REQUIRE(all_finite(values), InvalidInputError, "RBF values have non-finite entries");
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(n + polynomial_terms_, values.cols());
  rhs.topRows(n) = values;
  return lu_.solve(rhs);
}

RbfInterpolator::RowMajorXd RbfInterpolator::evaluation_matrix(const Eigen::MatrixXd& points) const {
  PM_REQUIRE(points.cols() == dimension(), InvalidInputError, "RBF points must be M by ",
             dimension(), ", got M by ", points.cols());
  PM_REQUIRE(all_finite(points), InvalidInputError, "RBF points have non-finite coordinates");
  const RowMajorXd X = normalized(points);
  const Index m = Index(X.rows()), size = num_centres() + polynomial_terms_;
  RowMajorXd E(m, size);  // one point's row is contiguous while filling
#pragma omp parallel for schedule(static) if (Index(m) * size > 100000)
  for (Index i = 0; i < m; ++i) fill_row(X.row(i).data(), E.row(i).data(), 1);
  return E;
}

Eigen::MatrixXd RbfInterpolator::evaluate(const Eigen::MatrixXd& points,
                                          const Eigen::MatrixXd& coefficients) const {
  PM_REQUIRE(coefficients.rows() == num_centres() + polynomial_terms_, InvalidInputError,
             "RBF coefficients must have N + P = ", num_centres() + polynomial_terms_,
             " rows, got ", coefficients.rows());
  return evaluation_matrix(points) * coefficients;
}

}  // namespace paramorph::paste
