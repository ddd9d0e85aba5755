// Interactive feature paste (paste/paste_session.h; thesis 5.2, DESIGN.md §4.5).
#include "paste/paste_session.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <optional>
#include <vector>

#include "common/errors.h"
#include "mesh/vertex_normals.h"
#include "mesh/closest_points.h"
#include "paste/disc_map.h"
#include "paste/disc_region.h"
#include "paste/exponential_map.h"
#include "paste/fill_between_loops.h"
#include "paste/plane_polygon.h"
#include "paste/refine_region.h"
#include "paste/locate_in_map.h"
#include "paste/sample_feature.h"  // bilinear_displacement

namespace paramorph::paste {

namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

/// Moving control points: at most this many per feature (its boundary vertices,
/// evenly thinned); stationary ones on the rim circle.
constexpr Index kMaxMovingPoints = 128;
constexpr Index kRimPoints = 64;
/// The X axis is the reference for rotation 0 unless it is within 25 degrees
/// of the normal (then Y): a stable choice an artist can predict.
const double kReferenceLimit = std::cos(25.0 * M_PI / 180.0);

double cross2(const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return a.x() * b.y() - a.y() * b.x(); }

/// Distance from the origin to the segment [a, b].
double origin_segment_distance(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  const Eigen::Vector2d d = b - a;
  const double len2 = d.squaredNorm();
  const double t = len2 > 0 ? std::clamp(-a.dot(d) / len2, 0.0, 1.0) : 0.0;
  return (a + t * d).norm();
}

/// Distance from the origin to the triangle (a, b, c) of either orientation.
double origin_triangle_distance(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c) {
  const double s0 = cross2(b - a, -a), s1 = cross2(c - b, -b), s2 = cross2(a - c, -c);
  if ((s0 >= 0 && s1 >= 0 && s2 >= 0) || (s0 <= 0 && s1 <= 0 && s2 <= 0)) return 0.0;
  return std::min({origin_segment_distance(a, b), origin_segment_distance(b, c), origin_segment_distance(c, a)});
}

/// The feature in the plane of its own exponential map. Target and feature
/// are matched by the same construction (the map around the anchor, the map
/// around the feature's origin on its base), so a feature cut from a curved
/// surface lands on a like one at its own size; the base map (an isometric
/// compromise between radial and circumferential lengths) would not. The base
/// map stands in where the origin is not on the base (an annulus) or the
/// exponential map folds; the two agree on flat bases.
struct FeaturePlane {
  std::vector<Eigen::Vector2d> q;  ///< per feature vertex
  MatrixX2d q_matrix;              ///< the same, as a matrix (the locator's input)
  double radius = 0;               ///< max |q| over the boundary
  /// The feature's detail length: the 10th percentile of its edge lengths in
  /// the plane. Steep walls are squeezed there (a boss's sides), so this,
  /// not the 3D mean, says how finely the plane must be sampled.
  double detail = 0;
};

/// plane.radius and plane.detail from its coordinates.
void measure(FeaturePlane& plane, const Feature& f) {
  for (const auto& loop : f.boundary_loops)
    for (const Index v : loop) plane.radius = std::max(plane.radius, plane.q[v].norm());
  std::vector<double> lengths;
  lengths.reserve(3 * std::size_t(f.F.rows()));
  for (Index k = 0; k < Index(f.F.rows()); ++k)
    for (int j = 0; j < 3; ++j) lengths.push_back((plane.q[f.F(k, j)] - plane.q[f.F(k, (j + 1) % 3)]).norm());
  const auto tenth = lengths.begin() + std::ptrdiff_t(lengths.size() / 10);
  std::nth_element(lengths.begin(), tenth, lengths.end());
  plane.detail = *tenth > 0 ? *tenth : f.mean_edge_length;
}

FeaturePlane feature_plane(const Feature& f) {
  FeaturePlane plane;
  const TriMesh base(f.base_V, f.F);
  // The origin: uv = 0 of the base map, on the base (feature frame: ~0).
  // It is off the base for an annulus (in its hole): the base map then.
  const MapLocation at = MapLocator(f.base_uv, f.F).locate(MatrixX2d::Zero(1, 2));
  const Index face = at.face[0];
  const auto use_base_map = [&] {
    plane.q_matrix = f.base_uv;
    plane.q.resize(std::size_t(f.base_uv.rows()));
    for (Index v = 0; v < Index(plane.q.size()); ++v) plane.q[v] = f.base_uv.row(v).transpose();
    measure(plane, f);
    return plane;
  };
  if (at.distance(0) > 1e-9 * f.radius) return use_base_map();
  const Eigen::Vector3d origin = interpolate(f.F, at, f.base_V).row(0).transpose();
  const ExponentialMap map = exponential_map(base, area_weighted_vertex_normals(f.base_V, f.F), face, origin, Eigen::Vector3d::UnitX(),
                                             Eigen::Vector3d::UnitZ(), std::numeric_limits<double>::infinity());
  plane.q = map.q;
  plane.q_matrix.resize(Index(map.q.size()), 2);
  bool folds = false;
  for (Index v = 0; v < Index(map.q.size()); ++v) {
    folds |= !map.reached[v];
    plane.q_matrix.row(v) = map.q[v].transpose();
  }
  for (Index k = 0; k < Index(f.F.rows()) && !folds; ++k) {
    const Eigen::Vector2d a = map.q[f.F(k, 0)], b = map.q[f.F(k, 1)], c = map.q[f.F(k, 2)];
    folds = !(cross2(b - a, c - a) > 0);
  }
  // A boundary that crosses itself (a map that winds round twice, though no
  // face is turned over) would give the carried feature's seam no ring.
  for (std::size_t l = 0; l < f.boundary_loops.size() && !folds; ++l) {
    std::vector<Eigen::Vector2d> loop;
    for (const Index v : f.boundary_loops[l]) loop.push_back(map.q[v]);
    folds = self_crossing(loop);
  }
  // A base curved past the map's reach (it folds): the base map, which never does.
  if (folds) return use_base_map();
  measure(plane, f);
  return plane;
}

/// What a point of the feature plane holds: the feature's position (feature
/// frame) and its displacement map's value, or nothing (outside the domain).
struct FeatureLookup {
  MapLocator locator;  ///< over the feature plane
  const Feature* feature;

