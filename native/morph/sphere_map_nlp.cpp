#include "morph/sphere_map_nlp.h"

#include <algorithm>
#include <limits>

#include <Eigen/Geometry>

namespace paramorph::morph {

namespace {

using Vec3 = Eigen::Vector3d;

Vec3 at(const double* x, Index v) { return Vec3(x[3 * v], x[3 * v + 1], x[3 * v + 2]); }

/// E(t) with E_pq = sum_r eps_pqr t_r (= -[t]x): d^2 det(u, w, t) / du_p dw_q.
Eigen::Matrix3d mixed_block(const Vec3& t) {
  Eigen::Matrix3d E;
  E << 0, t.z(), -t.y(), -t.z(), 0, t.x(), t.y(), -t.x(), 0;
  return E;
}

}  // namespace

SphereMapNlp::SphereMapNlp(const TriMesh& mesh, MatrixX3d target)
    : vertices_(mesh.num_vertices()), faces_(mesh.num_faces()), F_(mesh.F()),
      target_(std::move(target)) {
  for (Index v = 0; v < vertices_; ++v)
    for (int d = 0; d < 3; ++d) jac_row_.push_back(v), jac_col_.push_back(3 * v + d);
  for (Index f = 0; f < faces_; ++f)
    for (int k = 0; k < 3; ++k)
      for (int d = 0; d < 3; ++d) jac_row_.push_back(vertices_ + f), jac_col_.push_back(3 * F_(f, k) + d);

  for (Index v = 0; v < vertices_; ++v)
    for (int d = 0; d < 3; ++d) hess_row_.push_back(3 * v + d), hess_col_.push_back(3 * v + d);
  edge_block_start_ = Index(hess_row_.size());
  const MatrixX2i& edges = mesh.edges();  // (a < b): block rows of b, columns of a
  for (Index e = 0; e < edges.rows(); ++e)
    for (int p = 0; p < 3; ++p)
      for (int q = 0; q < 3; ++q)
        hess_row_.push_back(3 * edges(e, 1) + p), hess_col_.push_back(3 * edges(e, 0) + q);
  face_edge_ = mesh.face_edges();
  block_from_first_.resize(faces_);
  for (Index f = 0; f < faces_; ++f)
    for (int k = 0; k < 3; ++k) block_from_first_[f][k] = F_(f, (k + 1) % 3) == edges(face_edge_(f, k), 1);
}

double SphereMapNlp::objective(const double* x) const {
  double sum = 0;
  for (Index v = 0; v < vertices_; ++v) sum += target_.row(v).dot(at(x, v));
  return -sum;
}

void SphereMapNlp::objective_gradient(const double*, double* grad) const {
  for (Index v = 0; v < vertices_; ++v)
    for (int d = 0; d < 3; ++d) grad[3 * v + d] = -target_(v, d);
}

void SphereMapNlp::constraints(const double* x, double* g) const {
  for (Index v = 0; v < vertices_; ++v) g[v] = at(x, v).squaredNorm();
  for (Index f = 0; f < faces_; ++f)
    g[vertices_ + f] = at(x, F_(f, 0)).dot(at(x, F_(f, 1)).cross(at(x, F_(f, 2))));
}

double SphereMapNlp::min_triple(const double* x) const {
  double smallest = std::numeric_limits<double>::infinity();
  for (Index f = 0; f < faces_; ++f)
    smallest = std::min(smallest, at(x, F_(f, 0)).dot(at(x, F_(f, 1)).cross(at(x, F_(f, 2)))));
  return smallest;
}

void SphereMapNlp::jacobian_values(const double* x, double* values) const {
  Index k = 0;
  for (Index v = 0; v < vertices_; ++v)
    for (int d = 0; d < 3; ++d) values[k++] = 2.0 * x[3 * v + d];
  for (Index f = 0; f < faces_; ++f) {
    const Vec3 a = at(x, F_(f, 0)), b = at(x, F_(f, 1)), c = at(x, F_(f, 2));
    const Vec3 d_of[3] = {b.cross(c), c.cross(a), a.cross(b)};
    for (const Vec3& d : d_of)
      for (int i = 0; i < 3; ++i) values[k++] = d[i];
  }
}

void SphereMapNlp::hessian_values(const double* x, double, const double* lambda,
                                  double* values) const {
  std::fill(values, values + hess_row_.size(), 0.0);
  for (Index v = 0; v < vertices_; ++v)
    for (int d = 0; d < 3; ++d) values[3 * v + d] = 2.0 * lambda[v];
  for (Index f = 0; f < faces_; ++f) {
    const double mu = lambda[vertices_ + f];
    if (mu == 0.0) continue;
    for (int k = 0; k < 3; ++k) {
      // Pair (u, w) = corners (k+1, k+2), third t = corner k: block d^2/du dw = E(t).
      const Eigen::Matrix3d E = mu * mixed_block(at(x, F_(f, k)));
      double* block = values + edge_block_start_ + 9 * face_edge_(f, k);
      for (int p = 0; p < 3; ++p)
        for (int q = 0; q < 3; ++q) block[3 * p + q] += block_from_first_[f][k] ? E(p, q) : E(q, p);
    }
  }
}

}  // namespace paramorph::morph
