// Merging arrangement vertices that stand for one point (morph/merge_close_vertices.h).
#include "morph/merge_close_vertices.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <limits>
#include <utility>

namespace paramorph::morph {

namespace {

using Vec3 = Eigen::Vector3d;

/// A great-circle arc p0 -> p1 (shorter than pi) ready for distance queries:
/// its unit normal and the inward normals of the half-planes through its ends.
struct Arc {
  Vec3 p0, p1, normal, after_p0, before_p1;
  Arc() = default;
  Arc(const Vec3& a, const Vec3& b) : p0(a), p1(b) {
    normal = a.cross(b).normalized();
    after_p0 = normal.cross(a);
    before_p1 = b.cross(normal);
  }
  /// Angular distance (as a chord, equal to the angle at these scales) from
  /// the unit vector P: inside the lune between the half-planes through the
  /// ends the nearest point is the foot on the circle, outside it an end.
  double distance(const Vec3& P) const {
    if (P.dot(after_p0) >= 0 && P.dot(before_p1) >= 0) return std::abs(P.dot(normal));
    return std::min((P - p0).norm(), (P - p1).norm());
  }
};

/// Where each arrangement vertex is and what it must stay close to.
class Supports {
 public:
  Supports(const SphereArrangement& ar, const SphereMapTopology& a, const SphereMapTopology& b)
      : ar_(ar), a_(a), b_(b) {
    // The arcs of the edges that have crossings, each built once.
    std::vector<Index> arc_of_a(std::size_t(a.edges.rows()), -1);
    std::vector<Index> arc_of_b(std::size_t(b.edges.rows()), -1);
    auto arc = [&](const SphereMapTopology& map, std::vector<Index>& arc_of, Index e) {
      if (arc_of[e] < 0) {
        arc_of[e] = Index(arcs_.size());
        arcs_.emplace_back(map.X.row(map.edges(e, 0)).transpose(),
                           map.X.row(map.edges(e, 1)).transpose());
      }
      return arc_of[e];
    };
    crossing_arcs_.resize(std::size_t(ar.num_crossings()));
    for (Index c = 0; c < ar.num_crossings(); ++c)
      crossing_arcs_[c] = {arc(a, arc_of_a, ar.crossing_edge_a[c]),
                           arc(b, arc_of_b, ar.crossing_edge_b[c])};
  }

  bool is_a(Index v) const { return v < ar_.num_a; }
  bool is_b(Index v) const { return v >= ar_.num_a && v < ar_.num_a + ar_.num_b; }
  /// The edge of A (of B) of a crossing; -1 for a vertex.
  Index edge_a(Index v) const {
    return is_a(v) || is_b(v) ? -1 : ar_.crossing_edge_a[v - ar_.num_a - ar_.num_b];
  }
  Index edge_b(Index v) const {
    return is_a(v) || is_b(v) ? -1 : ar_.crossing_edge_b[v - ar_.num_a - ar_.num_b];
  }

  Vec3 position(Index v) const {
    if (is_a(v)) return a_.X.row(v);
    if (is_b(v)) return b_.X.row(v - ar_.num_a);
    return ar_.crossing_position[std::size_t(v - ar_.num_a - ar_.num_b)];
  }

  /// How far P is from what v must stay on: its own point for a vertex of A
  /// or B, both arcs for a crossing.
  double deviation(Index v, const Vec3& P) const {
    if (is_a(v) || is_b(v)) return (P - position(v)).norm();
    const auto& [arc_a, arc_b] = crossing_arcs_[std::size_t(v - ar_.num_a - ar_.num_b)];
    return std::max(arcs_[arc_a].distance(P), arcs_[arc_b].distance(P));
  }

 private:
  const SphereArrangement& ar_;
  const SphereMapTopology& a_;
  const SphereMapTopology& b_;
  std::vector<Arc> arcs_;
  std::vector<std::pair<Index, Index>> crossing_arcs_;  // per crossing: its arcs of A and B
};

struct Candidate {
  double cost;
  Index u, v;
  bool operator<(const Candidate& o) const { return cost < o.cost; }
};

/// Union-find over arrangement vertices; each root knows its vertex of A and
/// of B (-1 if none), the edge of A and of B of its crossings (-1 if none),
/// its position's vertex, and its members (a circular list).
class Groups {
 public:
  Groups(Index n, const Supports& s)
      : s_(s), parent_(n), size_(n, 1), next_(n), a_(n, -1), b_(n, -1), ea_(n), eb_(n), rep_(n) {
    for (Index v = 0; v < n; ++v) {
      parent_[v] = next_[v] = rep_[v] = v;
      if (s.is_a(v)) a_[v] = v;
      if (s.is_b(v)) b_[v] = v;
      ea_[v] = s.edge_a(v);
      eb_[v] = s.edge_b(v);
    }
  }

