// Feature matching between two meshes (features/match_features.h, thesis 4.5).
#include "features/match_features.h"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>
#include <string>

#include "common/errors.h"
#include "features/concavity.h"
#include "features/min_cost_assignment.h"

namespace paramorph::features {

namespace {

/// A candidate beats the identity-started one only when cheaper by more than this share.
constexpr double kIdentityPreference = 0.05;
/// How many of the cheapest rotation candidates are refined.
constexpr std::size_t kRefined = 8;
/// Refinement rounds at most (each: fit R to the pairs, pair again).
constexpr int kRefineRounds = 20;

/// Everything matching needs to know about one mesh.
struct Side {
  Segmentation regions;
  FeaturePoints points;
  RegionGraph graph;
  Eigen::Vector3d centre;
  Eigen::Matrix3d axes;  ///< principal axes (columns), of the second moments
  double scale = 1.0;
  double diagonal = 1.0;                       ///< bounding-box diagonal as given
  Eigen::MatrixXd centroids;                   ///< #regions by 3, normalised
  VectorXd share;                              ///< per region, share of the surface area
  VectorXd degree;                             ///< per region, reduced-graph degree, at least 1
  std::vector<std::vector<Index>> neighbours;  ///< per region, in the reduced graph, ascending
};

/// Area-weighted centroid, second-moment matrix about it (integrated over
/// the surface, exact per triangle) and total area.
struct Moments {
  Eigen::Vector3d centre;
  Eigen::Matrix3d second;
  double area;
};

Moments surface_moments(const MatrixX3d& V, const MatrixX3i& F) {
  Moments m{Eigen::Vector3d::Zero(), Eigen::Matrix3d::Zero(), 0.0};
  VectorXd area(F.rows());
  for (Index f = 0; f < Index(F.rows()); ++f) {
    const Eigen::Vector3d a = V.row(F(f, 0)), b = V.row(F(f, 1)), c = V.row(F(f, 2));
    area[f] = 0.5 * (b - a).cross(c - a).norm();
    m.area += area[f];
    m.centre += area[f] * (a + b + c) / 3.0;
  }
  PM_REQUIRE(m.area > 0 && std::isfinite(m.area), InvalidInputError, "the mesh has no area");
  m.centre /= m.area;
  for (Index f = 0; f < Index(F.rows()); ++f) {
    // Integral of x x^T over a triangle: A/12 (sum v v^T + (sum v)(sum v)^T).
    const Eigen::Vector3d a = V.row(F(f, 0)).transpose() - m.centre,
                          b = V.row(F(f, 1)).transpose() - m.centre,
                          c = V.row(F(f, 2)).transpose() - m.centre;
    const Eigen::Vector3d s = a + b + c;
    m.second += area[f] / 12.0 *
                (a * a.transpose() + b * b.transpose() + c * c.transpose() + s * s.transpose());
  }
  return m;
}

/// Forwards a nested stage's 0..1 into [lo, hi] of the caller's progress.
class Nested {
 public:
  Nested(Progress* parent, double lo, double hi, std::string prefix)
      : inner_(
            [parent, lo, hi, prefix](double fraction, const std::string& stage) {
              parent->report(lo + (hi - lo) * fraction, prefix + stage);  // throws Cancelled itself
              return true;
            },
            0.0),
        active_(parent != nullptr) {}
  Progress* get() { return active_ ? &inner_ : nullptr; }

