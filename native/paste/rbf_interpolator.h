// Radial basis function interpolation (thesis 5.2, equations (5.1) and (5.2)):
// s(x) = sum_i w_i phi(|x - x_i|) + p(x), with the coefficients w and the
// polynomial p solving the saddle-point system [Phi P; P^T 0] [w; c] = [f; 0].
//
// A solver object (DESIGN.md §6): the system depends on the centres only, so it
// is built and LU-factored once (dense Eigen::PartialPivLU, the "Eigen LU" of
// issue 6) and every new right-hand side costs a back-substitution. Paste
// sessions move the feature by changing the values at fixed centres, and
// evaluate a fixed point set through evaluation_matrix(): one matrix product
// per update.
#pragma once

#include <Eigen/Core>
#include <Eigen/LU>
#include <string>

#include "mesh/types.h"

namespace paramorph::paste {

/// The basic function phi of (5.1).
enum class RbfBasis {
  /// phi(r) = r^3, conditionally positive definite of order 2: it needs a
  /// polynomial of degree >= 1 for the system to be solvable, so 1 or 2 only.
  Polyharmonic,
  /// Wendland's C2 function phi(r) = (1 - r/h)^4_+ (4 r/h + 1), support
  /// radius h; positive definite, so the polynomial is optional.
  Wendland,
};

struct RbfOptions {
  RbfBasis basis = RbfBasis::Polyharmonic;
  /// Degree of p(x): -1 (none; Wendland only), 0 (constant; Wendland only),
  /// 1 (linear; the default, the least the polyharmonic r^3 needs) or 2
  /// (quadratic).
  int polynomial_degree = 1;
  /// Wendland's support radius h, in the centres' units (> 0, required for
  /// Wendland); ignored by Polyharmonic.
  double support_radius = 0.0;
};

/// "polyharmonic" | "wendland" -> RbfBasis; InvalidInputError otherwise.
RbfBasis parse_rbf_basis(const std::string& name);

class RbfInterpolator {
 public:
  /// Row-major like the rest of the module boundary: numpy takes it in one copy.
  using RowMajorXd = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

  /// centres: N by d control points x_i (d = 2 or 3), pairwise distinct and
  /// unisolvent for the polynomial (not all on one line for a linear p in 2D,
  /// not on one conic for a quadratic one, ...).
  ///
  /// Throws InvalidInputError for: d not 2 or 3, non-finite coordinates, too
  /// few centres for the polynomial, two coincident centres (names them), a
  /// bad option (degree for the basis, support radius), centres that are not
  /// unisolvent (rank of P), and a system whose LU factor has an estimated
  /// reciprocal condition number below 1e-13 (nearly coincident centres).
  RbfInterpolator(const Eigen::MatrixXd& centres, const RbfOptions& options = {});

  /// values: N by m (one column per interpolated function, e.g. x, y, z of a
  /// displacement). Returns the (N + P) by m coefficients [w; c] of (5.2) by
  /// back-substitution through the stored factor. InvalidInputError for a
  /// wrong row count or non-finite values.
  Eigen::MatrixXd solve(const Eigen::MatrixXd& values) const;

  /// points: M by d. Returns the M by (N + P) matrix E with s(points) =
  /// E * coefficients, so a fixed point set is evaluated by one product.
  RowMajorXd evaluation_matrix(const Eigen::MatrixXd& points) const;

  /// s at points (M by d) for coefficients from solve(): M by m.
  Eigen::MatrixXd evaluate(const Eigen::MatrixXd& points,
                           const Eigen::MatrixXd& coefficients) const;

  Index num_centres() const { return Index(centres_.rows()); }
  Index dimension() const { return Index(centres_.cols()); }
  /// P: the number of polynomial terms (0, 1, d + 1 or (d + 1)(d + 2) / 2).
  Index num_polynomial_terms() const { return polynomial_terms_; }
  /// Estimated reciprocal condition number (L1) of the factored system.
  double rcond() const { return rcond_; }
  const RbfOptions& options() const { return options_; }

 private:
  /// Internally every point is mapped by (x - shift_) / scale_ so the centres
  /// fit the unit ball: the conditioning test is then independent of units.
  RowMajorXd normalized(const Eigen::MatrixXd& points) const;
  /// Row [phi(|x - x_j|)_j, monomials(x)] of x (normalized, d contiguous
  /// coordinates), written with the given stride between entries.
  void fill_row(const double* x, double* row, Index stride) const;

  RowMajorXd centres_;  ///< normalized, N by d
  RbfOptions options_;
  Eigen::RowVectorXd shift_;
  double scale_ = 1.0;
  double support_ = 0.0;  ///< normalized Wendland radius
  Index polynomial_terms_ = 0;
  Eigen::PartialPivLU<Eigen::MatrixXd> lu_;
  double rcond_ = 0.0;
};

}  // namespace paramorph::paste