  FeatureLookup(const Feature& f, const FeaturePlane& plane) : locator(plane.q_matrix, f.F), feature(&f) {}

  /// Exact: located in the plane's triangles, the feature's own vertices
  /// interpolated (so the feature is rebuilt as it was cut), the displacement
  /// read through the base map.
  void at(const MatrixX2d& points, MatrixX3d* position, MatrixX3d* displacement, VectorXd* distance) const {
    const MapLocation where = locator.locate(points);
    *position = interpolate(feature->F, where, feature->V);
    *displacement = bilinear_displacement(*feature, interpolate(feature->F, where, feature->base_uv));
    *distance = where.distance;
  }
};

/// FeatureLookup on a regular grid over the plane's square, built once, read
/// bilinearly in cells wholly inside the domain; the cells its boundary
/// crosses are left to exact lookups.
struct FeatureGrid {
  int n = 0;
  Eigen::Vector2d origin;
  double spacing = 0;
  MatrixX3d position, displacement;
  VectorXd distance;

  FeatureGrid(const Feature& feature, const FeaturePlane& plane, const FeatureLookup& lookup) {
    const double r = plane.radius * (1 + 1e-9);
    // About two nodes per short feature edge, within bounds that keep the
    // one-off cost (one exact lookup per node) small.
    n = int(std::clamp(std::ceil(4 * r / plane.detail) + 1, 65.0, 257.0));
    origin = Eigen::Vector2d(-r, -r);
    spacing = 2 * r / (n - 1);
    MatrixX2d uv(Index(n) * n, 2);
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) uv.row(Index(i) * n + j) = origin + spacing * Eigen::Vector2d(j, i);
    lookup.at(uv, &position, &displacement, &distance);
  }

  /// 1: q inside the domain (bilinear position and displacement out);
  /// 0: outside; -1: a boundary cell, for an exact lookup.
  int lookup(const Eigen::Vector2d& q, Eigen::Vector3d* x, Eigen::Vector3d* d, double inside_tolerance) const {
    const Eigen::Vector2d g = (q - origin) / spacing;
    if (!(g.x() >= 0 && g.y() >= 0 && g.x() <= n - 1 && g.y() <= n - 1)) return 0;
    const int j = std::min(int(g.x()), n - 2), i = std::min(int(g.y()), n - 2);
    const Index k00 = Index(i) * n + j, k01 = k00 + 1, k10 = k00 + n, k11 = k10 + 1;
    const int inside = (distance(k00) <= inside_tolerance) + (distance(k01) <= inside_tolerance) +
                       (distance(k10) <= inside_tolerance) + (distance(k11) <= inside_tolerance);
    if (inside == 0) return 0;
    if (inside < 4) return -1;
    const double s = g.x() - j, t = g.y() - i;
    const auto bilinear = [&](const MatrixX3d& m) -> Eigen::Vector3d {
      return ((1 - t) * ((1 - s) * m.row(k00) + s * m.row(k01)) + t * ((1 - s) * m.row(k10) + s * m.row(k11)))
          .transpose();
    };
    *x = bilinear(position);
    *d = bilinear(displacement);
    return 1;
  }
};

/// Faces of the region in feature-plane coordinates, bucketed on a square
/// grid for point location (rebuilt per placement: the region moves). Not
/// MapLocator: building its CGAL tree over the region on every update made
/// updates 20-45% slower (measured: 9.0 against 7.4 ms at the benchmark's
/// scale 0.3, 27.8 against 19 ms at 0.6).
class PlaneLocator {
 public:
  PlaneLocator(const std::vector<Index>& faces, const MatrixX3i& F, const std::vector<Eigen::Vector2d>& q,
               double half_width)
      : faces_(faces), F_(F), q_(q), half_(half_width) {
    cell_ = 2 * half_ / kCells;
    buckets_.assign(std::size_t(kCells) * kCells, {});
    for (const Index f : faces_) {
      Eigen::Vector2d lo = q_[F(f, 0)], hi = lo;
      for (int k = 1; k < 3; ++k) lo = lo.cwiseMin(q_[F(f, k)]), hi = hi.cwiseMax(q_[F(f, k)]);
      const int j0 = clamp_cell(lo.x()), j1 = clamp_cell(hi.x()), i0 = clamp_cell(lo.y()), i1 = clamp_cell(hi.y());
      if (hi.x() < -half_ || hi.y() < -half_ || lo.x() > half_ || lo.y() > half_) continue;
      for (int i = i0; i <= i1; ++i)
        for (int j = j0; j <= j1; ++j) buckets_[std::size_t(i) * kCells + j].push_back(f);
    }
  }

  /// The face whose projection holds p (counter-clockwise ones first) and the
  /// barycentric coordinates; false when none does.
  bool locate(const Eigen::Vector2d& p, Index* face, Eigen::Vector3d* bary) const {
    if (std::abs(p.x()) > half_ || std::abs(p.y()) > half_) return false;
    bool found = false;
    for (const Index f : buckets_[std::size_t(clamp_cell(p.y())) * kCells + clamp_cell(p.x())]) {
      const Eigen::Vector2d a = q_[F_(f, 0)], b = q_[F_(f, 1)], c = q_[F_(f, 2)];
      const double area = cross2(b - a, c - a);
      if (area == 0) continue;
      const double l0 = cross2(b - p, c - p) / area, l1 = cross2(c - p, a - p) / area, l2 = 1 - l0 - l1;
      const double slack = -1e-12;
      if (l0 < slack || l1 < slack || l2 < slack) continue;
      if (found && area < 0) continue;  // keep an earlier counter-clockwise hit
      *face = f;
      *bary = Eigen::Vector3d(l0, l1, l2).cwiseMax(0.0);
      *bary /= bary->sum();
      found = true;
      if (area > 0) return true;
    }
    return found;
  }

