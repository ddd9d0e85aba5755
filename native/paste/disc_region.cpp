// The region under a feature as a disc (paste/disc_region.h).
#include "paste/disc_region.h"

#include <algorithm>
#include <functional>
#include <numeric>
#include <limits>
#include <queue>

#include "common/errors.h"

namespace paramorph::paste {

namespace {

/// Dijkstra along edges from the anchor face's corners (seeded with their
/// distance to the anchor point), stopping at `limit`.
std::vector<double> path_distances(const TriMesh& mesh, Index anchor_face, const Eigen::Vector3d& anchor,
                                   double limit, std::vector<Index>* visited) {
  const MatrixX3d& V = mesh.V();
  const Csr& ring = mesh.vertex_neighbors();
  std::vector<double> distance(std::size_t(V.rows()), std::numeric_limits<double>::infinity());
  std::vector<char> done(std::size_t(V.rows()), 0);
  using Entry = std::pair<double, Index>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> heap;
  for (int k = 0; k < 3; ++k) {
    const Index v = mesh.F()(anchor_face, k);
    distance[v] = (V.row(v).transpose() - anchor).norm();
    heap.push({distance[v], v});
  }
  while (!heap.empty()) {
    const auto [d, v] = heap.top();
    heap.pop();
    if (done[v]) continue;
    done[v] = 1;
    visited->push_back(v);
    for (Index j = ring.begin(v); j < ring.end(v); ++j) {
      const Index u = ring.items[j];
      const double du = d + (V.row(u) - V.row(v)).norm();
      if (!done[u] && du < distance[u] && du <= limit) distance[u] = du, heap.push({du, u});
    }
  }
  return distance;
}

}  // namespace

DiscRegion grow_disc_region(const TriMesh& mesh, Index anchor_face, const Eigen::Vector3d& anchor, double cover,
                            double grow, double limit) {
  const MatrixX3i& F = mesh.F();
  const MatrixX3i& FE = mesh.face_edges();
  const Csr& EF = mesh.edge_faces();
  const Csr& corners = mesh.vertex_corners();
  const Index nf = Index(F.rows());
  DiscRegion out;
  std::vector<Index> visited;
  out.distance = path_distances(mesh, anchor_face, anchor, limit, &visited);
  const std::vector<double>& d = out.distance;
  // A face is within a distance when all its corners are (must join), and
  // near when one is (may join): a vertex nearer than `grow` then has all
  // its faces in the disc, so the disc's cut lies beyond `grow`.
  const auto key = [&](Index f) { return std::max({d[F(f, 0)], d[F(f, 1)], d[F(f, 2)]}); };
  const auto near = [&](Index f) { return std::min({d[F(f, 0)], d[F(f, 1)], d[F(f, 2)]}); };
  /// The face across edge k of f, or -1 (the target's boundary).
  const auto across = [&](Index f, int k) -> Index {
    const Index e = FE(f, k);
    if (EF.size(e) < 2) return -1;
    const Index a = EF.items[EF.begin(e)], b = EF.items[EF.begin(e) + 1];
    return a == f ? b : a;
  };

  // The faces that must join: every face whose corners all lie within `cover`.
  Index missing = 0;
  {
    std::vector<char> counted(std::size_t(nf), 0);
    for (const Index v : visited) {
      if (d[v] >= cover) continue;
      for (Index j = corners.begin(v); j < corners.end(v); ++j) {
        const Index f = corners.items[j] / 3;
        if (!counted[f] && key(f) < cover) counted[f] = 1, ++missing;
      }
    }
  }

  out.in_disc.assign(std::size_t(nf), 0);
  std::vector<int> uses(std::size_t(mesh.num_vertices()), 0);  // the disc's faces at each vertex
  using Entry = std::pair<double, Index>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> heap;
  const auto add = [&](Index f) {
    out.in_disc[f] = 1;
    out.faces.push_back(f);
    const double k = key(f);
    if (k < cover) --missing;
    for (int c = 0; c < 3; ++c) {
      const Index v = F(f, c);
      if (uses[v]++ == 0) out.vertices.push_back(v);
      const Index g = across(f, c);
      if (g >= 0 && !out.in_disc[g] && near(g) <= limit) heap.push({near(g), g});
    }
  };
  /// Whether f keeps the disc a disc (see the header).
  const auto keeps_disc = [&](Index f) {
    int shared = 0, lone = -1;
    for (int c = 0; c < 3; ++c) {
      const Index g = across(f, c);
      if (g >= 0 && out.in_disc[g]) ++shared, lone = c;  // edge c lies opposite corner c
    }
    if (shared == 2) return true;
    return shared == 1 && uses[F(f, lone)] == 0;
  };

  add(anchor_face);
  while (!heap.empty()) {
    const auto [k, f] = heap.top();
    if (k > limit || (k >= grow && missing == 0)) break;
    heap.pop();
    if (out.in_disc[f] || !keeps_disc(f)) continue;  // a neighbour joining pushes f again
    add(f);
  }
  PM_REQUIRE(missing == 0, TargetTooSmallError,
             "the surface under the feature is not a single disc: within the blend radius it has a hole, a "
             "handle, or it wraps around a part thinner than the feature. Move the feature, make it smaller, "
             "lower its blend radius, or close the hole first");

  std::vector<char> on_cut(std::size_t(mesh.num_vertices()), 0);
  for (const Index f : out.faces)
    for (int c = 0; c < 3; ++c) {
      const Index g = across(f, c);
      if (g < 0 || out.in_disc[g]) continue;
      for (const Index v : {F(f, (c + 1) % 3), F(f, (c + 2) % 3)})
        if (!on_cut[v]) on_cut[v] = 1, out.cut_vertices.push_back(v);
    }
  return out;
}

bool is_disc_up_to_holes(const TriMesh& mesh, const std::vector<Index>& faces) {
  if (faces.empty()) return false;
  const MatrixX3i& F = mesh.F();
  const MatrixX3i& FE = mesh.face_edges();
  const MatrixX2i& E = mesh.edges();
  const Csr& EF = mesh.edge_faces();
  std::vector<Index> edges, vertices;
  edges.reserve(3 * faces.size());
  vertices.reserve(3 * faces.size());
  for (const Index f : faces)
    for (int c = 0; c < 3; ++c) edges.push_back(FE(f, c)), vertices.push_back(F(f, c));
  // An edge listed once is on the region's boundary (the mesh is manifold).
  std::sort(edges.begin(), edges.end());
  std::vector<Index> boundary;
  Index distinct_edges = 0;
  for (std::size_t i = 0; i < edges.size();) {
    std::size_t j = i;
    while (j < edges.size() && edges[j] == edges[i]) ++j;
    ++distinct_edges;
    if (j - i == 1) boundary.push_back(edges[i]);
    i = j;
  }
  std::sort(vertices.begin(), vertices.end());
  const Index distinct_vertices = Index(std::unique(vertices.begin(), vertices.end()) - vertices.begin());
  vertices.resize(std::size_t(distinct_vertices));
  const auto slot = [&](Index v) { return Index(std::lower_bound(vertices.begin(), vertices.end(), v) - vertices.begin()); };

  // Boundary loops: components of the boundary edges (union-find on their
  // vertices); a vertex on more than two boundary edges is a bow-tie.
  std::vector<Index> parent(vertices.size()), degree(vertices.size(), 0);
  std::iota(parent.begin(), parent.end(), Index(0));
  const std::function<Index(Index)> root = [&](Index x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  for (const Index e : boundary) {
    const Index a = slot(E(e, 0)), b = slot(E(e, 1));
    if (++degree[a] > 2 || ++degree[b] > 2) return false;
    parent[root(a)] = root(b);
  }
  std::vector<char> is_loop(vertices.size(), 0), cut(vertices.size(), 0);
  for (const Index e : boundary) {
    const Index r = root(slot(E(e, 0)));
    is_loop[r] = 1;
    if (EF.size(e) > 1) cut[r] = 1;
  }
  Index cut_loops = 0, holes = 0;
  for (std::size_t r = 0; r < vertices.size(); ++r)
    if (is_loop[r]) (cut[r] ? cut_loops : holes) += 1;
  const Index euler = distinct_vertices - distinct_edges + Index(faces.size());
  return cut_loops == 1 && euler + holes == 1;
}

}  // namespace paramorph::paste
