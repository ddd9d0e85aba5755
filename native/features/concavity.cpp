// Concavity intensity (features/concavity.h): Qhull for the hull, a Morton
// tree over the vertices to prune facets for the distance.
#include "features/concavity.h"

#include <Eigen/Eigenvalues>

#include <Eigen/Dense>
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <memory>
#include <numeric>

#include "common/errors.h"
#include "common/morton.h"
#include "mesh/validate.h"

extern "C" {
#include "libqhull_r/libqhull_r.h"
}

namespace paramorph::features {

namespace {

/// A scratch FILE for Qhull's messages: Qhull must never print to the user's
/// console (Blender's terminal). tmpfile() is standard C; the null device is
/// the fallback where no temporary file can be made.
class QuietFile {
 public:
  QuietFile() {
    file_ = std::tmpfile();
#ifdef _WIN32
    if (!file_) file_ = std::fopen("NUL", "w");
#else
    if (!file_) file_ = std::fopen("/dev/null", "w");
#endif
    if (!file_)
      throw std::runtime_error("convex hull: cannot open a scratch file for Qhull's messages");
  }
  ~QuietFile() {
    std::fclose(file_);
  }
  QuietFile(const QuietFile&) = delete;
  QuietFile& operator=(const QuietFile&) = delete;
  FILE* get() const {
    return file_;
  }

 private:
  FILE* file_ = nullptr;
};

/// One reentrant Qhull instance, freed however we leave the scope.
class QhullRun {
 public:
  explicit QhullRun(FILE* errfile) : qh_(std::make_unique<qhT>()) { qh_zero(qh_.get(), errfile); }
  ~QhullRun() {
    int curlong = 0, totlong = 0;
    qh_freeqhull(qh_.get(), !qh_ALL);
    qh_memfreeshort(qh_.get(), &curlong, &totlong);
  }
  QhullRun(const QhullRun&) = delete;
  QhullRun& operator=(const QhullRun&) = delete;
  qhT* get() const { return qh_.get(); }

 private:
  std::unique_ptr<qhT> qh_;
};

/// Facet planes as separate arrays (vectorizes): inside when n · p <= h.
struct Planes {
  std::vector<double> nx, ny, nz, h;
  Index size() const { return Index(h.size()); }
};

/// Points in Morton order, separate coordinate arrays, relative to the hull's origin.
struct SortedPoints {
  std::vector<double> x, y, z;
  std::vector<Index> original;  ///< sorted position -> input row
};

constexpr Index kLeafSize = 16;
constexpr Index kTaskSize = 2048;  ///< nodes with more points split into parallel tasks

/// A node's oriented bounding box: centre c, orthonormal axes a_k (its points'
/// principal directions), half extents e_k. For any unit n and any point p in
/// the box, |n · (p - c)| <= w(n) = sum_k |n · a_k| e_k. Points near the hull
/// form thin boxes, so w is small for the facets around them.
struct Box {
  Eigen::Vector3d centre;
  Eigen::Matrix3d axes;  ///< columns
  Eigen::Vector3d half;
};

Box bounding_box(const SortedPoints& p, Index lo, Index hi) {
  const double count = double(hi - lo);
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (Index k = lo; k < hi; ++k) mean += Eigen::Vector3d(p.x[k], p.y[k], p.z[k]);
  mean /= count;
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  for (Index k = lo; k < hi; ++k) {
    const Eigen::Vector3d q = Eigen::Vector3d(p.x[k], p.y[k], p.z[k]) - mean;
    scatter.noalias() += q * q.transpose();
  }
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen;
  eigen.computeDirect(scatter);
  // Any orthonormal frame gives a valid bound; make this one orthonormal to
  // rounding whatever computeDirect returned for repeated eigenvalues.
  Eigen::Vector3d a0 = eigen.eigenvectors().col(2), a1 = eigen.eigenvectors().col(1);
  if (!(a0.allFinite() && a0.norm() > 0.5)) a0 = Eigen::Vector3d::UnitX();
  a0.normalize();
  a1 -= a0.dot(a1) * a0;
  if (!(a1.allFinite() && a1.norm() > 1e-3)) a1 = a0.unitOrthogonal();
  a1.normalize();
  Box box;
  box.axes.col(0) = a0;
  box.axes.col(1) = a1;
  box.axes.col(2) = a0.cross(a1).normalized();
  Eigen::Vector3d lo_q = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d hi_q = -lo_q;
  for (Index k = lo; k < hi; ++k) {
    const Eigen::Vector3d q =
        box.axes.transpose() * (Eigen::Vector3d(p.x[k], p.y[k], p.z[k]) - mean);
    lo_q = lo_q.cwiseMin(q), hi_q = hi_q.cwiseMax(q);
  }
  box.centre = mean + box.axes * (0.5 * (lo_q + hi_q));
  box.half = 0.5 * (hi_q - lo_q);
  return box;
}

/// The recursive pruning. For a node's box and facet i, s_i = h_i - n_i · c
/// is the facet's distance at the box centre, so every point p of the node
/// has s_i - w_i <= h_i - n_i · p <= s_i + w_i. Every point's minimum is then
/// at most U = min_i (s_i + w_i), and a facet with s_i - w_i > U is the
/// minimum of none of them: it is dropped. Children start from their parent's
/// survivors; only the leaves compare points with facets one by one.
class PlaneTree {
 public:
  PlaneTree(const SortedPoints& points, const Planes& planes, double slack, VectorXd& out)
      : p_(points), planes_(planes), slack_(slack), out_(out) {}

