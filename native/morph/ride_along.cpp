// Separate parts riding along a morphing body (morph/ride_along.h).
#include "morph/ride_along.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <string>

#include "common/best_rotation.h"
#include "common/errors.h"
#include "mesh/bounding_box_diagonal.h"
#include "mesh/closest_points.h"
#include "mesh/face_neighbors.h"
#include "mesh/tri_mesh.h"
#include "mesh/validate.h"

namespace paramorph::morph {

namespace {

/// Angle-weighted pseudonormals of a mesh: per face, per vertex, and per
/// face corner for the edge opposite it (the two faces' normals summed).
struct Pseudonormals {
  MatrixX3d face, vertex;
  MatrixX3d edge;  ///< rows 3f + k: the edge opposite corner k of face f

  Pseudonormals(const MatrixX3d& V, const MatrixX3i& F) {
    const Index nf = Index(F.rows());
    face = MatrixX3d::Zero(nf, 3);
    vertex = MatrixX3d::Zero(V.rows(), 3);
    for (Index f = 0; f < nf; ++f) {
      const Eigen::RowVector3d a = V.row(F(f, 0)), b = V.row(F(f, 1)), c = V.row(F(f, 2));
      const Eigen::RowVector3d n = (b - a).cross(c - a);
      const double length = n.norm();
      if (!(length > 0)) continue;
      face.row(f) = n / length;
      for (int k = 0; k < 3; ++k) {
        const Eigen::RowVector3d p = V.row(F(f, k));
        const Eigen::RowVector3d u = V.row(F(f, (k + 1) % 3)) - p, w = V.row(F(f, (k + 2) % 3)) - p;
        const double angle = std::atan2(u.cross(w).norm(), u.dot(w));
        vertex.row(F(f, k)) += angle * face.row(f);
      }
    }
    const MatrixX3i across = face_neighbors(TriMesh(V, F));
    edge = MatrixX3d::Zero(3 * nf, 3);
    for (Index f = 0; f < nf; ++f)
      for (int k = 0; k < 3; ++k)
        edge.row(3 * f + k) = face.row(f) + (across(f, k) >= 0 ? Eigen::RowVector3d(face.row(across(f, k))) : Eigen::RowVector3d::Zero());
  }