 private:
  static constexpr int kCells = 64;
  int clamp_cell(double x) const { return std::clamp(int(std::floor((x + half_) / cell_)), 0, kCells - 1); }
  const std::vector<Index>& faces_;
  const MatrixX3i& F_;
  const std::vector<Eigen::Vector2d>& q_;
  double half_, cell_;
  std::vector<std::vector<Index>> buckets_;
};


/// A carried feature sewn into the target (see A FEATURE CARRIED AS ITS OWN
/// MESH in the header): what place() commits.
struct Sewn {
  MatrixX3d V;
  MatrixX3i F;
  VectorXi new_faces, replaced_faces, new_face_parents;
};

/// target: the target; q: its feature-plane coordinates where reached;
/// normals: its vertex normals; candidates: the mapped faces the feature's
/// disc touches; polygon: the feature's boundary in the plane
/// (counter-clockwise), loop: its vertices; placed: the feature's vertices
/// placed in the world; up: the anchor's normal; shift(i): the blend's
/// displacement of target vertex i (zero beyond the rim).
template <typename Shift>
Sewn sew_carried(const TriMesh& target, const std::vector<Eigen::Vector2d>& q, const std::vector<char>& reached,
                 const MatrixX3d& normals, const std::vector<Index>& candidates, Index anchor_face,
                 const std::vector<Eigen::Vector2d>& polygon, const std::vector<Index>& loop,
                 const std::vector<Eigen::Vector2d>& feature_q, const MatrixX3i& feature_F, const MatrixX3d& placed,
                 const Eigen::Vector3d& up, double rim, const Shift& shift) {
  const MatrixX3d& V = target.V();
  const MatrixX3i& F = target.F();
  const Index nv = Index(V.rows()), nf = Index(F.rows());
  const Csr& corners = target.vertex_corners();
  const Csr& EF = target.edge_faces();
  const MatrixX3i& FE = target.face_edges();
  MatrixX3d moved(nv, 3);  // the target bent by the blend
  for (Index v = 0; v < nv; ++v) moved.row(v) = V.row(v) + shift(v).transpose();

  // The faces cut away: every face around a vertex within half a boundary
  // segment of the feature's boundary or inside it (the seam then has room
  // for well-shaped triangles), and those the boundary crosses or holds a
  // corner of; the anchor's face in any case.
  double segment = 0;
  for (std::size_t k = 0; k < polygon.size(); ++k) segment += (polygon[(k + 1) % polygon.size()] - polygon[k]).norm();
  const double clearance = 0.5 * segment / double(polygon.size());
  std::vector<char> cut(std::size_t(nf), 0);
  std::vector<Index> faces;
  // Faces the boundary meets must go (else the feature does not fit);
  // those only near it go where the plane reaches them.
  const auto take = [&](Index f, bool needed) {
    if (cut[f]) return;
    const bool mapped = reached[F(f, 0)] && reached[F(f, 1)] && reached[F(f, 2)];
    PM_REQUIRE(mapped || !needed, TargetTooSmallError,
               "the feature's root does not fit on the surface here; move it or make it smaller");
    if (!mapped) return;
    cut[f] = 1;
    faces.push_back(f);
  };
  const auto take_around = [&](Index v) {
    for (Index j = corners.begin(v); j < corners.end(v); ++j) take(corners.items[j] / 3, false);
  };
  take(anchor_face, true);
  for (const Index f : candidates) {
    const Eigen::Vector2d &a = q[F(f, 0)], &b = q[F(f, 1)], &c = q[F(f, 2)];
    bool meets = false;
    for (int k = 0; k < 3; ++k)
      if (inside_or_near(polygon, q[F(f, k)], clearance)) {
        // Inside: every face around it must go; only near: where mapped.
        if (inside_or_near(polygon, q[F(f, k)], 0.0))
          for (Index j = corners.begin(F(f, k)); j < corners.end(F(f, k)); ++j) take(corners.items[j] / 3, true);
        take_around(F(f, k));
        meets = true;
      }
    for (std::size_t i = 0, j = polygon.size() - 1; i < polygon.size() && !meets; j = i++) {
      const Eigen::Vector2d& x = polygon[i];
      const double s0 = plane_cross(b - a, x - a), s1 = plane_cross(c - b, x - b), s2 = plane_cross(a - c, x - c);
      meets = (s0 >= 0 && s1 >= 0 && s2 >= 0) || segments_meet(a, b, polygon[j], x) ||
              segments_meet(b, c, polygon[j], x) || segments_meet(c, a, polygon[j], x);
    }
    if (meets) take(f, true);
  }

  // The seam: the hole's edges and the boundary's as loops in the plane,
  // the ring between them triangulated. A seam face turned over in the bent
  // target (a hole vertex bent past the boundary) widens the hole by a ring.
  std::vector<Eigen::Vector2d> points;
  std::vector<Index> point_vertex;  // output vertex of each point
  std::optional<MatrixX3i> seam;
  for (int widen = 0;; ++widen) {
    points.clear(), point_vertex.clear();
    std::vector<Index> point_of(std::size_t(nv), -1);
    std::vector<std::array<Index, 2>> segments;
    std::vector<Index> rim_vertices;
    const auto point = [&](Index v) {
      if (point_of[v] < 0) {
        point_of[v] = Index(points.size()), points.push_back(q[v]), point_vertex.push_back(v);
        rim_vertices.push_back(v);
      }
      return point_of[v];
    };
    for (const Index f : faces)
      for (int k = 0; k < 3; ++k) {
        const Index e = FE(f, k);
        PM_REQUIRE(EF.size(e) == 2, TargetTooSmallError,
                   "the feature reaches the target's boundary (an open edge of the mesh) here; move it inwards or "
                   "make it smaller");
        const Index other = EF.items[EF.begin(e)] == f ? EF.items[EF.begin(e) + 1] : EF.items[EF.begin(e)];
        if (!cut[other]) segments.push_back({point(F(f, (k + 1) % 3)), point(F(f, (k + 2) % 3))});  // opposite k
      }
    const Index first = Index(points.size());
    for (std::size_t k = 0; k < loop.size(); ++k) {
      points.push_back(polygon[k]);
      point_vertex.push_back(nv + loop[k]);
      segments.push_back({first + Index(k), first + Index((k + 1) % loop.size())});
    }
    seam = fill_between_loops(points, segments);
    PM_REQUIRE(seam.has_value() && seam->rows() > 0, TargetTooSmallError,
               "the surface around the feature's root folds over here; move the feature or make it smaller");
    const auto position = [&](Index i) -> Eigen::Vector3d {
      const Index v = point_vertex[i];
      return v < nv ? Eigen::Vector3d(moved.row(v).transpose()) : Eigen::Vector3d(placed.row(v - nv).transpose());
    };
    bool turned = false;
    for (Index r = 0; r < seam->rows() && !turned; ++r) {
      const Eigen::Vector3d a = position((*seam)(r, 0)), b = position((*seam)(r, 1)), c = position((*seam)(r, 2));
      Eigen::Vector3d reference = Eigen::Vector3d::Zero();
      for (int k = 0; k < 3; ++k)
        if (point_vertex[(*seam)(r, k)] < nv) reference += normals.row(point_vertex[(*seam)(r, k)]).transpose();
      if (reference.squaredNorm() == 0) reference = up;
      turned = !((b - a).cross(c - a).dot(reference) > 0);
    }
    if (!turned || widen == 2) break;
    for (const Index v : rim_vertices) take_around(v);
  }

  Sewn out;
  out.V.resize(nv + Index(placed.rows()), 3);
  out.V << moved, placed;
  std::sort(faces.begin(), faces.end());
  const Index kept = nf - Index(faces.size()), sewn = Index(seam->rows()), own = Index(feature_F.rows());
  out.F.resize(kept + sewn + own, 3);
  Index row = 0;
  for (Index f = 0; f < nf; ++f)
    if (!cut[f]) out.F.row(row++) = F.row(f);
  // Each new face's parent: the cut face under its centre in the plane.
  PlaneLocator locator(faces, F, q, rim);
  out.new_faces.resize(sewn + own);
  out.new_face_parents.resize(sewn + own);
  const auto add = [&](const Eigen::Vector3i& face, const Eigen::Vector2d& centre) {
    Index parent = anchor_face;
    Eigen::Vector3d bary;
    locator.locate(centre, &parent, &bary);
    out.new_faces[row - kept] = row;
    out.new_face_parents[row - kept] = parent;
    out.F.row(row++) = face.transpose();
  };
  for (Index r = 0; r < sewn; ++r) {
    const Eigen::Vector3i face(point_vertex[(*seam)(r, 0)], point_vertex[(*seam)(r, 1)], point_vertex[(*seam)(r, 2)]);
    add(face, (points[(*seam)(r, 0)] + points[(*seam)(r, 1)] + points[(*seam)(r, 2)]) / 3.0);
  }
  for (Index r = 0; r < own; ++r)
    add(Eigen::Vector3i(nv + feature_F(r, 0), nv + feature_F(r, 1), nv + feature_F(r, 2)),
        (feature_q[feature_F(r, 0)] + feature_q[feature_F(r, 1)] + feature_q[feature_F(r, 2)]) / 3.0);
  out.replaced_faces = Eigen::Map<const VectorXi>(faces.data(), Index(faces.size()));
  return out;
}

}  // namespace

