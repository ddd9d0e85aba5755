// TriMesh topology (mesh/tri_mesh.h), built once on first use.
//
// Everything comes from one ordering of the 3F half-edges by their undirected
// key (min vertex, max vertex): a counting sort on the min vertex followed by
// a sort of each (small) bucket, so O(F) plus O(F log valence) in practice and
// no per-element map. Broken input (non-manifold edges, repeated indices,
// isolated vertices, flipped faces) must not crash or hang: validation reads
// this topology to say what is wrong.
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

// Half-edge h = 3 * face + corner runs opposite that corner, from
// F(f, corner + 1) to F(f, corner + 2): the same convention as face_edges().
inline Index face_of(Index h) { return h / 3; }
inline Index corner_of(Index h) { return h % 3; }
inline Index tail(const MatrixX3i& F, Index h) { return F(h / 3, (h % 3 + 1) % 3); }
inline Index head(const MatrixX3i& F, Index h) { return F(h / 3, (h % 3 + 2) % 3); }
/// The half-edge leaving head(h) inside the same face.
inline Index next_in_face(Index h) { return 3 * face_of(h) + (corner_of(h) + 1) % 3; }

/// Offsets of a CSR from per-row counts (counts become row starts).
std::vector<Index> offsets_from_counts(const std::vector<Index>& counts) {
  std::vector<Index> offsets(counts.size() + 1, 0);
  std::partial_sum(counts.begin(), counts.end(), offsets.begin() + 1);
  return offsets;
}

Index find_root(std::vector<Index>& parent, Index v) {
  while (parent[v] != v) v = parent[v] = parent[parent[v]];
  return v;
}

/// Half-edges grouped by undirected edge, edges in lexicographic (a < b)
/// order, half-edges of one edge in ascending h (so faces ascending).
struct SortedHalfEdges {
  std::vector<Index> order;       ///< 3F half-edge ids
  std::vector<Index> edge_start;  ///< #E + 1 offsets into `order`
  std::vector<Index> edge_of;     ///< per half-edge, its edge
};

SortedHalfEdges sort_half_edges(const MatrixX3i& F, Index num_vertices) {
  const Index num_half = 3 * Index(F.rows());
  // Endpoints once per half-edge: the sorts below compare them many times.
  std::vector<Index> lo_of(static_cast<std::size_t>(num_half)), hi_of(lo_of.size());
  for (Index h = 0; h < num_half; ++h) {
    const Index u = tail(F, h), v = head(F, h);
    lo_of[h] = std::min(u, v);
    hi_of[h] = std::max(u, v);
  }
  auto lo = [&](Index h) { return lo_of[h]; };
  auto hi = [&](Index h) { return hi_of[h]; };

  // Counting sort by the smaller endpoint: stable, so each bucket is in h order.
  std::vector<Index> count(static_cast<std::size_t>(num_vertices), 0);
  for (Index h = 0; h < num_half; ++h) ++count[lo(h)];
  std::vector<Index> bucket = offsets_from_counts(count);
  SortedHalfEdges s;
  s.order.resize(std::size_t(num_half));
  {
    std::vector<Index> cursor(bucket.begin(), bucket.end() - 1);
    for (Index h = 0; h < num_half; ++h) s.order[cursor[lo(h)]++] = h;
  }
  // Then by the larger endpoint inside each bucket (about 6 entries each;
  // std::sort keeps a huge fan centre from going quadratic).
  for (Index v = 0; v < num_vertices; ++v) {
    auto first = s.order.begin() + bucket[v], last = s.order.begin() + bucket[v + 1];
    if (last - first > 1)
      std::sort(first, last, [&](Index x, Index y) {
        const Index hx = hi(x), hy = hi(y);
        return hx != hy ? hx < hy : x < y;
      });
  }
  s.edge_of.resize(std::size_t(num_half));
  for (Index i = 0; i < num_half; ++i) {
    const Index h = s.order[i];
    if (i == 0 || lo(h) != lo(s.order[i - 1]) || hi(h) != hi(s.order[i - 1]))
      s.edge_start.push_back(i);
    s.edge_of[h] = Index(s.edge_start.size()) - 1;
  }
  s.edge_start.push_back(num_half);
  return s;
}

/// The boundary half-edge that follows boundary half-edge `h` (which ends at
/// u = head(h)) around the same fan of u, found by rotating across interior
/// edges; -1 when the fan is broken (edge with > 2 faces, or a neighbour that
/// runs the shared edge the same way). Following fans instead of "any boundary
/// edge leaving u" keeps two holes touching at one vertex as two loops.
Index next_boundary_in_fan(const MatrixX3i& F, const SortedHalfEdges& s, Index h,
                           Index max_steps) {
  const Index u = head(F, h);
  Index out = next_in_face(h);  // leaves u
  for (Index step = 0; step <= max_steps; ++step) {
    const Index e = s.edge_of[out];
    const Index size = s.edge_start[e + 1] - s.edge_start[e];
    if (size == 1) return out;
    if (size != 2) return -1;
    const Index a = s.order[s.edge_start[e]], b = s.order[s.edge_start[e] + 1];
    const Index twin = a == out ? b : a;
    if (head(F, twin) != u) return -1;  // inconsistent orientation across this edge
    out = next_in_face(twin);
  }
  return -1;
}

