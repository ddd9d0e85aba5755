// Discrete exponential map (paste/exponential_map.h).
#include "paste/exponential_map.h"

#include <Eigen/Geometry>
#include <functional>
#include <limits>
#include <queue>

namespace paramorph::paste {

Eigen::Vector3d transport_tangent(const Eigen::Vector3d& t, const Eigen::Vector3d& from, const Eigen::Vector3d& to) {
  const Eigen::Vector3d turned = Eigen::Quaterniond::FromTwoVectors(from, to) * t;
  const Eigen::Vector3d tangent = turned - turned.dot(to) * to;
  const double len = tangent.norm();
  return len > 1e-12 ? Eigen::Vector3d(tangent / len) : t;
}

namespace {

/// The edge from x_u to x_v in u's tangent frame, at the edge's length.
Eigen::Vector2d edge_in_frame(const Eigen::Vector3d& edge, const Eigen::Vector3d& t, const Eigen::Vector3d& n) {
  const Eigen::Vector2d in_plane(t.dot(edge), n.cross(t).dot(edge));
  const double len = in_plane.norm();
  return len > 1e-300 ? Eigen::Vector2d(in_plane * (edge.norm() / len)) : in_plane;
}

}  // namespace

ExponentialMap exponential_map(const TriMesh& mesh, const MatrixX3d& vertex_normals, Index anchor_face,
                               const Eigen::Vector3d& anchor, const Eigen::Vector3d& tangent,
                               const Eigen::Vector3d& normal, double radius) {
  const MatrixX3d& V = mesh.V();
  const MatrixX3i& F = mesh.F();
  const Csr& ring = mesh.vertex_neighbors();
  const Index nv = Index(V.rows());
  ExponentialMap out;
  out.q.assign(std::size_t(nv), Eigen::Vector2d::Zero());
  out.reached.assign(std::size_t(nv), 0);
  std::vector<double> distance(std::size_t(nv), std::numeric_limits<double>::infinity());
  std::vector<Index> parent(std::size_t(nv), -1);
  std::vector<Eigen::Vector3d> frame(static_cast<std::size_t>(nv));  // tangent t_v; the normal is vertex_normals
  using Entry = std::pair<double, Index>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> heap;
  for (int k = 0; k < 3; ++k) {
    const Index v = F(anchor_face, k);
    distance[v] = (V.row(v).transpose() - anchor).norm();
    heap.push({distance[v], v});
  }
  const auto normal_of = [&](Index v) -> Eigen::Vector3d {
    const Eigen::Vector3d n = vertex_normals.row(v).transpose();
    return n.squaredNorm() > 0 ? n : normal;
  };
  while (!heap.empty()) {
    const auto [d, v] = heap.top();
    heap.pop();
    if (out.reached[v] || d > distance[v]) continue;
    const Eigen::Vector3d x = V.row(v).transpose(), n_v = normal_of(v);
    const bool seed = parent[v] < 0;
    frame[v] = transport_tangent(tangent, normal, n_v);
    if (seed) {  // a corner of the anchor face: straight from the anchor's frame
      out.q[v] = edge_in_frame(x - anchor, tangent, normal);
    } else {
      Eigen::Vector2d sum = Eigen::Vector2d::Zero();
      double weights = 0;
      for (Index j = ring.begin(v); j < ring.end(v); ++j) {
        const Index u = ring.items[j];
        if (!out.reached[u]) continue;
        const Eigen::Vector3d edge = x - V.row(u).transpose();
        const double w = 1.0 / std::max(edge.squaredNorm(), 1e-300);
        sum += w * (out.q[u] + edge_in_frame(edge, frame[u], normal_of(u)));
        weights += w;
      }
      out.q[v] = sum / weights;
    }
    out.reached[v] = 1;
    out.vertices.push_back(v);
    if (!seed && out.q[v].norm() >= radius && d >= radius) continue;
    for (Index j = ring.begin(v); j < ring.end(v); ++j) {
      const Index u = ring.items[j];
      if (out.reached[u]) continue;
      const double du = d + (V.row(u) - V.row(v)).norm();
      if (du < distance[u]) distance[u] = du, parent[u] = v, heap.push({du, u});
    }
  }
  return out;
}

}  // namespace paramorph::paste
