#include "mesh/tri_mesh.h"

#include <algorithm>
#include <mutex>
#include <numeric>

namespace paramorph {

struct TriMesh::Cache {
  std::once_flag once;
  MatrixX2i edges;
  MatrixX3i face_edges;
  Csr edge_faces, vertex_corners, vertex_neighbors, vertex_neighbor_edges;
  std::vector<std::vector<Index>> boundary_loops;
  VectorXi component;
  Index num_components = 0;
};

TriMesh::TriMesh(MatrixX3d V, MatrixX3i F)
    : V_(std::move(V)), F_(std::move(F)), cache_(std::make_shared<Cache>()) {}

namespace {

/// Rows from (row, item) pairs by counting sort; items keep their input order per row.
Csr build_csr(Index rows, const std::vector<std::pair<Index, Index>>& pairs) {
  Csr csr;
  csr.offsets.assign(std::size_t(rows) + 1, 0);
  for (const auto& [r, item] : pairs) ++csr.offsets[r + 1];
  std::partial_sum(csr.offsets.begin(), csr.offsets.end(), csr.offsets.begin());
  csr.items.resize(pairs.size());
  std::vector<Index> cursor(csr.offsets.begin(), csr.offsets.end() - 1);
  for (const auto& [r, item] : pairs) csr.items[cursor[r]++] = item;
  return csr;
}

Index find_root(std::vector<Index>& parent, Index v) {
  while (parent[v] != v) v = parent[v] = parent[parent[v]];
  return v;
}

}  // namespace

// All topology is built together on first use: every piece comes out of the
// same sorted half-edge list, and algorithms need most of it anyway.
static void build(const MatrixX3d& V, const MatrixX3i& F, TriMesh::Cache& c);

void build(const MatrixX3d& V, const MatrixX3i& F, TriMesh::Cache& c) {
  const Index n = Index(V.rows()), m = Index(F.rows());
  // Half-edge keys (min, max, face, corner), sorted: equal edges become adjacent.
  struct Key {
    Index a, b, face, corner;
  };
  std::vector<Key> keys(std::size_t(3) * m);
  for (Index f = 0; f < m; ++f)
    for (Index k = 0; k < 3; ++k) {
      const Index u = F(f, (k + 1) % 3), v = F(f, (k + 2) % 3);
      keys[3 * f + k] = {std::min(u, v), std::max(u, v), f, k};
    }
  std::sort(keys.begin(), keys.end(), [](const Key& x, const Key& y) {
    return x.a != y.a ? x.a < y.a : x.b != y.b ? x.b < y.b : x.face < y.face;
  });
  std::vector<std::pair<Index, Index>> edge_list;
  std::vector<std::pair<Index, Index>> edge_face_pairs;
  c.face_edges.resize(m, 3);
  for (std::size_t i = 0; i < keys.size(); ++i) {
    if (i == 0 || keys[i].a != keys[i - 1].a || keys[i].b != keys[i - 1].b)
      edge_list.emplace_back(keys[i].a, keys[i].b);
    const Index e = Index(edge_list.size()) - 1;
    c.face_edges(keys[i].face, keys[i].corner) = e;
    edge_face_pairs.emplace_back(e, keys[i].face);
  }
  const Index ne = Index(edge_list.size());
  c.edges.resize(ne, 2);
  for (Index e = 0; e < ne; ++e) c.edges.row(e) << edge_list[e].first, edge_list[e].second;
  c.edge_faces = build_csr(ne, edge_face_pairs);

  std::vector<std::pair<Index, Index>> corner_pairs;
  corner_pairs.reserve(std::size_t(3) * m);
  for (Index f = 0; f < m; ++f)
    for (Index k = 0; k < 3; ++k) corner_pairs.emplace_back(F(f, k), 3 * f + k);
  c.vertex_corners = build_csr(n, corner_pairs);

  // 1-rings from both directions of every edge, then each row sorted.
  std::vector<std::pair<Index, Index>> nbr_pairs, nbr_edge_pairs;
  nbr_pairs.reserve(std::size_t(2) * ne);
  nbr_edge_pairs.reserve(std::size_t(2) * ne);
  for (Index e = 0; e < ne; ++e) {
    nbr_pairs.emplace_back(c.edges(e, 0), c.edges(e, 1));
    nbr_edge_pairs.emplace_back(c.edges(e, 0), e);
    nbr_pairs.emplace_back(c.edges(e, 1), c.edges(e, 0));
    nbr_edge_pairs.emplace_back(c.edges(e, 1), e);
  }
  c.vertex_neighbors = build_csr(n, nbr_pairs);
  c.vertex_neighbor_edges = build_csr(n, nbr_edge_pairs);
  for (Index v = 0; v < n; ++v) {  // sort each row, carrying the edge ids along
    const Index b = c.vertex_neighbors.begin(v), s = c.vertex_neighbors.size(v);
    std::vector<std::pair<Index, Index>> row(static_cast<std::size_t>(s));
    for (Index k = 0; k < s; ++k)
      row[k] = {c.vertex_neighbors.items[b + k], c.vertex_neighbor_edges.items[b + k]};
    std::sort(row.begin(), row.end());
    for (Index k = 0; k < s; ++k) {
      c.vertex_neighbors.items[b + k] = row[k].first;
      c.vertex_neighbor_edges.items[b + k] = row[k].second;
    }
  }

  // Boundary loops: follow boundary half-edges (u -> v as they run in their
  // face) from vertex to vertex; each half-edge is used once, so broken
  // boundaries end instead of looping forever.
  std::vector<std::pair<Index, Index>> boundary_next;  // (u, half-edge id)
  std::vector<Index> half_to;                          // v of each boundary half-edge
  for (Index e = 0; e < ne; ++e) {
    if (c.edge_faces.size(e) != 1) continue;
    const Index f = c.edge_faces.items[c.edge_faces.begin(e)];
    for (Index k = 0; k < 3; ++k)
      if (c.face_edges(f, k) == e) {
        boundary_next.emplace_back(F(f, (k + 1) % 3), Index(half_to.size()));
        half_to.push_back(F(f, (k + 2) % 3));
      }
  }
  const Csr outgoing = build_csr(n, boundary_next);
  std::vector<char> used(half_to.size(), 0);
  std::vector<Index> cursor(outgoing.offsets.begin(), outgoing.offsets.end() - 1);
  for (Index v = 0; v < n; ++v) {
    while (cursor[v] < outgoing.end(v)) {
      std::vector<Index> loop;
      Index u = v;
      while (cursor[u] < outgoing.end(u)) {
        const Index h = outgoing.items[cursor[u]++];
        if (used[h]) continue;
        used[h] = 1;
        loop.push_back(u);
        u = half_to[h];
        if (u == v) break;
      }
      if (!loop.empty()) c.boundary_loops.push_back(std::move(loop));
    }
  }

  // Components by union-find over face corners; isolated vertices stand alone.
  std::vector<Index> parent(n);
  std::iota(parent.begin(), parent.end(), 0);
  for (Index f = 0; f < m; ++f)
    for (Index k = 1; k < 3; ++k) {
      const Index a = find_root(parent, F(f, 0)), b = find_root(parent, F(f, k));
      if (a != b) parent[std::max(a, b)] = std::min(a, b);
    }
  c.component.resize(n);
  std::vector<Index> label(n, -1);
  for (Index v = 0; v < n; ++v) {
    const Index r = find_root(parent, v);
    if (label[r] < 0) label[r] = c.num_components++;
    c.component[v] = label[r];
  }
}

#define PM_TOPOLOGY(member)                                          \
  std::call_once(cache_->once, [this] { build(V_, F_, *cache_); }); \
  return cache_->member

const MatrixX2i& TriMesh::edges() const { PM_TOPOLOGY(edges); }
const MatrixX3i& TriMesh::face_edges() const { PM_TOPOLOGY(face_edges); }
const Csr& TriMesh::edge_faces() const { PM_TOPOLOGY(edge_faces); }
const Csr& TriMesh::vertex_corners() const { PM_TOPOLOGY(vertex_corners); }
const Csr& TriMesh::vertex_neighbors() const { PM_TOPOLOGY(vertex_neighbors); }
const Csr& TriMesh::vertex_neighbor_edges() const { PM_TOPOLOGY(vertex_neighbor_edges); }
const std::vector<std::vector<Index>>& TriMesh::boundary_loops() const {
  PM_TOPOLOGY(boundary_loops);
}
const VectorXi& TriMesh::vertex_component() const { PM_TOPOLOGY(component); }
Index TriMesh::num_components() const { PM_TOPOLOGY(num_components); }

#undef PM_TOPOLOGY

}  // namespace paramorph
