// Closest points on a triangle mesh through CGAL's AABB tree (mesh/closest_points.h).
#include "mesh/closest_points.h"

#include <Eigen/Geometry>
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
    : tree_(std::make_unique<Tree>()), V_(V), F_(F) {
  PM_REQUIRE(V.allFinite() && F.rows() > 0, InvalidInputError, "closest points need a finite mesh with faces");
  auto point = [&V](Index v) { return Point(V(v, 0), V(v, 1), V(v, 2)); };
  for (Index f = 0; f < Index(F.rows()); ++f) {
    PM_REQUIRE((F.row(f).array() >= 0).all() && (F.row(f).array() < V.rows()).all(), InvalidInputError,
               "face ", f, " has a vertex index out of range");
    const Triangle t(point(F(f, 0)), point(F(f, 1)), point(F(f, 2)));
    tree_->triangle.push_back(-1);
    if (t.is_degenerate()) continue;
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
    const Point q(Q(i, 0), Q(i, 1), Q(i, 2));
    Index hinted = hint && hint->face[i] >= 0 && hint->face[i] < Index(tree_->triangle.size())
                       ? tree_->triangle[hint->face[i]] : -1;
    const auto [p, it] =
        hinted >= 0
            ? tree_->tree.closest_point_and_primitive(
                  q, std::make_pair(Point(hint->points(i, 0), hint->points(i, 1), hint->points(i, 2)),
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
    out.points.row(i) = x;
    out.distance[i] = (x - Q.row(i)).norm();
  }
  return out;
}

}  // namespace paramorph