  Index root(Index v) {
    while (parent_[v] != v) v = parent_[v] = parent_[parent_[v]];
    return v;
  }

  /// Merges the groups of u and v when the rule of the header allows it
  /// (any distance when `force`).
  bool try_merge(Index u, Index v, double tolerance, bool force = false) {
    Index ru = root(u), rv = root(v);
    if (ru == rv) return false;
    if (!may_merge({a_[ru], b_[ru], ea_[ru], eb_[ru]}, {a_[rv], b_[rv], ea_[rv], eb_[rv]}))
      return false;
    const double limit = force ? std::numeric_limits<double>::infinity() : tolerance;
    Index rep;
    double spread;
    if (a_[ru] >= 0 || a_[rv] >= 0) {
      rep = a_[ru] >= 0 ? a_[ru] : a_[rv];
      spread = worst(ru, rv, s_.position(rep), limit);
    } else if (b_[ru] >= 0 || b_[rv] >= 0) {
      rep = b_[ru] >= 0 ? b_[ru] : b_[rv];
      spread = worst(ru, rv, s_.position(rep), limit);
    } else {  // crossings only: the better placed of the two positions
      rep = rep_[ru];
      spread = worst(ru, rv, s_.position(rep), limit);
      const double other = worst(ru, rv, s_.position(rep_[rv]), std::min(limit, spread));
      if (other < spread) rep = rep_[rv], spread = other;
    }
    if (!(spread <= limit)) return false;
    if (size_[ru] < size_[rv]) std::swap(ru, rv);
    parent_[rv] = ru;
    size_[ru] += size_[rv];
    std::swap(next_[ru], next_[rv]);  // splices the two circular member lists
    a_[ru] = std::max(a_[ru], a_[rv]);
    b_[ru] = std::max(b_[ru], b_[rv]);
    ea_[ru] = std::max(ea_[ru], ea_[rv]);
    eb_[ru] = std::max(eb_[ru], eb_[rv]);
    rep_[ru] = rep;
    return true;
  }

  Index rep(Index root) const { return rep_[root]; }
  Index vertex_a(Index root) const { return a_[root]; }
  Index vertex_b(Index root) const { return b_[root]; }
  Index next(Index v) const { return next_[v]; }

 private:
  /// Largest deviation of the members of two groups from P (any value above
  /// `limit` once one member is past it).
  double worst(Index ru, Index rv, const Vec3& P, double limit) const {
    double d = 0;
    for (Index r : {ru, rv}) {
      Index v = r;
      do {
        d = std::max(d, s_.deviation(v, P));
        if (d > limit) return d;
        v = next_[v];
      } while (v != r);
    }
    return d;
  }

