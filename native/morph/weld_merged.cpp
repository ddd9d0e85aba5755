// Welding a morph's merged mesh (morph/weld_merged.h).
#include "morph/weld_merged.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <tuple>
#include <vector>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include "mesh/bounding_box_diagonal.h"
#include "morph/sphere_predicates.h"

namespace paramorph::morph {

namespace {

/// Edges shorter than this share of the diagonal at one end or both are
/// tried for welding (the surface check decides).
constexpr double kWeldReach = 1e-4;

Eigen::Vector3d normal_of(const MatrixX3d& P, Index a, Index b, Index c) {
  return (P.row(b) - P.row(a)).cross(P.row(c) - P.row(a)).transpose();
}

/// Barycentric coordinates of p's projection into triangle (x0, x1, x2),
/// clamped to it.
Eigen::Vector3d barycentric(const Eigen::Vector3d& p, const Eigen::Vector3d& x0, const Eigen::Vector3d& x1,
                            const Eigen::Vector3d& x2) {
  const Eigen::Vector3d e1 = x1 - x0, e2 = x2 - x0, d = p - x0;
  const double a = e1.dot(e1), b = e1.dot(e2), c = e2.dot(e2), det = a * c - b * b;
  if (!(det > 0)) return Eigen::Vector3d(1.0, 0.0, 0.0);
  const double s = (c * e1.dot(d) - b * e2.dot(d)) / det, t = (a * e2.dot(d) - b * e1.dot(d)) / det;
  Eigen::Vector3d w(1.0 - s - t, s, t);
  w = w.cwiseMax(0.0);
  return w / w.sum();
}

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;

Kernel::Point_3 point(const MatrixX3d& P, Index v) { return {P(v, 0), P(v, 1), P(v, 2)}; }

/// Sampled one-sided distance from the faces `from` (vertices, edge
/// midpoints, centroids) to the faces `to`, positions P and Q.
double faces_distance(const std::vector<std::array<Index, 3>>& from, const MatrixX3d& P,
                      const std::vector<std::array<Index, 3>>& to, const MatrixX3d& Q) {
  std::vector<Kernel::Triangle_3> triangles;
  for (const auto& t : to) triangles.emplace_back(point(Q, t[0]), point(Q, t[1]), point(Q, t[2]));
  double worst = 0;
  for (const auto& t : from) {
    const Eigen::RowVector3d a = P.row(t[0]), b = P.row(t[1]), c = P.row(t[2]);
    for (const Eigen::RowVector3d& s : {a, b, c, Eigen::RowVector3d(0.5 * (a + b)), Eigen::RowVector3d(0.5 * (b + c)),
                                        Eigen::RowVector3d(0.5 * (c + a)), Eigen::RowVector3d((a + b + c) / 3.0)}) {
      const Kernel::Point_3 q(s[0], s[1], s[2]);
      double best = std::numeric_limits<double>::infinity();
      for (const auto& tri : triangles)
        best = std::min(best, tri.is_degenerate() ? CGAL::to_double(CGAL::squared_distance(q, tri.vertex(0)))
                                                  : CGAL::to_double(CGAL::squared_distance(q, tri)));
      worst = std::max(worst, best);
    }
  }
  return std::sqrt(worst);
}

/// Distance from p to face t of (V, F) (the triangle, not its plane: a
/// merged face must stay inside one face of each input, where the carry
/// reads its corners).
double triangle_distance(const Eigen::RowVector3d& p, const MatrixX3d& V, const MatrixX3i& F, Index t) {
  const Kernel::Triangle_3 tri(point(V, F(t, 0)), point(V, F(t, 1)), point(V, F(t, 2)));
  const Kernel::Point_3 q(p[0], p[1], p[2]);
  return std::sqrt(CGAL::to_double(tri.is_degenerate() ? CGAL::squared_distance(q, tri.vertex(0))
                                                        : CGAL::squared_distance(q, tri)));
}

/// A merged face keeps the overlay's promise on the sphere: positively
/// oriented (exactly) and no thinner than the overlay leaves its triangles
/// (kMinAltitudeInTolerances times its merge tolerance), so its orientation
/// reads the same in floating point.
bool well_placed_on_sphere(const MergedTopology& g, Index a, Index b, Index c) {
  if (orientation(g.V.row(a).data(), g.V.row(b).data(), g.V.row(c).data()) <= 0) return false;
  const Eigen::Vector3d p = g.V.row(a).transpose(), q = g.V.row(b).transpose(), r = g.V.row(c).transpose();
  const double longest = std::max({(q - p).norm(), (r - q).norm(), (p - r).norm()});
  const double altitude = (q - p).cross(r - p).norm() / std::max(longest, 1e-300);
  return altitude >= kMinAltitudeInTolerances * g.stats.merge_tolerance;
}

struct Mesh {
  MatrixX3i F;
  std::vector<char> face_alive, vertex_alive;
  std::vector<std::vector<Index>> faces_of;

