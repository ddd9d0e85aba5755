#include "param/spherical/progressive_sphere_map.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include "common/errors.h"
#include "mesh/collapse_sequence.h"
#include "param/spherical/tangent_newton.h"

namespace paramorph::spherical {

namespace {

using Vec2 = Eigen::Vector2d;
using Vec3 = Eigen::Vector3d;
using Mat2 = Eigen::Matrix2d;
using Mat3 = Eigen::Matrix3d;
constexpr double kInfinity = std::numeric_limits<double>::infinity();

using Polygon = std::vector<Vec2>;

/// Sutherland-Hodgman: the part of the convex polygon where alpha + beta . q > 0.
Polygon clip(const Polygon& polygon, double alpha, const Vec2& beta) {
  Polygon out;
  const std::size_t n = polygon.size();
  for (std::size_t i = 0; i < n; ++i) {
    const Vec2& p = polygon[i];
    const Vec2& q = polygon[(i + 1) % n];
    const double sp = alpha + beta.dot(p), sq = alpha + beta.dot(q);
    if (sp > 0) out.push_back(p);
    if ((sp > 0) != (sq > 0)) out.push_back(p + (sp / (sp - sq)) * (q - p));
  }
  return out;
}

/// Area centroid of a convex polygon (its vertex mean when it is too thin).
Vec2 centroid(const Polygon& polygon) {
  double area = 0;
  Vec2 sum = Vec2::Zero(), mean = Vec2::Zero();
  for (std::size_t i = 0; i < polygon.size(); ++i) {
    const Vec2& p = polygon[i];
    const Vec2& q = polygon[(i + 1) % polygon.size()];
    const double cross = p.x() * q.y() - p.y() * q.x();
    area += cross;
    sum += cross * (p + q);
    mean += p;
  }
  mean /= double(polygon.size());
  return area > 1e-30 ? Vec2(sum / (3 * area)) : mean;
}

class Embedding {
 public:
  Embedding(const TriMesh& mesh, const CollapseSequence& sequence, const ProgressiveSphereOptions& options)
      : V_(mesh.V()), sequence_(sequence), o_(options), G_(mesh.F()) {
    const Index n = mesh.num_vertices(), m = mesh.num_faces();
    alive_.assign(std::size_t(m), 1);
    for (Index c = 0; c < Index(sequence.removed.size()); ++c) apply_collapse(sequence, c, G_, alive_);
    X_.setZero(n, 3);
    incident_.resize(std::size_t(n));
    cotangent_.setZero(m, 3);
    area_.setZero(m);
    for (const Index f : sequence.base_faces) {
      update_rest(f);
      total_area_ += area_[f];
      for (int k = 0; k < 3; ++k) incident_[std::size_t(G_(f, k))].push_back(f);
    }
    // The tetrahedron: a regular one, mirrored if its faces come out inward.
    const double s = 1 / std::sqrt(3.0);
    const Vec3 corners[4] = {{s, s, s}, {s, -s, -s}, {-s, s, -s}, {-s, -s, s}};
    for (int k = 0; k < 4; ++k) {
      const Index v = sequence.base_vertices[std::size_t(k)];
      X_.row(v) = corners[k].transpose();
      order_.push_back(v);
    }
    const Index f0 = sequence.base_faces[0];
    if (triple(f0) < 0) X_.col(0) = -X_.col(0);
  }

  void run(ProgressWindow& progress, ProgressiveSphereResult& result) {
    progress_ = &progress;
    const Index collapses = Index(sequence_.removed.size());
    Index next_level = Index(std::ceil(4 * o_.level_ratio));
    for (Index c = collapses; c-- > 0;) {
      insert(c);
      if (Index(order_.size()) >= next_level || c == 0) {
        relax_all();
        ++result.levels;
        next_level = std::max(next_level + 1, Index(std::ceil(double(order_.size()) * o_.level_ratio)));
      }
      done_ = double(collapses - c) / double(std::max<Index>(collapses, 1));
      if (c % 512 == 0) progress.report(done_, "embed coarse to fine");
    }
    result.vertex_steps = steps_;
  }

  MatrixX3d& positions() { return X_; }

 private:
  double triple(Index f) const {
    return X_.row(G_(f, 0)).dot(X_.row(G_(f, 1)).cross(X_.row(G_(f, 2))));
  }

