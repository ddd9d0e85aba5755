#include "morph/correspondence.h"

#include <algorithm>
#include <chrono>
#include <memory>
#include <optional>
#include <cmath>
#include <set>
#include <sstream>

#include <Eigen/LU>
#include <Eigen/Geometry>
#include <Eigen/SVD>

#include "common/best_rotation.h"
#include "common/errors.h"
#include "common/principal_axes.h"
#include "features/min_cost_assignment.h"
#include "features/mirror_plane.h"
#include "features/protrusion_tips.h"
#include "mesh/closest_points.h"
#include "mesh/edge_path_distances.h"
#include "mesh/gaussian_curvature.h"
#include "mesh/simplify.h"
#include "morph/flow_sphere_map.h"
#include "morph/map_distortion.h"
#include "morph/pin_order.h"
#include "morph/point_location.h"
#include "morph/sphere_warp.h"
#include "morph/tip_assignments.h"
#include "morph/tip_path_pairs.h"
#include "param/spherical/balanced_sphere_map.h"
#include "param/spherical/sphere_map.h"

namespace paramorph::morph {

namespace {

/// Rounds straightening the placement by its tips: each pairs them again.
constexpr int kPlacementRounds = 5;

using Pairs = std::vector<std::array<Index, 2>>;

VectorXd vertex_areas(const MatrixX3d& V, const MatrixX3i& F) {
  VectorXd area = VectorXd::Zero(V.rows());
  for (Index f = 0; f < F.rows(); ++f) {
    const double a = 0.5 * (V.row(F(f, 1)) - V.row(F(f, 0))).cross(V.row(F(f, 2)) - V.row(F(f, 0))).norm();
    for (int k = 0; k < 3; ++k) area[F(f, k)] += a / 3.0;
  }
  return area;
}

/// One model's side: its proxy, the proxy's placed balanced map, and its
/// extremities (with each model vertex's extremity, for the tips).
struct Side {
  const MatrixX3d* model_V = nullptr;
  const MatrixX3i* model_F = nullptr;
  MatrixX3d V;
  MatrixX3i F;
  MatrixX3d map;
  VectorXd area;                            ///< per proxy vertex
  VectorXd curvature;                       ///< smoothed Gaussian curvature per proxy vertex
  std::optional<features::Segmentation> extremities;
  features::ExtremityTips tips;
  std::string tips_note;                    ///< why there are no tips, when there are none
  std::vector<Index> model_tip;             ///< per tip: the model's peak of distance from the body it stands for
  features::ProtrusionTips protrusions;     ///< on the proxy (tip_path_pairs)
  std::vector<Index> protrusion_model_tip;  ///< per protrusion tip: the model's peak of distance from the core
  VectorXd protrusion_loneliness;           ///< per protrusion tip: how alone it is under the proxy's mirror plane
  std::shared_ptr<const ClosestPointTree> tree;  ///< over the proxy, to read model points on its map

