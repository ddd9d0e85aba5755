#include "paste/target_patch.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <optional>
#include <queue>
#include <set>
#include <vector>

#include <Eigen/Dense>
#include <Eigen/Geometry>

#include "common/errors.h"
#include "param/planar/initial_maps.h"

namespace paramorph::paste {

namespace {

using Vec3 = Eigen::Vector3d;
using Vec2 = Eigen::Vector2d;

/// Edge-path distances from the anchor (its face's corners start at their
/// straight distance to it), settled up to `radius` only.
std::vector<double> distances_from(const TriMesh& mesh, Index face, const Vec3& point, double radius) {
  const MatrixX3d& V = mesh.V();
  std::vector<double> distance(std::size_t(mesh.num_vertices()), std::numeric_limits<double>::infinity());
  using Entry = std::pair<double, Index>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<>> queue;
  for (int k = 0; k < 3; ++k) {
    const Index v = mesh.F()(face, k);
    distance[v] = (V.row(v).transpose() - point).norm();
    queue.emplace(distance[v], v);
  }
  const Csr& neighbors = mesh.vertex_neighbors();
  while (!queue.empty()) {
    const auto [d, v] = queue.top();
    queue.pop();
    if (d > distance[v] || d > radius) continue;
    for (Index k = neighbors.begin(v); k < neighbors.end(v); ++k) {
      const Index w = neighbors.items[k];
      const double through = d + (V.row(w) - V.row(v)).norm();
      if (through < distance[w]) {
        distance[w] = through;
        queue.emplace(through, w);
      }
    }
  }
  return distance;
}

struct Patch {
  std::vector<Index> faces, vertices;
  MatrixX3i local_faces;
  MatrixX3d local_positions;
};

Patch local_patch(const TriMesh& mesh, const std::vector<char>& in_patch) {
  Patch patch;
  std::vector<Index> local(std::size_t(mesh.num_vertices()), -1);
  for (Index f = 0; f < mesh.num_faces(); ++f) {
    if (!in_patch[f]) continue;
    patch.faces.push_back(f);
    for (int k = 0; k < 3; ++k) {
      const Index v = mesh.F()(f, k);
      if (local[v] < 0) {
        local[v] = Index(patch.vertices.size());
        patch.vertices.push_back(v);
      }
    }
  }
  patch.local_faces.resize(Index(patch.faces.size()), 3);
  for (Index i = 0; i < Index(patch.faces.size()); ++i)
    for (int k = 0; k < 3; ++k) patch.local_faces(i, k) = local[mesh.F()(patch.faces[i], k)];
  patch.local_positions.resize(Index(patch.vertices.size()), 3);
  for (Index i = 0; i < Index(patch.vertices.size()); ++i) patch.local_positions.row(i) = mesh.V().row(patch.vertices[i]);
  return patch;
}

/// Unit normal at a vertex: the sum of its faces' area vectors.
Vec3 vertex_normal(const TriMesh& mesh, Index v) {
  const MatrixX3d& V = mesh.V();
  const Csr& corners = mesh.vertex_corners();
  Vec3 sum = Vec3::Zero();
  for (Index k = corners.begin(v); k < corners.end(v); ++k) {
    const Index f = corners.items[k] / 3;
    const Vec3 a = V.row(mesh.F()(f, 0)), b = V.row(mesh.F()(f, 1)), c = V.row(mesh.F()(f, 2));
    sum += (b - a).cross(c - a);
  }
  return sum.normalized();
}

double segment_distance(const Vec2& a, const Vec2& b) {  // from the origin
  const Vec2 d = b - a;
  const double t = d.squaredNorm() > 0 ? std::clamp(-a.dot(d) / d.squaredNorm(), 0.0, 1.0) : 0.0;
  return (a + t * d).norm();
}

TargetPatch patch_within(const TriMesh& target, Index anchor_face, const Eigen::Vector3d& anchor_bary,
                         const Eigen::Vector3d& reference, double radius) {
  const MatrixX3d& V = target.V();
  const MatrixX3i& F = target.F();
  TargetPatch result;
  result.anchor_face = anchor_face;
  result.anchor_bary = anchor_bary;
  for (int k = 0; k < 3; ++k) result.anchor_point += anchor_bary[k] * V.row(F(anchor_face, k)).transpose();

  // Faces with a corner within the radius; then pinches (a vertex where the
  // patch's boundary touches itself) and holes (boundary loops besides the
  // outer one) are closed by taking every face around their vertices.
  const std::vector<double> distance = distances_from(target, anchor_face, result.anchor_point, radius);
  std::vector<char> in_patch(std::size_t(target.num_faces()), 0);
  for (Index f = 0; f < target.num_faces(); ++f)
    for (int k = 0; k < 3; ++k) in_patch[f] |= distance[F(f, k)] <= radius;
  in_patch[anchor_face] = 1;
  const Csr& corners = target.vertex_corners();
  Patch patch;
  std::optional<TriMesh> local_mesh;  // the patch as a mesh, kept for the map below
  for (int attempt = 0;; ++attempt) {
    patch = local_patch(target, in_patch);
    PM_REQUIRE(Index(patch.faces.size()) < target.num_faces(), TargetTooSmallError,
               "the target is too small for the feature here: the region of radius ", radius,
               " around the anchor covers the whole target");
    const TriMesh& local = local_mesh.emplace(patch.local_positions, patch.local_faces);
    const auto& loops = local.boundary_loops();
    const Index euler = local.num_vertices() - Index(local.edges().rows()) + local.num_faces();
    if (loops.size() == 1 && euler == 1 && local.num_components() == 1) break;
    PM_REQUIRE(attempt < 8, TargetTooSmallError,
               "the target is too small or too thin for the feature here: the region of radius ", radius,
               " around the anchor is not a disc (", loops.size(), " boundary loops, Euler characteristic ",
               euler, ")");
    // Vertices on more than one loop, or on any loop but the longest.
    std::size_t longest = 0;
    for (std::size_t i = 1; i < loops.size(); ++i)
      if (loops[i].size() > loops[longest].size()) longest = i;
    std::vector<int> seen(std::size_t(local.num_vertices()), 0);
    std::set<Index> widen;
    for (std::size_t i = 0; i < loops.size(); ++i)
      for (Index v : loops[i])
        if (i != longest || ++seen[v] > 1) widen.insert(v);
    for (std::size_t i = 0; i < loops.size(); ++i)
      for (Index v : loops[i])
        if (i != longest && seen[v] > 0) widen.insert(v);
    if (widen.empty())  // one loop but not a disc (a handle): nothing local to close
      PM_REQUIRE(false, TargetTooSmallError,
                 "the target is too small or too thin for the feature here: the region of radius ", radius,
                 " around the anchor is not a disc (Euler characteristic ", euler, ")");
    for (Index v : widen) {
      const Index global = patch.vertices[v];
      for (Index k = corners.begin(global); k < corners.end(global); ++k) in_patch[corners.items[k] / 3] = 1;
    }
  }

  result.faces = Eigen::Map<const VectorXi>(patch.faces.data(), Index(patch.faces.size())).cast<int>();
  result.vertices = Eigen::Map<const VectorXi>(patch.vertices.data(), Index(patch.vertices.size())).cast<int>();
  result.local_faces = patch.local_faces;
  const TriMesh& local = *local_mesh;
  MatrixX2d uv = planar::lscm_map(local);
  // Orientation: counter-clockwise in uv where the target's faces are.
  double signed_area = 0;
  for (Index f = 0; f < local.num_faces(); ++f) {
    const Vec2 a = uv.row(patch.local_faces(f, 0)), b = uv.row(patch.local_faces(f, 1)),
               c = uv.row(patch.local_faces(f, 2));
    const Vec2 ab = b - a, ac = c - a;
    signed_area += ab.x() * ac.y() - ab.y() * ac.x();
  }
  if (signed_area < 0) uv.col(1) *= -1;

  Vec3 normal = Vec3::Zero();
  for (int k = 0; k < 3; ++k) normal += anchor_bary[k] * vertex_normal(target, F(anchor_face, k));
  result.normal = normal.normalized();
  Vec3 tangent = Vec3::Zero();
  for (const Vec3& direction : {reference, Vec3(Vec3::UnitX()), Vec3(Vec3::UnitY())}) {
    const Vec3 projected = direction - direction.dot(result.normal) * result.normal;
    if (projected.norm() > 1e-3 * direction.norm()) {
      tangent = projected.normalized();
      break;
    }
  }
  result.tangent = tangent;

  // The map's Jacobian on the anchor face: the image of the tangent gives
  // the scale and turn that make it unit length along +u.
  Index anchor_local = -1;
  for (Index i = 0; i < Index(patch.faces.size()); ++i)
    if (patch.faces[i] == anchor_face) anchor_local = i;
  const Vec3 x0 = V.row(F(anchor_face, 0)), x1 = V.row(F(anchor_face, 1)), x2 = V.row(F(anchor_face, 2));
  const Vec2 u0 = uv.row(patch.local_faces(anchor_local, 0)), u1 = uv.row(patch.local_faces(anchor_local, 1)),
             u2 = uv.row(patch.local_faces(anchor_local, 2));
  Eigen::Matrix<double, 3, 2> E;
  E << x1 - x0, x2 - x0;
  Eigen::Matrix2d D;
  D << u1 - u0, u2 - u0;
  const Vec2 coefficients = E.colPivHouseholderQr().solve(tangent);  // tangent in the face's edge basis
  const Vec2 image = D * coefficients;
  PM_REQUIRE(image.norm() > 0 && std::isfinite(image.norm()), ComputeError,
             "the target patch's map is degenerate at the anchor");
  const double scale = 1.0 / image.norm(), turn = -std::atan2(image.y(), image.x());
  Eigen::Matrix2d rotation;
  rotation << std::cos(turn), -std::sin(turn), std::sin(turn), std::cos(turn);
  const Vec2 anchor_uv = anchor_bary[0] * u0 + anchor_bary[1] * u1 + anchor_bary[2] * u2;
  result.uv = ((uv.rowwise() - anchor_uv.transpose()) * rotation.transpose()) * scale;

  result.reach = std::numeric_limits<double>::infinity();
  for (const auto& loop : local.boundary_loops())
    for (std::size_t k = 0; k < loop.size(); ++k)
      result.reach = std::min(result.reach, segment_distance(result.uv.row(loop[k]).transpose(),
                                                             result.uv.row(loop[(k + 1) % loop.size()]).transpose()));
  return result;
}

}  // namespace

TargetPatch target_patch(const TriMesh& target, Index anchor_face, const Eigen::Vector3d& anchor_bary,
                         const Eigen::Vector3d& reference, double radius) {
  PM_REQUIRE(anchor_face >= 0 && anchor_face < target.num_faces(), InvalidInputError,
             "anchor face ", anchor_face, " is not a face of the target (", target.num_faces(), " faces)");
  PM_REQUIRE(anchor_bary.allFinite() && anchor_bary.minCoeff() >= -1e-9 && std::abs(anchor_bary.sum() - 1) < 1e-9,
             InvalidInputError, "anchor barycentric coordinates must be >= 0 and sum to 1");
  PM_REQUIRE(std::isfinite(radius) && radius > 0, InvalidInputError, "patch radius must be > 0, got ", radius);
  PM_REQUIRE(reference.allFinite(), InvalidInputError, "reference direction must be finite");
  // Edge paths overestimate distances (up to sqrt 2 along a grid's
  // unsplit diagonals): grow the path radius until the map's disc fits.
  for (double path_radius = 1.2 * radius;; path_radius *= 1.25) {
    TargetPatch patch = patch_within(target, anchor_face, anchor_bary, reference, path_radius);
    if (patch.reach >= radius) return patch;
    PM_REQUIRE(path_radius < 4 * radius, TargetTooSmallError,
               "the target is too small for the feature here: no disc of radius ", radius,
               " around the anchor fits in it (", patch.reach, " at most)");
  }
}

}  // namespace paramorph::paste