  /// The rest triangle of face f (its corners' input positions), laid in
  /// the plane with its longest edge as base and raised, if it is a sliver,
  /// until twice its area is kSliver times its summed squared edge lengths
  /// (about 2 degrees): coarse levels join input vertices by long edges, and
  /// three nearly collinear ones would weigh without bound. A real triangle
  /// keeps the Dirichlet term non-negative (clamping cotangents does not).
  void update_rest(Index f) {
    constexpr double kSliver = 0.01;
    const Vec3 p[3] = {V_.row(G_(f, 0)), V_.row(G_(f, 1)), V_.row(G_(f, 2))};
    int base = 0;  // the longest edge runs from corner base to base + 1
    for (int k = 1; k < 3; ++k)
      if ((p[(k + 1) % 3] - p[k]).squaredNorm() > (p[(base + 1) % 3] - p[base]).squaredNorm()) base = k;
    const Vec3 e = p[(base + 1) % 3] - p[base], g = p[(base + 2) % 3] - p[base];
    const double length = e.norm();
    const double along = length > 0 ? g.dot(e) / length : 0.0;
    double height = length > 0 ? e.cross(g).norm() / length : 0.0;
    const double squares = e.squaredNorm() + g.squaredNorm() + (g - e).squaredNorm();
    height = std::max(height, kSliver * squares / std::max(length, 1e-300));
    const Vec2 q[3] = {{0, 0}, {length, 0}, {along, height}};  // corners base, base + 1, base + 2
    const double doubled = length * height;
    for (int k = 0; k < 3; ++k) {
      const Vec2 u = q[(k + 1) % 3] - q[k], v = q[(k + 2) % 3] - q[k];
      cotangent_(f, (base + k) % 3) = doubled > 0 ? u.dot(v) / doubled : 0.0;
    }
    area_[f] = 0.5 * doubled;
  }

  static int corner_of(const MatrixX3i& G, Index f, Index v) { return G(f, 0) == v ? 0 : G(f, 1) == v ? 1 : 2; }

  /// The isometric energy of vertex x's faces with x at y (+inf if one turns over).
  double energy(Index x, const Vec3& y) const {
    const double scale = 4 * M_PI / total_area_;
    double total = 0;
    for (const Index f : incident_[std::size_t(x)]) {
      const int k = corner_of(G_, f, x);
      const Vec3 a = X_.row(G_(f, (k + 1) % 3)), b = X_.row(G_(f, (k + 2) % 3));
      const double det = y.dot(a.cross(b));
      if (!(det > 0)) return kInfinity;
      const double D = 0.5 * (cotangent_(f, k) * (a - b).squaredNorm() +
                              cotangent_(f, (k + 1) % 3) * (b - y).squaredNorm() +
                              cotangent_(f, (k + 2) % 3) * (y - a).squaredNorm());
      const double A = scale * area_[f];
      total += D * (1 + 4 * A * A / (det * det));
    }
    return total;
  }