  std::vector<Index> alive_faces_of(Index v) const {
    std::vector<Index> out;
    for (Index f : faces_of[v])
      if (face_alive[f] && (F(f, 0) == v || F(f, 1) == v || F(f, 2) == v)) out.push_back(f);
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
  }
  std::vector<Index> neighbours(Index v) const {
    std::vector<Index> out;
    for (Index f : alive_faces_of(v))
      for (int c = 0; c < 3; ++c)
        if (F(f, c) != v) out.push_back(F(f, c));
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
  }
  bool has(Index f, Index v) const { return F(f, 0) == v || F(f, 1) == v || F(f, 2) == v; }
};

}  // namespace

WeldStats weld_merged(MergedTopology& g, MatrixX3d& source_positions, MatrixX3d& target_positions,
                      const MatrixX3d& VA, const MatrixX3i& FA, const MatrixX3d& VB, const MatrixX3i& FB,
                      double tolerance, Progress* progress) {
  struct Ends {
    MatrixX3d& source;
    MatrixX3d& target;
  } m{source_positions, target_positions};
  const MatrixX3i& fa = FA;
  const MatrixX3i& fb = FB;
  const Index n = Index(g.V.rows()), k = Index(g.F.rows());
  const double diag_a = bounding_box_diagonal(VA), diag_b = bounding_box_diagonal(VB);
  const double reach_a = tolerance * diag_a, reach_b = tolerance * diag_b;
  const double sliver_a = 2 * kSliverArea * diag_a * diag_a, sliver_b = 2 * kSliverArea * diag_b * diag_b;
  WeldStats stats;
  stats.faces_before = k;

  Mesh mesh{g.F, std::vector<char>(k, 1), std::vector<char>(n, 1), std::vector<std::vector<Index>>(n)};
  for (Index f = 0; f < k; ++f)
    for (int c = 0; c < 3; ++c) mesh.faces_of[g.F(f, c)].push_back(f);
  auto is_sliver = [&](Index a, Index b, Index c) {
    return normal_of(m.source, a, b, c).norm() < sliver_a || normal_of(m.target, a, b, c).norm() < sliver_b;
  };
  for (Index f = 0; f < k; ++f) stats.slivers_before += is_sliver(g.F(f, 0), g.F(f, 1), g.F(f, 2));

  std::vector<Index> a_of(n, -1), b_of(n, -1);
  for (Index i = 0; i < Index(g.vertex_of_a.size()); ++i) a_of[g.vertex_of_a[i]] = i;
  for (Index i = 0; i < Index(g.vertex_of_b.size()); ++i) b_of[g.vertex_of_b[i]] = i;
  std::vector<char> rebary(k, 0);  // faces whose corner coordinates must be recomputed

  // 1. Collapses, shortest first: edges shorter than kWeldReach times the
  // diagonal at one end or both, each taken when the surface it leaves stays
  // within `tolerance` of both inputs (sampled against the faces of A and B
  // under it, and the old faces against the new).
  std::vector<std::tuple<double, Index, Index>> short_edges;
  for (Index f = 0; f < k; ++f)
    for (int c = 0; c < 3; ++c) {
      const Index u = g.F(f, c), v = g.F(f, (c + 1) % 3);
      if (u > v) continue;  // each interior edge once (its other face has it as v -> u)
      const double la = (m.source.row(u) - m.source.row(v)).norm() / diag_a;
      const double lb = (m.target.row(u) - m.target.row(v)).norm() / diag_b;
      if (std::min(la, lb) <= kWeldReach) short_edges.emplace_back(std::max(la, lb), u, v);
    }
  std::sort(short_edges.begin(), short_edges.end());
  std::size_t visited = 0;
  for (const auto& [length, u0, v0] : short_edges) {
    (void)length;
    if (progress && ++visited % 256 == 0)
      progress->report(0.9 * double(visited) / double(short_edges.size()), "welding");
    if (!mesh.vertex_alive[u0] || !mesh.vertex_alive[v0]) continue;
    if ((a_of[u0] >= 0 && a_of[v0] >= 0) || (b_of[u0] >= 0 && b_of[v0] >= 0)) continue;  // one input's two vertices
    // Keep the vertex tied to more inputs; an input's vertex keeps its place on that input.
    const int anchors_u = (a_of[u0] >= 0) + (b_of[u0] >= 0), anchors_v = (a_of[v0] >= 0) + (b_of[v0] >= 0);
    // Ties keep the lower index (u0 < v0): A's vertices, first among the merged
    // ones (vertex_of_a[i] == i), are never the one dropped.
    const Index keep = anchors_u >= anchors_v ? u0 : v0, drop = keep == u0 ? v0 : u0;
    const Eigen::RowVector3d at_a = a_of[drop] >= 0 ? m.source.row(drop) : m.source.row(keep);
    const Eigen::RowVector3d at_b = b_of[drop] >= 0 ? m.target.row(drop) : m.target.row(keep);
    const std::vector<Index> around_drop = mesh.alive_faces_of(drop), around_keep = mesh.alive_faces_of(keep);
    std::vector<Index> shared;
    for (Index f : around_drop)
      if (mesh.has(f, keep)) shared.push_back(f);
    if (shared.size() != 2) continue;
    // Link condition: the two ends' common neighbours are the shared faces' third corners.
    std::vector<Index> common, third;
    const std::vector<Index> nd = mesh.neighbours(drop), nk = mesh.neighbours(keep);
    std::set_intersection(nd.begin(), nd.end(), nk.begin(), nk.end(), std::back_inserter(common));
    for (Index f : shared)
      for (int c = 0; c < 3; ++c)
        if (mesh.F(f, c) != drop && mesh.F(f, c) != keep) third.push_back(mesh.F(f, c));
    std::sort(third.begin(), third.end());
    if (common != third) continue;
    // The faces before and after; no face turns over (on the sphere, exactly,
    // or at either end) and the surface stays within reach of A and B.
    std::vector<Index> region = around_drop;
    region.insert(region.end(), around_keep.begin(), around_keep.end());
    std::sort(region.begin(), region.end());
    region.erase(std::unique(region.begin(), region.end()), region.end());
    // Local copies: the region's vertices before and after (keep moved).
    std::vector<Index> local(region.size() * 3);
    for (std::size_t r = 0; r < region.size(); ++r)
      for (int c = 0; c < 3; ++c) local[3 * r + std::size_t(c)] = mesh.F(region[r], c);
    std::sort(local.begin(), local.end());
    local.erase(std::unique(local.begin(), local.end()), local.end());
    auto index_of = [&](Index v) { return Index(std::lower_bound(local.begin(), local.end(), v) - local.begin()); };
    MatrixX3d old_a(Index(local.size()), 3), old_b(Index(local.size()), 3);
    for (std::size_t i = 0; i < local.size(); ++i) old_a.row(Index(i)) = m.source.row(local[i]), old_b.row(Index(i)) = m.target.row(local[i]);
    MatrixX3d new_a = old_a, new_b = old_b;
    new_a.row(index_of(keep)) = at_a, new_b.row(index_of(keep)) = at_b;
    std::vector<std::array<Index, 3>> before, after, under_a, under_b;
    bool sound = true;
    for (Index f : region) {
      const std::array<Index, 3> old{index_of(mesh.F(f, 0)), index_of(mesh.F(f, 1)), index_of(mesh.F(f, 2))};
      before.push_back(old);
      under_a.push_back({fa(g.source_face_a[f], 0), fa(g.source_face_a[f], 1), fa(g.source_face_a[f], 2)});
      under_b.push_back({fb(g.source_face_b[f], 0), fb(g.source_face_b[f], 1), fb(g.source_face_b[f], 2)});
      if (std::find(shared.begin(), shared.end(), f) != shared.end()) continue;
      std::array<Index, 3> c{mesh.F(f, 0), mesh.F(f, 1), mesh.F(f, 2)};
      for (auto& x : c) x = index_of(x == drop ? keep : x);
      after.push_back(c);
      // Each corner stays within reach of its face's faces of A and B (where the carry reads it).
      for (const Index x : c) {
        if (triangle_distance(new_a.row(x), VA, fa, g.source_face_a[f]) > reach_a ||
            triangle_distance(new_b.row(x), VB, fb, g.source_face_b[f]) > reach_b)
          sound = false;
      }
      const Eigen::Vector3d was_a = normal_of(old_a, old[0], old[1], old[2]), was_b = normal_of(old_b, old[0], old[1], old[2]);
      const Eigen::Vector3d now_a = normal_of(new_a, c[0], c[1], c[2]), now_b = normal_of(new_b, c[0], c[1], c[2]);
      if ((was_a.norm() >= sliver_a && now_a.dot(was_a) <= 0) || (was_b.norm() >= sliver_b && now_b.dot(was_b) <= 0))
        sound = false;
      const Index s0 = local[std::size_t(c[0])], s1 = local[std::size_t(c[1])], s2 = local[std::size_t(c[2])];
      if (!well_placed_on_sphere(g, s0, s1, s2)) sound = false;
    }
    if (!sound) continue;
    if (faces_distance(after, new_a, under_a, VA) > reach_a || faces_distance(after, new_b, under_b, VB) > reach_b ||
        faces_distance(before, old_a, after, new_a) > reach_a || faces_distance(before, old_b, after, new_b) > reach_b)
      continue;
    // Weld: drop's faces now use keep; the two shared faces go.
    for (Index f : shared) mesh.face_alive[f] = 0;
    for (Index f : around_drop) {
      if (!mesh.face_alive[f]) continue;
      for (int c = 0; c < 3; ++c)
        if (mesh.F(f, c) == drop) mesh.F(f, c) = keep;
      mesh.faces_of[keep].push_back(f);
    }
    for (Index f : mesh.alive_faces_of(keep)) rebary[f] = 1;
    mesh.vertex_alive[drop] = 0;
    m.source.row(keep) = at_a, m.target.row(keep) = at_b;
    if (a_of[drop] >= 0) {
      a_of[keep] = a_of[drop];
      g.face_a[keep] = g.face_a[drop], g.bary_a.row(keep) = g.bary_a.row(drop);
    }
    if (b_of[drop] >= 0) {
      b_of[keep] = b_of[drop];
      g.face_b[keep] = g.face_b[drop], g.bary_b.row(keep) = g.bary_b.row(drop);
    }
    ++stats.collapsed_edges;
  }

  // 2. Flips of slivers inside a cell.
  auto better = [&](Index a, Index b, Index c, double floor_a, double floor_b) {
    return normal_of(m.source, a, b, c).norm() > floor_a && normal_of(m.target, a, b, c).norm() > floor_b &&
           well_placed_on_sphere(g, a, b, c);
  };
  for (int pass = 0; pass < 3; ++pass) {
    Index flipped = 0;
    for (Index f = 0; f < k; ++f) {
      if (!mesh.face_alive[f] || !is_sliver(mesh.F(f, 0), mesh.F(f, 1), mesh.F(f, 2))) continue;
      // Its longest side at the end where it is flattest.
      const bool flat_a = normal_of(m.source, mesh.F(f, 0), mesh.F(f, 1), mesh.F(f, 2)).norm() < sliver_a;
      const MatrixX3d& P = flat_a ? m.source : m.target;
      int side = 0;
      double longest = -1;
      for (int c = 0; c < 3; ++c) {
        const double l = (P.row(mesh.F(f, (c + 1) % 3)) - P.row(mesh.F(f, (c + 2) % 3))).norm();
        if (l > longest) longest = l, side = c;
      }
      const Index opposite = mesh.F(f, side), a = mesh.F(f, (side + 1) % 3), b = mesh.F(f, (side + 2) % 3);
      Index other = -1;
      for (Index h : mesh.alive_faces_of(a))
        if (h != f && mesh.has(h, b)) other = h;
      if (other < 0 || g.source_face_a[other] != g.source_face_a[f] || g.source_face_b[other] != g.source_face_b[f])
        continue;
      Index across = -1;
      for (int c = 0; c < 3; ++c)
        if (mesh.F(other, c) != a && mesh.F(other, c) != b) across = mesh.F(other, c);
      const std::vector<Index> no = mesh.neighbours(opposite);
      if (std::binary_search(no.begin(), no.end(), across)) continue;  // the new side exists already
      // f = (opposite, a, b), other = (b, a, across): new faces (opposite, a, across), (opposite, across, b).
      const double worst_a = std::min(normal_of(m.source, opposite, a, b).norm(), normal_of(m.source, b, a, across).norm());
      const double worst_b = std::min(normal_of(m.target, opposite, a, b).norm(), normal_of(m.target, b, a, across).norm());
      if (!better(opposite, a, across, worst_a, worst_b) || !better(opposite, across, b, worst_a, worst_b)) continue;
      // Corner coordinates: every corner is one of the cell's, already known in f or other.
      auto corner = [&](Index v, int side_ab) {
        for (Index h : {f, other})
          for (int c = 0; c < 3; ++c)
            if (mesh.F(h, c) == v) {
              const auto& cb = side_ab == 0 ? g.corner_bary_a : g.corner_bary_b;
              return Eigen::Vector3d(cb(h, 3 * c), cb(h, 3 * c + 1), cb(h, 3 * c + 2));
            }
        return Eigen::Vector3d(1.0, 0.0, 0.0);
      };
      const std::array<std::array<Index, 3>, 2> made{{{opposite, a, across}, {opposite, across, b}}};
      std::array<std::array<Eigen::Vector3d, 3>, 2> ca, cb;
      for (int t = 0; t < 2; ++t)
        for (int c = 0; c < 3; ++c) ca[t][c] = corner(made[t][c], 0), cb[t][c] = corner(made[t][c], 1);
      const Index targets[2] = {f, other};
      for (int t = 0; t < 2; ++t) {
        const Index h = targets[t];
        for (int c = 0; c < 3; ++c) {
          mesh.F(h, c) = made[t][c];
          for (int j = 0; j < 3; ++j) g.corner_bary_a(h, 3 * c + j) = ca[t][c][j], g.corner_bary_b(h, 3 * c + j) = cb[t][c][j];
        }
      }
      mesh.faces_of[opposite].push_back(other);
      mesh.faces_of[across].push_back(f);
      rebary[f] = rebary[other] = char(rebary[f] || rebary[other]);  // a corner copied from a welded face
      ++flipped;
    }
    stats.flipped_edges += flipped;
    if (!flipped) break;
  }

  // 3. Compact, and the welded faces' corner coordinates from their positions.
  VectorXi new_index = VectorXi::Constant(n, -1);
  Index vertices = 0;
  for (Index v = 0; v < n; ++v)
    if (mesh.vertex_alive[v]) new_index[v] = vertices++;
  MergedTopology out = g;
  out.V.resize(vertices, 3), out.face_a.resize(vertices), out.face_b.resize(vertices);
  out.bary_a.resize(vertices, 3), out.bary_b.resize(vertices, 3), out.vertex_kind.resize(vertices);
  MatrixX3d source(vertices, 3), target(vertices, 3);
  for (Index v = 0; v < n; ++v) {
    const Index w = new_index[v];
    if (w < 0) continue;
    out.V.row(w) = g.V.row(v), out.face_a[w] = g.face_a[v], out.face_b[w] = g.face_b[v];
    out.bary_a.row(w) = g.bary_a.row(v), out.bary_b.row(w) = g.bary_b.row(v);
    out.vertex_kind[w] = a_of[v] >= 0 && b_of[v] >= 0 ? 2 : a_of[v] >= 0 ? 0 : b_of[v] >= 0 ? 1 : g.vertex_kind[v];
    source.row(w) = m.source.row(v), target.row(w) = m.target.row(v);
    if (a_of[v] >= 0) out.vertex_of_a[a_of[v]] = w;
    if (b_of[v] >= 0) out.vertex_of_b[b_of[v]] = w;
  }
  Index faces = 0;
  for (Index f = 0; f < k; ++f) faces += mesh.face_alive[f];
  out.F.resize(faces, 3), out.source_face_a.resize(faces), out.source_face_b.resize(faces);
  out.corner_bary_a.resize(faces, 9), out.corner_bary_b.resize(faces, 9);
  Index j = 0;
  for (Index f = 0; f < k; ++f) {
    if (!mesh.face_alive[f]) continue;
    out.source_face_a[j] = g.source_face_a[f], out.source_face_b[j] = g.source_face_b[f];
    out.corner_bary_a.row(j) = g.corner_bary_a.row(f), out.corner_bary_b.row(j) = g.corner_bary_b.row(f);
    for (int c = 0; c < 3; ++c) {
      const Index v = mesh.F(f, c);
      out.F(j, c) = new_index[v];
      if (!rebary[f]) continue;
      const Index ta = g.source_face_a[f], tb = g.source_face_b[f];
      const Eigen::Vector3d wa = barycentric(m.source.row(v).transpose(), VA.row(fa(ta, 0)).transpose(),
                                             VA.row(fa(ta, 1)).transpose(), VA.row(fa(ta, 2)).transpose());
      const Eigen::Vector3d wb = barycentric(m.target.row(v).transpose(), VB.row(fb(tb, 0)).transpose(),
                                             VB.row(fb(tb, 1)).transpose(), VB.row(fb(tb, 2)).transpose());
      for (int q = 0; q < 3; ++q) out.corner_bary_a(j, 3 * c + q) = wa[q], out.corner_bary_b(j, 3 * c + q) = wb[q];
    }
    ++j;
  }
  g = std::move(out);
  m.source = std::move(source), m.target = std::move(target);
  stats.faces_after = faces;
  for (Index f = 0; f < faces; ++f) stats.slivers_after += is_sliver(g.F(f, 0), g.F(f, 1), g.F(f, 2));
  return stats;
}

}  // namespace paramorph::morph
