// Spherical overlay (morph/spherical_overlay.h): input checks, the three steps
// (arrangement, merging, triangulation), barycentric coordinates, and a final
// check of the merged mesh that the stats report.
#include "morph/spherical_overlay.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "common/errors.h"
#include "mesh/face_neighbors.h"
#include "mesh/validate.h"
#include "morph/merge_close_vertices.h"
#include "morph/sphere_arrangement.h"
#include "morph/sphere_predicates.h"
#include "morph/triangulate_spherical_polygon.h"

namespace paramorph::morph {

namespace {

using Vec3 = Eigen::Vector3d;
using Clock = std::chrono::steady_clock;
constexpr double kPi = 3.14159265358979323846;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

/// Re-raises the MeshError being handled with the map's name in front, keeping its type.
[[noreturn]] void rethrow_named(const std::string& name) {
  try {
    throw;
  } catch (const NotClosedError& e) {
    throw NotClosedError(name + ": " + e.what());
  } catch (const NotGenusZeroError& e) {
    throw NotGenusZeroError(name + ": " + e.what());
  } catch (const DisconnectedError& e) {
    throw DisconnectedError(name + ": " + e.what());
  } catch (const NonManifoldError& e) {
    throw NonManifoldError(name + ": " + e.what());
  } catch (const DegenerateFaceError& e) {
    throw DegenerateFaceError(name + ": " + e.what());
  } catch (const InvalidInputError& e) {
    throw InvalidInputError(name + ": " + e.what());
  }
}

/// Checks one sphere map (see overlay()) and builds the topology the walk needs.
SphereMapTopology prepare(const MatrixX3d& sphere, const MatrixX3i& F, const std::string& name) {
  SphereMapTopology map;
  try {
    validate_arrays(sphere, F);
    const TriMesh mesh(sphere, F);
    // No area threshold: a fold-free map may squeeze faces far below any
    // relative tolerance; the exact orientation test below is what counts.
    require_closed_genus0(validate(mesh, 0.0));
    std::vector<Index> off;
    double worst = 0;
    for (Index v = 0; v < sphere.rows(); ++v) {
      const double error = std::abs(sphere.row(v).norm() - 1.0);
      if (!(error <= 1e-9)) off.push_back(v), worst = std::max(worst, error);
    }
    PM_REQUIRE(off.empty(), InvalidInputError, off.size(),
               " vertices are not unit vectors (| |v| - 1 | up to ", worst, "; vertices ",
               format_indices(off), "): give points on the unit sphere");
    map.X = sphere.rowwise().normalized();
    std::vector<Index> folded;
    double area = 0;
    for (Index f = 0; f < F.rows(); ++f) {
      const Vec3 a = map.X.row(F(f, 0)), b = map.X.row(F(f, 1)), c = map.X.row(F(f, 2));
      if (orientation(a.data(), b.data(), c.data()) <= 0) folded.push_back(f);
      area += spherical_triangle_area(a, b, c);
    }
    PM_REQUIRE(folded.empty(), InvalidInputError, "the map folds ", folded.size(),
               " faces (det <= 0: ", format_indices(folded), "); give a fold-free sphere map");
    // All faces positive: the map covers the sphere a whole number of times.
    const double covers = area / (4 * kPi);
    PM_REQUIRE(std::abs(covers - 1.0) < 0.5, InvalidInputError, "the map covers the sphere ",
               std::lround(covers), " times (its faces' spherical area is ", area,
               "); it must cover it once");
    map.F = F;
    map.neighbors = face_neighbors(mesh);
    map.face_edges = mesh.face_edges();
    map.edges = mesh.edges();
  } catch (const MeshError&) {
    rethrow_named(name);
  }
  return map;
}

/// Smallest altitude (as a chord, the angle at that scale) of the map's faces:
/// twice the flat triangle's area over its longest edge.
double thinnest_face(const SphereMapTopology& map) {
  double thinnest = std::numeric_limits<double>::infinity();
  for (Index f = 0; f < map.F.rows(); ++f) {
    const Vec3 a = map.X.row(map.F(f, 0)), b = map.X.row(map.F(f, 1)), c = map.X.row(map.F(f, 2));
    const double longest =
        std::max({(b - a).squaredNorm(), (c - b).squaredNorm(), (a - c).squaredNorm()});
    thinnest = std::min(thinnest, (b - a).cross(c - a).norm() / std::sqrt(longest));
  }
  return thinnest;
}

/// Barycentric coordinates of P in face (s0, s1, s2) by central projection,
/// rounding's small negatives clamped (the nearest corner if nothing is left).
Vec3 central_bary(const Vec3& P, const Vec3& s0, const Vec3& s1, const Vec3& s2) {
  Vec3 w(P.dot(s1.cross(s2)), P.dot(s2.cross(s0)), P.dot(s0.cross(s1)));
  w = w.cwiseMax(0.0);
  const double sum = w.sum();
  if (sum > 0) return w / sum;
  Vec3 d((P - s0).squaredNorm(), (P - s1).squaredNorm(), (P - s2).squaredNorm());
  Vec3 unit = Vec3::Zero();
  Eigen::Index k;
  d.minCoeff(&k);
  unit[k] = 1;
  return unit;
}

/// Weights (of p0, of p1) of the point of the chord p0 p1 on the ray through
/// P. Exactly antisymmetric in the ends: both faces of an edge get one answer.
Eigen::Vector2d edge_bary(const Vec3& P, const Vec3& p0, const Vec3& p1) {
  const Vec3 n = p0.cross(p1);
  Eigen::Vector2d w(P.cross(p1).dot(n), p0.cross(P).dot(n));
  w = w.cwiseMax(0.0);
  const double sum = w.sum();
  if (sum > 0) return w / sum;
  return (P - p0).squaredNorm() <= (P - p1).squaredNorm() ? Eigen::Vector2d(1, 0)
                                                          : Eigen::Vector2d(0, 1);
}

/// Where a cluster lies in one map: on a vertex, on an edge, or inside a face.
struct Support {
  Index vertex = -1, edge = -1, face = -1;
};

/// A merged vertex as a combination of one map's vertices (weights summing to
/// 1): its vertex, the two ends of its edge, or the corners of its face.
struct Combination {
  Index vertex[3] = {-1, -1, -1};
  double weight[3] = {0, 0, 0};
};

/// Locating merged vertices in one map (A or B): a combination of its
/// vertices per merged vertex, read off in any face that has those vertices.
class Locator {
 public:
  explicit Locator(const SphereMapTopology& map) : map_(map) {
    vertex_corner_.assign(std::size_t(map.X.rows()), -1);
    edge_corner_.assign(std::size_t(map.edges.rows()), -1);
    for (Index f = 0; f < map.F.rows(); ++f)
      for (int k = 0; k < 3; ++k) {
        vertex_corner_[map.F(f, k)] = 3 * f + k;
        edge_corner_[map.face_edges(f, k)] = 3 * f + k;
      }
  }