  /// Newton steps on the sphere for vertex x alone, each cut back until
  /// the energy falls (so no face of x turns over). Returns steps taken.
  int relax(Index x, int max_steps) {
    const double scale = 4 * M_PI / total_area_;
    int taken = 0;
    for (int step = 0; step < max_steps; ++step) {
      const Vec3 y = X_.row(x);
      double E = 0;
      Vec3 g = Vec3::Zero();
      Mat3 H = Mat3::Zero();
      for (const Index f : incident_[std::size_t(x)]) {
        const int k = corner_of(G_, f, x);
        const Vec3 a = X_.row(G_(f, (k + 1) % 3)), b = X_.row(G_(f, (k + 2) % 3));
        const Vec3 m = a.cross(b);
        const double det = y.dot(m);
        if (!(det > 0)) return taken;  // not from a valid map: leave it
        const double ca = cotangent_(f, (k + 1) % 3), cb = cotangent_(f, (k + 2) % 3);
        const double D = 0.5 * (cotangent_(f, k) * (a - b).squaredNorm() + ca * (b - y).squaredNorm() +
                                cb * (y - a).squaredNorm());
        const double A = scale * area_[f];
        const double q = 4 * A * A / (det * det);
        const Vec3 gD = ca * (y - b) + cb * (y - a);
        const Vec3 gq = (-2 * q / det) * m;
        E += D * (1 + q);
        g += gD * (1 + q) + D * gq;
        H += (ca + cb) * (1 + q) * Mat3::Identity() + gD * gq.transpose() + gq * gD.transpose() +
             (6 * D * q / (det * det)) * m * m.transpose();
      }
      const Mat32 T = tangent_basis(y);
      const Vec2 gt = T.transpose() * g;
      Mat2 Ht = T.transpose() * H * T - y.dot(g) * Mat2::Identity();
      Eigen::SelfAdjointEigenSolver<Mat2> eigen;
      eigen.computeDirect(Ht);  // closed form for 2 by 2
      Vec2 lambda = eigen.eigenvalues();
      const double floor = std::max(1e-12, 1e-8 * std::abs(lambda[1]));
      lambda = lambda.cwiseMax(floor);
      const Vec2 delta = -(eigen.eigenvectors() * lambda.cwiseInverse().asDiagonal() *
                           eigen.eigenvectors().transpose() * gt);
      const double decrement = -gt.dot(delta);
      if (!(decrement > 1e-12 * E)) break;
      double t = 1;
      bool moved = false;
      for (int k = 0; k < 40; ++k, t *= 0.5) {
        const Vec3 trial = (y + t * (T * delta)).normalized();
        if (energy(x, trial) <= E - 1e-4 * t * decrement) {
          X_.row(x) = trial.transpose();
          moved = true;
          break;
        }
      }
      if (!moved) break;
      ++taken;
    }
    steps_ += taken;
    return taken;
  }

  void relax_all(int sweeps = -1) {
    const Index n = Index(order_.size());
    if (sweeps < 0) sweeps = int(std::clamp(o_.level_work / double(n), double(o_.min_sweeps), double(o_.max_sweeps)));
    // A sweep over a million vertices takes a second: report within it.
    const std::string stage = "relax " + std::to_string(n) + " vertices";
    for (int sweep = 0; sweep < sweeps; ++sweep)
      for (Index k = 0; k < n; ++k) {
        relax(order_[std::size_t(k)], 1);
        if (progress_ && k % 4096 == 4095) progress_->report(done_, stage);
      }
  }

  /// Where collapse c's removed vertex goes back: the centroid of the kernel
  /// of its ring (NaN when rounding leaves no room). The kernel is found in
  /// the plane tangent at the kept vertex u (gnomonic: y = (u + T q) / |u +
  /// T q|), where det(y, r_i, r_i+1) > 0 is the half-plane
  /// u.n + (T^T n).q > 0, n = r_i x r_i+1.
  Vec3 place(Index c) const {
    const Index ring_begin = sequence_.rings.begin(c), degree = sequence_.rings.size(c);
    const Vec3 at = X_.row(sequence_.kept[std::size_t(c)]);
    const Mat32 T = tangent_basis(at);
    const double reach = 3.0;  // tan(72 degrees): the search stays in front of u
    Polygon kernel{{-reach, -reach}, {reach, -reach}, {reach, reach}, {-reach, reach}};
    std::vector<Vec3> normals;
    for (Index k = 0; k < degree && !kernel.empty(); ++k) {
      const Vec3 a = X_.row(sequence_.rings.items[ring_begin + k]);
      const Vec3 b = X_.row(sequence_.rings.items[ring_begin + (k + 1) % degree]);
      normals.push_back(a.cross(b));
      kernel = clip(kernel, at.dot(normals.back()), T.transpose() * normals.back());
    }
    const Vec3 nan = Vec3::Constant(std::numeric_limits<double>::quiet_NaN());
    if (kernel.size() < 3) return nan;
    const Vec3 y = (at + T * centroid(kernel)).normalized();
    for (const Vec3& n : normals)
      if (!(y.dot(n) > 0)) return nan;
    return y;
  }

