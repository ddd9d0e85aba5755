// Closest points on a triangle mesh through CGAL's AABB tree (mesh/closest_points.h).
#include "mesh/closest_points.h"

#include "common/parallel.h"

#include <Eigen/Geometry>
#include <cmath>
#include <vector>

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include "common/errors.h"

namespace paramorph {

namespace {
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Triangle = Kernel::Triangle_3;
using Iterator = std::vector<Triangle>::const_iterator;
using Primitive = CGAL::AABB_triangle_primitive<Kernel, Iterator>;
using AabbTree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive>>;
}  // namespace

struct ClosestPointTree::Tree {
  std::vector<Triangle> triangles;
  std::vector<Index> face;      ///< per triangle, its face of F
  std::vector<Index> triangle;  ///< per face of F, its triangle (-1: degenerate, skipped)
  AabbTree tree;
};

ClosestPointTree::ClosestPointTree(const MatrixX3d& V, const MatrixX3i& F)
    : tree_(std::make_unique<Tree>()), F_(F) {
  PM_REQUIRE(V.allFinite() && F.rows() > 0, InvalidInputError, "closest points need a finite mesh with faces");
  // Squared lengths and the projections of a closest-point construction
  // overflow (or underflow) far short of double's range; a power of two
  // brings the largest coordinate into [1, 2) without rounding anything.
  const double largest = V.size() ? V.cwiseAbs().maxCoeff() : 0.0;
  if (largest > 0) scale_ = std::ldexp(1.0, -std::ilogb(largest));
  V_ = V * scale_;
  auto point = [this](Index v) { return Point(V_(v, 0), V_(v, 1), V_(v, 2)); };
  for (Index f = 0; f < Index(F.rows()); ++f) {
    PM_REQUIRE((F.row(f).array() >= 0).all() && (F.row(f).array() < V.rows()).all(), InvalidInputError,
               "face ", f, " has a vertex index out of range");
    const Triangle t(point(F(f, 0)), point(F(f, 1)), point(F(f, 2)));
    tree_->triangle.push_back(-1);
    // A sliver whose normal's squared length is below 1e-150 (coordinates in
    // [1, 2)) is degenerate to any rounding, and CGAL's projection onto its
    // plane divides by that length: inf and NaN, then GMP aborts on NaN.
    const Eigen::RowVector3d a = V_.row(F(f, 0));
    if (t.is_degenerate() || (V_.row(F(f, 1)) - a).cross(V_.row(F(f, 2)) - a).squaredNorm() < 1e-150) continue;
    tree_->triangle.back() = Index(tree_->triangles.size());
    tree_->triangles.push_back(t);
    tree_->face.push_back(f);
  }
  PM_REQUIRE(!tree_->triangles.empty(), InvalidInputError, "closest points need a face of non-zero area");
  tree_->tree.insert(tree_->triangles.cbegin(), tree_->triangles.cend());
  tree_->tree.accelerate_distance_queries();
}

ClosestPointTree::~ClosestPointTree() = default;
ClosestPointTree::ClosestPointTree(ClosestPointTree&&) noexcept = default;
ClosestPointTree& ClosestPointTree::operator=(ClosestPointTree&&) noexcept = default;

ClosestPoints ClosestPointTree::query(const MatrixX3d& Q, const ClosestPoints* hint) const {
  const Index n = Index(Q.rows());
  PM_REQUIRE(!hint || (hint->face.size() == n && hint->points.rows() == n), InvalidInputError,
             "a hint must answer as many queries (", n, ")");
  ClosestPoints out{VectorXi(n), MatrixX3d(n, 3), MatrixX3d(n, 3), VectorXd(n)};
  for (Index i = 0; i < n; ++i) {
    const Eigen::RowVector3d qi = Q.row(i) * scale_;
    PM_REQUIRE(qi.allFinite() && qi.cwiseAbs().maxCoeff() <= 1e100, InvalidInputError, "closest points: query ", i,
               " (", Q(i, 0), ", ", Q(i, 1), ", ", Q(i, 2), ") is not finite or too far from the mesh");
  }
  auto answer = [&](Index i) {
    const Eigen::RowVector3d qi = Q.row(i) * scale_;
    const Point q(qi[0], qi[1], qi[2]);
    Index hinted = hint && hint->face[i] >= 0 && hint->face[i] < Index(tree_->triangle.size())
                       ? tree_->triangle[hint->face[i]] : -1;
    const auto [p, it] =
        hinted >= 0
            ? tree_->tree.closest_point_and_primitive(
                  q, std::make_pair(Point(hint->points(i, 0) * scale_, hint->points(i, 1) * scale_,
                                          hint->points(i, 2) * scale_),
                                    tree_->triangles.cbegin() + hinted))
            : tree_->tree.closest_point_and_primitive(q);
    const std::size_t t = std::size_t(it - tree_->triangles.cbegin());
    const Index f = tree_->face[t];
    const Eigen::RowVector3d x(p.x(), p.y(), p.z());
    // Barycentrics of x in its (non-degenerate) face, clamped against round-off.
    const Eigen::RowVector3d a = V_.row(F_(f, 0)), b = V_.row(F_(f, 1)), c = V_.row(F_(f, 2));
    const Eigen::RowVector3d e1 = b - a, e2 = c - a, d = x - a;
    const double d11 = e1.dot(e1), d12 = e1.dot(e2), d22 = e2.dot(e2), det = d11 * d22 - d12 * d12;
    double u = (d22 * e1.dot(d) - d12 * e2.dot(d)) / det, w = (d11 * e2.dot(d) - d12 * e1.dot(d)) / det;
    u = std::max(0.0, u), w = std::max(0.0, w);
    const double s = u + w > 1.0 ? u + w : 1.0;
    u /= s, w /= s;
    out.face[i] = f;
    out.bary.row(i) << 1.0 - u - w, u, w;
    out.points.row(i) = x / scale_;
    out.distance[i] = (x - qi).norm() / scale_;
  };
  // The first query builds the tree and its search structure (CGAL does it
  // lazily, under a lock): alone, so the other threads do not queue on that
  // lock. After it queries only read the tree, so they run in parallel, each
  // writing its own row: the same answers on any number of threads.
  if (n > 0) answer(0);
#pragma omp parallel for schedule(dynamic, 512) if (worth_parallel(n))
  for (Index i = 1; i < n; ++i) answer(i);
  return out;
}

}  // namespace paramorph