  const Supports& s_;
  std::vector<Index> parent_, size_, next_, a_, b_, ea_, eb_, rep_;
};

}  // namespace

bool may_merge(const ClusterAnchors& p, const ClusterAnchors& q) {
  if ((p.vertex_a >= 0 && q.vertex_a >= 0) || (p.vertex_b >= 0 && q.vertex_b >= 0)) return false;
  // Without a vertex of A, a group lies on at most one edge of A (else two of
  // A's arcs would share a piece next to their common vertex); same for B.
  const bool a_ok =
      p.vertex_a >= 0 || q.vertex_a >= 0 || p.edge_a < 0 || q.edge_a < 0 || p.edge_a == q.edge_a;
  const bool b_ok =
      p.vertex_b >= 0 || q.vertex_b >= 0 || p.edge_b < 0 || q.edge_b < 0 || p.edge_b == q.edge_b;
  return a_ok && b_ok;
}

ClusterAnchors VertexClusters::anchors(Index k) const {
  return {vertex_a[k], vertex_b[k], edge_a[k], edge_b[k]};
}

VertexClusters merge_close_vertices(const SphereArrangement& ar, const SphereMapTopology& a,
                                    const SphereMapTopology& b, double tolerance,
                                    const std::vector<std::pair<Index, Index>>& forced) {
  const Supports supports(ar, a, b);
  const Index n = ar.num_vertices();

  // Cost of merging a pair: the deviation it causes with the better of the
  // two positions (a vertex of A, else of B, takes precedence).
  auto pair_cost = [&](Index u, Index v) {
    const bool au = supports.is_a(u), av = supports.is_a(v);
    const bool bu = supports.is_b(u), bv = supports.is_b(v);
    if ((au && av) || (bu && bv)) return -1.0;
    if (au || av)
      return au ? supports.deviation(v, supports.position(u))
                : supports.deviation(u, supports.position(v));
    if (bu || bv)
      return bu ? supports.deviation(v, supports.position(u))
                : supports.deviation(u, supports.position(v));
    return std::min(supports.deviation(v, supports.position(u)),
                    supports.deviation(u, supports.position(v)));
  };
  std::vector<Candidate> candidates;
  for (Index cell = 0; cell < ar.num_cells(); ++cell) {
    const Index begin = ar.cell_start[cell], size = ar.cell_start[cell + 1] - begin;
    for (Index i = 0; i < size; ++i)
      for (Index j = i + 1; j < size; ++j) {
        const Index u = ar.corner[begin + i], v = ar.corner[begin + j];
        const bool side = j == i + 1 || (i == 0 && j == size - 1);
        // Each side is seen from its two cells: keep it once (u < v on one of them).
        if (side && u > v) continue;
        // Diagonals by distance alone (a cell pinched to a point).
        if (!side && !((supports.position(u) - supports.position(v)).norm() <= tolerance)) continue;
        const double cost = pair_cost(u, v);
        if (cost >= 0 && cost <= tolerance) candidates.push_back({cost, u, v});
      }
  }
  std::sort(candidates.begin(), candidates.end());

  Groups groups(n, supports);
  VertexClusters out;
  // Whether a pair may merge depends on what the groups hold by then (a
  // crossing of two edges of A joins a group once its vertex of A is in it),
  // so the pairs left over are tried again until nothing changes.
  for (bool changed = true; changed;) {
    changed = false;
    std::size_t kept = 0;
    for (const Candidate& c : candidates) {
      if (groups.root(c.u) == groups.root(c.v)) continue;
      if (groups.try_merge(c.u, c.v, tolerance))
        ++out.merged, changed = true;
      else
        candidates[kept++] = c;
    }
    candidates.resize(kept);
  }
  for (const auto& [u, v] : forced) out.merged += groups.try_merge(u, v, tolerance, true);

  // Clusters numbered by their smallest member: a cluster holding vertex i of
  // A gets number i, then the clusters of B's vertices, then of crossings.
  out.cluster = VectorXi::Constant(n, -1);
  std::vector<Index> root_cluster(std::size_t(n), -1);
  Index count = 0;
  for (Index v = 0; v < n; ++v) {
    const Index r = groups.root(v);
    if (root_cluster[r] < 0) root_cluster[r] = count++;
    out.cluster[v] = root_cluster[r];
  }
  out.position.resize(count, 3);
  out.vertex_a = VectorXi::Constant(count, -1);
  out.vertex_b = VectorXi::Constant(count, -1);
  out.edge_a = VectorXi::Constant(count, -1);
  out.edge_b = VectorXi::Constant(count, -1);
  out.representative.resize(count);
  for (Index v = 0; v < n; ++v) {
    const Index r = groups.root(v), k = out.cluster[v];
    if (r == v) {
      out.representative[k] = groups.rep(r);
      out.position.row(k) = supports.position(groups.rep(r)).transpose();
      out.vertex_a[k] = groups.vertex_a(r);
      if (groups.vertex_b(r) >= 0) out.vertex_b[k] = groups.vertex_b(r) - ar.num_a;
    }
    if (out.edge_a[k] < 0) out.edge_a[k] = supports.edge_a(v);
    if (out.edge_b[k] < 0) out.edge_b[k] = supports.edge_b(v);
  }
  for (Index k = 0; k < count; ++k) {
    if (out.vertex_a[k] >= 0) out.edge_a[k] = -1;
    if (out.vertex_b[k] >= 0) out.edge_b[k] = -1;
  }
  for (Index v = 0; v < n; ++v)
    if (groups.root(v) != v || groups.next(v) != v)  // members of merged groups
      out.max_deviation =
          std::max(out.max_deviation, supports.deviation(v, out.position.row(out.cluster[v])));
  return out;
}

}  // namespace paramorph::morph