  void descend(Index lo, Index hi, const std::vector<Index>& candidates) const {
    const Box box = bounding_box(p_, lo, hi);
    const Index count = Index(candidates.size());
    std::vector<double> low(count);
    double upper = std::numeric_limits<double>::infinity();
    const double *nx = planes_.nx.data(), *ny = planes_.ny.data(), *nz = planes_.nz.data(),
                 *h = planes_.h.data();
    const Eigen::Vector3d c = box.centre, e = box.half;
    const Eigen::Matrix3d& A = box.axes;
    for (Index k = 0; k < count; ++k) {
      const Index i = candidates[k];
      const double s = h[i] - (nx[i] * c[0] + ny[i] * c[1] + nz[i] * c[2]);
      const double w = std::abs(nx[i] * A(0, 0) + ny[i] * A(1, 0) + nz[i] * A(2, 0)) * e[0] +
                       std::abs(nx[i] * A(0, 1) + ny[i] * A(1, 1) + nz[i] * A(2, 1)) * e[1] +
                       std::abs(nx[i] * A(0, 2) + ny[i] * A(1, 2) + nz[i] * A(2, 2)) * e[2];
      low[k] = s - w;
      upper = std::min(upper, s + w);
    }
    const double keep_below = upper + slack_;
    std::vector<Index> kept;
    kept.reserve(count);
    for (Index k = 0; k < count; ++k)
      if (low[k] <= keep_below) kept.push_back(candidates[k]);
    std::vector<double>().swap(low);

    if (hi - lo <= kLeafSize) {
      leaf(lo, hi, kept);
      return;
    }
    const Index mid = lo + (hi - lo) / 2;
    if (hi - lo > kTaskSize) {
#pragma omp task default(none) shared(kept) firstprivate(lo, mid)
      descend(lo, mid, kept);
#pragma omp task default(none) shared(kept) firstprivate(mid, hi)
      descend(mid, hi, kept);
#pragma omp taskwait
    } else {
      descend(lo, mid, kept);
      descend(mid, hi, kept);
    }
  }