  /// The pseudonormal at a closest point given by its face and barycentrics.
  Eigen::RowVector3d at(const MatrixX3i& F, Index f, const Eigen::RowVector3d& bary) const {
    constexpr double kOnFeature = 1e-9;  // a barycentric this small: on the opposite edge
    int zeros = 0, zero = 0, largest = 0;
    for (int k = 0; k < 3; ++k) {
      if (bary(k) <= kOnFeature) ++zeros, zero = k;
      if (bary(k) > bary(largest)) largest = k;
    }
    if (zeros == 0) return face.row(f);
    if (zeros == 1) return edge.row(3 * f + zero);
    return vertex.row(F(f, largest));
  }
};

VectorXd signed_distances(const ClosestPointTree& tree, const Pseudonormals& normals, const MatrixX3i& F,
                          const MatrixX3d& points) {
  const ClosestPoints found = tree.query(points);
  VectorXd out(points.rows());
  for (Index q = 0; q < Index(points.rows()); ++q) {
    const Eigen::RowVector3d n = normals.at(F, found.face(q), found.bary.row(q));
    const double side = (points.row(q) - found.points.row(q)).dot(n);
    out(q) = side < 0 ? -found.distance(q) : found.distance(q);
  }
  return out;
}

double depth_of(const VectorXd& signed_distance) {
  return signed_distance.size() ? std::max(0.0, -signed_distance.minCoeff()) : 0.0;
}

}  // namespace

VectorXd signed_distance(const MatrixX3d& V, const MatrixX3i& F, const MatrixX3d& points) {
  validate_arrays(V, F);
  return signed_distances(ClosestPointTree(V, F), Pseudonormals(V, F), F, points);
}

PartRider::PartRider(const MatrixX3d& body_V, const MatrixX3i& body_F, const MatrixX3d& part_V,
                     const VectorXi& part_of, const RideAlongOptions& options)
    : body_rest_(body_V), body_F_(body_F), part_rest_(part_V) {
  validate_arrays(body_V, body_F);
  if (part_of.size() != part_V.rows())
    throw InvalidInputError("part_of has " + std::to_string(part_of.size()) + " labels for " +
                            std::to_string(part_V.rows()) + " part vertices");
  if (!part_V.allFinite()) throw InvalidInputError("part_V has a non-finite coordinate");
  const Index parts = part_of.size() ? Index(part_of.maxCoeff()) + 1 : 0;
  if (part_of.size() && part_of.minCoeff() < 0) throw InvalidInputError("part_of has a negative label");
  members_.assign(parts, {});
  for (Index i = 0; i < Index(part_of.size()); ++i) members_[part_of(i)].push_back(i);
  const std::vector<std::vector<Index>>& members = members_;
  for (Index p = 0; p < parts; ++p)
    if (members[p].empty())
      throw InvalidInputError("part " + std::to_string(p) + " has no vertex (labels must be 0..parts-1, each used)");

  const ClosestPointTree tree(body_V, body_F);
  const Pseudonormals normals(body_V, body_F);
  const TriMesh body(body_V, body_F);
  const Csr& ring = body.vertex_neighbors();
  patches_.resize(parts);
  weights_.resize(parts);
  rest_depth_ = VectorXd::Zero(parts);
  rest_gap_ = VectorXd::Zero(parts);
  riding_.assign(parts, true);
  const double body_diagonal = bounding_box_diagonal(body_V);
  std::vector<char> taken(body_V.rows(), 0);
  for (Index p = 0; p < parts; ++p) {
    MatrixX3d points(members[p].size(), 3);
    for (std::size_t k = 0; k < members[p].size(); ++k) points.row(Index(k)) = part_V.row(members[p][k]);
    const ClosestPoints found = tree.query(points);
    const Eigen::RowVector3d centre = found.points.colwise().mean();
    const Eigen::RowVector3d middle = points.colwise().mean();
    double size = found.distance.maxCoeff();
    for (Index k = 0; k < Index(points.rows()); ++k) {
      size = std::max(size, (points.row(k) - middle).norm());
      size = std::max(size, (found.points.row(k) - centre).norm());
    }
    const double reach = options.patch_scale * size;
    // Grow from the faces holding the closest points across the body's
    // edges (a ball would take the other side of a thin neck or the nose).
    std::vector<Index> patch, frontier;
    auto take = [&](Index v) {
      if (!taken[v]) taken[v] = 1, patch.push_back(v), frontier.push_back(v);
    };
    for (Index k = 0; k < Index(found.face.size()); ++k)
      for (int c = 0; c < 3; ++c) take(body_F(found.face(k), c));
    std::vector<Index> beyond;  // vertices met past the reach, for the rings past it
    for (std::size_t head = 0; head < frontier.size(); ++head) {
      const Index v = frontier[head];
      for (Index e = ring.begin(v); e < ring.end(v); ++e) {
        const Index w = ring.items[e];
        if (taken[w]) continue;
        if ((body_V.row(w) - centre).norm() <= reach) take(w);
        else beyond.push_back(w);
      }
    }
    while (Index(patch.size()) < options.min_patch && !beyond.empty()) {
      std::vector<Index> next;
      for (Index w : beyond) {
        if (taken[w]) continue;
        take(w);
        for (Index e = ring.begin(w); e < ring.end(w); ++e)
          if (!taken[ring.items[e]]) next.push_back(ring.items[e]);
      }
      beyond.swap(next);
    }
    std::sort(patch.begin(), patch.end());
    for (Index v : patch) taken[v] = 0;
    double far = reach;
    for (Index v : patch) far = std::max(far, (body_V.row(v) - centre).norm());
    VectorXd w(patch.size());
    for (std::size_t k = 0; k < patch.size(); ++k) {
      const double d = far > 0 ? (body_V.row(patch[k]) - centre).norm() / far : 0.0;
      w(Index(k)) = std::exp(-d * d);
    }
    patches_[p] = std::move(patch);
    weights_[p] = std::move(w);
    const VectorXd sides = signed_distances(tree, normals, body_F, points);
    rest_depth_(p) = depth_of(sides);
    rest_gap_(p) = std::max(0.0, sides.minCoeff());
    double own = 0.0;
    for (Index k = 0; k < Index(points.rows()); ++k) own = std::max(own, (points.row(k) - middle).norm());
    riding_[p] = rest_gap_(p) <= std::max(own, options.attach_share * body_diagonal);
  }
}

CarriedParts PartRider::at(const MatrixX3d& body_now) const {
  if (body_now.rows() != body_rest_.rows())
    throw InvalidInputError("body_now has " + std::to_string(body_now.rows()) + " rows, the body " +
                            std::to_string(body_rest_.rows()));
  if (!body_now.allFinite()) throw InvalidInputError("body_now has a non-finite coordinate");
  CarriedParts out;
  out.positions.resize(part_rest_.rows(), 3);
  out.pushed = VectorXd::Zero(parts());
  if (parts() == 0) return out;
  const ClosestPointTree tree(body_now, body_F_);
  const Pseudonormals normals(body_now, body_F_);
  const double tolerance = 1e-4 * bounding_box_diagonal(body_now);
  const std::vector<std::vector<Index>>& members = members_;
  for (Index p = 0; p < parts(); ++p) {
    if (!riding_[p]) {
      for (Index i : members[p]) out.positions.row(i) = part_rest_.row(i);
      continue;
    }
    const std::vector<Index>& patch = patches_[p];
    const VectorXd& w = weights_[p];
    MatrixX3d from(patch.size(), 3), to(patch.size(), 3);
    for (std::size_t k = 0; k < patch.size(); ++k) {
      from.row(Index(k)) = body_rest_.row(patch[k]);
      to.row(Index(k)) = body_now.row(patch[k]);
    }
    const double total = w.sum();
    const Eigen::RowVector3d from_mean = (w.transpose() * from) / total, to_mean = (w.transpose() * to) / total;
    from.rowwise() -= from_mean;
    to.rowwise() -= to_mean;
    const Eigen::Matrix3d R = best_rotation(from, to, w);
    const double spread = (w.array() * from.rowwise().squaredNorm().array()).sum();
    const double along = (w.array() * ((from * R).array() * to.array()).rowwise().sum()).sum();
    const double scale = spread > 0 && along > 0 ? along / spread : 1.0;

    MatrixX3d points(members[p].size(), 3);
    for (std::size_t k = 0; k < members[p].size(); ++k)
      points.row(Index(k)) = to_mean + scale * (part_rest_.row(members[p][k]) - from_mean) * R;
    // No deeper into the body than at rest (scaled with the part).
    const double allowed = scale * rest_depth_(p) + tolerance;
    double depth = depth_of(signed_distances(tree, normals, body_F_, points));
    if (depth > allowed) {
      Eigen::RowVector3d outward = Eigen::RowVector3d::Zero();
      for (std::size_t k = 0; k < patch.size(); ++k) outward += w(Index(k)) * normals.vertex.row(patch[k]);
      if (!(outward.norm() > 0)) outward = points.colwise().mean() - to_mean;
      if (outward.norm() > 0) {
        outward.normalize();
        for (int round = 0; round < 8 && depth > allowed; ++round) {
          const double step = depth - allowed + tolerance;
          points.rowwise() += step * outward;
          out.pushed(p) += step;
          depth = depth_of(signed_distances(tree, normals, body_F_, points));
        }
      }
    }
    for (std::size_t k = 0; k < members[p].size(); ++k) out.positions.row(members[p][k]) = points.row(Index(k));
  }
  return out;
}

}  // namespace paramorph::morph
