// RBF interpolation of thesis 5.2 (paste/rbf_interpolator): interpolation at
// the centres, polynomial reproduction, Wendland's compact support, repeated
// back-substitution, typed errors.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "common/errors.h"
#include "paste/rbf_interpolator.h"

using namespace paramorph;
using namespace paramorph::paste;

namespace {

Eigen::MatrixXd random_points(Index n, Index d, unsigned seed, double scale = 1.0) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::MatrixXd X(n, d);
  for (Index i = 0; i < n; ++i)
    for (Index k = 0; k < d; ++k) X(i, k) = scale * u(rng);
  return X;
}

/// Three smooth test functions of the points (columns).
Eigen::MatrixXd smooth_values(const Eigen::MatrixXd& X) {
  Eigen::MatrixXd f(X.rows(), 3);
  for (Index i = 0; i < X.rows(); ++i) {
    const double x = X(i, 0), y = X(i, 1), z = X.cols() > 2 ? X(i, 2) : 0.0;
    f(i, 0) = std::sin(2 * x) * std::cos(y) + z;
    f(i, 1) = std::exp(-x * x - 2 * y * y);
    f(i, 2) = 3.0 + x * y * y - z * z;
  }
  return f;
}

/// A polynomial of the given degree (with all its terms) at the points.
Eigen::VectorXd polynomial(const Eigen::MatrixXd& X, int degree) {
  Eigen::VectorXd f(X.rows());
  for (Index i = 0; i < X.rows(); ++i) {
    const double x = X(i, 0), y = X(i, 1), z = X.cols() > 2 ? X(i, 2) : 0.0;
    double v = 1.5;
    if (degree >= 1) v += 2.0 * x - 0.7 * y + 0.3 * z;
    if (degree >= 2) v += 0.9 * x * x - 1.1 * x * y + 0.4 * y * y + 0.6 * y * z - 0.8 * z * z;
    f(i) = v;
  }
  return f;
}

struct Case {
  RbfBasis basis;
  int degree;
  Index d;
};

RbfOptions options_for(const Case& c) {
  RbfOptions o;
  o.basis = c.basis;
  o.polynomial_degree = c.degree;
  o.support_radius = 1.5;  // in units of the points (cube [-1, 1]^d)
  return o;
}

const Case kCases[] = {{RbfBasis::Polyharmonic, 1, 2}, {RbfBasis::Polyharmonic, 2, 2},
                       {RbfBasis::Polyharmonic, 1, 3}, {RbfBasis::Polyharmonic, 2, 3},
                       {RbfBasis::Wendland, -1, 2},    {RbfBasis::Wendland, 1, 2},
                       {RbfBasis::Wendland, 2, 3}};

}  // namespace

TEST(RbfInterpolator, InterpolatesAtTheCentres) {
  for (const Case& c : kCases) {
    for (double scale : {1e-3, 1.0, 1e3}) {
      const Eigen::MatrixXd X = random_points(150, c.d, 3, scale);
      RbfOptions o = options_for(c);
      o.support_radius *= scale;
      const RbfInterpolator rbf(X, o);
      const Eigen::MatrixXd f = smooth_values(X / scale);
      const Eigen::MatrixXd coefficients = rbf.solve(f);
      ASSERT_EQ(coefficients.rows(), 150 + rbf.num_polynomial_terms());
      const Eigen::MatrixXd s = rbf.evaluate(X, coefficients);
      EXPECT_LE((s - f).cwiseAbs().maxCoeff(), 1e-10 * f.cwiseAbs().maxCoeff())
          << "basis " << int(c.basis) << " degree " << c.degree << " d " << c.d << " scale " << scale;
    }
  }
}

TEST(RbfInterpolator, ReproducesPolynomialsOfItsDegree) {
  for (const Case& c : kCases) {
    if (c.degree < 0) continue;
    const Eigen::MatrixXd X = random_points(80, c.d, 5);
    const RbfInterpolator rbf(X, options_for(c));
    const Eigen::MatrixXd Y = random_points(200, c.d, 6) * 1.2;  // inside and just outside
    for (int degree = 0; degree <= c.degree; ++degree) {
      const Eigen::MatrixXd coefficients = rbf.solve(polynomial(X, degree));
      // The RBF weights of a reproduced polynomial vanish.
      EXPECT_LE(coefficients.topRows(80).cwiseAbs().maxCoeff(), 1e-8);
      const Eigen::VectorXd s = rbf.evaluate(Y, coefficients);
      EXPECT_LE((s - polynomial(Y, degree)).cwiseAbs().maxCoeff(), 1e-9)
          << "basis " << int(c.basis) << " degree " << c.degree << " d " << c.d
          << " reproducing degree " << degree;
    }
  }
  // A linear interpolant does not reproduce a quadratic: the test can fail.
  const Eigen::MatrixXd X = random_points(80, 2, 5);
  const RbfInterpolator linear(X, options_for({RbfBasis::Polyharmonic, 1, 2}));
  const Eigen::MatrixXd Y = random_points(200, 2, 6);
  EXPECT_GT((linear.evaluate(Y, linear.solve(polynomial(X, 2))) - polynomial(Y, 2)).cwiseAbs().maxCoeff(),
            1e-6);
}