void build(const MatrixX3d& V, const MatrixX3i& F, TriMesh::Cache& c) {
  const Index n = Index(V.rows()), m = Index(F.rows());
  const SortedHalfEdges s = sort_half_edges(F, n);
  const Index ne = Index(s.edge_start.size()) - 1;

  // Edges, face_edges and edge_faces straight from the sorted order.
  c.edges.resize(ne, 2);
  c.edge_faces.offsets = s.edge_start;
  c.edge_faces.items.resize(s.order.size());
  for (Index e = 0; e < ne; ++e) {
    const Index h = s.order[s.edge_start[e]];
    c.edges(e, 0) = std::min(tail(F, h), head(F, h));
    c.edges(e, 1) = std::max(tail(F, h), head(F, h));
  }
  for (std::size_t i = 0; i < s.order.size(); ++i) c.edge_faces.items[i] = face_of(s.order[i]);
  c.face_edges.resize(m, 3);
  for (Index h = 0; h < 3 * m; ++h) c.face_edges(face_of(h), corner_of(h)) = s.edge_of[h];

  // vertex -> corners, by a counting sort (corners ascending per vertex).
  {
    std::vector<Index> count(static_cast<std::size_t>(n), 0);
    for (Index k = 0; k < 3 * m; ++k) ++count[F.data()[k]];  // row-major: data()[k] is corner k
    c.vertex_corners.offsets = offsets_from_counts(count);
    c.vertex_corners.items.resize(std::size_t(3) * m);
    std::vector<Index> cursor(c.vertex_corners.offsets.begin(), c.vertex_corners.offsets.end() - 1);
    for (Index k = 0; k < 3 * m; ++k) c.vertex_corners.items[cursor[F.data()[k]]++] = k;
  }

  // 1-rings, sorted without sorting: edges are ordered by (a, b), so filling
  // every row first with its smaller neighbours (pass over edges as (b <- a))
  // and then with its larger ones (a <- b) leaves each row ascending.
  // Self-edges (a face repeating an index) are not neighbours.
  {
    std::vector<Index> count(static_cast<std::size_t>(n), 0);
    for (Index e = 0; e < ne; ++e)
      if (c.edges(e, 0) != c.edges(e, 1)) ++count[c.edges(e, 0)], ++count[c.edges(e, 1)];
    c.vertex_neighbors.offsets = offsets_from_counts(count);
    c.vertex_neighbor_edges.offsets = c.vertex_neighbors.offsets;
    const std::size_t total = std::size_t(c.vertex_neighbors.offsets.back());
    c.vertex_neighbors.items.resize(total);
    c.vertex_neighbor_edges.items.resize(total);
    std::vector<Index> cursor(c.vertex_neighbors.offsets.begin(), c.vertex_neighbors.offsets.end() - 1);
    for (int pass = 0; pass < 2; ++pass)
      for (Index e = 0; e < ne; ++e) {
        const Index a = c.edges(e, 0), b = c.edges(e, 1);
        if (a == b) continue;
        const Index row = pass == 0 ? b : a, other = pass == 0 ? a : b;
        c.vertex_neighbors.items[cursor[row]] = other;
        c.vertex_neighbor_edges.items[cursor[row]++] = e;
      }
  }

  // Boundary loops over the half-edges of one-face edges, in face orientation.
  // Each half-edge is used once, so broken boundaries end instead of looping.
  {
    std::vector<Index> count(static_cast<std::size_t>(n), 0);
    std::vector<Index> boundary;
    for (Index h = 0; h < 3 * m; ++h)
      if (c.edge_faces.size(s.edge_of[h]) == 1 && tail(F, h) != head(F, h)) {
        boundary.push_back(h);
        ++count[tail(F, h)];
      }
    const std::vector<Index> out_start = offsets_from_counts(count);
    std::vector<Index> outgoing(boundary.size());
    std::vector<Index> cursor(out_start.begin(), out_start.end() - 1);
    for (Index h : boundary) outgoing[cursor[tail(F, h)]++] = h;
    std::vector<char> used(std::size_t(3) * m, 0);
    auto any_unused_from = [&](Index v) -> Index {
      for (Index k = out_start[v]; k < out_start[v + 1]; ++k)
        if (!used[outgoing[k]]) return outgoing[k];
      return -1;
    };
    for (Index h0 : outgoing) {  // by start vertex, so loops start at their lowest free vertex
      if (used[h0]) continue;
      std::vector<Index> loop;
      for (Index h = h0; h >= 0;) {
        used[h] = 1;
        loop.push_back(tail(F, h));
        const Index u = head(F, h);
        Index next = next_boundary_in_fan(F, s, h, c.vertex_corners.size(u));
        if (next == h0) break;  // closed
        if (next < 0 || used[next]) next = u == tail(F, h0) ? -1 : any_unused_from(u);
        h = next;
      }
      c.boundary_loops.push_back(std::move(loop));
    }
  }

  // Components by union-find over face corners; isolated vertices stand alone.
  // Labels are numbered by their lowest vertex.
  std::vector<Index> parent(static_cast<std::size_t>(n));
  std::iota(parent.begin(), parent.end(), 0);
  for (Index f = 0; f < m; ++f)
    for (Index k = 1; k < 3; ++k) {
      const Index a = find_root(parent, F(f, 0)), b = find_root(parent, F(f, k));
      if (a != b) parent[std::max(a, b)] = std::min(a, b);
    }
  c.component.resize(n);
  std::vector<Index> label(static_cast<std::size_t>(n), -1);
  for (Index v = 0; v < n; ++v) {
    const Index r = find_root(parent, v);
    if (label[r] < 0) label[r] = c.num_components++;
    c.component[v] = label[r];
  }
}

}  // namespace

// std::call_once: concurrent first calls from several threads build once and
// the others wait; later calls cost one atomic load.
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