TargetMap parse_target_map(const std::string& name) {
  if (name == "auto") return TargetMap::Auto;
  if (name == "exponential") return TargetMap::Exponential;
  if (name == "disc") return TargetMap::Disc;
  PM_REQUIRE(false, InvalidInputError, "target_map must be \"auto\", \"exponential\" or \"disc\", got \"", name,
             "\"");
  return TargetMap::Auto;
}

PasteFit parse_paste_fit(const std::string& name) {
  if (name == "keep_form") return PasteFit::KeepForm;
  if (name == "follow_surface") return PasteFit::FollowSurface;
  PM_REQUIRE(false, InvalidInputError, "fit must be \"keep_form\" or \"follow_surface\", got \"", name, "\"");
  return PasteFit::KeepForm;
}

struct PasteSession::Impl {
  Feature feature;
  PasteOptions options;
  RegionRefiner refiner;
  ClosestPointTree tree;
  MatrixX3d vertex_normals;
  FeaturePlane plane;
  FeatureLookup lookup;
  FeatureGrid grid;
  MatrixX2d centres;            ///< moving first, then stationary; feature plane
  MatrixX3d moving_points;      ///< the feature's boundary points, feature frame
  std::unique_ptr<RbfInterpolator> rbf;
  double rim = 0;               ///< stationary circle's radius, feature plane

  // The current placement and its result.
  Eigen::Vector3d anchor_point = Eigen::Vector3d::Zero(), normal = Eigen::Vector3d::UnitZ();
  MatrixX3d out_V;
  MatrixX3i out_F;
  VectorXi new_faces, replaced_faces, new_face_parents;
  PasteStats stats;