TEST(RbfInterpolator, WendlandVanishesBeyondItsSupport) {
  const Eigen::MatrixXd X = random_points(60, 2, 9, 0.5);
  RbfOptions o;
  o.basis = RbfBasis::Wendland;
  o.polynomial_degree = -1;
  o.support_radius = 0.4;
  const RbfInterpolator rbf(X, o);
  const Eigen::MatrixXd coefficients = rbf.solve(smooth_values(X));
  // Points farther than h from every centre: exactly zero; points within: not all zero.
  const Eigen::MatrixXd Y = random_points(4000, 2, 10, 2.0);
  Index far = 0, near_nonzero = 0;
  const Eigen::MatrixXd s = rbf.evaluate(Y, coefficients);
  for (Index i = 0; i < Y.rows(); ++i) {
    const double nearest = (X.rowwise() - Y.row(i)).rowwise().norm().minCoeff();
    if (nearest >= o.support_radius) {
      ++far;
      EXPECT_EQ(s.row(i).cwiseAbs().maxCoeff(), 0.0) << "point " << i;
    } else if (s.row(i).cwiseAbs().maxCoeff() > 0.0) {
      ++near_nonzero;
    }
  }
  EXPECT_GT(far, 100);
  EXPECT_GT(near_nonzero, 100);
}

TEST(RbfInterpolator, RepeatedSolvesMatchFreshInterpolators) {
  const Eigen::MatrixXd X = random_points(120, 2, 11);
  const RbfOptions o;
  const RbfInterpolator session(X, o);
  const Eigen::MatrixXd Y = random_points(300, 2, 12);
  const Eigen::MatrixXd E = session.evaluation_matrix(Y);
  const Eigen::MatrixXd f1 = smooth_values(X);
  const Eigen::MatrixXd f2 = smooth_values(X * 0.7).array() + 2.0;
  const Eigen::MatrixXd c1 = session.solve(f1), c2 = session.solve(f2);
  const RbfInterpolator fresh1(X, o), fresh2(X, o);
  EXPECT_LE((c1 - fresh1.solve(f1)).cwiseAbs().maxCoeff(), 1e-12 * c1.cwiseAbs().maxCoeff());
  EXPECT_LE((c2 - fresh2.solve(f2)).cwiseAbs().maxCoeff(), 1e-12 * c2.cwiseAbs().maxCoeff());
  // The precomputed matrix gives what evaluate() gives.
  EXPECT_LE((E * c2 - fresh2.evaluate(Y, fresh2.solve(f2))).cwiseAbs().maxCoeff(), 1e-10);
  EXPECT_GT((E * c1 - E * c2).cwiseAbs().maxCoeff(), 1e-3);  // the two really differ
}

TEST(RbfInterpolator, TypedErrors) {
  const Eigen::MatrixXd X = random_points(30, 2, 13);
  // Coincident centres.
  Eigen::MatrixXd dup = X;
  dup.row(7) = dup.row(19);
  EXPECT_THROW(RbfInterpolator{dup}, InvalidInputError);
  // Non-finite input.
  Eigen::MatrixXd bad = X;
  bad(3, 1) = std::nan("");
  EXPECT_THROW(RbfInterpolator{bad}, InvalidInputError);
  // Collinear centres cannot determine a linear polynomial in 2D.
  Eigen::MatrixXd line(10, 2);
  for (Index i = 0; i < 10; ++i) line.row(i) << i, 2.0 * i + 1.0;
  EXPECT_THROW(RbfInterpolator{line}, InvalidInputError);
  // ... nor can 6 centres on one circle determine a quadratic.
  Eigen::MatrixXd circle(12, 2);
  for (Index i = 0; i < 12; ++i) circle.row(i) << std::cos(0.5 * i), std::sin(0.5 * i);
  RbfOptions quadratic;
  quadratic.polynomial_degree = 2;
  EXPECT_THROW(RbfInterpolator(circle, quadratic), InvalidInputError);
  EXPECT_NO_THROW(RbfInterpolator{circle});  // a circle is fine for a linear one
  // Wrong dimension, bad options.
  EXPECT_THROW(RbfInterpolator{Eigen::MatrixXd::Zero(5, 4)}, InvalidInputError);
  RbfOptions none;
  none.polynomial_degree = -1;
  EXPECT_THROW(RbfInterpolator(X, none), InvalidInputError);  // r^3 needs a polynomial
  RbfOptions wendland;
  wendland.basis = RbfBasis::Wendland;
  EXPECT_THROW(RbfInterpolator(X, wendland), InvalidInputError);  // no support radius
  // Values with the wrong row count or non-finite entries.
  const RbfInterpolator rbf(X);
  EXPECT_THROW(rbf.solve(Eigen::MatrixXd::Zero(29, 3)), InvalidInputError);
  Eigen::MatrixXd values = Eigen::MatrixXd::Zero(30, 3);
  values(0, 0) = INFINITY;
  EXPECT_THROW(rbf.solve(values), InvalidInputError);
  EXPECT_THROW(rbf.evaluation_matrix(Eigen::MatrixXd::Zero(4, 3)), InvalidInputError);
  EXPECT_THROW(parse_rbf_basis("gaussian"), InvalidInputError);
}