 private:
  void leaf(Index lo, Index hi, const std::vector<Index>& kept) const {
    const Index count = Index(kept.size());
    std::vector<double> gathered(4 * std::size_t(count));
    double *nx = gathered.data(), *ny = nx + count, *nz = ny + count, *h = nz + count;
    for (Index k = 0; k < count; ++k) {
      const Index i = kept[k];
      nx[k] = planes_.nx[i], ny[k] = planes_.ny[i], nz[k] = planes_.nz[i], h[k] = planes_.h[i];
    }
    for (Index k = lo; k < hi; ++k) {
      const double x = p_.x[k], y = p_.y[k], z = p_.z[k];
      double d = std::numeric_limits<double>::infinity();
#pragma omp simd reduction(min : d)
      for (Index j = 0; j < count; ++j) d = std::min(d, h[j] - (nx[j] * x + ny[j] * y + nz[j] * z));
      out_[p_.original[k]] = d;
    }
  }

  const SortedPoints& p_;
  const Planes& planes_;
  double slack_;
  VectorXd& out_;
};

}  // namespace

ConvexHull convex_hull(const MatrixX3d& points) {
  const Index n = Index(points.rows());
  PM_REQUIRE(points.allFinite(), InvalidInputError,
             "convex hull: the points have non-finite (NaN or inf) coordinates");
  PM_REQUIRE(n >= 4, InvalidInputError, "convex hull: ", n,
             " points span no volume; at least 4 points not in one plane are needed");
  ConvexHull hull;
  // Relative to the box centre: a mesh far from the origin keeps its precision.
  hull.origin = 0.5 * (points.colwise().minCoeff() + points.colwise().maxCoeff()).transpose();
  MatrixX3d centred = points.rowwise() - hull.origin.transpose();  // row-major: x0 y0 z0 x1 ...

  // Coincident or flat input: said plainly here, where Qhull would stop
  // with an internal error (code 5) for points all at one place.
  PM_REQUIRE(centred.cwiseAbs().maxCoeff() > 0, InvalidInputError, "convex hull: the ", n,
             " points are all at one place, so their convex hull has no volume; concavity needs a solid mesh");
  {
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> spread(centred.transpose() * centred);
    PM_REQUIRE(spread.eigenvalues()[0] > 1e-24 * spread.eigenvalues()[2], InvalidInputError, "convex hull: the ", n,
               " points lie in one plane (or on a line), so their convex hull has no volume; concavity needs a "
               "solid mesh");
  }
  QuietFile quiet;
  QhullRun run(quiet.get());
  qhT* qh = run.get();       // the name the FORALL macros expect
  // Defaults (coplanar facets merged, C-0) plus Q5: skip computing the
  // maximum outer-plane distance over all points (qh_check_maxout), which we
  // never use; about 30% of Qhull's time on smooth 50k-point blobs.
  char options[] = "qhull Q5";
  const int exitcode = qh_new_qhull(qh, 3, int(n), centred.data(), False, options,
                                    /*outfile=*/nullptr, quiet.get());
  PM_REQUIRE(exitcode != qh_ERRsingular, InvalidInputError, "convex hull: the ", n,
             " points lie in one plane (or on a line, or at one point), so their convex hull "
             "has no volume; concavity needs a solid mesh");
  PM_REQUIRE(exitcode == 0, InvalidInputError,
             "convex hull: Qhull could not build the hull of the ", n, " points (",
             exitcode == qh_ERRprec    ? "precision problem: nearly coincident or nearly flat input"
             : exitcode == qh_ERRmem   ? "out of memory"
             : exitcode == qh_ERRinput ? "invalid input"
                                       : "internal error",
             ", Qhull code ", exitcode, ")");

  Index facets = 0;
  facetT* facet;
  FORALLfacets++ facets;
  hull.normals.resize(facets, 3);
  hull.offsets.resize(facets);
  Index f = 0;
  FORALLfacets {
    const Eigen::Vector3d normal(facet->normal[0], facet->normal[1], facet->normal[2]);
    const double length = normal.norm();
    hull.normals.row(f) = (normal / length).transpose();
    hull.offsets[f] = facet->offset / length;
    ++f;
  }
  vertexT* vertex;
  FORALLvertices {
    const int id = qh_pointid(qh, vertex->point);
    if (id >= 0 && id < n) hull.vertices.push_back(Index(id));
  }
  std::sort(hull.vertices.begin(), hull.vertices.end());
  return hull;
}

VectorXd depth_below_planes(const MatrixX3d& points, const ConvexHull& hull) {
  const Index n = Index(points.rows());
  const Index facets = Index(hull.offsets.size());
  VectorXd out = VectorXd::Constant(n, std::numeric_limits<double>::infinity());
  if (n == 0 || facets == 0) return out;

  Planes planes;
  planes.nx.resize(facets), planes.ny.resize(facets), planes.nz.resize(facets),
      planes.h.resize(facets);
  for (Index f = 0; f < facets; ++f) {
    planes.nx[f] = hull.normals(f, 0), planes.ny[f] = hull.normals(f, 1);
    planes.nz[f] = hull.normals(f, 2), planes.h[f] = -hull.offsets[f];
  }

  // Morton order over the points' bounding box.
  const MatrixX3d P = points.rowwise() - hull.origin.transpose();
  const Eigen::RowVector3d lo = P.colwise().minCoeff(), hi = P.colwise().maxCoeff();
  const double extent = std::max((hi - lo).maxCoeff(), std::numeric_limits<double>::min());
  const double cells = double((1 << 21) - 1) / extent;
  std::vector<std::pair<std::uint64_t, Index>> keyed(n);
#pragma omp parallel for schedule(static)
  for (Index k = 0; k < n; ++k) {
    const Eigen::RowVector3d q = (P.row(k) - lo) * cells;
    keyed[k] = {morton_code(std::uint64_t(q[0]), std::uint64_t(q[1]), std::uint64_t(q[2])), k};
  }
  std::sort(keyed.begin(), keyed.end());
  SortedPoints sorted;
  sorted.x.resize(n), sorted.y.resize(n), sorted.z.resize(n), sorted.original.resize(n);
  for (Index k = 0; k < n; ++k) {
    const Index i = keyed[k].second;
    sorted.original[k] = i;
    sorted.x[k] = P(i, 0), sorted.y[k] = P(i, 1), sorted.z[k] = P(i, 2);
  }

  // Rounding in s_i is a few ulps of the coordinates' size: never prune on it.
  const double scale = std::max(P.cwiseAbs().maxCoeff(), hull.offsets.cwiseAbs().maxCoeff());
  const double slack = 1e-12 * scale;
  std::vector<Index> all(facets);
  std::iota(all.begin(), all.end(), Index(0));
  const PlaneTree tree(sorted, planes, slack, out);
#pragma omp parallel
#pragma omp single
  tree.descend(0, n, all);
  return out;
}

VectorXd concavity(const MatrixX3d& V, const MatrixX3i& F) {
  validate_arrays(V, F);
  const ConvexHull hull = convex_hull(V);
  // Hull vertices are at distance 0 (whatever the merged planes' rounding
  // says); only the others need the planes.
  std::vector<char> on_hull(V.rows(), 0);
  for (Index v : hull.vertices) on_hull[v] = 1;
  std::vector<Index> inside;
  inside.reserve(V.rows() - hull.vertices.size());
  for (Index v = 0; v < Index(V.rows()); ++v)
    if (!on_hull[v]) inside.push_back(v);
  MatrixX3d P(inside.size(), 3);
  for (std::size_t k = 0; k < inside.size(); ++k) P.row(Index(k)) = V.row(inside[k]);
  const VectorXd depth = depth_below_planes(P, hull);
  VectorXd I = VectorXd::Zero(V.rows());
  for (std::size_t k = 0; k < inside.size(); ++k) I[inside[k]] = std::max(0.0, depth[Index(k)]);
  return I;
}

}  // namespace paramorph::features