  Impl(const MatrixX3d& V_, const MatrixX3i& F_, Feature feature_, const PasteOptions& options_)
      : feature(std::move(feature_)),
        options(options_),
        refiner(V_, F_),  // holds the target (its TriMesh): V and F below are its
        tree(V_, F_),
        plane(feature_plane(feature)),
        lookup(feature, plane),
        grid(feature, plane, lookup) {}

  /// A full placement; writes the result members only when it succeeds.
  void place(const Eigen::Vector3d& anchor, double rotation, double scale);
};

namespace {

void check_options(const PasteOptions& o) {
  PM_REQUIRE(o.anchor.allFinite(), InvalidInputError, "anchor must be a finite point");
  PM_REQUIRE(std::isfinite(o.rotation), InvalidInputError, "rotation must be finite");
  PM_REQUIRE(std::isfinite(o.scale) && o.scale > 0, InvalidInputError, "scale must be > 0, got ", o.scale);
  PM_REQUIRE(std::isfinite(o.blend_radius) && o.blend_radius > 1.1, InvalidInputError,
             "blend_radius (in feature radii) must be > 1.1, got ", o.blend_radius);
  PM_REQUIRE(o.subdivision_level >= -1 && o.subdivision_level <= 6, InvalidInputError,
             "subdivision_level must be -1 (automatic) or 0..6, got ", o.subdivision_level);
}

void check_feature(const Feature& f) {
  PM_REQUIRE(f.F.rows() > 0 && f.V.rows() > 0 && f.base_uv.rows() == f.V.rows() && f.base_V.rows() == f.V.rows() &&
                 !f.boundary_loops.empty() && f.radius > 0 && f.mean_edge_length > 0,
             InvalidInputError, "the feature is empty or incomplete (use extract_feature or Feature.from_arrays)");
}

}  // namespace