  /// Where model vertices are on the proxy's map: at their closest points
  /// on the proxy, interpolated (exact points, not the nearest proxy vertex:
  /// a pin then needs no more than a rounding-sized nudge on the model).
  MatrixX3d on_map(const std::vector<Index>& model_vertices) const {
    MatrixX3d P(Index(model_vertices.size()), 3);
    for (std::size_t k = 0; k < model_vertices.size(); ++k) P.row(Index(k)) = model_V->row(model_vertices[k]);
    const ClosestPoints at = tree->query(P);
    MatrixX3d out(P.rows(), 3);
    for (Index k = 0; k < P.rows(); ++k) {
      const auto f = F.row(at.face[k]);
      out.row(k) = (at.bary(k, 0) * map.row(f[0]) + at.bary(k, 1) * map.row(f[1]) + at.bary(k, 2) * map.row(f[2])).normalized();
    }
    return out;
  }
};

Index nearest_vertex(const MatrixX3d& V, const Eigen::RowVector3d& p) {
  Index v;
  (V.rowwise() - p).rowwise().squaredNorm().minCoeff(&v);
  return v;
}

/// The model's own tips for tips of its proxy: from the model vertex nearest
/// each, up the model's distance along edges from `from` (the body, or the
/// core) to its peak, no farther than `reach` from the proxy's tip: the
/// proxy's tip is a proxy edge short of the end, and an unbounded climb from
/// a muzzle ran over the head to a horn.
std::vector<Index> climb_model_tips(const TriMesh& mesh, const MatrixX3d& proxy_V,
                                    const std::vector<Index>& proxy_tips, const std::vector<Index>& from,
                                    double reach = std::numeric_limits<double>::infinity()) {
  const MatrixX3d& V = mesh.V();
  VectorXd dist = from.empty() ? VectorXd::Zero(V.rows()) : edge_path_distances(mesh, from);
  for (Index v = 0; v < dist.size(); ++v)
    if (!std::isfinite(dist[v])) dist[v] = 0;
  const Csr& ring = mesh.vertex_neighbors();
  std::vector<Index> out;
  for (const Index tip : proxy_tips) {
    Index v = nearest_vertex(V, proxy_V.row(tip));
    for (Index higher = v; higher >= 0;) {
      v = higher;
      higher = -1;
      for (Index k = ring.begin(v); k < ring.end(v); ++k)
        if (dist[ring.items[k]] > dist[higher >= 0 ? higher : v] &&
            (V.row(ring.items[k]) - proxy_V.row(tip)).norm() <= reach)
          higher = ring.items[k];
    }
    out.push_back(v);
  }
  return out;
}

Side build_side(const MatrixX3d& V, const MatrixX3i& F, const CorrespondenceOptions& o, Progress* progress) {
  Side side;
  side.model_V = &V;
  side.model_F = &F;
  // Simplifying a large model is most of this stage (97k faces: 2 s): it
  // reports too, so Esc acts within the half second (issue 20).
  SimplifiedMesh proxy = run_stage("simplify", 0.0, 0.5, progress, [&](Progress* p) {
    return simplify(V, F, o.proxy_faces, p);
  });
  side.V = std::move(proxy.V);
  side.F = std::move(proxy.F);
  side.area = vertex_areas(side.V, side.F);
  if (progress) progress->report(0.5, "proxy");
  side.tree = std::make_shared<const ClosestPointTree>(side.V, side.F);
  side.curvature = smoothed_gaussian_curvature(TriMesh(side.V, side.F), 8);
  side.map = run_stage("proxy map", 0.5, 0.7, progress, [&](Progress* p) {
    return spherical::balanced_sphere_map(side.V, side.F, {}, p).positions;
  });
  side.map = side.map * best_rotation(side.map, side.V.rowwise().normalized(), side.area);
  // The model's own mesh for climbing to its tips: built once for both
  // kinds of tip (97k faces: a tenth of a second each).
  std::optional<TriMesh> model_mesh;
  auto model = [&]() -> const TriMesh& {
    if (!model_mesh) model_mesh.emplace(V, F);
    return *model_mesh;
  };
  if (o.extremities && o.tip_paths) {
    features::ProtrusionOptions protrusion;
    protrusion.radius = o.protrusion_radius;
    side.protrusions = features::protrusion_tips(side.V, side.F, protrusion);
    MatrixX3d tip_points(Index(side.protrusions.vertices.size()), 3);
    for (Index t = 0; t < tip_points.rows(); ++t) tip_points.row(t) = side.V.row(side.protrusions.vertices[std::size_t(t)]);
    side.protrusion_loneliness =
        features::mirror_loneliness(tip_points, features::mirror_plane(side.V, side.F, side.area));
    side.protrusion_model_tip = climb_model_tips(model(), side.V, side.protrusions.vertices,
                                                 {nearest_vertex(V, side.V.row(side.protrusions.core))},
                                                 o.protrusion_radius / 3);
  }
  if (!o.extremities && !o.registration) return side;
  // Extremities come from the conformal map's area stretch (3.5.1).
  try {
    features::ExtremityOptions extremity = o.extremity;
    extremity.sphere = run_stage("extremities", 0.7, 0.8, progress, [&](Progress* p) {
      spherical::SphereMapOptions conformal;
      conformal.keep_squeezed_start = true;  // segment_extremities' own map
      return spherical::sphere_map(side.V, side.F, conformal, p).positions;
    });
    side.extremities = run_stage("extremities", 0.8, 0.88, progress, [&](Progress* p) {
      return features::segment_extremities(side.V, side.F, extremity, p);
    });
    side.tips = features::extremity_tips(side.V, side.F, *side.extremities, o.tip_prominence);
    if (side.tips.vertices.size() > o.max_tips) {  // farthest first: keep the first
      side.tips.vertices.resize(o.max_tips);
      side.tips.regions.resize(o.max_tips);
      side.tips.lengths.resize(o.max_tips);
    }
  } catch (const ComputeError& e) {
    side.tips_note = std::string("no conformal map of the proxy: ") + e.what();
    return side;
  }
  if (side.tips.vertices.empty()) {
    side.tips_note = "no extremities found";
    return side;
  }
  // A tip of the model: from the model vertex nearest the proxy's tip, up
  // the model's own distance from the body to its peak.
  if (progress) progress->report(0.9, "model tips");
  const ClosestPoints on = side.tree->query(V);
  if (progress) progress->report(0.94, "model tips");
  std::vector<Index> body;
  for (Index v = 0; v < V.rows(); ++v)
    if (side.extremities->face_labels[on.face[v]] == side.tips.body) body.push_back(v);
  if (progress) progress->report(0.96, "model tips");
  side.model_tip = climb_model_tips(model(), side.V, side.tips.vertices, body);
  return side;
}

/// The model vertex standing for a proxy vertex: a tip's own model tip,
/// else the nearest model vertex.
Index model_vertex(const Side& side, Index proxy_vertex) {
  for (std::size_t t = 0; t < side.tips.vertices.size(); ++t)
    if (side.tips.vertices[t] == proxy_vertex && !side.model_tip.empty()) return side.model_tip[t];
  for (std::size_t t = 0; t < side.protrusions.vertices.size(); ++t)
    if (side.protrusions.vertices[t] == proxy_vertex) return side.protrusion_model_tip[t];
  Index nearest;
  (side.model_V->rowwise() - side.V.row(proxy_vertex)).rowwise().squaredNorm().minCoeff(&nearest);
  return nearest;
}

/// The points a candidate's map must bring together: on A's map and on B's.
struct PairPoints {
  std::vector<Eigen::RowVector3d> a, b;
  void add(const Eigen::RowVector3d& on_a, const Eigen::RowVector3d& on_b) { a.push_back(on_a), b.push_back(on_b); }
  MatrixX3d rows(const std::vector<Eigen::RowVector3d>& points) const {
    MatrixX3d out(Index(points.size()), 3);
    for (std::size_t k = 0; k < points.size(); ++k) out.row(Index(k)) = points[k];
    return out;
  }
};

/// A candidate before scoring: its pairs (carried to the models if it wins)
/// and the pairs that only shape its map (a registration's samples).
struct Raw {
  std::string kind, detail;
  Pairs pairs;
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();  ///< B's map's turn where there are no points
  Pairs shape_pairs;
};

/// A candidate's map of B's proxy: B's map turned so the points face their
/// partners (Kabsch; by `fallback` when there are none), then carried onto
/// them by the checked flow (flow_sphere_map), fold-free; where the proxy is
/// too coarse for the flow (pins a proxy edge apart that the model can still
/// hold) the same flow unchecked, whose folds the score then counts.
MatrixX3d candidate_map(const Side& B, const PairPoints& points, const Eigen::Matrix3d& fallback,
                        ProgressWindow progress = {}) {
  const MatrixX3d on_a = points.rows(points.a), on_b = points.rows(points.b);
  const Eigen::Matrix3d R = on_a.rows() ? best_rotation(on_b, on_a) : fallback;
  SphereFlowOptions flow;
  flow.model = &B.V;
  const SphereFlowResult flowed = flow_sphere_map(B.F, B.map * R, on_b * R, on_a, {}, flow, progress);
  if (flowed.reached >= 1) return flowed.positions;
  return warp_points(B.map * R, on_b * R, on_a, 16);
}

/// Whether the points ask for a mirror image (pin_order).
PinOrder points_order(const PairPoints& points) {
  return points.a.size() >= 3 ? pin_order(points.rows(points.b), points.rows(points.a)) : PinOrder{};
}

/// Farthest-point samples of a point set (Euclidean), starting at row 0.
std::vector<Index> farthest_points(const MatrixX3d& P, std::size_t count) {
  std::vector<Index> out;
  if (P.rows() == 0) return out;
  VectorXd nearest = VectorXd::Constant(P.rows(), std::numeric_limits<double>::infinity());
  Index next = 0;
  while (out.size() < std::min<std::size_t>(count, std::size_t(P.rows()))) {
    out.push_back(next);
    nearest = nearest.cwiseMin((P.rowwise() - P.row(next)).rowwise().norm());
    nearest.maxCoeff(&next);
  }
  return out;
}

/// How unlike the curvature of every vertex of B's proxy is to A's where
/// the candidate map puts it: the area-weighted mean absolute difference of
/// the smoothed Gaussian curvatures, over their mean spread (`at`: where
/// each vertex of B's proxy lands on A's map). Distortion alone
/// cannot see a map that slides along a smooth surface (a bump carried
/// beside its partner bends little); this can.
double curvature_mismatch(const Side& A, const Side& B, const SphereLocations& at) {
  auto spread = [](const VectorXd& K, const VectorXd& w) {
    const double mean = K.dot(w) / w.sum();
    return (K.array() - mean).abs().matrix().dot(w) / w.sum();
  };
  const double scale = 0.5 * (spread(A.curvature, A.area) + spread(B.curvature, B.area));
  double sum = 0;
  for (Index v = 0; v < B.V.rows(); ++v) {
    const auto f = A.F.row(at.face[v]);
    const double there = at.bary(v, 0) * A.curvature[f[0]] + at.bary(v, 1) * A.curvature[f[1]] +
                         at.bary(v, 2) * A.curvature[f[2]];
    sum += B.area[v] * std::abs(B.curvature[v] - there);
  }
  return scale > 0 ? sum / B.area.sum() / scale : 0.0;
}

/// How far a candidate's map puts B's protrusion tips from the partners
/// their paths chose as placed (tip_path_pairs): per pair, the distance from
/// where B's tip lands on A's proxy to A's tip over `radius`, at most 1,
/// weighted by the pair's confidence (1 - cost / max_cost); 0 with no pairs.
/// Distortion and curvature alone scored a lion's muzzle put on a cow's horn
/// within 0.5 % of the right map (issue 29).
double tip_disagreement(const Side& A, const SphereLocations& at, const std::vector<TipPathPair>& pairs,
                        double radius, double max_cost) {
  double sum = 0, weights = 0;
  for (const TipPathPair& pair : pairs) {
    const auto f = A.F.row(at.face[pair.b]);
    const Eigen::RowVector3d landed =
        at.bary(pair.b, 0) * A.V.row(f[0]) + at.bary(pair.b, 1) * A.V.row(f[1]) + at.bary(pair.b, 2) * A.V.row(f[2]);
    const double weight = std::max(0.0, 1.0 - pair.cost / max_cost);
    sum += weight * std::min(1.0, (landed - A.V.row(pair.a)).norm() / radius);
    weights += weight;
  }
  return weights > 0 ? sum / weights : 0.0;
}

double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

std::string degrees(double radians) {
  std::ostringstream out;
  out.precision(0);
  out << std::fixed << radians * 180.0 / M_PI << " deg";
  return out.str();
}

/// With three or more pins the tips can pair by where they are relative to
/// them: each tip's distances along the surface to the pins, as a unit
/// vector (proportions, not lengths: a cat's long tail and a cow's short
/// one are both far from the front hooves and near the hind ones). Tips
/// assigned at least cost (min_cost_assignment) and close enough pair;
/// tips beside a pin (the pinned hooves themselves) do not.
Pairs tips_by_pin_distances(const Side& A, const Side& B, const MatrixX3d& VA, const MatrixX3d& VB,
                            const Pairs& pins, const CorrespondenceOptions& o) {
  // Units of the frame (unit area): a pinned hoof's own tip and its
  // neighbours are this close to the pin.
  constexpr double kBesidePin = 0.15;
  const Index k = Index(pins.size());
  auto descriptors = [&](const Side& side, const MatrixX3d& model, int column, VectorXd& nearest_pin) {
    const TriMesh mesh(side.V, side.F);
    const Index tips = Index(side.tips.vertices.size());
    Eigen::MatrixXd D(tips, k);
    for (Index j = 0; j < k; ++j) {
      Index at;
      (side.V.rowwise() - model.row(pins[std::size_t(j)][std::size_t(column)])).rowwise().squaredNorm().minCoeff(&at);
      const VectorXd d = edge_path_distances(mesh, {at});
      for (Index t = 0; t < tips; ++t) D(t, j) = d[side.tips.vertices[std::size_t(t)]];
    }
    nearest_pin = D.rowwise().minCoeff();
    for (Index t = 0; t < tips; ++t) D.row(t) /= std::max(D.row(t).norm(), 1e-300);
    return D;
  };
  VectorXd near_a, near_b;
  const Eigen::MatrixXd da = descriptors(A, VA, 0, near_a), db = descriptors(B, VB, 1, near_b);
  Eigen::MatrixXd cost(da.rows(), db.rows());
  for (Index i = 0; i < da.rows(); ++i)
    for (Index j = 0; j < db.rows(); ++j) cost(i, j) = (da.row(i) - db.row(j)).norm();
  Pairs out;
  if (!cost.allFinite()) return out;  // a pin apart from a tip along no path: nothing to say
  const std::vector<Index> assigned = features::min_cost_assignment(cost);
  for (Index i = 0; i < da.rows(); ++i) {
    const Index j = assigned[std::size_t(i)];
    if (j >= 0 && cost(i, j) < o.pin_distance_match && near_a[i] > kBesidePin && near_b[j] > kBesidePin)
      out.push_back({A.tips.vertices[std::size_t(i)], B.tips.vertices[std::size_t(j)]});
  }
  return out;
}

/// tip_path_pairs with B turned by `rotation` into A's frame, without the
/// tips within half a protrusion radius of a pin on either model: a pinned
/// hoof's tip is a few edges from the pin, and holding both where the two
/// models put them differently stalled the map (lion -> scanned cow, four
/// hooves pinned).
std::vector<TipPathPair> unpinned_tip_path_pairs(const Side& A, const Side& B, const MatrixX3d& VA,
                                                 const MatrixX3d& VB, const Pairs& pins,
                                                 const Eigen::Matrix3d& rotation, const CorrespondenceOptions& o) {
  std::vector<TipPathPair> out;
  for (const TipPathPair& pair : tip_path_pairs(A.V, A.area, A.protrusions, B.V * rotation.transpose(), B.area,
                                                B.protrusions, o.tip_path_samples, o.tip_path_cost,
                                                A.protrusion_loneliness, B.protrusion_loneliness, o.mirror_weight)) {
    bool pinned = false;
    for (const auto& pin : pins)
      pinned = pinned || (A.V.row(pair.a) - VA.row(pin[0])).norm() < 0.5 * o.protrusion_radius ||
               (B.V.row(pair.b) - VB.row(pin[1])).norm() < 0.5 * o.protrusion_radius;
    if (!pinned) out.push_back(pair);
  }
  return out;
}

/// Where B is placed beside A, straightened by its own tips (issue 31): the
/// tips paired by their paths as placed give the best turn of B's tips onto
/// their partners (Kabsch about the frames' common centre); under that turn
/// the tips are paired again, and the turn is kept while it pairs more of
/// them, up to max_placement_turn. (As many, more cheaply, is no sign: the
/// lion as the files lie paired its 6 more cheaply turned 20 degrees off,
/// its muzzle onto a horn, 29 %.) A lion set down
/// turned 20 degrees and tilted 10 beside the horned cow paired 5 of its 6
/// tips as placed and the principal axes' candidate won, its muzzle 23 % of
/// the diagonal off (3 % as the files lie); straightened, all 6 pair as they
/// do as the files lie. A larger misplacement is taken as placed: two
/// quadrupeds fit about as closely end for end as the right way round.
struct Placement {
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();  // column vectors: x_A = R x_B
  std::vector<TipPathPair> pairs;                          // the tips' pairing under it
};

Placement straightened_placement(const Side& A, const Side& B, const MatrixX3d& VA, const MatrixX3d& VB,
                                 const Pairs& pins, const CorrespondenceOptions& o) {
  Placement placed{Eigen::Matrix3d::Identity(), unpinned_tip_path_pairs(A, B, VA, VB, pins, Eigen::Matrix3d::Identity(), o)};
  for (int round = 0; round < kPlacementRounds && placed.pairs.size() >= 3; ++round) {
    MatrixX3d from(Index(placed.pairs.size()), 3), to(Index(placed.pairs.size()), 3);
    for (std::size_t k = 0; k < placed.pairs.size(); ++k) {
      from.row(Index(k)) = B.V.row(placed.pairs[k].b);
      to.row(Index(k)) = A.V.row(placed.pairs[k].a);
    }
    const Eigen::Matrix3d turn = best_rotation(from, to).transpose();  // rows: from R ~ to
    if (Eigen::AngleAxisd(turn).angle() > o.max_placement_turn) break;
    std::vector<TipPathPair> pairs = unpinned_tip_path_pairs(A, B, VA, VB, pins, turn, o);
    if (pairs.size() <= placed.pairs.size()) break;
    placed = {turn, std::move(pairs)};
  }
  return placed;
}

/// A turn of B's proxy into A's frame to start from: as placed
/// (straightened), or one of the four proper sign choices of their
/// principal axes (area-weighted).
struct Start {
  std::string detail;
  Eigen::Matrix3d rotation;  // column vectors: x_A = R x_B
};

std::vector<Start> shape_starts(const Side& A, const Side& B, const Placement& placed) {
  const Eigen::Matrix3d axes_a = principal_axes(A.V, A.area).axes, axes_b = principal_axes(B.V, B.area).axes;
  std::vector<Start> starts{{placed.rotation == Eigen::Matrix3d::Identity()
                                 ? std::string("as placed")
                                 : "as placed, straightened by " + degrees(Eigen::AngleAxisd(placed.rotation).angle()),
                             placed.rotation}};
  const char* turns[4] = {"principal axes", "principal axes, turned 180 deg about the first",
                          "principal axes, turned 180 deg about the second", "principal axes, turned 180 deg about the third"};
  const double signs[4][3] = {{1, 1, 1}, {1, -1, -1}, {-1, 1, -1}, {-1, -1, 1}};
  for (int s = 0; s < 4; ++s)
    starts.push_back({turns[s], axes_a * Eigen::Vector3d(signs[s][0], signs[s][1], signs[s][2]).asDiagonal() * axes_b.transpose()});
  return starts;
}

/// Every candidate (DESIGN: none, extremities, registration, features), or
/// the one "given" candidate.
std::vector<Raw> make_candidates(const Side& A, const Side& B, const MatrixX3d& VA, const MatrixX3d& VB,
                                 const Pairs& pins, const std::optional<Pairs>& given,
                                 const Placement& placed, const CorrespondenceOptions& o,
                                 Progress* progress) {
  std::vector<Raw> raw;
  if (given) {
    Pairs proxy;
    MatrixX3d pa(Index(given->size()), 3), pb(Index(given->size()), 3);
    for (std::size_t k = 0; k < given->size(); ++k) {
      pa.row(Index(k)) = VA.row((*given)[k][0]);
      pb.row(Index(k)) = VB.row((*given)[k][1]);
    }
    const ClosestPoints ca = A.tree->query(pa), cb = B.tree->query(pb);
    for (std::size_t k = 0; k < given->size(); ++k) {
      Index ka, kb;
      ca.bary.row(Index(k)).maxCoeff(&ka);
      cb.bary.row(Index(k)).maxCoeff(&kb);
      proxy.push_back({A.F(ca.face[Index(k)], ka), B.F(cb.face[Index(k)], kb)});
    }
    raw.push_back({"given", std::to_string(given->size()) + " pairs", proxy, Eigen::Matrix3d::Identity(), {}});
  } else {
    raw.push_back({"none", "the models as placed", {}, Eigen::Matrix3d::Identity(), {}});
    if (o.extremities && !A.tips.vertices.empty() && !B.tips.vertices.empty()) {
      MatrixX3d ta(Index(A.tips.vertices.size()), 3), tb(Index(B.tips.vertices.size()), 3);
      for (Index t = 0; t < ta.rows(); ++t) ta.row(t) = A.map.row(A.tips.vertices[std::size_t(t)]);
      for (Index t = 0; t < tb.rows(); ++t) tb.row(t) = B.map.row(B.tips.vertices[std::size_t(t)]);
      for (const TipAssignment& assignment : tip_assignments(ta, tb, o.tip_angle, o.max_tip_assignments)) {
        Raw r{"extremities", "", {}, Eigen::Matrix3d::Identity(), {}};
        for (const auto& [a, b] : assignment.pairs) r.pairs.push_back({A.tips.vertices[std::size_t(a)], B.tips.vertices[std::size_t(b)]});
        r.detail = std::to_string(r.pairs.size()) + " of " + std::to_string(A.tips.vertices.size()) + " and " +
                   std::to_string(B.tips.vertices.size()) + " tips paired, " + degrees(assignment.mean_angle) + " apart";
        raw.push_back(std::move(r));
      }
    }
    if (o.extremities && pins.size() >= 3 && !A.tips.vertices.empty() && !B.tips.vertices.empty()) {
      Raw r{"pin distances", "", tips_by_pin_distances(A, B, VA, VB, pins, o), Eigen::Matrix3d::Identity(), {}};
      r.detail = std::to_string(r.pairs.size()) + " tips paired by their distances along the surface to the " +
                 std::to_string(pins.size()) + " pins";
      if (!r.pairs.empty()) raw.push_back(std::move(r));
    }
    if (progress) progress->report(0.82, "correspondence candidates");
    const std::vector<Start> starts = shape_starts(A, B, placed);
    if (o.extremities && o.tip_paths) {
      for (const Start& start : starts) {
        const std::vector<TipPathPair> paired = &start == &starts.front()
                                                    ? placed.pairs
                                                    : unpinned_tip_path_pairs(A, B, VA, VB, pins, start.rotation, o);
        if (paired.size() < 2) continue;
        Raw r{"tip paths", "", {}, Eigen::Matrix3d::Identity(), {}};
        double cost = 0;
        for (const TipPathPair& pair : paired) r.pairs.push_back({pair.a, pair.b}), cost += pair.cost;
        std::ostringstream detail;
        detail.precision(2);
        detail << start.detail << ", " << paired.size() << " of " << A.protrusions.vertices.size() << " and "
               << B.protrusions.vertices.size() << " tips paired by their paths from the core, mean cost "
               << cost / double(paired.size());
        r.detail = detail.str();
        raw.push_back(std::move(r));
      }
    }
    if (o.registration) {
      for (const Start& start : starts) {
        // Each registration reports: the five of them were 1.5-5 s without a
        // report on 97k faces (Esc waited that long, issue 20).
        const double first = 0.82 + 0.04 * double(&start - starts.data()) / double(starts.size());
        const Registration registration = run_stage(
            "correspondence candidates", first, first + 0.04 / double(starts.size()), progress, [&](Progress* p) {
              return register_surfaces(A.V, A.F, B.V, B.F,
                                       {PolynomialWarp::similarity(Eigen::RowVector3d::Zero(), 1.0, start.rotation,
                                                                   Eigen::RowVector3d::Zero(), 1.0)},
                                       o.registration_options, p);
            });
        const MatrixX3d moved = registration.warp(B.V);
        // The registration as a smooth map: farthest-point samples of B's
        // proxy paired with A's vertex at their registered closest points,
        // where that is near (a closest-point map read vertex by vertex
        // zigzags at the proxy's resolution and would be scored for it).
        const ClosestPoints on = A.tree->query(moved);
        Raw r{"registration", start.detail, {}, Eigen::Matrix3d::Identity(), {}};
        std::set<Index> sampled_a;
        for (const Index v : farthest_points(B.V, o.registration_samples)) {
          if (!(on.distance[v] < o.registered_tip_distance)) continue;
          Index corner;
          on.bary.row(v).maxCoeff(&corner);
          const Index a = A.F(on.face[v], corner);
          if (sampled_a.insert(a).second) r.shape_pairs.push_back({a, v});
        }
        // Tips mutually nearest after the registration.
        for (std::size_t tb = 0; tb < B.tips.vertices.size(); ++tb) {
          const Eigen::RowVector3d p = moved.row(B.tips.vertices[tb]);
          std::size_t best = 0;
          double nearest = std::numeric_limits<double>::infinity();
          for (std::size_t ta = 0; ta < A.tips.vertices.size(); ++ta) {
            const double d = (A.V.row(A.tips.vertices[ta]) - p).norm();
            if (d < nearest) nearest = d, best = ta;
          }
          if (!(nearest < o.registered_tip_distance)) continue;
          bool mutual = true;
          for (std::size_t other = 0; other < B.tips.vertices.size(); ++other)
            mutual = mutual && (other == tb || (moved.row(B.tips.vertices[other]) - A.V.row(A.tips.vertices[best])).norm() >= nearest);
          if (mutual) r.pairs.push_back({A.tips.vertices[best], B.tips.vertices[tb]});
        }
        std::ostringstream detail;
        detail.precision(3);
        detail << r.detail << ", residual " << registration.cost << ", " << r.pairs.size() << " tips paired";
        r.detail = detail.str();
        raw.push_back(std::move(r));
      }
    }
    if (progress) progress->report(0.86, "correspondence candidates");
    if (o.features) {
      try {
        const features::FeatureMatch match = run_stage(
            "correspondence candidates", 0.86, 0.88, progress,
            [&](Progress* p) { return features::match_features(A.V, A.F, B.V, B.F, o.match, p); });
        if (!match.point_pairs.empty())
          raw.push_back({"features", std::to_string(match.point_pairs.size()) + " feature points paired",
                         match.point_pairs, Eigen::Matrix3d::Identity(), {}});
      } catch (const MeshError&) {
        // A proxy the feature matcher cannot take (e.g. flat, Qhull): no candidate.
      }
    }
  }
  return raw;
}

}  // namespace

Correspondence correspondence(const MatrixX3d& VA, const MatrixX3i& FA, const MatrixX3d& VB, const MatrixX3i& FB,
                              const Pairs& pins, const std::optional<Pairs>& given, const CorrespondenceOptions& o,
                              Progress* progress) {
  PM_REQUIRE(o.proxy_faces >= 100 && o.max_tips >= 1 && std::isfinite(o.tip_angle) && o.tip_angle > 0 &&
                 std::isfinite(o.registered_tip_distance) && o.registered_tip_distance > 0 &&
                 std::isfinite(o.pin_radius) && o.pin_radius >= 0 && o.fallbacks >= 0 &&
                 std::isfinite(o.protrusion_radius) && o.protrusion_radius > 0 && o.tip_path_samples >= 2 &&
                 std::isfinite(o.tip_path_cost) && o.tip_path_cost > 0 && std::isfinite(o.mirror_weight) &&
                 o.mirror_weight >= 0 && std::isfinite(o.max_placement_turn) && o.max_placement_turn >= 0,
             InvalidInputError,
             "proxy_faces >= 100, max_tips >= 1, tip_angle, registered_tip_distance, protrusion_radius and tip_path_cost > 0, "
             "tip_path_samples >= 2, pin_radius, mirror_weight, max_placement_turn and fallbacks >= 0");
  Correspondence out;
  auto clock = std::chrono::steady_clock::now();
  auto mark = [&](const char* stage) {
    out.timings.emplace_back(stage, seconds_since(clock));
    clock = std::chrono::steady_clock::now();
  };
  const Side A = for_mesh("A", [&] { return run_stage("proxy map A", 0.0, 0.4, progress, [&](Progress* p) { return build_side(VA, FA, o, p); }); });
  const Side B = for_mesh("B", [&] { return run_stage("proxy map B", 0.4, 0.8, progress, [&](Progress* p) { return build_side(VB, FB, o, p); }); });
  mark("proxies and their maps");
  out.proxy_a = A.V, out.proxy_b = B.V, out.proxy_faces_a = A.F, out.proxy_faces_b = B.F;
  out.map_a = A.map, out.map_b = B.map;

  // The pins as exact points of the proxies' maps.
  PairPoints pin_points;
  {
    std::vector<Index> va, vb;
    for (const auto& pin : pins) va.push_back(pin[0]), vb.push_back(pin[1]);
    const MatrixX3d on_a = A.on_map(va), on_b = B.on_map(vb);
    for (Index j = 0; j < on_a.rows(); ++j) pin_points.add(on_a.row(j), on_b.row(j));
    const PinOrder order = points_order(pin_points);
    PM_REQUIRE(!order.mirrored(), ConstraintError, mirrored_pins_message(order));
  }
  // The tips' own pairing as the models are placed (straightened): a
  // candidate, and every candidate is scored for keeping it
  // (tip_disagreement) and for how far it turns B from that placement.
  const Placement placed =
      !given && o.extremities && o.tip_paths ? straightened_placement(A, B, VA, VB, pins, o) : Placement{};
  out.placement_turn = Eigen::AngleAxisd(placed.rotation).angle();
  const std::vector<Raw> raw = make_candidates(A, B, VA, VB, pins, given, placed, o, progress);
  mark("candidates");

  // A proxy pair within pin_radius of a pin on either model.
  auto near_pin = [&](const std::array<Index, 2>& pair) {
    for (const auto& pin : pins)
      if ((A.V.row(pair[0]) - VA.row(pin[0])).norm() < o.pin_radius ||
          (B.V.row(pair[1]) - VB.row(pin[1])).norm() < o.pin_radius)
        return true;
    return false;
  };

  // Score every distinct candidate; keep what its realisation needs.
  std::set<Pairs> seen;
  std::vector<std::size_t> raw_of;  // per kept candidate, its raw index
  for (std::size_t c = 0; c < raw.size(); ++c) {
    if (progress) progress->report(0.88 + 0.1 * double(c) / double(raw.size()), "scoring correspondences");
    const Raw& r = raw[c];
    CorrespondenceCandidate candidate;
    candidate.kind = r.kind;
    candidate.detail = r.detail;
    // Automatic pairs away from the pins and from each other.
    PairPoints points = pin_points;
    std::set<Index> used_a, used_b;
    for (const auto& pair : r.pairs) {
      if (used_a.count(pair[0]) || used_b.count(pair[1]) || near_pin(pair)) continue;
      used_a.insert(pair[0]), used_b.insert(pair[1]);
      candidate.proxy_pairs.push_back(pair);
      points.add(A.map.row(pair[0]), B.map.row(pair[1]));
    }
    for (const auto& pair : r.shape_pairs) {
      if (used_a.count(pair[0]) || used_b.count(pair[1]) || near_pin(pair)) continue;
      used_a.insert(pair[0]), used_b.insert(pair[1]);
      points.add(A.map.row(pair[0]), B.map.row(pair[1]));
    }
    Pairs key = candidate.proxy_pairs;
    std::sort(key.begin(), key.end());
    // Pairs make the candidate unless it has its own samples (a
    // registration) or is "none"/"given"; the same pairs as an earlier
    // candidate add nothing.
    const bool by_pairs = r.shape_pairs.empty() && r.kind != "none" && r.kind != "given";
    if (by_pairs && (key.empty() || !seen.insert(key).second)) continue;
    raw_of.push_back(c);
    const PinOrder order = points_order(points);
    // The user's own pairs in mirrored order are a contradiction to report,
    // not a candidate to pass over.
    PM_REQUIRE(!(r.kind == "given" && order.mirrored()), ConstraintError, "the given pairs are in mirrored order: ",
               order.disagreeing, " of ", order.oriented,
               " clearly oriented triples turn the other way on one mesh than on the other; are left and right "
               "swapped, or is one file mirrored?");
    if (order.mirrored()) {
      candidate.rejected = "its pairs are in mirrored order";
    } else {
      // Each candidate's map and measures took 0.4 s on the octopus pair: reports between.
      auto step = [&](double part) {
        if (progress)
          progress->report(0.88 + 0.1 * (double(c) + part) / double(raw.size()), "scoring correspondences");
      };
      const MatrixX3d warped =
          candidate_map(B, points, r.rotation,
                        ProgressWindow(progress, 0.88 + 0.1 * double(c) / double(raw.size()),
                                       0.88 + 0.1 * (double(c) + 0.4) / double(raw.size())));
      step(0.4);
      candidate.distortion = map_distortion(A.V, A.F, A.map, B.V, B.F, warped).mean;
      step(0.7);
      const SphereLocations landed = locate_on_sphere_map(A.map, A.F, warped);
      candidate.curvature_mismatch = curvature_mismatch(A, B, landed);
      candidate.tip_disagreement =
          tip_disagreement(A, landed, placed.pairs, o.protrusion_radius, o.tip_path_cost);
      // Rows: B.map turn ~ warped; the placement's own turn of B is placed.rotation.
      const Eigen::Matrix3d turn = best_rotation(B.map, warped, B.area);
      candidate.turn = Eigen::AngleAxisd(turn * placed.rotation).angle();
      candidate.score = (candidate.distortion + o.curvature_weight * candidate.curvature_mismatch) *
                        (1 + o.placement_weight * candidate.turn / M_PI) *
                        (1 + o.tip_weight * candidate.tip_disagreement);
      if (!std::isfinite(candidate.score)) candidate.rejected = "its correspondence could not be measured";
    }
    out.candidates.push_back(candidate);
  }
  mark("scores");

  // Ranked: "given" first (the user's), then by score; rejected ones never.
  std::vector<Index> ranked;
  for (Index k = 0; k < Index(out.candidates.size()); ++k)
    if (out.candidates[std::size_t(k)].rejected.empty()) ranked.push_back(k);
  std::stable_sort(ranked.begin(), ranked.end(), [&](Index x, Index y) {
    const auto& cx = out.candidates[std::size_t(x)];
    const auto& cy = out.candidates[std::size_t(y)];
    if ((cx.kind == "given") != (cy.kind == "given")) return cx.kind == "given";
    return cx.score < cy.score;
  });
  PM_REQUIRE(!ranked.empty(), ComputeError, "correspondence: no candidate could be scored");
  if (ranked.size() > std::size_t(o.fallbacks) + 1) ranked.resize(std::size_t(o.fallbacks) + 1);
  // "none" (the pins alone) last of all: with no pins it always holds.
  for (Index k = 0; k < Index(out.candidates.size()); ++k)
    if (out.candidates[std::size_t(k)].kind == "none" && out.candidates[std::size_t(k)].rejected.empty() &&
        std::find(ranked.begin(), ranked.end(), k) == ranked.end())
      ranked.push_back(k);

  // The ranked candidates carried to the models: their pairs on the models'
  // own vertices, and their map again with every pair and pin at its exact
  // point (a registration's samples as they were).
  for (const Index k : ranked) {
    const Raw& r = raw[raw_of[std::size_t(k)]];
    Realization real;
    real.candidate = k;
    std::set<Index> used_a, used_b;
    for (const auto& pin : pins) used_a.insert(pin[0]), used_b.insert(pin[1]);
    // Given pairs are the user's vertices already; automatic ones stand for
    // proxy vertices.
    Pairs on_models = given ? *given : Pairs{};
    if (!given)
      for (const auto& pair : out.candidates[std::size_t(k)].proxy_pairs)
        on_models.push_back({model_vertex(A, pair[0]), model_vertex(B, pair[1])});
    // On the models too, an automatic pair must keep pin_radius from every
    // pin and earlier pair on both (a tip climbed to beside a pinned vertex
    // would squeeze the map between them).
    for (const auto& [a, b] : on_models) {
      if (used_a.count(a) || used_b.count(b)) continue;
      bool crowded = false;
      for (const auto& pin : pins)
        crowded = crowded || (VA.row(a) - VA.row(pin[0])).norm() < o.pin_radius ||
                  (VB.row(b) - VB.row(pin[1])).norm() < o.pin_radius;
      for (const auto& pair : real.pairs)
        crowded = crowded || (VA.row(a) - VA.row(pair[0])).norm() < o.pin_radius ||
                  (VB.row(b) - VB.row(pair[1])).norm() < o.pin_radius;
      if (crowded && !given) continue;
      used_a.insert(a), used_b.insert(b);
      real.pairs.push_back({a, b});
    }
    PairPoints exact, shape;
    std::vector<Index> va, vb;
    for (const auto& pin : pins) va.push_back(pin[0]), vb.push_back(pin[1]);
    for (const auto& pair : real.pairs) va.push_back(pair[0]), vb.push_back(pair[1]);
    const MatrixX3d on_a = A.on_map(va), on_b = B.on_map(vb);
    for (Index j = 0; j < on_a.rows(); ++j) exact.add(on_a.row(j), on_b.row(j));
    std::set<Index> sampled_a, sampled_b;
    for (const auto& pair : r.shape_pairs) {
      bool near_pair = near_pin(pair);
      for (std::size_t j = 0; j < real.pairs.size() && !near_pair; ++j)
        near_pair = (B.V.row(pair[1]) - VB.row(real.pairs[j][1])).norm() < o.pin_radius;
      if (!near_pair && sampled_a.insert(pair[0]).second && sampled_b.insert(pair[1]).second) {
        exact.add(A.map.row(pair[0]), B.map.row(pair[1]));
        shape.add(A.map.row(pair[0]), B.map.row(pair[1]));
      }
    }
    real.rotation = r.rotation;
    real.shape_a = shape.rows(shape.a);
    real.shape_b = shape.rows(shape.b);
    real.warped_b = candidate_map(B, exact, r.rotation);
    out.ranked.push_back(std::move(real));
  }
  out.chosen = out.ranked.front().candidate;
  out.pairs = out.ranked.front().pairs;
  out.warped_b = out.ranked.front().warped_b;
  mark("pairs on the models");
  if (progress) progress->report(1.0, "correspondence");
  return out;
}

}  // namespace paramorph::morph