  /// The combination for a point P with support s, and a face holding it.
  Combination combine(const Support& s, const Vec3& P, Index& face) const {
    Combination c;
    if (s.vertex >= 0) {
      face = vertex_corner_[s.vertex] / 3;
      c.vertex[0] = s.vertex, c.weight[0] = 1;
    } else if (s.edge >= 0) {
      face = edge_corner_[s.edge] / 3;
      const Index p0 = map_.edges(s.edge, 0), p1 = map_.edges(s.edge, 1);
      const Eigen::Vector2d w = edge_bary(P, map_.X.row(p0), map_.X.row(p1));
      c.vertex[0] = p0, c.weight[0] = w[0];
      c.vertex[1] = p1, c.weight[1] = w[1];
    } else {
      face = s.face;
      const Vec3 w = central(P, face);
      for (int k = 0; k < 3; ++k) c.vertex[k] = map_.F(face, k), c.weight[k] = w[k];
    }
    return c;
  }

  /// Coordinates in face f of the point with combination c (at P): read off
  /// when f has all of c's vertices (exact corners, the same weights from
  /// both faces of an edge), central projection otherwise.
  Vec3 in_face(const Combination& c, const Vec3& P, Index f) const {
    Vec3 w = Vec3::Zero();
    int found = 0, needed = 0;
    for (int j = 0; j < 3; ++j) {
      if (c.vertex[j] < 0) continue;
      ++needed;
      for (int k = 0; k < 3; ++k)
        if (map_.F(f, k) == c.vertex[j]) w[k] = c.weight[j], ++found;
    }
    return found == needed ? w : central(P, f);
  }

