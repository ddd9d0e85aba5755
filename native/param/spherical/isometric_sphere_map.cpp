#include "param/spherical/isometric_sphere_map.h"

#include <cmath>
#include <limits>
#include <vector>

#include <Eigen/Geometry>

#include "common/errors.h"
#include "common/parallel.h"
#include "param/spherical/tangent_newton.h"

namespace paramorph::spherical {

namespace {

using Vec3 = Eigen::Vector3d;
using Mat9 = Eigen::Matrix<double, 9, 9>;
using Vec9 = Eigen::Matrix<double, 9, 1>;
constexpr double kInfinity = std::numeric_limits<double>::infinity();

/// One face: E = D (1 + 4 A^2 / d^2), D = sum_k c_k |e_k|^2 / 2 the
/// Dirichlet energy of the map from the rest triangle (area A, cotangents c)
/// to the chord triangle x, d = det(x0, x1, x2) (twice its area for a small
/// face, and 0 for a face spanning a great circle, however long its sides):
/// A (|J|^2 + |J^-1|^2). +inf when the face is turned over or degenerate.
double face_energy(const double* c, double area, const Vec3 x[3], Vec9* g) {
  const Vec3 cross[3] = {x[1].cross(x[2]), x[2].cross(x[0]), x[0].cross(x[1])};  // d det / d x_k
  const double det = x[0].dot(cross[0]);
  if (!(det > 0)) return kInfinity;
  double D = 0;
  for (int k = 0; k < 3; ++k) D += 0.5 * c[k] * (x[(k + 2) % 3] - x[(k + 1) % 3]).squaredNorm();
  const double q = 4 * area * area / (det * det);
  if (g) {
    Vec3 dD[3] = {Vec3::Zero(), Vec3::Zero(), Vec3::Zero()};
    for (int k = 0; k < 3; ++k) {
      const int a = (k + 1) % 3, b = (k + 2) % 3;
      dD[a] += c[k] * (x[a] - x[b]);
      dD[b] += c[k] * (x[b] - x[a]);
    }
    for (int j = 0; j < 3; ++j) g->segment<3>(3 * j) = dD[j] * (1 + q) - (2 * D * q / det) * cross[j];
  }
  return D * (1 + q);
}

Vec3 corner(const MatrixX3d& X, const MatrixX3i& F, Index f, int k) { return X.row(F(f, k)).transpose(); }

}  // namespace

IsometricSphereRest isometric_sphere_rest(const MatrixX3d& V, const MatrixX3i& F, double area_scale) {
  IsometricSphereRest rest;
  rest.cotangents.resize(F.rows(), 3);
  rest.area.resize(F.rows());
  for (Index f = 0; f < F.rows(); ++f) {
    const Vec3 p[3] = {corner(V, F, f, 0), corner(V, F, f, 1), corner(V, F, f, 2)};
    const double doubled = (p[1] - p[0]).cross(p[2] - p[0]).norm();
    rest.area[f] = 0.5 * doubled;
    for (int k = 0; k < 3; ++k) {
      const Vec3 u = p[(k + 1) % 3] - p[k], v = p[(k + 2) % 3] - p[k];
      rest.cotangents(f, k) = u.dot(v) / doubled;  // scale-free
    }
  }
  const double total = rest.area.sum();
  PM_REQUIRE(total > 0 && std::isfinite(total) && (rest.area.array() > 0).all(), InvalidInputError,
             "isometric sphere map: the mesh has degenerate faces");
  rest.area *= area_scale > 0 ? area_scale : 4 * M_PI / total;
  return rest;
}

double isometric_sphere_energy(const IsometricSphereRest& rest, const MatrixX3i& F, const MatrixX3d& X,
                               MatrixX3d* gradient) {
  if (gradient) gradient->setZero(X.rows(), 3);
  double energy = 0;
  for (Index f = 0; f < F.rows(); ++f) {
    const Vec3 x[3] = {corner(X, F, f, 0), corner(X, F, f, 1), corner(X, F, f, 2)};
    Vec9 g;
    const double e = face_energy(rest.cotangents.row(f).data(), rest.area[f], x, gradient ? &g : nullptr);
    if (!std::isfinite(e)) return kInfinity;
    energy += e;
    if (gradient)
      for (int k = 0; k < 3; ++k) gradient->row(F(f, k)) += g.segment<3>(3 * k).transpose();
  }
  return energy;
}

VectorXd isometric_face_ratios(const IsometricSphereRest& rest, const MatrixX3i& F, const MatrixX3d& X) {
  VectorXd ratio(F.rows());
#pragma omp parallel for schedule(static) if (worth_parallel(F.rows()))
  for (Index f = 0; f < F.rows(); ++f) {
    const Vec3 x[3] = {corner(X, F, f, 0), corner(X, F, f, 1), corner(X, F, f, 2)};
    ratio[f] = face_energy(rest.cotangents.row(f).data(), rest.area[f], x, nullptr) / (4 * rest.area[f]);
  }
  return ratio;
}

IsometricSphereResult isometric_sphere_map(const MatrixX3d& V, const MatrixX3i& F, const MatrixX3d& start,
                                           const IsometricSphereOptions& o, ProgressWindow progress) {
  PM_REQUIRE(start.rows() == V.rows() && start.allFinite(), InvalidInputError,
             "start must be a finite (", V.rows(), ", 3) array");
  PM_REQUIRE(o.max_steps >= 0 && std::isfinite(o.tol) && o.tol > 0, InvalidInputError,
             "max_steps >= 0 and tol > 0");
  PM_REQUIRE(std::isfinite(o.area_scale) && o.area_scale >= 0, InvalidInputError, "area_scale must be >= 0");
  const IsometricSphereRest rest = isometric_sphere_rest(V, F, o.area_scale);
  const Index faces = Index(F.rows()), vertices = Index(V.rows());
  IsometricSphereResult result;
  // Rows already unit (to rounding) are kept bit for bit: a fixed vertex
  // (a pin) must stay exactly where it was given.
  result.positions = start;
  for (Index v = 0; v < start.rows(); ++v)
    if (std::abs(start.row(v).norm() - 1) > 1e-12) result.positions.row(v).normalize();
  MatrixX3d& X = result.positions;
  const double minimum = 4 * rest.area.sum();  // every face at E_f = 4 A_f: an isometry
  // Faces in parallel, summed in order: the same energy, so the same steps
  // and the same map, on every run.
  VectorXd face_energies(faces);
  auto energy_of = [&](const MatrixX3d& Y) {
#pragma omp parallel for schedule(static) if (worth_parallel(faces))
    for (Index f = 0; f < faces; ++f) {
      const Vec3 x[3] = {corner(Y, F, f, 0), corner(Y, F, f, 1), corner(Y, F, f, 2)};
      face_energies[f] = face_energy(rest.cotangents.row(f).data(), rest.area[f], x, nullptr);
    }
    double total = 0;
    for (Index f = 0; f < faces; ++f) total += face_energies[f];
    return std::isfinite(total) ? total : kInfinity;
  };
  double energy = energy_of(X);
  PM_REQUIRE(std::isfinite(energy), InvalidInputError,
             "isometric sphere map: the start has faces turned over or degenerate");
  result.start_energy = energy / minimum;

  int step = 0;  // (for the reports while the analysis and factorisations run)
  std::function<void()> tick;
  if (progress.active())
    tick = [&] { progress.report(double(step) / std::max(1, o.max_steps), "isometric sphere map: factor"); };
  TangentNewton newton(F, vertices, o.fixed, tick);
  std::vector<Mat6> face_hessian(static_cast<std::size_t>(faces));
  std::vector<Vec6> face_gradient(static_cast<std::size_t>(faces));
  MatrixX3d trial(vertices, 3);
  for (; step < o.max_steps; ++step) {
    newton.begin(X);
    // Per face: the Euclidean Hessian by central differences of the exact
    // gradient, then in the corners' tangent coordinates,
    // T^T H T - (x . g) I on the diagonal blocks (the renormalisation's
    // curvature), projected positive semi-definite.
#pragma omp parallel for schedule(static) if (worth_parallel(faces))
    for (Index f = 0; f < faces; ++f) {
      const double* c = rest.cotangents.row(f).data();
      Vec3 x[3] = {corner(X, F, f, 0), corner(X, F, f, 1), corner(X, F, f, 2)};
      Vec9 g;
      face_energy(c, rest.area[f], x, &g);
      const double h = 1e-7 * std::sqrt((x[1] - x[0]).squaredNorm() + (x[2] - x[1]).squaredNorm() +
                                        (x[0] - x[2]).squaredNorm());
      Mat9 H;
      for (int j = 0; j < 9; ++j) {
        Vec9 plus, minus;
        const double saved = x[j / 3][j % 3];
        x[j / 3][j % 3] = saved + h;
        const double ep = face_energy(c, rest.area[f], x, &plus);
        x[j / 3][j % 3] = saved - h;
        const double em = face_energy(c, rest.area[f], x, &minus);
        x[j / 3][j % 3] = saved;
        H.col(j) = std::isfinite(ep) && std::isfinite(em) ? Vec9((plus - minus) / (2 * h)) : Vec9::Zero();
      }
      H = 0.5 * (H + H.transpose()).eval();
      Mat6 Ht;
      Vec6 gt;
      for (int k = 0; k < 3; ++k) {
        const Mat32& Tk = newton.basis(F(f, k));
        gt.segment<2>(2 * k) = Tk.transpose() * g.segment<3>(3 * k);
        for (int l = 0; l < 3; ++l) Ht.block<2, 2>(2 * k, 2 * l) = Tk.transpose() * H.block<3, 3>(3 * k, 3 * l) * newton.basis(F(f, l));
        Ht.block<2, 2>(2 * k, 2 * k) -= x[k].dot(g.segment<3>(3 * k)) * Eigen::Matrix2d::Identity();
      }
      face_gradient[std::size_t(f)] = gt;
      face_hessian[std::size_t(f)] = project_psd(Ht);
    }
    for (Index f = 0; f < faces; ++f) newton.add_face(f, face_gradient[std::size_t(f)], face_hessian[std::size_t(f)]);
    const VectorXd direction = newton.solve();
    const double decrement = -newton.gradient().dot(direction);
    if (!(decrement > o.tol * energy)) {
      result.converged = true;
      break;
    }
    double t = 1.0, next = kInfinity;
    for (int k = 0; k < 60; ++k, t *= 0.5) {
      newton.move(X, direction, t, trial);
      next = energy_of(trial);
      if (next <= energy - 1e-4 * t * decrement) break;
    }
    if (!(next <= energy - 1e-4 * t * decrement)) {
      result.converged = true;  // no descent left to rounding
      break;
    }
    X.swap(trial);
    energy = next;
    ++result.steps;
    progress.report(double(step + 1) / o.max_steps, "isometric sphere map");
  }
  result.factorizations = newton.factorizations();
  result.energy = energy / minimum;
  return result;
}

}  // namespace paramorph::spherical