void PasteSession::Impl::place(const Eigen::Vector3d& anchor, double rotation, double scale) {
  const auto t0 = Clock::now();
  PasteOptions next = options;
  next.anchor = anchor, next.rotation = rotation, next.scale = scale;
  check_options(next);
  const TriMesh& mesh = refiner.mesh();
  const MatrixX3d& V = mesh.V();
  const MatrixX3i& F = mesh.F();
  const MatrixX3i& FE = mesh.face_edges();
  const Csr& EF = mesh.edge_faces();
  const MatrixX2i& E = mesh.edges();

  // 1. Snap and frame.
  const ClosestPoints hit = tree.query(anchor.transpose());
  const Index anchor_face = hit.face(0);
  const Eigen::Vector3d p = hit.points.row(0).transpose();
  const Eigen::Vector3d face_normal = (V.row(F(anchor_face, 1)) - V.row(F(anchor_face, 0)))
                                          .cross(V.row(F(anchor_face, 2)) - V.row(F(anchor_face, 0)))
                                          .transpose()
                                          .normalized();
  Eigen::Vector3d n = Eigen::Vector3d::Zero();
  for (int k = 0; k < 3; ++k) n += hit.bary(0, k) * vertex_normals.row(F(anchor_face, k)).transpose();
  // A rough surface can tilt the smoothed normal past the face's own: use the face's then.
  n = n.dot(face_normal) > 1e-12 ? n.normalized() : face_normal;
  const Eigen::Vector3d reference =
      std::abs(n.x()) > kReferenceLimit ? Eigen::Vector3d::UnitY() : Eigen::Vector3d::UnitX();
  const Eigen::Vector3d t_ref = (reference - reference.dot(n) * n).normalized();
  const Eigen::Vector3d t = std::cos(rotation) * t_ref + std::sin(rotation) * n.cross(t_ref);
  Eigen::Matrix3d axes;  // feature frame -> world, before scaling
  axes << t, n.cross(t), n;
  // The feature's origin goes to p + lift n; lift is set below so that its
  // boundary sits on the target on average (the base deforms least).
  double lift = 0;
  const auto world = [&](const Eigen::Vector3d& x_frame) -> Eigen::Vector3d {
    return p + lift * n + scale * axes * x_frame;
  };

  // 2. Feature-plane coordinates of the target: its exponential map around
  // the anchor, in feature units; the disc map where that folds (see THE
  // PARAMETERIZATIONS in the header).
  const auto map_start = Clock::now();
  const Index nv = Index(V.rows()), nf = Index(F.rows());
  ExponentialMap map = exponential_map(mesh, vertex_normals, anchor_face, p, t, n, rim * scale);
  std::vector<Eigen::Vector2d>& q = map.q;
  for (const Index v : map.vertices) q[v] /= scale;
  // Beyond the map (the far corner of a huge face next to the refined ones):
  // the projection onto the tangent plane stands in; such vertices never move.
  std::vector<char> projected(std::size_t(nv), 0);
  const auto q_of = [&](Index v) -> const Eigen::Vector2d& {
    if (!map.reached[v] && !projected[v]) {
      const Eigen::Vector3d d = V.row(v).transpose() - p;
      q[v] = Eigen::Vector2d(axes.col(0).dot(d), axes.col(1).dot(d)) / scale;
      projected[v] = 1;
    }
    return q[v];
  };
  const double radius = plane.radius;
  const Csr& corners = mesh.vertex_corners();
  std::vector<char> seen(std::size_t(nf), 0);
  std::vector<Index> region, refined;
  // Region: the mapped faces within the rim (of `allowed`, when given);
  // refined: those the feature's disc touches. Whether any is turned over.
  bool region_folds = false, refined_folds = false;
  const auto select = [&](const std::vector<Index>& vertices, const std::vector<char>* allowed) {
    region.clear(), refined.clear();
    region_folds = refined_folds = false;
    std::vector<Index> touched;
    for (const Index v : vertices) {
      for (Index j = corners.begin(v); j < corners.end(v); ++j) {
        const Index f = corners.items[j] / 3;
        if (seen[f]) continue;
        seen[f] = 1;
        touched.push_back(f);
        if (allowed && !(*allowed)[f]) continue;
        if (!(map.reached[F(f, 0)] && map.reached[F(f, 1)] && map.reached[F(f, 2)])) continue;  // the map's edge
        const Eigen::Vector2d &a = q_of(F(f, 0)), &b = q_of(F(f, 1)), &c = q_of(F(f, 2));
        const double d = origin_triangle_distance(a, b, c);
        if (d >= rim && f != anchor_face) continue;
        region.push_back(f);
        const bool turned = !(cross2(b - a, c - a) > 0);
        region_folds |= turned;
        if (d > radius) continue;
        refined.push_back(f);
        refined_folds |= turned;
      }
    }
    for (const Index f : touched) seen[f] = 0;
  };
  select(map.vertices, nullptr);
  bool use_disc = options.target_map == TargetMap::Disc;
  if (options.target_map == TargetMap::Exponential) {
    PM_REQUIRE(!refined_folds, TargetTooSmallError,
               "the target's surface folds over under the feature: it is too curved there for the feature at this "
               "size; paste it smaller or elsewhere");
  } else if (options.target_map == TargetMap::Auto) {
    use_disc = region_folds || !is_disc_up_to_holes(mesh, region);
  }
  DiscRegion disc;
  int disc_iterations = 0;
  if (use_disc) {
    // The disc within about 1.25 rims of path distance; grown further (once)
    // where its map ends inside the rim, so the blend fades out within it.
    // Where the exponential map is still fold-free near the anchor (within
    // half the feature's radius), the disc map is fitted to it there.
    std::vector<std::pair<Index, Eigen::Vector2d>> reference;
    for (const Index v : map.vertices) {
      if (!(q[v].norm() < 0.5 * radius)) continue;
      bool fold_free = true;
      for (Index j = corners.begin(v); j < corners.end(v) && fold_free; ++j) {
        const Index f = corners.items[j] / 3;
        if (!(map.reached[F(f, 0)] && map.reached[F(f, 1)] && map.reached[F(f, 2)])) continue;
        fold_free = cross2(q[F(f, 1)] - q[F(f, 0)], q[F(f, 2)] - q[F(f, 0)]) > 0;
      }
      if (fold_free) reference.emplace_back(v, scale * q[v]);
    }
    double grow = 1.25 * rim * scale;
    DiscMap flat;
    for (int attempt = 0;; ++attempt) {
      disc = grow_disc_region(mesh, anchor_face, p, rim * scale, grow, 1.6 * grow);
      flat = disc_map(mesh, disc, anchor_face, hit.bary.row(0).transpose(), t, n, reference);
      double reach = std::numeric_limits<double>::infinity();
      for (const Index v : disc.cut_vertices) reach = std::min(reach, flat.q[v].norm());
      if (reach >= rim * scale || attempt == 1) break;
      grow *= 1.5;
    }
    disc_iterations = flat.iterations;
    for (const Index v : map.vertices) map.reached[v] = 0;
    std::fill(projected.begin(), projected.end(), 0);
    q = std::move(flat.q);
    for (const Index v : disc.vertices) q[v] /= scale, map.reached[v] = 1;
    map.vertices = disc.vertices;
    select(map.vertices, &disc.in_disc);
    PM_REQUIRE(!region_folds, TargetTooSmallError,  // a fold-free map; never expected
               "the surface under the feature could not be flattened without folds; move the feature or make it "
               "smaller");
  }
  // The feature must not hang over the target's boundary, nor over the disc
  // map's edge.
  for (const Index f : refined)
    for (int k = 0; k < 3; ++k) {
      const Index e = FE(f, k);
      const bool open = EF.size(e) < 2;
      const bool cut = use_disc && !open &&
                       !(disc.in_disc[EF.items[EF.begin(e)]] && disc.in_disc[EF.items[EF.begin(e) + 1]]);
      if ((!open && !cut) || origin_segment_distance(q_of(E(e, 0)), q_of(E(e, 1))) > radius) continue;
      PM_REQUIRE(!open, TargetTooSmallError,
                 "the feature reaches the target's boundary (an open edge of the mesh) here; move it inwards or "
                 "make it smaller");
      PM_REQUIRE(false, TargetTooSmallError,
                 "the surface under the feature is not a single disc (it wraps around or folds back within the "
                 "feature); move the feature or make it smaller");
    }
  std::sort(region.begin(), region.end());
  std::sort(refined.begin(), refined.end());
  const double map_seconds = seconds_since(map_start);

  // The RBF that bends the target to the feature's boundary (where it lands:
  // the target point with the same q), by back-substitution; sets lift.
  const auto bend = [&]() -> Eigen::MatrixXd {
    const Index moving = Index(moving_points.rows()), controls = Index(centres.rows());
    PlaneLocator locator(region, F, q, rim);
    Eigen::MatrixXd values = Eigen::MatrixXd::Zero(controls, 3);
    for (Index c = 0; c < moving; ++c) {
      Index f = -1;
      Eigen::Vector3d b;
      PM_REQUIRE(locator.locate(centres.row(c).transpose(), &f, &b), TargetTooSmallError,
                 "the target does not extend under the feature's boundary here; move it or make it smaller");
      const Eigen::Vector3d under =
          (b(0) * V.row(F(f, 0)) + b(1) * V.row(F(f, 1)) + b(2) * V.row(F(f, 2))).transpose();
      values.row(c) = (world(moving_points.row(c).transpose()) - under).transpose();
    }
    lift = -(values.topRows(moving) * n).mean();
    values.topRows(moving).rowwise() += lift * n.transpose();
    return rbf->solve(values);
  };
  // What either way of pasting records of the placement, once it succeeded.
  const auto record_placement = [&] {
    options = next;
    anchor_point = p;
    normal = n;
    stats.anchor_face = anchor_face;
    stats.lift = lift;
    stats.feature_radius = radius * scale;
    stats.influence_radius = rim * scale;
    stats.disc_map = use_disc;
    stats.disc_faces = use_disc ? Index(disc.faces.size()) : 0;
    stats.disc_iterations = disc_iterations;
    stats.map_seconds = map_seconds;
    stats.update_seconds = seconds_since(t0);
  };
  const bool follow = options.fit == PasteFit::FollowSurface;
  if (feature.carried && !follow) {
    const Eigen::MatrixXd coefficients = bend();
    const std::vector<Index>& loop = feature.boundary_loops.front();
    std::vector<Eigen::Vector2d> polygon;
    for (const Index v : loop) polygon.push_back(plane.q[v]);
    MatrixX3d placed(feature.V.rows(), 3);
    for (Index i = 0; i < Index(placed.rows()); ++i) placed.row(i) = world(feature.V.row(i).transpose()).transpose();
    // The blend at the target's vertices within the rim, by one product.
    std::vector<Index> blended;
    for (const Index v : map.vertices)
      if (q[v].norm() < rim) blended.push_back(v);
    Eigen::MatrixXd points(Index(blended.size()), 2);
    for (std::size_t k = 0; k < blended.size(); ++k) points.row(Index(k)) = q[blended[k]].transpose();
    const Eigen::MatrixXd shift = rbf->evaluate(points, coefficients);
    std::vector<Index> shift_row(std::size_t(nv), -1);
    for (std::size_t k = 0; k < blended.size(); ++k) shift_row[blended[k]] = Index(k);
    Sewn sewn = sew_carried(mesh, q, map.reached, vertex_normals, refined, anchor_face, polygon, loop, plane.q,
                            feature.F, placed, n, rim, [&](Index v) -> Eigen::Vector3d {
                              return shift_row[v] < 0 ? Eigen::Vector3d::Zero()
                                                      : Eigen::Vector3d(shift.row(shift_row[v]).transpose());
                            });
    Index moved = 0;
    for (Index v = 0; v < nv; ++v) moved += (sewn.V.row(v) != V.row(v));
    out_V = std::move(sewn.V);
    out_F = std::move(sewn.F);
    new_faces = std::move(sewn.new_faces);
    replaced_faces = std::move(sewn.replaced_faces);
    new_face_parents = std::move(sewn.new_face_parents);
    stats.level = 0;
    stats.refined_faces = Index(replaced_faces.size());
    stats.replaced_faces = Index(replaced_faces.size());
    stats.moved_vertices = moved;
    stats.feature_vertices = Index(feature.V.rows());
    stats.control_points = Index(centres.rows());
    record_placement();
    return;
  }

  // 3. Level: refined edges about as long as the feature's short ones, scaled.
  int level = options.subdivision_level;
  if (level < 0) {
    double length = 0;
    for (const Index f : refined)
      for (int k = 0; k < 3; ++k) length += (V.row(F(f, k)) - V.row(F(f, (k + 1) % 3))).norm();
    length /= 3.0 * double(refined.size());
    level = int(std::clamp(std::ceil(std::log2(length / (scale * plane.detail))), 0.0, 6.0));
  }
  RefinedRegion refined_mesh = refiner.refine(refined, level, follow ? LimitAt::RegionVertices : LimitAt::Nowhere);
  const Index total = Index(refined_mesh.V.rows());
  std::vector<Eigen::Vector2d> q_out(std::size_t(total), Eigen::Vector2d::Zero());
  for (Index v = 0; v < nv; ++v)
    if (map.reached[v]) q_out[v] = q[v];
  for (Index i = nv; i < total; ++i) {
    const Index f = refined_mesh.base_face(i);
    for (int k = 0; k < 3; ++k) q_out[i] += refined_mesh.bary(i, k) * q_of(F(f, k));
  }
  // The base each output vertex starts from: the Loop limit surface inside
  // the refined area when following the surface; else the faces as they are
  // (the limit surface lies inside a coarse mesh: it would dent the skirt).
  const auto base_of = [&](Index i) -> Eigen::RowVector3d {
    return follow && refined_mesh.region_interior(i) ? refined_mesh.limit.row(i) : refined_mesh.V.row(i);
  };

  // 4. Keep form: the RBF that bends the target to the feature's boundary.
  const Index controls = Index(centres.rows());
  Eigen::MatrixXd coefficients;
  if (!follow) coefficients = bend();

  // 5. Positions: the feature inside its domain, the blended base elsewhere
  // within the rim; the rest as it was.
  MatrixX3d out = refined_mesh.V;
  const double inside_tolerance = 1e-9 * radius;
  std::vector<Index> inside, blend, exact;
  std::vector<Eigen::Vector3d> inside_position, inside_displacement;  // feature frame / map components
  for (Index i = 0; i < total; ++i) {
    if (!((i >= nv || map.reached[i]) && q_out[i].norm() < rim)) continue;
    Eigen::Vector3d x, d;
    const int where = grid.lookup(q_out[i], &x, &d, inside_tolerance);
    if (where == 1) inside.push_back(i), inside_position.push_back(x), inside_displacement.push_back(d);
    else if (where == 0) blend.push_back(i);
    else exact.push_back(i);
  }
  if (!exact.empty()) {
    MatrixX2d points(Index(exact.size()), 2);
    for (std::size_t k = 0; k < exact.size(); ++k) points.row(Index(k)) = q_out[exact[k]].transpose();
    MatrixX3d position, displacement;
    VectorXd distance;
    lookup.at(points, &position, &displacement, &distance);
    for (std::size_t k = 0; k < exact.size(); ++k) {
      if (distance(Index(k)) <= inside_tolerance) {
        inside.push_back(exact[k]);
        inside_position.push_back(position.row(Index(k)).transpose());
        inside_displacement.push_back(displacement.row(Index(k)).transpose());
      } else {
        blend.push_back(exact[k]);
      }
    }
  }
  if (follow) {
    // The feature's vector displacement, in the frame of the target's limit
    // surface (normal from Loop, u axis turned from the anchor's like the map's).
    for (std::size_t k = 0; k < inside.size(); ++k) {
      const Index i = inside[k];
      Eigen::Vector3d normal_i = refined_mesh.limit_normal.row(i).transpose();
      if (!(normal_i.squaredNorm() > 0)) normal_i = n;
      const Eigen::Vector3d e_u = transport_tangent(t, n, normal_i);
      Eigen::Matrix3d frame;
      frame << e_u, normal_i.cross(e_u), normal_i;
      out.row(i) = base_of(i) + scale * (frame * inside_displacement[k]).transpose();
    }
    for (const Index i : blend) out.row(i) = base_of(i);
  } else {
    for (std::size_t k = 0; k < inside.size(); ++k) out.row(inside[k]) = world(inside_position[k]).transpose();
    if (!blend.empty()) {
      Eigen::MatrixXd points(Index(blend.size()), 2);
      for (std::size_t k = 0; k < blend.size(); ++k) points.row(Index(k)) = q_out[blend[k]].transpose();
      const Eigen::MatrixXd shift = rbf->evaluate(points, coefficients);
      for (std::size_t k = 0; k < blend.size(); ++k) out.row(blend[k]) = base_of(blend[k]) + shift.row(Index(k));
    }
  }
  const Index on_feature = Index(inside.size());

  // Commit.
  Index moved = 0;
  for (Index v = 0; v < nv; ++v) moved += (out.row(v) != V.row(v));
  out_V = std::move(out);
  out_F = std::move(refined_mesh.F);
  new_faces = std::move(refined_mesh.new_faces);
  replaced_faces = std::move(refined_mesh.replaced_faces);
  new_face_parents = std::move(refined_mesh.new_face_parents);
  stats.level = level;
  stats.refined_faces = Index(refined.size());
  stats.replaced_faces = Index(replaced_faces.size());
  stats.moved_vertices = moved;
  stats.feature_vertices = on_feature;
  stats.control_points = controls;
  record_placement();
}