  /// Undoes collapse c: its removed vertex goes back inside its ring.
  void insert(Index c) {
    const Index v = sequence_.removed[std::size_t(c)], u = sequence_.kept[std::size_t(c)];
    const Index ring_begin = sequence_.rings.begin(c), ring_end = sequence_.rings.end(c);
    const Index degree = ring_end - ring_begin;
    Vec3 y = place(c);
    // In exact arithmetic the kernel always has room (the collapse left u
    // inside it); in doubles a ring squeezed by many insertions nearby may
    // leave none. Relaxing the ring around u opens it again.
    // Relaxing the ring around u opens it again; where the whole level is
    // squeezed (options without sweeps), relaxing the whole level does.
    for (int attempt = 0; !y.allFinite() && attempt < 6; ++attempt) {
      if (attempt < 2) {
        relax(u, 4);
        for (Index k = ring_begin + 1; k < ring_end; ++k) relax(sequence_.rings.items[k], 2);
        relax(u, 4);
      } else {
        relax_all(std::max(4, o_.min_sweeps));
      }
      y = place(c);
    }
    PM_REQUIRE(y.allFinite(), ComputeError, "progressive sphere map: no room for vertex ", v, " inside its ring (",
               degree, " neighbours)");

    // Connectivity: v takes back its faces from u; the two across the edge return.
    const Index face_begin = sequence_.faces.begin(c), face_end = sequence_.faces.end(c);
    for (Index k = face_begin; k < face_end; ++k) {
      const Index f = sequence_.faces.items[k];
      if (alive_[std::size_t(f)]) total_area_ -= area_[f];
    }
    auto& from = incident_[std::size_t(u)];
    for (Index k = face_begin + 1; k + 1 < face_end; ++k) {
      const Index f = sequence_.faces.items[k];
      from.erase(std::find(from.begin(), from.end(), f));
    }
    undo_collapse(sequence_, c, G_, alive_);
    for (Index k = face_begin; k < face_end; ++k) {
      const Index f = sequence_.faces.items[k];
      update_rest(f);
      total_area_ += area_[f];
      incident_[std::size_t(v)].push_back(f);
    }
    for (const Index f : {sequence_.faces.items[face_begin], sequence_.faces.items[face_end - 1]})
      for (int k = 0; k < 3; ++k)
        if (G_(f, k) != v) incident_[std::size_t(G_(f, k))].push_back(f);
    X_.row(v) = y.transpose();
    order_.push_back(v);
    relax(v, o_.insert_steps);
    relax(u, 2);
    for (Index k = ring_begin + 1; k < ring_end; ++k) relax(sequence_.rings.items[k], 1);
    relax(v, 1);
  }

  const MatrixX3d& V_;
  const CollapseSequence& sequence_;
  const ProgressiveSphereOptions& o_;
  MatrixX3i G_;
  std::vector<char> alive_;
  MatrixX3d X_;
  std::vector<std::vector<Index>> incident_;
  Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> cotangent_;
  VectorXd area_;
  double total_area_ = 0;
  std::vector<Index> order_;
  long long steps_ = 0;
  ProgressWindow* progress_ = nullptr;
  double done_ = 0;  ///< share of the insertions done
};

}  // namespace

ProgressiveSphereResult progressive_sphere_map(const TriMesh& mesh, const ProgressiveSphereOptions& o,
                                               ProgressWindow progress) {
  PM_REQUIRE(o.level_ratio > 1 && std::isfinite(o.level_ratio) && o.level_work >= 0 && std::isfinite(o.level_work) &&
                 o.min_sweeps >= 1 && o.max_sweeps >= o.min_sweeps && o.insert_steps >= 1,
             InvalidInputError,
             "progressive sphere map: need level_ratio > 1, a finite level_work >= 0, 1 <= min_sweeps <= max_sweeps, "
             "insert_steps >= 1 (without relaxation, insertions squeeze each other to rounding)");
  ProgressiveSphereResult result;
  const auto t0 = std::chrono::steady_clock::now();
  progress.report(0.0, "collapse");
  const CollapseSequence sequence = collapse_sequence(mesh, progress.part(0.0, 0.25));
  const auto t1 = std::chrono::steady_clock::now();
  result.collapse_seconds = std::chrono::duration<double>(t1 - t0).count();
  result.geometric_refusals = sequence.geometric_refusals;
  Embedding embedding(mesh, sequence, o);
  ProgressWindow window = progress.part(0.25, 1.0);
  embedding.run(window, result);
  result.positions = std::move(embedding.positions());
  result.embed_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count();
  double smallest = kInfinity;
  const MatrixX3d& X = result.positions;
  const MatrixX3i& F = mesh.F();
  for (Index f = 0; f < F.rows(); ++f)
    smallest = std::min(smallest, X.row(F(f, 0)).dot(X.row(F(f, 1)).cross(X.row(F(f, 2)))));
  result.min_triple = smallest;
  return result;
}

}  // namespace paramorph::spherical
