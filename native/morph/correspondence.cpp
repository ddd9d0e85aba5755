#include "morph/correspondence.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <set>
#include <sstream>

#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <Eigen/Geometry>
#include <Eigen/SVD>

#include "common/errors.h"
#include "mesh/closest_points.h"
#include "mesh/edge_path_distances.h"
#include "mesh/gaussian_curvature.h"
#include "mesh/simplify.h"
#include "morph/map_distortion.h"
#include "morph/pin_order.h"
#include "morph/point_location.h"
#include "morph/sphere_warp.h"
#include "morph/tip_assignments.h"
#include "param/spherical/balanced_sphere_map.h"
#include "param/spherical/sphere_map.h"

namespace paramorph::morph {

namespace {

using Pairs = std::vector<std::array<Index, 2>>;

/// The proper rotation R (rows: p R) that best turns the weighted rows of
/// `from` onto `to` (Kabsch); the shortest rotation for one row; the
/// identity for none.
Eigen::Matrix3d best_rotation(const MatrixX3d& from, const MatrixX3d& to, const VectorXd& w) {
  if (from.rows() == 0) return Eigen::Matrix3d::Identity();
  if (from.rows() == 1)
    return Eigen::Quaterniond::FromTwoVectors(from.row(0).transpose(), to.row(0).transpose())
        .toRotationMatrix()
        .transpose();
  const Eigen::Matrix3d covariance = from.transpose() * w.asDiagonal() * to;
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(covariance, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d flip = Eigen::Matrix3d::Identity();
  flip(2, 2) = (svd.matrixU() * svd.matrixV().transpose()).determinant() < 0 ? -1.0 : 1.0;
  return svd.matrixU() * flip * svd.matrixV().transpose();
}

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
};

Side build_side(const MatrixX3d& V, const MatrixX3i& F, const CorrespondenceOptions& o, Progress* progress) {
  Side side;
  side.model_V = &V;
  side.model_F = &F;
  SimplifiedMesh proxy = simplify(V, F, o.proxy_faces);
  side.V = std::move(proxy.V);
  side.F = std::move(proxy.F);
  side.area = vertex_areas(side.V, side.F);
  side.curvature = smoothed_gaussian_curvature(TriMesh(side.V, side.F), 8);
  side.map = spherical::balanced_sphere_map(side.V, side.F, {}, progress).positions;
  side.map = side.map * best_rotation(side.map, side.V.rowwise().normalized(), side.area);
  if (!o.extremities && !o.registration) return side;
  // Extremities come from the conformal map's area stretch (3.5.1).
  try {
    features::ExtremityOptions extremity = o.extremity;
    extremity.sphere = spherical::sphere_map(side.V, side.F).positions;
    side.extremities = features::segment_extremities(side.V, side.F, extremity);
    side.tips = features::extremity_tips(side.V, side.F, *side.extremities, o.tip_prominence);
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
  const ClosestPoints on = ClosestPointTree(side.V, side.F).query(V);
  const TriMesh mesh(V, F);
  std::vector<Index> body;
  for (Index v = 0; v < V.rows(); ++v)
    if (side.extremities->face_labels[on.face[v]] == side.tips.body) body.push_back(v);
  VectorXd dist = body.empty() ? VectorXd::Zero(V.rows()) : edge_path_distances(mesh, body);
  for (Index v = 0; v < dist.size(); ++v)
    if (!std::isfinite(dist[v])) dist[v] = 0;
  const Csr& ring = mesh.vertex_neighbors();
  for (const Index tip : side.tips.vertices) {
    Index v;
    (V.rowwise() - side.V.row(tip)).rowwise().squaredNorm().minCoeff(&v);
    for (Index higher = v; higher >= 0;) {
      v = higher;
      higher = -1;
      for (Index k = ring.begin(v); k < ring.end(v); ++k)
        if (dist[ring.items[k]] > dist[higher >= 0 ? higher : v]) higher = ring.items[k];
    }
    side.model_tip.push_back(v);
  }
  return side;
}

/// The model vertex standing for a proxy vertex: a tip's own model tip,
/// else the nearest model vertex.
Index model_vertex(const Side& side, Index proxy_vertex) {
  for (std::size_t t = 0; t < side.tips.vertices.size(); ++t)
    if (side.tips.vertices[t] == proxy_vertex && !side.model_tip.empty()) return side.model_tip[t];
  Index nearest;
  (side.model_V->rowwise() - side.V.row(proxy_vertex)).rowwise().squaredNorm().minCoeff(&nearest);
  return nearest;
}

/// Principal axes (columns, largest variance first) of a proxy, area-weighted, det +1.
Eigen::Matrix3d principal_axes(const Side& side) {
  const VectorXd w = side.area / side.area.sum();
  const Eigen::RowVector3d mean = w.transpose() * side.V;
  const MatrixX3d centred = side.V.rowwise() - mean;
  const Eigen::Matrix3d covariance = centred.transpose() * w.asDiagonal() * centred;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(covariance);
  Eigen::Matrix3d axes = eigen.eigenvectors().rowwise().reverse();
  if (axes.determinant() < 0) axes.col(2) *= -1;
  return axes;
}

/// Proxy points of a candidate's pairs and the pins, on the two maps.
struct PairPoints {
  std::vector<Index> a, b;
};

/// A candidate's map of B's proxy: B's map turned so the points face their
/// partners (Kabsch; by `fallback` when there are none), then warped onto them.
MatrixX3d candidate_map(const Side& A, const Side& B, const PairPoints& points, const Eigen::Matrix3d& fallback) {
  const Index k = Index(points.a.size());
  MatrixX3d on_a(k, 3), on_b(k, 3);
  for (Index j = 0; j < k; ++j) {
    on_a.row(j) = A.map.row(points.a[std::size_t(j)]);
    on_b.row(j) = B.map.row(points.b[std::size_t(j)]);
  }
  const Eigen::Matrix3d R = k >= 1 ? best_rotation(on_b, on_a, VectorXd::Ones(k)) : fallback;
  const MatrixX3d turned = B.map * R;
  if (k == 0) return turned;
  MatrixX3d warped = warp_points(turned, on_b * R, on_a, 16);
  for (Index j = 0; j < k; ++j) warped.row(points.b[std::size_t(j)]) = on_a.row(j);
  return warped;
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
/// the smoothed Gaussian curvatures, over their mean spread. Distortion alone
/// cannot see a map that slides along a smooth surface (a bump carried
/// beside its partner bends little); this can.
double curvature_mismatch(const Side& A, const Side& B, const MatrixX3d& warped) {
  const SphereLocations at = locate_on_sphere_map(A.map, A.F, warped);
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

double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

std::string degrees(double radians) {
  std::ostringstream out;
  out.precision(0);
  out << std::fixed << radians * 180.0 / M_PI << " deg";
  return out.str();
}

}  // namespace

Correspondence correspondence(const MatrixX3d& VA, const MatrixX3i& FA, const MatrixX3d& VB, const MatrixX3i& FB,
                              const Pairs& pins, const std::optional<Pairs>& given, const CorrespondenceOptions& o,
                              Progress* progress) {
  PM_REQUIRE(o.proxy_faces >= 100 && std::isfinite(o.tip_angle) && o.tip_angle > 0 &&
                 std::isfinite(o.registered_tip_distance) && o.registered_tip_distance > 0 &&
                 std::isfinite(o.pin_radius) && o.pin_radius >= 0,
             InvalidInputError, "proxy_faces >= 100, tip_angle and registered_tip_distance > 0, pin_radius >= 0");
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

  // The pins on the proxies: each model vertex's nearest proxy vertex.
  const ClosestPoints pins_on_a = ClosestPointTree(A.V, A.F).query([&] {
    MatrixX3d P(Index(pins.size()), 3);
    for (std::size_t j = 0; j < pins.size(); ++j) P.row(Index(j)) = VA.row(pins[j][0]);
    return P;
  }());
  const ClosestPoints pins_on_b = ClosestPointTree(B.V, B.F).query([&] {
    MatrixX3d P(Index(pins.size()), 3);
    for (std::size_t j = 0; j < pins.size(); ++j) P.row(Index(j)) = VB.row(pins[j][1]);
    return P;
  }());
  PairPoints pin_points;
  for (std::size_t j = 0; j < pins.size(); ++j) {
    Index a, b;
    pins_on_a.bary.row(Index(j)).maxCoeff(&a);
    pins_on_b.bary.row(Index(j)).maxCoeff(&b);
    pin_points.a.push_back(A.F(pins_on_a.face[Index(j)], a));
    pin_points.b.push_back(B.F(pins_on_b.face[Index(j)], b));
  }
  if (pins.size() >= 3) {
    MatrixX3d on_a(Index(pins.size()), 3), on_b(Index(pins.size()), 3);
    for (std::size_t j = 0; j < pins.size(); ++j) {
      on_a.row(Index(j)) = A.map.row(pin_points.a[j]);
      on_b.row(Index(j)) = B.map.row(pin_points.b[j]);
    }
    const PinOrder order = pin_order(on_b, on_a);
    PM_REQUIRE(!order.mirrored(), ConstraintError, mirrored_pins_message(order));
  }

  // Candidates: (kind, detail, proxy pairs, rotation used below two pairs).
  struct Raw {
    std::string kind, detail;
    Pairs pairs;
    Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
    /// Pairs that only shape the candidate's map (a registration's samples):
    /// they are not carried to the models.
    Pairs shape_pairs;
  };
  std::vector<Raw> raw;
  if (given) {
    Pairs proxy;
    MatrixX3d pa(Index(given->size()), 3), pb(Index(given->size()), 3);
    for (std::size_t k = 0; k < given->size(); ++k) {
      pa.row(Index(k)) = VA.row((*given)[k][0]);
      pb.row(Index(k)) = VB.row((*given)[k][1]);
    }
    const ClosestPoints ca = ClosestPointTree(A.V, A.F).query(pa), cb = ClosestPointTree(B.V, B.F).query(pb);
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
    if (progress) progress->report(0.82, "correspondence candidates");
    if (o.registration) {
      const Eigen::Matrix3d axes_a = principal_axes(A), axes_b = principal_axes(B);
      struct Start {
        std::string detail;
        Eigen::Matrix3d rotation;  // column vectors: x_A = R x_B
      };
      std::vector<Start> starts{{"as placed", Eigen::Matrix3d::Identity()}};
      const char* turns[4] = {"principal axes", "principal axes, turned 180 deg about the first",
                              "principal axes, turned 180 deg about the second", "principal axes, turned 180 deg about the third"};
      const double signs[4][3] = {{1, 1, 1}, {1, -1, -1}, {-1, 1, -1}, {-1, -1, 1}};
      for (int s = 0; s < 4; ++s)
        starts.push_back({turns[s], axes_a * Eigen::Vector3d(signs[s][0], signs[s][1], signs[s][2]).asDiagonal() * axes_b.transpose()});
      const ClosestPointTree tree_a(A.V, A.F);
      for (const Start& start : starts) {
        const Registration registration = register_surfaces(
            A.V, A.F, B.V, B.F,
            {PolynomialWarp::similarity(Eigen::RowVector3d::Zero(), 1.0, start.rotation, Eigen::RowVector3d::Zero(), 1.0)},
            o.registration_options);
        const MatrixX3d moved = registration.warp(B.V);
        // The registration as a smooth map: farthest-point samples of B's
        // proxy paired with A's vertex at their registered closest points,
        // where that is near (a closest-point map read vertex by vertex
        // zigzags at the proxy's resolution and would be scored for it).
        const ClosestPoints on = tree_a.query(moved);
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
        const features::FeatureMatch match = features::match_features(A.V, A.F, B.V, B.F, o.match);
        if (!match.point_pairs.empty())
          raw.push_back({"features", std::to_string(match.point_pairs.size()) + " feature points paired",
                         match.point_pairs, Eigen::Matrix3d::Identity(), {}});
      } catch (const MeshError&) {
        // A proxy the feature matcher cannot take (e.g. flat, Qhull): no candidate.
      }
    }
  }
  mark("candidates");

  // Score every distinct candidate.
  std::set<Pairs> seen;
  double best_score = std::numeric_limits<double>::infinity();
  for (std::size_t c = 0; c < raw.size(); ++c) {
    if (progress) progress->report(0.88 + 0.1 * double(c) / double(raw.size()), "scoring correspondences");
    Raw& r = raw[c];
    CorrespondenceCandidate candidate;
    candidate.kind = r.kind;
    candidate.detail = r.detail;
    // Automatic pairs away from the pins and from each other.
    PairPoints points = pin_points;
    std::set<Index> used_a(pin_points.a.begin(), pin_points.a.end()), used_b(pin_points.b.begin(), pin_points.b.end());
    for (const auto& pair : r.pairs) {
      bool clash = used_a.count(pair[0]) || used_b.count(pair[1]);
      for (std::size_t j = 0; j < pins.size() && !clash; ++j)
        clash = (A.V.row(pair[0]) - VA.row(pins[j][0])).norm() < o.pin_radius ||
                (B.V.row(pair[1]) - VB.row(pins[j][1])).norm() < o.pin_radius;
      if (clash) continue;
      used_a.insert(pair[0]), used_b.insert(pair[1]);
      candidate.proxy_pairs.push_back(pair);
      points.a.push_back(pair[0]);
      points.b.push_back(pair[1]);
    }
    for (const auto& pair : r.shape_pairs) {
      if (used_a.count(pair[0]) || used_b.count(pair[1])) continue;
      used_a.insert(pair[0]), used_b.insert(pair[1]);
      points.a.push_back(pair[0]);
      points.b.push_back(pair[1]);
    }
    Pairs key = candidate.proxy_pairs;
    std::sort(key.begin(), key.end());
    // Pairs make the candidate unless it has its own map (a registration) or
    // is "none"/"given"; the same pairs as an earlier candidate add nothing.
    const bool by_pairs = r.shape_pairs.empty() && r.kind != "none" && r.kind != "given";
    if (by_pairs && (key.empty() || !seen.insert(key).second)) continue;
    if (points.a.size() >= 3) {
      MatrixX3d on_a(Index(points.a.size()), 3), on_b(Index(points.a.size()), 3);
      for (std::size_t j = 0; j < points.a.size(); ++j) {
        on_a.row(Index(j)) = A.map.row(points.a[j]);
        on_b.row(Index(j)) = B.map.row(points.b[j]);
      }
      const PinOrder order = pin_order(on_b, on_a);
      if (order.mirrored()) {
        candidate.rejected = "its pairs are in mirrored order";
        out.candidates.push_back(candidate);
        continue;
      }
    }
    const MatrixX3d warped = candidate_map(A, B, points, r.rotation);
    candidate.distortion = map_distortion(A.V, A.F, A.map, B.V, B.F, warped).mean;
    candidate.curvature_mismatch = curvature_mismatch(A, B, warped);
    candidate.score = candidate.distortion + o.curvature_weight * candidate.curvature_mismatch;
    if (!std::isfinite(candidate.score)) candidate.rejected = "its correspondence could not be measured";
    out.candidates.push_back(candidate);
    if (candidate.score < best_score || (r.kind == "given")) {
      best_score = r.kind == "given" ? -1.0 : candidate.score;
      out.chosen = Index(out.candidates.size()) - 1;
      out.warped_b = warped;
    }
  }
  PM_REQUIRE(out.warped_b.rows() == B.V.rows(), ComputeError, "correspondence: no candidate could be scored");
  mark("scores");

  // The winner's pairs on the models.
  std::set<Index> used_a, used_b;
  for (const auto& pin : pins) used_a.insert(pin[0]), used_b.insert(pin[1]);
  // Given pairs are the user's vertices already; automatic ones stand for
  // proxy vertices.
  Pairs on_models = given ? *given : Pairs{};
  if (!given)
    for (const auto& pair : out.candidates[std::size_t(out.chosen)].proxy_pairs)
      on_models.push_back({model_vertex(A, pair[0]), model_vertex(B, pair[1])});
  for (const auto& [a, b] : on_models) {
    if (used_a.count(a) || used_b.count(b)) continue;
    used_a.insert(a), used_b.insert(b);
    out.pairs.push_back({a, b});
  }
  mark("pairs on the models");
  if (progress) progress->report(1.0, "correspondence");
  return out;
}

}  // namespace paramorph::morph
