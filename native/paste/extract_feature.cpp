#include "paste/extract_feature.h"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

#include "common/errors.h"
#include "mesh/tri_mesh.h"
#include "mesh/validate.h"
#include "param/planar/initial_maps.h"
#include "param/planar/isometric_map.h"
#include "param/planar/untangle.h"
#include "mesh/cotangent_weights.h"
#include "paste/base_surface.h"
#include "paste/locate_in_map.h"
#include "paste/map_frames.h"
#include "paste/plane_polygon.h"
#include "paste/sample_feature.h"
#include "paste/selection_patch.h"

namespace paramorph::paste {

namespace {

/// Degenerate faces matter only inside the selection (the rest is not touched).
void require_sound_selection(const MeshReport& r, const SelectionPatch& patch) {
  std::vector<Index> bad;
  for (Index f : r.degenerate_faces)
    if (std::binary_search(patch.faces.data(), patch.faces.data() + patch.faces.size(), f))
      bad.push_back(f);
  PM_REQUIRE(bad.empty(), DegenerateFaceError, "the selection has ", bad.size(),
             " degenerate (zero-area) faces: ", format_indices(bad));
}

/// Signed area of face f in the map uv.
double signed_area(const MatrixX2d& uv, const MatrixX3i& F, Index f) {
  const Eigen::RowVector2d a = uv.row(F(f, 0)), b = uv.row(F(f, 1)), c = uv.row(F(f, 2));
  return 0.5 * ((b - a).x() * (c - a).y() - (b - a).y() * (c - a).x());
}

/// Moves a free map of X so its area centroid is uv = 0 and turns it about 0
/// so e_u there follows the world x axis projected on the surface (y where x
/// is within 25° of the normal). Returns where uv = 0 lies (a rotation about
/// 0 keeps its face and barycentric coordinates).
MapLocation place_canonically(const MatrixX3d& X, const MatrixX3i& F, MatrixX2d& uv) {
  Eigen::RowVector2d centroid = Eigen::RowVector2d::Zero();
  double total = 0;
  for (Index f = 0; f < Index(F.rows()); ++f) {
    const double area = signed_area(uv, F, f);
    centroid += area * (uv.row(F(f, 0)) + uv.row(F(f, 1)) + uv.row(F(f, 2))) / 3.0;
    total += area;
  }
  uv.rowwise() -= centroid / total;
  MapLocation at0 = MapLocator(uv, F).locate(MatrixX2d::Zero(1, 2));
  const Eigen::Matrix3d R = frame_at(map_frames(X, F, uv), F, at0.face[0], at0.bary.row(0).transpose());
  const Eigen::Vector3d n = R.col(2);
  Eigen::Vector3d t = std::abs(n.x()) < std::cos(25.0 * M_PI / 180.0) ? Eigen::Vector3d::UnitX()
                                                                        : Eigen::Vector3d::UnitY();
  t -= t.dot(n) * n;
  const double phi = std::atan2(R.col(0).cross(t).dot(n), R.col(0).dot(t));
  // uv' = rot(-phi) uv turns ∂X/∂u' by +phi about n (e_v = n × e_u).
  const double c = std::cos(phi), s = std::sin(phi);
  const MatrixX2d old = uv;
  uv.col(0) = c * old.col(0) + s * old.col(1);
  uv.col(1) = -s * old.col(0) + c * old.col(1);
  return at0;
}

planar::PlanarMapResult fold_free_map(const MatrixX3d& X, const MatrixX3i& F, planar::PlanarMapOptions o,
                                      const char* what, Progress* progress) {
  planar::PlanarMapResult m = planar::isometric_map(X, F, o, progress);
  // Hard pins exactly at their targets (the start's blend can leave round-off there).
  for (std::size_t k = 0; k < o.pinned.size(); ++k) m.uv.row(o.pinned[k]) = o.pinned_uv.row(k);
  const std::size_t folded = planar::folded_faces(F, m.uv).size();
  PM_REQUIRE(folded == 0, ConstraintError, "the ", what, " map has ", folded,
             " folded faces; the feature cannot be stored as a displacement map");
  return m;
}


/// A base for a long protrusion whose thin-plate base cannot be laid flat
/// (its interior, spread by the protrusion's own weights, folds): the
/// boundary on its best-fit plane (its own outline, or a circle of the same
/// length where that outline gives folds), the interior a positive-weight
/// average of its neighbours (fold-free for a convex outline: Floater), and
/// the same average in 3D spanning the root's ring (base rows of the
/// boundary exact). Throws ConstraintError when even the circle folds.
struct FlatBase {
  MatrixX3d V;
  MatrixX2d uv;
};

FlatBase flat_base(const MatrixX3d& X, const MatrixX3i& F, const std::vector<Index>& loop) {
  const TriMesh mesh(X, F);
  const VectorXd w = clamped_cotangent_weights(mesh);
  std::vector<char> pinned(std::size_t(X.rows()), 0);
  for (const Index v : loop) pinned[v] = 1;
  Eigen::RowVector3d centre = Eigen::RowVector3d::Zero();
  for (const Index v : loop) centre += X.row(v);
  centre /= double(loop.size());
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  Eigen::Vector3d turn = Eigen::Vector3d::Zero();  // the loop's vector area: its normal, faces' way round
  for (std::size_t k = 0; k < loop.size(); ++k) {
    const Eigen::Vector3d a = (X.row(loop[k]) - centre).transpose();
    const Eigen::Vector3d b = (X.row(loop[(k + 1) % loop.size()]) - centre).transpose();
    covariance += a * a.transpose();
    turn += a.cross(b);
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(covariance);
  Eigen::Vector3d n = eigen.eigenvectors().col(0);
  if (n.dot(turn) < 0) n = -n;
  const Eigen::Vector3d e1 = eigen.eigenvectors().col(2), e2 = n.cross(e1);
  MatrixX2d uv = MatrixX2d::Zero(X.rows(), 2);
  for (const Index v : loop) {
    const Eigen::Vector3d d = (X.row(v) - centre).transpose();
    uv.row(v) << d.dot(e1), d.dot(e2);
  }
  FlatBase out;
  std::vector<Eigen::Vector2d> outline;
  for (const Index v : loop) outline.push_back(uv.row(v).transpose());
  const bool winds = self_crossing(outline);
  if (!winds) out.uv = planar::harmonic_fill(mesh, w, pinned, uv);
  if (winds || !planar::folded_faces(F, out.uv).empty()) {  // a circle of the outline's length instead
    std::vector<double> along{0.0};
    for (std::size_t k = 0; k < loop.size(); ++k)
      along.push_back(along.back() + (X.row(loop[(k + 1) % loop.size()]) - X.row(loop[k])).norm());
    const double length = along.back(), r = length / (2 * M_PI);
    for (std::size_t k = 0; k < loop.size(); ++k) {
      const double angle = 2 * M_PI * along[k] / length;
      uv.row(loop[k]) << r * std::cos(angle), r * std::sin(angle);
    }
    out.uv = planar::harmonic_fill(mesh, w, pinned, uv);
    PM_REQUIRE(planar::folded_faces(F, out.uv).empty(), ConstraintError,
               "the ground under the selection cannot be laid flat without overlapping itself: select a rounder "
               "ring of faces around the part's root");
  }
  MatrixX2d xy = MatrixX2d::Zero(X.rows(), 2), z0 = MatrixX2d::Zero(X.rows(), 2);
  for (const Index v : loop) xy.row(v) = X.row(v).head<2>(), z0(v, 0) = X(v, 2);
  xy = planar::harmonic_fill(mesh, w, pinned, xy);
  z0 = planar::harmonic_fill(mesh, w, pinned, z0);
  out.V.resize(X.rows(), 3);
  out.V << xy, z0.col(0);
  for (const Index v : loop) out.V.row(v) = X.row(v);
  return out;
}

/// How far the base map squeezes the feature: the ratio (3D length / base
/// map length) that a tenth of its edges exceed. A protrusion's walls are squeezed
/// into a thin ring of the base, which a resampling on the base's plane
/// would need a far finer refinement than the feature's own to show.
double squeeze(const MatrixX3d& X, const MatrixX3i& F, const MatrixX2d& uv) {
  std::vector<double> ratios;
  ratios.reserve(3 * std::size_t(F.rows()));
  for (Index f = 0; f < Index(F.rows()); ++f)
    for (int k = 0; k < 3; ++k) {
      const Index a = F(f, k), b = F(f, (k + 1) % 3);
      const double flat = (uv.row(a) - uv.row(b)).norm(), length = (X.row(a) - X.row(b)).norm();
      ratios.push_back(flat > 0 ? length / flat : std::numeric_limits<double>::infinity());
    }
  const auto tenth = ratios.begin() + std::ptrdiff_t(ratios.size() - 1 - ratios.size() / 10);
  std::nth_element(ratios.begin(), tenth, ratios.end());
  return *tenth;
}

}  // namespace

Carry parse_carry(const std::string& name) {
  if (name == "auto") return Carry::Auto;
  if (name == "always") return Carry::Always;
  if (name == "never") return Carry::Never;
  PM_REQUIRE(false, InvalidInputError, "carry must be \"auto\", \"always\" or \"never\", got \"", name, "\"");
  return Carry::Auto;
}

Feature extract_feature(const MatrixX3d& V, const MatrixX3i& F, const std::vector<Index>& feature_faces,
                        const ExtractFeatureOptions& o, Progress* progress) {
  PM_REQUIRE(o.resolution >= 2 && o.resolution <= kMaxFeatureResolution, InvalidInputError,
             "resolution must be between 2 and ", kMaxFeatureResolution, ", got ", o.resolution);
  if (progress) progress->report(0.0, "validate");
  validate_arrays(V, F);
  const TriMesh mesh(V, F);
  const MeshReport report = validate(mesh);
  require_manifold(report);  // before the selection, whose edge walks need a manifold
  if (progress) progress->report(0.01, "selection");
  SelectionPatch patch = selection_patch(mesh, feature_faces);
  require_sound_selection(report, patch);
  const Index n = Index(patch.vertices.size());

  // Work at unit scale around the feature: the maps' tolerances then see the
  // same numbers whatever the input's units.
  MatrixX3d X(n, 3);
  for (Index i = 0; i < n; ++i) X.row(i) = V.row(patch.vertices[i]);
  const Eigen::RowVector3d centre = X.colwise().mean();
  double mean_edge = 0;
  Index edges = 0;
  for (Index f = 0; f < Index(patch.F.rows()); ++f)
    for (int k = 0; k < 3; ++k, ++edges)
      mean_edge += (X.row(patch.F(f, k)) - X.row(patch.F(f, (k + 1) % 3))).norm();
  mean_edge /= double(edges);  // interior edges counted twice, boundary once: close enough for a scale
  const double scale = mean_edge;
  auto normalise = [&](const MatrixX3d& P) {
    return MatrixX3d((P.rowwise() - centre) / scale);
  };

  if (progress) progress->report(0.02, "base surface");
  MatrixX3d base = normalise(base_surface(mesh, patch));
  const MatrixX3d feature = normalise(X);

  // Base map, free boundary, placed canonically (centred, turned) both as a
  // start and as a result, so the solver sees the same start whatever the
  // input's units or LSCM's choice among tied boundary pairs.
  planar::PlanarMapOptions mo;
  mo.backend = o.backend;
  mo.init = planar::PlanarInit::Given;
  {
    if (progress) progress->report(0.03, "base map start");
    const TriMesh base_mesh(base, patch.F);
    MatrixX2d start = planar::lscm_map(base_mesh);
    double area3 = 0, area2 = 0;
    for (Index f = 0; f < Index(patch.F.rows()); ++f) {
      const Eigen::Vector3d a = base.row(patch.F(f, 0)), b = base.row(patch.F(f, 1)), c = base.row(patch.F(f, 2));
      area3 += 0.5 * (b - a).cross(c - a).norm();
      area2 += 0.5 * std::abs(signed_area(start, patch.F, f));
    }
    if (area2 > 0) start *= std::sqrt(area3 / area2);
    place_canonically(base, patch.F, start);
    mo.initial_uv = start;
  }
  planar::PlanarMapResult base_map;
  bool flat = false;  // the base had to be laid flat another way: a long protrusion
  try {
    base_map = run_stage("base map", 0.05, 0.4, progress, [&](Progress* p) {
      return fold_free_map(base, patch.F, mo, "base", p);
    });
  } catch (const MeshError& e) {
    // Folds that untangling cannot undo, or faces the thin plate collapsed.
    if (!dynamic_cast<const ConstraintError*>(&e) && !dynamic_cast<const DegenerateFaceError*>(&e)) throw;
    PM_REQUIRE(patch.boundary_loops.size() == 1, SelectionTopologyError,
               "the selection is a ring around a long part whose ground cannot be laid flat: select the whole "
               "part, up to and including its tip, with a ring of faces around its root");
    flat = true;
  }
  // A base map whose boundary crosses itself winds round twice (no face is
  // turned over, yet the domain overlaps): a disc's base is laid flat then.
  if (!flat && patch.boundary_loops.size() == 1) {
    std::vector<Eigen::Vector2d> loop;
    for (const Index v : patch.boundary_loops.front()) loop.push_back(base_map.uv.row(v).transpose());
    flat = self_crossing(loop);
  }
  if (flat) {
    FlatBase laid = flat_base(feature, patch.F, patch.boundary_loops.front());
    base = std::move(laid.V);
    base_map.uv = std::move(laid.uv);
  }
  const MapLocation at0 = place_canonically(base, patch.F, base_map.uv);
  mo.init = planar::PlanarInit::Auto;
  mo.initial_uv.reset();

  // Feature map, every boundary vertex pinned to the base map.
  for (const auto& loop : patch.boundary_loops)
    mo.pinned.insert(mo.pinned.end(), loop.begin(), loop.end());
  mo.pinned_uv.resize(Index(mo.pinned.size()), 2);
  for (std::size_t k = 0; k < mo.pinned.size(); ++k) mo.pinned_uv.row(k) = base_map.uv.row(mo.pinned[k]);
  // A long protrusion (a tube closed at its tip, pinned along its rim) has
  // no such map, or one too squeezed to resample: it is carried as its own
  // mesh, its map the base map.
  PM_REQUIRE(!(flat && o.carry == Carry::Never), SelectionTopologyError,
             "the selection sticks out too far to be stored as relief on its base: copy it as a part (carry "
             "\"auto\" or \"always\")");
  const bool disc = patch.boundary_loops.size() == 1;
  // A ring around a long part: the base map shrinks the inner border to a
  // point (its ground is a cap, not a ring), and no paste could meet it.
  for (const auto& loop : patch.boundary_loops) {
    double flat_length = 0, length = 0;
    for (std::size_t k = 0; k < loop.size(); ++k) {
      const Index a = loop[k], b = loop[(k + 1) % loop.size()];
      flat_length += (base_map.uv.row(a) - base_map.uv.row(b)).norm();
      length += (base.row(a) - base.row(b)).norm();
    }
    PM_REQUIRE(disc || flat_length > 0.01 * length, SelectionTopologyError,
               "the selection is a ring around a long part: select the whole part, up to and including its tip, "
               "with a ring of faces around its root");
  }
  PM_REQUIRE(disc || o.carry != Carry::Always, SelectionTopologyError,
             "the selection is a ring: only a part selected whole, up to and including its tip, can be carried");
  bool carry = o.carry == Carry::Always || flat ||
               (o.carry == Carry::Auto && disc && squeeze(feature, patch.F, base_map.uv) > kCarrySqueeze);
  std::optional<planar::PlanarMapResult> feature_map;
  if (!carry) {
    try {
      feature_map = run_stage("feature map", 0.4, 0.85, progress, [&](Progress* p) {
        return fold_free_map(feature, patch.F, mo, "feature", p);
      });
    } catch (const ConstraintError&) {
      PM_REQUIRE(o.carry == Carry::Auto && patch.boundary_loops.size() == 1, SelectionTopologyError,
                 patch.boundary_loops.size() == 1
                     ? "the selection sticks out too far to be stored as relief on its base: copy it as a part "
                       "(carry \"auto\" or \"always\")"
                     : "the selection is a ring around a long part that cannot be laid flat between its two "
                       "borders: select the whole part, up to and including its tip, with a ring of faces around "
                       "its root");
      carry = true;
    }
  }
  if (progress) progress->report(0.85, "frame");

  // The feature frame: the base at uv = 0 (for an annulus uv = 0 lies in the
  // hole: the tangent plane at the closest domain point, continued to 0).
  // (The rotation about 0 kept uv = 0's face and barycentric coordinates.)
  const MapFrames frames = map_frames(base, patch.F, base_map.uv);
  const Eigen::Matrix3d axes = frame_at(frames, patch.F, at0.face[0], at0.bary.row(0).transpose());
  Eigen::Vector3d origin = interpolate(patch.F, at0, base).row(0).transpose();
  const Eigen::Vector2d uv0 = interpolate(patch.F, at0, base_map.uv).row(0).transpose();
  origin -= axes.leftCols<2>() * uv0;

  Feature out;
  auto to_frame = [&](const MatrixX3d& P) {  // rows: axesᵀ (p - origin), back at the input's scale
    return MatrixX3d(scale * ((P.rowwise() - origin.transpose()) * axes));
  };
  out.F = patch.F;
  out.V = to_frame(feature);
  out.base_V = to_frame(base);
  out.base_uv = scale * base_map.uv;
  out.carried = carry;
  out.uv = out.carried ? out.base_uv : MatrixX2d(scale * feature_map->uv);
  for (Index v : mo.pinned) out.uv.row(v) = out.base_uv.row(v);  // bit-identical boundaries
  out.boundary_loops = patch.boundary_loops;
  out.source_faces = patch.faces;
  out.source_vertices = patch.vertices;
  out.origin = centre.transpose() + scale * origin;
  out.axes = axes;
  for (Index v : mo.pinned) out.radius = std::max(out.radius, out.base_uv.row(v).norm());
  double area = 0, length = 0;
  for (Index f = 0; f < Index(out.F.rows()); ++f) {
    const Eigen::Vector3d a = out.V.row(out.F(f, 0)), b = out.V.row(out.F(f, 1)), c = out.V.row(out.F(f, 2));
    area += 0.5 * (b - a).cross(c - a).norm();
  }
  const TriMesh feature_mesh(out.V, out.F);
  const MatrixX2i& E = feature_mesh.edges();
  for (Index e = 0; e < Index(E.rows()); ++e) length += (out.V.row(E(e, 0)) - out.V.row(E(e, 1))).norm();
  out.area = area;
  out.mean_edge_length = length / double(E.rows());

  // The displacement grid (nodes; feature.h).
  const int r = o.resolution;
  out.resolution = r;
  out.grid_spacing = 2.0 * out.radius / double(r - 1);
  out.grid_origin = Eigen::Vector2d(-out.radius, -out.radius);
  MatrixX2d nodes(Index(r) * r, 2);
  for (int i = 0; i < r; ++i)
    for (int j = 0; j < r; ++j)
      nodes.row(Index(i) * r + j) = out.grid_origin.transpose() + out.grid_spacing * Eigen::RowVector2d(j, i);
  const BaseSample b = sample_base(out, nodes);
  const MapLocation on_feature = MapLocator(out.uv, out.F).locate(nodes);
  const Eigen::MatrixXd P = interpolate(out.F, on_feature, out.V);
  const double inside = 1e-12 * out.radius, reach = std::sqrt(2.0) * out.grid_spacing;
  out.displacement = MatrixX3d::Zero(nodes.rows(), 3);
  out.mask = VectorXi::Zero(nodes.rows());
  for (Index q = 0; q < Index(nodes.rows()); ++q) {
    if (b.distance[q] > reach) continue;
    const Eigen::Vector3d d = P.row(q) - b.base.row(q);
    out.displacement.row(q) << b.e_u.row(q).dot(d), b.e_v.row(q).dot(d), b.n.row(q).dot(d);
    out.mask[q] = b.distance[q] <= inside;
  }
  if (progress) progress->report(1.0, "done");
  return out;
}

}  // namespace paramorph::paste
