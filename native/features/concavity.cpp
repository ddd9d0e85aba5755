// Concavity intensity (features/concavity.h): Qhull for the hull, a Morton
// tree over the vertices to prune facets for the distance.
#include "features/concavity.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <memory>
#include <numeric>

#include "common/errors.h"
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

/// Spreads the low 21 bits of x so that two zero bits follow each one.
std::uint64_t spread_bits(std::uint64_t x) {
  x &= 0x1fffff;
  x = (x | x << 32) & 0x1f00000000ffffULL;
  x = (x | x << 16) & 0x1f0000ff0000ffULL;
  x = (x | x << 8) & 0x100f00f00f00f00fULL;
  x = (x | x << 4) & 0x10c30c30c30c30c3ULL;
  x = (x | x << 2) & 0x1249249249249249ULL;
  return x;
}

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

/// The recursive pruning. For a node of points with bounding-sphere centre c
/// and radius r, s_i = h_i - n_i · c is facet i's distance at the centre, so
/// every point p of the node has s_i - r <= h_i - n_i · p <= s_i + r. With
/// m = min_i s_i, every point's minimum is <= m + r, and a facet with
/// s_i - r > m + r can be the minimum of none of them: it is dropped. Children
/// start from their parent's survivors.
class PlaneTree {
 public:
  PlaneTree(const SortedPoints& points, const Planes& planes, double slack, VectorXd& out)
      : p_(points), planes_(planes), slack_(slack), out_(out) {}

  void descend(Index lo, Index hi, const std::vector<Index>& candidates) {
    // Bounding sphere: box centre, farthest point.
    double lo_x = p_.x[lo], hi_x = lo_x, lo_y = p_.y[lo], hi_y = lo_y, lo_z = p_.z[lo], hi_z = lo_z;
    for (Index k = lo + 1; k < hi; ++k) {
      lo_x = std::min(lo_x, p_.x[k]), hi_x = std::max(hi_x, p_.x[k]);
      lo_y = std::min(lo_y, p_.y[k]), hi_y = std::max(hi_y, p_.y[k]);
      lo_z = std::min(lo_z, p_.z[k]), hi_z = std::max(hi_z, p_.z[k]);
    }
    const double cx = 0.5 * (lo_x + hi_x), cy = 0.5 * (lo_y + hi_y), cz = 0.5 * (lo_z + hi_z);
    double r2 = 0.0;
    for (Index k = lo; k < hi; ++k) {
      const double dx = p_.x[k] - cx, dy = p_.y[k] - cy, dz = p_.z[k] - cz;
      r2 = std::max(r2, dx * dx + dy * dy + dz * dz);
    }
    const double r = std::sqrt(r2);

    const Index count = Index(candidates.size());
    std::vector<double> s(count);
    double m = std::numeric_limits<double>::infinity();
    const double *nx = planes_.nx.data(), *ny = planes_.ny.data(), *nz = planes_.nz.data(),
                 *h = planes_.h.data();
    for (Index k = 0; k < count; ++k) {
      const Index i = candidates[k];
      s[k] = h[i] - (nx[i] * cx + ny[i] * cy + nz[i] * cz);
      m = std::min(m, s[k]);
    }
    const double keep_below = m + 2.0 * r + slack_;
    std::vector<Index> kept;
    kept.reserve(count);
    for (Index k = 0; k < count; ++k)
      if (s[k] <= keep_below) kept.push_back(candidates[k]);

    if (hi - lo <= kLeafSize) {
      leaf(lo, hi, kept);
      return;
    }
    const Index mid = lo + (hi - lo) / 2;
    descend(lo, mid, kept);
    descend(mid, hi, kept);
  }

 private:
  void leaf(Index lo, Index hi, const std::vector<Index>& kept) {
    const Index count = Index(kept.size());
    gx_.resize(count), gy_.resize(count), gz_.resize(count), gh_.resize(count);
    for (Index k = 0; k < count; ++k) {
      const Index i = kept[k];
      gx_[k] = planes_.nx[i], gy_[k] = planes_.ny[i], gz_[k] = planes_.nz[i], gh_[k] = planes_.h[i];
    }
    const double *nx = gx_.data(), *ny = gy_.data(), *nz = gz_.data(), *h = gh_.data();
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
  std::vector<double> gx_, gy_, gz_, gh_;  // a leaf's planes, gathered
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

  QuietFile quiet;
  QhullRun run(quiet.get());
  qhT* qh = run.get();       // the name the FORALL macros expect
  char options[] = "qhull";  // defaults: coplanar facets merged (C-0), no output
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
    keyed[k] = {spread_bits(std::uint64_t(q[0])) | spread_bits(std::uint64_t(q[1])) << 1 |
                    spread_bits(std::uint64_t(q[2])) << 2,
                k};
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
  // Independent chunks of consecutive (Morton-sorted) points, one tree each.
  const Index chunks = std::max<Index>(1, std::min<Index>(256, n / (32 * kLeafSize)));
#pragma omp parallel for schedule(dynamic, 1)
  for (Index c = 0; c < chunks; ++c) {
    const Index begin = Index(std::int64_t(n) * c / chunks);
    const Index end = Index(std::int64_t(n) * (c + 1) / chunks);
    PlaneTree tree(sorted, planes, slack, out);
    if (end > begin) tree.descend(begin, end, all);
  }
  return out;
}

VectorXd concavity(const MatrixX3d& V, const MatrixX3i& F) {
  validate_arrays(V, F);
  const ConvexHull hull = convex_hull(V);
  VectorXd I = depth_below_planes(V, hull).cwiseMax(0.0);
  for (Index v : hull.vertices) I[v] = 0.0;  // on the hull, whatever the merged planes' rounding
  return I;
}

}  // namespace paramorph::features