 private:
  Vec3 central(const Vec3& P, Index f) const {
    return central_bary(P, map_.X.row(map_.F(f, 0)), map_.X.row(map_.F(f, 1)),
                        map_.X.row(map_.F(f, 2)));
  }

  const SphereMapTopology& map_;
  std::vector<Index> vertex_corner_, edge_corner_;  // 3 f + k of one face naming it
};

/// Splits a closed walk of cluster ids into simple cycles (a cell pinched at
/// a merged vertex) and drops consecutive repeats and cycles of fewer than 3.
template <typename Emit>
void simple_cycles(std::vector<Index>& walk, std::vector<Index>& stack, Emit&& emit) {
  // Consecutive repeats (a merged side), the walk seen as a cycle.
  std::size_t size = 0;
  for (std::size_t k = 0; k < walk.size(); ++k)
    if (size == 0 || walk[k] != walk[size - 1]) walk[size++] = walk[k];
  while (size > 1 && walk[size - 1] == walk[0]) --size;
  walk.resize(size);
  stack.clear();
  for (Index v : walk) {
    std::size_t at = stack.size();
    for (std::size_t k = 0; k < stack.size(); ++k)
      if (stack[k] == v) at = k;
    if (at == stack.size()) {
      stack.push_back(v);
      continue;
    }
    if (stack.size() - at >= 3) emit(stack.data() + at, int(stack.size() - at));
    stack.resize(at + 1);
  }
  if (stack.size() >= 3) emit(stack.data(), int(stack.size()));
}

/// The merged triangles of every cell, with their faces of A and B.
struct CellTriangles {
  std::vector<Eigen::Matrix<Index, 1, 3>> triangles;
  std::vector<Index> face_a, face_b;
  Index degenerate = 0;  ///< cell pieces without a positive triangulation
};

/// Repair rounds at most, and how far apart (in tolerances) a pair of
/// vertices of a turned-over cell may be to be merged by the repair.
constexpr int kRepairRounds = 8;
constexpr double kRepairReach = 16.0;

/// Each cell with its corners replaced by their clusters, split where it is
/// pinched, triangulated. For each piece without a positive triangulation the
/// closest pair of its vertices that may be merged (may_merge(), at most
/// `reach` apart) is added to `repair`.
CellTriangles triangulate_cells(const SphereArrangement& ar, const VertexClusters& clusters,
                                double reach, std::vector<std::pair<Index, Index>>& repair) {
  CellTriangles out;
  out.triangles.reserve(std::size_t(2 * ar.num_cells()));
  out.face_a.reserve(out.triangles.capacity());
  out.face_b.reserve(out.triangles.capacity());
  std::vector<Index> walk, stack;
  Vec3 corners[kMaxPolygonCorners];
  std::array<int, 3> local[kMaxPolygonCorners];
  for (Index cell = 0; cell < ar.num_cells(); ++cell) {
    walk.clear();
    for (Index k = ar.cell_start[cell]; k < ar.cell_start[cell + 1]; ++k)
      walk.push_back(clusters.cluster[ar.corner[k]]);
    simple_cycles(walk, stack, [&](const Index* ids, int n) {
      for (int k = 0; k < n; ++k) corners[k] = clusters.position.row(ids[k]);
      if (!triangulate_spherical_polygon(corners, n, local)) {
        ++out.degenerate;
        double closest = reach;
        std::pair<Index, Index> pair{-1, -1};
        for (int i = 0; i < n; ++i)
          for (int j = i + 1; j < n; ++j) {
            const Index ci = ids[i], cj = ids[j];
            if (!may_merge(clusters.anchors(ci), clusters.anchors(cj))) continue;
            const double d = (corners[i] - corners[j]).norm();
            if (d <= closest)
              closest = d, pair = {clusters.representative[ci], clusters.representative[cj]};
          }
        if (pair.first >= 0) repair.push_back(pair);
      }
      for (int t = 0; t < n - 2; ++t) {
        out.triangles.push_back({ids[local[t][0]], ids[local[t][1]], ids[local[t][2]]});
        out.face_a.push_back(ar.cell_face_a[cell]);
        out.face_b.push_back(ar.cell_face_b[cell]);
      }
    });
  }
  return out;
}

/// Altitude of the triangle (a, b, c) of nearby unit vectors: twice its flat
/// area over its longest side (edge differences: exact enough for tiny ones).
double altitude(const Vec3& a, const Vec3& b, const Vec3& c) {
  const double longest =
      std::max({(b - a).squaredNorm(), (c - b).squaredNorm(), (a - c).squaredNorm()});
  return longest > 0 ? (b - a).cross(c - a).norm() / std::sqrt(longest) : 0.0;
}

/// How far apart (in tolerances) two corners of a sliver may be to be merged.
constexpr double kSliverReach = 2.0;

/// Smallest altitude of the merged triangles, and how many are thinner than
/// `thin`. With `repair`, for each of those the closest pair of its corners
/// that may be merged, at most `reach` apart, is added to it.
double find_slivers(const CellTriangles& cells, const VertexClusters& clusters, double thin,
                    double reach, Index& count,
                    std::vector<std::pair<Index, Index>>* repair = nullptr) {
  double thinnest = std::numeric_limits<double>::infinity();
  count = 0;
  for (const auto& t : cells.triangles) {
    const Vec3 p[3] = {clusters.position.row(t[0]), clusters.position.row(t[1]),
                       clusters.position.row(t[2])};
    const double h = altitude(p[0], p[1], p[2]);
    thinnest = std::min(thinnest, h);
    if (!(h < thin)) continue;
    ++count;
    if (!repair) continue;
    double closest = reach;
    std::pair<Index, Index> pair{-1, -1};
    for (int i = 0; i < 3; ++i) {
      const int j = (i + 1) % 3;
      if (!may_merge(clusters.anchors(t[i]), clusters.anchors(t[j]))) continue;
      const double d = (p[i] - p[j]).norm();
      if (d <= closest)
        closest = d, pair = {clusters.representative[t[i]], clusters.representative[t[j]]};
    }
    if (pair.first >= 0) repair->push_back(pair);
  }
  return thinnest;
}

/// Half-edges of F without exactly one twin running the other way (0 for a
/// closed, consistently oriented manifold), counted per vertex's out-edges.
Index open_half_edges(const MatrixX3i& F, Index vertices) {
  std::vector<Index> start(std::size_t(vertices) + 1, 0);
  for (Index t = 0; t < F.rows(); ++t)
    for (int k = 0; k < 3; ++k) ++start[std::size_t(F(t, k)) + 1];
  for (Index v = 0; v < vertices; ++v) start[v + 1] += start[v];
  std::vector<Index> head(std::size_t(3) * F.rows()), cursor(start.begin(), start.end() - 1);
  for (Index t = 0; t < F.rows(); ++t)
    for (int k = 0; k < 3; ++k) head[cursor[F(t, k)]++] = F(t, (k + 1) % 3);
  auto count = [&](Index u, Index v) {
    Index c = 0;
    for (Index i = start[u]; i < start[u + 1]; ++i) c += head[i] == v;
    return c;
  };
  Index open = 0;
  for (Index u = 0; u < vertices; ++u)
    for (Index i = start[u]; i < start[u + 1]; ++i)
      open += count(u, head[i]) != 1 || count(head[i], u) != 1;
  return open;
}

}  // namespace

double spherical_triangle_area(const Vec3& a, const Vec3& b, const Vec3& c) {
  const double det = a.dot(b.cross(c));
  return 2.0 * std::atan2(det, 1.0 + a.dot(b) + b.dot(c) + c.dot(a));
}

void check_overlay_options(const OverlayOptions& options) {
  PM_REQUIRE(std::isfinite(options.merge_tolerance) && options.merge_tolerance >= 0 &&
                 options.merge_tolerance < 1e-3,
             InvalidInputError, "merge_tolerance is an angle in radians in [0, 1e-3), got ",
             options.merge_tolerance);
}

MergedTopology overlay(const MatrixX3d& sphere_a, const MatrixX3i& FA, const MatrixX3d& sphere_b,
                       const MatrixX3i& FB, const OverlayOptions& options, Progress* progress) {
  const auto started = Clock::now();
  check_overlay_options(options);
  MergedTopology out;
  OverlayStats& stats = out.stats;
  if (progress) progress->report(0.0, "overlay");

  auto phase = Clock::now();
  const SphereMapTopology a = prepare(sphere_a, FA, "sphere_a");
  const SphereMapTopology b = prepare(sphere_b, FB, "sphere_b");
  // Merging must stay finer than either map's own detail, or it would have to
  // join two vertices of one map (which it never does) to stay consistent.
  const double thinnest = std::min(thinnest_face(a), thinnest_face(b));
  const double tolerance = std::max(std::min(options.merge_tolerance, 0.25 * thinnest), 1e-15);
  stats.merge_tolerance = tolerance;
  stats.seconds_validate = seconds_since(phase);

  phase = Clock::now();
  const SphereArrangement ar = arrange_sphere_maps(a, b, ProgressWindow(progress, 0.05, 0.6));
  stats.cells = ar.num_cells();
  stats.crossings = ar.num_crossings();
  stats.seconds_arrangement = seconds_since(phase);

  // Merge, triangulate; where a cell piece has no positive triangulation
  // (vertices moved by up to the tolerance turned a tiny cell over), merge its
  // closest pair of vertices as well and start again (see merge_close_vertices.h);
  // the same for slivers, once every cell has a positive triangulation.
  VertexClusters clusters;
  CellTriangles cells;
  std::vector<std::pair<Index, Index>> forced;
  const double thin = kMinAltitudeInTolerances * tolerance;
  Index merged_before = -1;
  for (int round = 0;; ++round) {
    phase = Clock::now();
    clusters = merge_close_vertices(ar, a, b, tolerance, forced);
    stats.seconds_merge += seconds_since(phase);
    if (progress) progress->report(0.65, "overlay: triangulate");
    phase = Clock::now();
    const std::size_t before = forced.size();
    cells = triangulate_cells(ar, clusters, kRepairReach * tolerance, forced);
    if (forced.size() == before)
      find_slivers(cells, clusters, thin, kSliverReach * tolerance, stats.thin_triangles, &forced);
    stats.seconds_triangulate += seconds_since(phase);
    // Done when nothing is left to repair, nothing repaired merges any more
    // (may_merge() refused it), or after the last round.
    if (forced.size() == before || clusters.merged == merged_before || round + 1 == kRepairRounds)
      break;
    merged_before = clusters.merged;
  }
  stats.min_altitude = find_slivers(cells, clusters, thin, 0.0, stats.thin_triangles);
  stats.merged_vertices = clusters.merged;
  stats.max_merge_distance = clusters.max_deviation;
  stats.degenerate_cells = cells.degenerate;
  const std::vector<Eigen::Matrix<Index, 1, 3>>& triangles = cells.triangles;
  const std::vector<Index>& tri_face_a = cells.face_a;
  const std::vector<Index>& tri_face_b = cells.face_b;

  // Merged vertices: the clusters that triangles use.
  phase = Clock::now();
  const Index num_clusters = clusters.size();
  VectorXi new_id = VectorXi::Constant(num_clusters, -1);
  for (const auto& t : triangles)
    for (int k = 0; k < 3; ++k) new_id[t[k]] = 0;
  Index count = 0, lost = 0;  // lost: input vertices in no triangle
  for (Index k = 0; k < num_clusters; ++k) {
    if (new_id[k] == 0)
      new_id[k] = count++;
    else
      lost += (clusters.vertex_a[k] >= 0) + (clusters.vertex_b[k] >= 0);
  }
  const Index K = Index(triangles.size());
  out.F.resize(K, 3);
  for (Index t = 0; t < K; ++t)
    for (int k = 0; k < 3; ++k) out.F(t, k) = new_id[triangles[t][k]];
  out.V.resize(count, 3);
  for (Index k = 0; k < num_clusters; ++k)
    if (new_id[k] >= 0) out.V.row(new_id[k]) = clusters.position.row(k);

  // The checks the contract promises (exact orientation, twins, every input
  // vertex present), before anything else is built on the result.
  for (Index t = 0; t < K; ++t)
    stats.folded += orientation(out.V.row(out.F(t, 0)).data(), out.V.row(out.F(t, 1)).data(),
                                out.V.row(out.F(t, 2)).data()) <= 0;
  stats.open_edges = open_half_edges(out.F, count);
  PM_REQUIRE(stats.folded == 0 && stats.open_edges == 0 && lost == 0, InvalidInputError,
             "the maps nearly coincide at a scale below what double precision resolves for "
             "their thinnest faces (altitude ",
             thinnest, " rad): the merged topology would have ", stats.folded,
             " folded triangles, ", stats.open_edges, " unmatched half-edges and ", lost,
             " input vertices missing; use fold-free maps with fatter faces "
             "(optimize_sphere_map) or turn one map slightly");
  out.source_face_a = Eigen::Map<const VectorXi>(tri_face_a.data(), K);
  out.source_face_b = Eigen::Map<const VectorXi>(tri_face_b.data(), K);

  // Supports: a vertex of the map if the cluster has one, else an edge of the
  // map through it (a crossing), else the face the perturbed walk found.
  std::vector<Support> support_a(static_cast<std::size_t>(count)), support_b(support_a);
  out.vertex_kind.resize(count);
  out.vertex_of_a.resize(a.X.rows());
  out.vertex_of_b.resize(b.X.rows());
  for (Index k = 0; k < num_clusters; ++k) {
    const Index m = new_id[k];
    if (m < 0) continue;
    const Index va = clusters.vertex_a[k], vb = clusters.vertex_b[k];
    out.vertex_kind[m] = va >= 0 ? (vb >= 0 ? 2 : 0) : (vb >= 0 ? 1 : 3);
    if (va >= 0) out.vertex_of_a[va] = m;
    if (vb >= 0) out.vertex_of_b[vb] = m;
    support_a[m] = {va, clusters.edge_a[k], va < 0 && vb >= 0 ? ar.face_a_of_b[vb] : -1};
    support_b[m] = {vb, clusters.edge_b[k], vb < 0 && va >= 0 ? ar.face_b_of_a[va] : -1};
  }
  const Locator locate_a(a), locate_b(b);
  std::vector<Combination> in_a(static_cast<std::size_t>(count)), in_b(in_a.size());
  out.face_a.resize(count);
  out.face_b.resize(count);
  out.bary_a.resize(count, 3);
  out.bary_b.resize(count, 3);
  for (Index m = 0; m < count; ++m) {
    const Vec3 P = out.V.row(m);
    in_a[m] = locate_a.combine(support_a[m], P, out.face_a[m]);
    in_b[m] = locate_b.combine(support_b[m], P, out.face_b[m]);
    out.bary_a.row(m) = locate_a.in_face(in_a[m], P, out.face_a[m]).transpose();
    out.bary_b.row(m) = locate_b.in_face(in_b[m], P, out.face_b[m]).transpose();
  }
  out.corner_bary_a.resize(K, 9);
  out.corner_bary_b.resize(K, 9);
  for (Index t = 0; t < K; ++t)
    for (int k = 0; k < 3; ++k) {
      const Index m = out.F(t, k);
      const Vec3 P = out.V.row(m);
      out.corner_bary_a.block<1, 3>(t, 3 * k) =
          locate_a.in_face(in_a[m], P, out.source_face_a[t]).transpose();
      out.corner_bary_b.block<1, 3>(t, 3 * k) =
          locate_b.in_face(in_b[m], P, out.source_face_b[t]).transpose();
    }

  stats.seconds_attributes = seconds_since(phase);
  stats.seconds = seconds_since(started);
  if (progress) progress->report(1.0, "overlay");
  return out;
}

}  // namespace paramorph::morph