 private:
  Progress inner_;
  bool active_;
};

Side analyse(const MatrixX3d& V, const MatrixX3i& F, const MatchOptions& o, Progress* progress,
             double lo, double hi, const char* name) {
  Side side;
  const std::string prefix = std::string("mesh ") + name + ": ";
  if (progress) progress->report(lo, prefix + "concavity");
  const VectorXd intensity = concavity(V, F);  // validates the arrays; needs volume
  const Moments m = surface_moments(V, F);
  side.centre = m.centre;
  side.scale = std::sqrt(m.second.trace() / m.area);
  side.diagonal = (V.colwise().maxCoeff() - V.colwise().minCoeff()).norm();

  // Thresholds as shares of the bounding-box diagonal in the principal axes.
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> axes(m.second);
  side.axes = axes.eigenvectors();
  const Eigen::MatrixXd aligned = (V.rowwise() - m.centre.transpose()) * side.axes;
  const double principal_diagonal =
      (aligned.colwise().maxCoeff() - aligned.colwise().minCoeff()).norm();
  const double rescale = principal_diagonal / side.diagonal;

  FeatureRegionOptions ro = o.regions;
  ro.concavity = intensity;
  ro.concavity_threshold *= rescale;
  Nested nested(progress, lo, lo + 0.8 * (hi - lo), prefix);
  side.regions = feature_regions(V, F, ro, nested.get());
  FeaturePointOptions po = o.points;
  po.spacing *= rescale;
  side.points = feature_points(V, F, side.regions.face_labels, intensity, po);
  if (progress) progress->report(lo + 0.8 * (hi - lo), prefix + "region graph");
  side.graph = region_graph(V, F, side.regions, o.graph);

  const Index regions = side.regions.regions();
  side.centroids = (side.regions.centroid.rowwise() - m.centre.transpose()) / side.scale;
  side.share = side.regions.area / side.regions.area.sum();
  side.degree.resize(regions);
  for (Index r = 0; r < regions; ++r) side.degree[r] = std::max(1, side.graph.degree[r]);
  side.neighbours.assign(regions, {});
  for (const auto& [a, b] : side.graph.edges) {
    side.neighbours[a].push_back(b);
    side.neighbours[b].push_back(a);
  }
  for (auto& n : side.neighbours) std::sort(n.begin(), n.end());
  return side;
}

/// The rotation R (det +1) minimising sum w_k |R b_k - a_k|^2 about the
/// origin (orthogonal Procrustes / Kabsch). False when the b's and a's span
/// less than a plane together (the fit is not determined).
bool fit_rotation(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b, const VectorXd& w,
                  Eigen::Matrix3d& R) {
  Eigen::Matrix3d H = Eigen::Matrix3d::Zero();
  for (Eigen::Index k = 0; k < a.rows(); ++k) H += w[k] * b.row(k).transpose() * a.row(k);
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(H, Eigen::ComputeFullU | Eigen::ComputeFullV);
  const Eigen::Vector3d sigma = svd.singularValues();
  if (!(sigma[1] > 1e-9 * std::max(1.0, sigma[0]))) return false;
  Eigen::Matrix3d D = Eigen::Matrix3d::Identity();
  D(2, 2) = (svd.matrixV() * svd.matrixU().transpose()).determinant() < 0 ? -1.0 : 1.0;
  R = svd.matrixV() * D * svd.matrixU().transpose();
  return true;
}

/// Scores (4.11) of every region pair under R.
Eigen::MatrixXd region_scores(const Side& A, const Side& B, const Eigen::Matrix3d& R) {
  const Eigen::MatrixXd turned = B.centroids * R.transpose();
  Eigen::MatrixXd S(A.centroids.rows(), B.centroids.rows());
  for (Eigen::Index i = 0; i < S.rows(); ++i)
    for (Eigen::Index j = 0; j < S.cols(); ++j) {
      const double area = std::max(A.share[i], B.share[j]) / std::min(A.share[i], B.share[j]);
      const double degree = std::max(A.degree[i], B.degree[j]) / std::min(A.degree[i], B.degree[j]);
      S(i, j) = (A.centroids.row(i) - turned.row(j)).norm() * area * degree;
    }
  return S;
}

/// A rotation's pairing: per region of A its region of B (or -1), and the
/// total truncated score (pairs at the cap count as the cap).
struct Pairing {
  Eigen::Matrix3d rotation;
  std::vector<Index> partner;
  double cost = 0.0;
};

Pairing pair_regions(const Side& A, const Side& B, const Eigen::Matrix3d& R, double cap) {
  Pairing p{R, {}, 0.0};
  const Eigen::MatrixXd S = region_scores(A, B, R).cwiseMin(cap);
  p.partner = min_cost_assignment(S);
  for (std::size_t i = 0; i < p.partner.size(); ++i)
    if (p.partner[i] >= 0) p.cost += S(Eigen::Index(i), p.partner[i]);
  return p;
}

/// ICP on the region centroids at one truncation level: fits R to the
/// pairs scoring below `level` (weights: the smaller area share) and pairs
/// again while the truncated cost falls.
Pairing refine_at(const Side& A, const Side& B, const Eigen::Matrix3d& start, double level) {
  Pairing p = pair_regions(A, B, start, level);
  for (int round = 0; round < kRefineRounds; ++round) {
    const Eigen::MatrixXd S = region_scores(A, B, p.rotation);
    std::vector<Index> rows;
    for (std::size_t i = 0; i < p.partner.size(); ++i)
      if (p.partner[i] >= 0 && S(Eigen::Index(i), p.partner[i]) < level) rows.push_back(Index(i));
    Eigen::MatrixXd a(rows.size(), 3), b(rows.size(), 3);
    VectorXd w(rows.size());
    for (std::size_t k = 0; k < rows.size(); ++k) {
      const Index i = rows[k], j = p.partner[i];
      a.row(k) = A.centroids.row(i);
      b.row(k) = B.centroids.row(j);
      w[k] = std::min(A.share[i], B.share[j]);
    }
    Eigen::Matrix3d R;
    if (!fit_rotation(a, b, w, R)) break;
    Pairing next = pair_regions(A, B, R, level);
    if (!(next.cost < p.cost - 1e-12 * std::max(1.0, p.cost))) break;
    p = std::move(next);
  }
  return p;
}

/// Refines a start: ICP at the cap, and coarse to fine (at 4 and 2 times
/// the cap first, so a rough start with few pairs below the cap still has
/// pairs to fit to); the cheapest of these and the start itself, at the cap.
Pairing refine(const Side& A, const Side& B, const Pairing& start, double cap) {
  Pairing best = pair_regions(A, B, start.rotation, cap);
  Pairing fine = refine_at(A, B, start.rotation, cap);
  if (fine.cost < best.cost) best = std::move(fine);
  Eigen::Matrix3d R = start.rotation;
  for (const double level : {4.0 * cap, 2.0 * cap, cap}) R = refine_at(A, B, R, level).rotation;
  Pairing coarse = pair_regions(A, B, R, cap);
  if (coarse.cost < best.cost) best = std::move(coarse);
  return best;
}

/// Regions in order of degree (highest first), then area, then index.
std::vector<Index> top_regions(const Side& s, int count) {
  std::vector<Index> order(s.regions.regions());
  std::iota(order.begin(), order.end(), Index(0));
  std::sort(order.begin(), order.end(), [&](Index x, Index y) {
    if (s.graph.degree[x] != s.graph.degree[y]) return s.graph.degree[x] > s.graph.degree[y];
    if (s.share[x] != s.share[y]) return s.share[x] > s.share[y];
    return x < y;
  });
  order.resize(std::min<std::size_t>(order.size(), std::size_t(count)));
  return order;
}

/// The 24 rotations taking B's principal axes onto A's, in any order and
/// direction (signed permutations P with det(E_A P E_B^T) = +1).
std::vector<Eigen::Matrix3d> principal_axes_candidates(const Side& A, const Side& B) {
  std::vector<Eigen::Matrix3d> out;
  int perm[3] = {0, 1, 2};
  do {
    for (int signs = 0; signs < 8; ++signs) {
      Eigen::Matrix3d P = Eigen::Matrix3d::Zero();
      for (int k = 0; k < 3; ++k) P(perm[k], k) = (signs >> k) & 1 ? -1.0 : 1.0;
      const Eigen::Matrix3d R = A.axes * P * B.axes.transpose();
      if (R.determinant() > 0) out.push_back(R);
    }
  } while (std::next_permutation(perm, perm + 3));
  return out;
}

/// Rotation candidates of the thesis' kind: a correspondence between a
/// top region i of A and a top region j of B, and a second one to fix the
/// twist, between i' (a neighbour of i in the reduced graph, or another top
/// region) and j' (likewise for j): R best turns (c_j, c_j') onto
/// (c_i, c_i'). Pairs of correspondences whose rigid invariants disagree
/// (distances to the centre, distance between the two) by more than
/// `tolerance` cannot come from one rotation and are skipped. A region
/// without a second gives the smallest rotation turning c_j onto c_i.
std::vector<Eigen::Matrix3d> rotation_candidates(const Side& A, const Side& B, int count,
                                                 double tolerance) {
  std::vector<Eigen::Matrix3d> out;
  const VectorXd w = VectorXd::Ones(2);
  const std::vector<Index> top_a = top_regions(A, count), top_b = top_regions(B, count);
  std::vector<char> is_top_a(A.regions.regions(), false), is_top_b(B.regions.regions(), false);
  for (Index i : top_a) is_top_a[i] = true;
  for (Index j : top_b) is_top_b[j] = true;
  auto seconds = [](const Side& s, const std::vector<Index>& top, Index i) {
    std::vector<Index> out = s.neighbours[i];
    out.insert(out.end(), top.begin(), top.end());
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    out.erase(std::remove(out.begin(), out.end(), i), out.end());
    return out;
  };
  for (Index i : top_a)
    for (Index j : top_b) {
      const Eigen::Vector3d ai = A.centroids.row(i), bj = B.centroids.row(j);
      if (std::abs(ai.norm() - bj.norm()) > tolerance) continue;
      const std::vector<Index> second_a = seconds(A, top_a, i), second_b = seconds(B, top_b, j);
      if (second_a.empty() || second_b.empty()) {
        if (ai.norm() > 1e-9 && bj.norm() > 1e-9)
          out.push_back(Eigen::Quaterniond::FromTwoVectors(bj, ai).toRotationMatrix());
        continue;
      }
      for (Index ii : second_a)
        for (Index jj : second_b) {
          // {(i, j), (ii, jj)} once when both could be the first.
          if (is_top_a[ii] && is_top_b[jj] && std::make_pair(ii, jj) < std::make_pair(i, j))
            continue;
          const Eigen::Vector3d aii = A.centroids.row(ii), bjj = B.centroids.row(jj);
          if (std::abs(aii.norm() - bjj.norm()) > tolerance ||
              std::abs((aii - ai).norm() - (bjj - bj).norm()) > tolerance)
            continue;
          Eigen::MatrixXd a(2, 3), b(2, 3);
          a << ai.transpose(), aii.transpose();
          b << bj.transpose(), bjj.transpose();
          Eigen::Matrix3d R;
          if (fit_rotation(a, b, w, R)) out.push_back(R);
        }
    }
  return out;
}

double median(std::vector<double> values) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  const std::size_t n = values.size();
  return n % 2 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

/// Per feature point, the regions of the faces around it, ascending.
std::vector<std::vector<Index>> point_regions(const MatrixX3i& F, const VectorXi& labels,
                                              const FeaturePoints& points, Index vertices) {
  std::vector<Index> slot(vertices, -1);
  for (std::size_t p = 0; p < points.vertices.size(); ++p) slot[points.vertices[p]] = Index(p);
  std::vector<std::vector<Index>> out(points.vertices.size());
  for (Index f = 0; f < Index(F.rows()); ++f)
    for (int k = 0; k < 3; ++k)
      if (slot[F(f, k)] >= 0) out[slot[F(f, k)]].push_back(labels[f]);
  for (auto& r : out) {
    std::sort(r.begin(), r.end());
    r.erase(std::unique(r.begin(), r.end()), r.end());
  }
  return out;
}

void check_options(const MatchOptions& o) {
  PM_REQUIRE(!o.regions.concavity, InvalidInputError,
             "match_features computes each mesh's concavity: leave regions.concavity empty");
  PM_REQUIRE(o.alignment_nodes >= 1, InvalidInputError, "alignment_nodes must be >= 1, got ",
             o.alignment_nodes);
  PM_REQUIRE(std::isfinite(o.max_region_score) && o.max_region_score > 0, InvalidInputError,
             "max_region_score must be finite and > 0, got ", o.max_region_score);
  PM_REQUIRE(o.outlier_factor >= 1 && !std::isnan(o.outlier_factor), InvalidInputError,
             "outlier_factor must be >= 1, got ", o.outlier_factor);
  PM_REQUIRE(std::isfinite(o.max_point_distance) && o.max_point_distance >= 0, InvalidInputError,
             "max_point_distance must be finite and >= 0, got ", o.max_point_distance);
}

}  // namespace

FeatureMatch match_features(const MatrixX3d& VA, const MatrixX3i& FA, const MatrixX3d& VB,
                            const MatrixX3i& FB, const MatchOptions& o, Progress* progress) {
  check_options(o);
  if (progress) progress->report(0.0, "feature matching");
  const Side A = for_mesh("A", [&] { return analyse(VA, FA, o, progress, 0.0, 0.45, "A"); });
  const Side B = for_mesh("B", [&] { return analyse(VB, FB, o, progress, 0.45, 0.9, "B"); });
  const double cap = o.max_region_score;

  // Rotation: the cheapest graph candidates and every principal-axes one
  // refined; the identity-started one wins unless clearly beaten.
  if (progress) progress->report(0.9, "alignment");
  const std::vector<Eigen::Matrix3d> candidates = rotation_candidates(A, B, o.alignment_nodes, cap);
  std::vector<Pairing> pairings;
  pairings.reserve(candidates.size());
  for (const Eigen::Matrix3d& R : candidates) pairings.push_back(pair_regions(A, B, R, cap));
  std::vector<std::size_t> order(pairings.size());
  std::iota(order.begin(), order.end(), std::size_t(0));
  std::stable_sort(order.begin(), order.end(), [&](std::size_t x, std::size_t y) {
    return pairings[x].cost < pairings[y].cost;
  });
  order.resize(std::min(kRefined, order.size()));
  std::vector<Pairing> starts;
  for (std::size_t k : order) starts.push_back(pairings[k]);
  for (const Eigen::Matrix3d& R : principal_axes_candidates(A, B))
    starts.push_back(pair_regions(A, B, R, cap));
  const Pairing identity = refine(A, B, pair_regions(A, B, Eigen::Matrix3d::Identity(), cap), cap);
  Pairing best = identity;
  for (const Pairing& start : starts) {
    Pairing p = refine(A, B, start, cap);
    if (p.cost < best.cost) best = std::move(p);
  }
  if (!(best.cost < (1.0 - kIdentityPreference) * identity.cost)) best = identity;

  FeatureMatch out;
  out.rotation = best.rotation;

  // Region pairs: below the cap, outliers dropped.
  const Eigen::MatrixXd S = region_scores(A, B, best.rotation);
  std::vector<double> made;
  for (std::size_t i = 0; i < best.partner.size(); ++i)
    if (best.partner[i] >= 0 && S(Eigen::Index(i), best.partner[i]) < cap)
      made.push_back(S(Eigen::Index(i), best.partner[i]));
  const double outlier = std::max(o.outlier_factor * median(made), 0.1 * cap);
  for (std::size_t i = 0; i < best.partner.size(); ++i) {
    const Index j = best.partner[i];
    if (j < 0) continue;
    const double s = S(Eigen::Index(i), j);
    if (s < cap && s <= outlier) {
      out.region_pairs.push_back({Index(i), j});
      out.region_scores.push_back(s);
    }
  }

  // Point pairs: per region pair, B's region moved onto A's centroid; the
  // smallest distance of each candidate pair over the region pairs it is in.
  if (progress) progress->report(0.95, "feature points");
  const auto regions_a = point_regions(FA, A.regions.face_labels, A.points, Index(VA.rows()));
  const auto regions_b = point_regions(FB, B.regions.face_labels, B.points, Index(VB.rows()));
  std::vector<std::vector<Index>> in_region_b(B.regions.regions());
  for (std::size_t q = 0; q < regions_b.size(); ++q)
    for (Index r : regions_b[q]) in_region_b[r].push_back(Index(q));
  std::vector<Index> partner_of_a(A.regions.regions(), -1);
  for (const auto& [i, j] : out.region_pairs) partner_of_a[i] = j;
  const double units = A.scale / A.diagonal;  // normalised length -> share of A's diagonal
  std::map<std::pair<Index, Index>, double> candidate;  // (point of A, point of B) -> distance
  for (std::size_t p = 0; p < regions_a.size(); ++p) {
    const Eigen::Vector3d pa = (VA.row(A.points.vertices[p]).transpose() - A.centre) / A.scale;
    for (Index i : regions_a[p]) {
      const Index j = partner_of_a[i];
      if (j < 0) continue;
      const Eigen::Vector3d shift =
          A.centroids.row(i).transpose() - best.rotation * B.centroids.row(j).transpose();
      for (Index q : in_region_b[j]) {
        if (B.points.kinds[q] != A.points.kinds[p]) continue;
        const Eigen::Vector3d pb =
            best.rotation * (VB.row(B.points.vertices[q]).transpose() - B.centre) / B.scale + shift;
        const double d = (pa - pb).norm() * units;
        if (d > o.max_point_distance) continue;
        auto [it, added] = candidate.emplace(std::make_pair(Index(p), q), d);
        if (!added) it->second = std::min(it->second, d);
      }
    }
  }
  // Mutually nearest (ties: the lower index).
  const Index none = -1;
  std::vector<Index> nearest_a(A.points.vertices.size(), none),
      nearest_b(B.points.vertices.size(), none);
  std::vector<double> best_a(nearest_a.size(), std::numeric_limits<double>::infinity()),
      best_b(nearest_b.size(), std::numeric_limits<double>::infinity());
  for (const auto& [key, d] : candidate) {  // map order: ascending (p, q)
    const auto [p, q] = key;
    if (d < best_a[p]) best_a[p] = d, nearest_a[p] = q;
    if (d < best_b[q]) best_b[q] = d, nearest_b[q] = p;
  }
  std::vector<std::pair<std::array<Index, 2>, double>> points;
  for (std::size_t p = 0; p < nearest_a.size(); ++p) {
    const Index q = nearest_a[p];
    if (q != none && nearest_b[q] == Index(p))
      points.push_back({{A.points.vertices[p], B.points.vertices[q]}, best_a[p]});
  }
  std::sort(points.begin(), points.end());
  for (const auto& [pair, d] : points) {
    out.point_pairs.push_back(pair);
    out.point_scores.push_back(d);
  }

  out.regions_a = A.regions;
  out.regions_b = B.regions;
  out.points_a = A.points;
  out.points_b = B.points;
  out.graph_a = A.graph;
  out.graph_b = B.graph;
  out.centre_a = A.centre;
  out.centre_b = B.centre;
  out.scale_a = A.scale;
  out.scale_b = B.scale;
  if (progress) progress->report(1.0, "feature matching");
  return out;
}

}  // namespace paramorph::features