PasteSession::PasteSession(const MatrixX3d& V, const MatrixX3i& F, Feature feature, const PasteOptions& options,
                           Progress* progress) {
  const auto t0 = Clock::now();
  check_options(options);
  check_feature(feature);
  if (progress) progress->report(0.0, "paste: target topology");
  impl_ = std::make_unique<Impl>(V, F, std::move(feature), options);
  Impl& s = *impl_;
  if (progress) progress->report(0.6, "paste: control points");
  s.vertex_normals = area_weighted_vertex_normals(V, F);

  // Control points in the feature plane: the boundary (thinned evenly) and
  // the rim circle. They never change, so the system is factored here once.
  const Feature& f = s.feature;
  Index boundary = 0;
  for (const auto& loop : f.boundary_loops) boundary += Index(loop.size());
  const Index step = std::max<Index>(1, (boundary + kMaxMovingPoints - 1) / kMaxMovingPoints);
  std::vector<Index> picked;
  for (const auto& loop : f.boundary_loops)
    for (std::size_t k = 0; k < loop.size(); k += std::size_t(step)) picked.push_back(loop[k]);
  const Index moving = Index(picked.size());
  s.rim = s.options.blend_radius * s.plane.radius;
  s.centres.resize(moving + kRimPoints, 2);
  s.moving_points.resize(moving, 3);
  for (Index c = 0; c < moving; ++c) {
    s.centres.row(c) = s.plane.q[picked[c]].transpose();
    s.moving_points.row(c) = f.base_V.row(picked[c]);
  }
  for (Index k = 0; k < kRimPoints; ++k) {
    const double a = 2 * M_PI * double(k) / double(kRimPoints);
    s.centres.row(moving + k) << s.rim * std::cos(a), s.rim * std::sin(a);
  }
  RbfOptions rbf;
  rbf.basis = s.options.basis;
  rbf.polynomial_degree = 1;
  if (rbf.basis == RbfBasis::Wendland) rbf.support_radius = 2 * s.rim;  // every point sees every other
  s.rbf = std::make_unique<RbfInterpolator>(s.centres, rbf);
  if (progress) progress->report(0.8, "paste: placement");
  s.place(options.anchor, options.rotation, options.scale);
  s.stats.setup_seconds = seconds_since(t0);
  if (progress) progress->report(1.0, "paste");
}

PasteSession::~PasteSession() = default;
PasteSession::PasteSession(PasteSession&&) noexcept = default;
PasteSession& PasteSession::operator=(PasteSession&&) noexcept = default;

void PasteSession::update(const Eigen::Vector3d& anchor, double rotation, double scale) {
  impl_->place(anchor, rotation, scale);
}

const MatrixX3d& PasteSession::V() const { return impl_->out_V; }
const MatrixX3i& PasteSession::F() const { return impl_->out_F; }
const VectorXi& PasteSession::new_faces() const { return impl_->new_faces; }
const VectorXi& PasteSession::replaced_faces() const { return impl_->replaced_faces; }
const VectorXi& PasteSession::new_face_parents() const { return impl_->new_face_parents; }
const PasteOptions& PasteSession::options() const { return impl_->options; }
const Eigen::Vector3d& PasteSession::anchor_point() const { return impl_->anchor_point; }
const Eigen::Vector3d& PasteSession::normal() const { return impl_->normal; }
const PasteStats& PasteSession::stats() const { return impl_->stats; }

}  // namespace paramorph::paste
