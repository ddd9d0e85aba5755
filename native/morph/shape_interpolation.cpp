// As-rigid-as-possible in-betweens (morph/shape_interpolation.h).
#include "morph/shape_interpolation.h"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <Eigen/SVD>
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <cmath>
#include <limits>
#include <deque>
#include <chrono>
#include <numeric>
#include <unordered_map>

#include "common/best_rotation.h"
#include "common/cholesky_solve_rows.h"
#include "common/errors.h"
#include "common/parallel.h"
#include "common/report_while.h"
#include "common/supernodal_cholesky.h"
#include "mesh/bounding_box_diagonal.h"
#include "mesh/self_intersections.h"

namespace paramorph::morph {

struct ShapeInterpolation::Factor {
  // CHOLMOD's supernodal factor: the merged mesh of a 100k-face morph has
  // ~185k unknowns, where the simplicial one took seconds. Its solves take
  // the BLAS lock, so at() (const, called from several threads with the GIL
  // released) solves one at a time.
  SupernodalCholesky<Eigen::SparseMatrix<double>> llt;
};

namespace {

constexpr double kPi = 3.14159265358979323846;
/// Weight of a degenerate face's edges against a sound face's 1: enough to
/// hold its vertices to the shape, too little to bend its neighbours.
constexpr double kDegenerateWeight = 1e-3;
/// Smallest face size (relative to the mean) a weight is computed from.
constexpr double kSizeFloor = 1e-6;
/// Sweeps adding each face's frame covariance to its neighbours': R̄ fits
/// the faces within about the square root of this many rings. Measured on a
/// horse onto a re-tessellated galloping copy (t = 1/2): 10 sweeps left the
/// volume 7 % above both ends', 100 sweeps 3.6 % (and 0.27 % of the diagonal
/// from the true half pose against 0.32 %); the large turns of legs and necks
/// span far more faces than that.
constexpr int kNeighbourhoodSweeps = 100;
/// Repairs of turned-over faces per frame, each over one more ring.
constexpr int kRepairs = 6;
/// Passes mirroring thin pieces' apexes back over their base (mirror_apexes).
constexpr int kMirrorPasses = 3;
/// Passes moving single vertices of faces still turned over
/// (untangle_vertices) at each reach: 1/8, 1/4, 1/2 and 1 times the longest
/// side around the vertex.
constexpr int kUntanglePasses = 4;
constexpr double kUntangleReach = 1.0;
/// The height a face turned back by untangle_vertices is given over its
/// base, relative to the base's length: its side is then certain (later
/// moves of its neighbours do not tip it back), and the move small. Measured
/// (issue 31, t = 1/2): 0.002 left 0.11 % of the horned cow onto the lion
/// turned against both ends, most within a degree of an end's side; 0.02
/// leaves 0.039 %. On tests/bench/in_betweens.py the turned share at t = 1/2
/// falls or holds on every pair (a cow onto a walking horse 0.038 -> 0.012
/// %), while faces passing through others rise on some (spot onto a horse
/// 178 -> 268, straight lines' 2138).
constexpr double kUntangleHeight = 0.02;
/// Dykstra's projection sweeps over a vertex's half-spaces.
constexpr int kProjectionSweeps = 200;

Eigen::Matrix3d rotation_of(const Eigen::Vector3d& log) {
  const double angle = log.norm();
  if (angle == 0) return Eigen::Matrix3d::Identity();
  return Eigen::AngleAxisd(angle, log / angle).toRotationMatrix();
}

/// The frame (two edges, normal scaled by sqrt of twice the area) of face f.
Eigen::Matrix3d face_frame(const MatrixX3d& V, const MatrixX3i& F, Index f, double* doubled_area,
                           double* edge_scale) {
  const Eigen::Vector3d a = V.row(F(f, 0)).transpose();
  const Eigen::Vector3d e1 = V.row(F(f, 1)).transpose() - a, e2 = V.row(F(f, 2)).transpose() - a;
  const Eigen::Vector3d n = e1.cross(e2);
  *doubled_area = n.norm();
  *edge_scale = e1.squaredNorm() + e2.squaredNorm();
  Eigen::Matrix3d frame;
  frame << e1, e2, (*doubled_area > 0 ? Eigen::Vector3d(n / std::sqrt(*doubled_area)) : Eigen::Vector3d::Zero());
  return frame;
}

/// The proper rotation nearest to M (polar decomposition by SVD).
Eigen::Matrix3d nearest_rotation(const Eigen::Matrix3d& M) {
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(M, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d U = svd.matrixU();
  if ((U * svd.matrixV().transpose()).determinant() < 0) U.col(2) *= -1;
  return U * svd.matrixV().transpose();
}

/// M = turn · stretch (polar decomposition); where the stretch is positive
/// definite, its eigenvectors and the logarithms of its eigenvalues.
struct Polar {
  Eigen::Matrix3d turn, stretch, axes = Eigen::Matrix3d::Identity();
  Eigen::Vector3d log_stretch = Eigen::Vector3d::Zero();
  bool positive = false;
};

Polar polar(const Eigen::Matrix3d& M) {
  Polar out;
  out.turn = nearest_rotation(M);
  out.stretch = out.turn.transpose() * M;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(0.5 * (out.stretch + out.stretch.transpose()));
  out.positive = eigen.eigenvalues().minCoeff() > 0;
  if (out.positive) {
    out.axes = eigen.eigenvectors();
    out.log_stretch = eigen.eigenvalues().array().log().matrix();
  }
  return out;
}

Eigen::Vector3d log_of(const Eigen::Matrix3d& R) {
  const Eigen::AngleAxisd turn(R);
  return turn.axis() * turn.angle();
}

/// A rotation by nearly pi reads the same as one by nearly -pi about the
/// opposite axis: each face's angle is taken on the side of the face it was
/// reached from (breadth first from the largest faces).
void make_logs_consistent(std::vector<Eigen::Vector3d>& logs, const std::vector<std::vector<Index>>& neighbours,
                          const std::vector<char>& skip, const std::vector<double>& area) {
  const Index m = Index(logs.size());
  std::vector<char> seen(m, 0);
  std::vector<Index> order(m);
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](Index a, Index b) { return area[a] > area[b]; });
  for (Index start : order) {
    if (seen[start] || skip[start]) continue;
    seen[start] = 1;
    std::deque<Index> queue{start};
    while (!queue.empty()) {
      const Index f = queue.front();
      queue.pop_front();
      for (Index g : neighbours[f]) {
        if (seen[g]) continue;
        seen[g] = 1;
        const double angle = logs[g].norm();
        if (angle > 0.5 * kPi) {
          const Eigen::Vector3d other = logs[g] * (1.0 - 2.0 * kPi / angle);
          if ((other - logs[f]).norm() < (logs[g] - logs[f]).norm()) logs[g] = other;
        }
        queue.push_back(g);
      }
    }
  }
}

Eigen::Vector3d face_normal(const MatrixX3d& V, const MatrixX3i& F, Index f) {
  return (V.row(F(f, 1)) - V.row(F(f, 0))).cross(V.row(F(f, 2)) - V.row(F(f, 0))).transpose();
}

Index find_root(std::vector<Index>& parent, Index v) {
  while (parent[v] != v) v = parent[v] = parent[parent[v]];
  return v;
}

}  // namespace

ShapeInterpolation::~ShapeInterpolation() = default;
ShapeInterpolation::ShapeInterpolation(ShapeInterpolation&&) noexcept = default;
ShapeInterpolation& ShapeInterpolation::operator=(ShapeInterpolation&&) noexcept = default;

ShapeInterpolation::ShapeInterpolation(const MatrixX3d& source, const MatrixX3d& target, const MatrixX3i& F,
                                       Progress* progress)
    : source_(source), target_(target), F_(F), factor_(std::make_shared<Factor>()) {
  auto report = [&](double fraction) {
    if (progress) progress->report(fraction, "in-betweens: setup");
  };
  report(0.0);
  const Index n = Index(source.rows()), m = Index(F.rows());
  PM_REQUIRE(target.rows() == n, InvalidInputError, "the source has ", n, " vertices and the target ",
             target.rows(), ": they must share one topology");
  PM_REQUIRE(source.allFinite() && target.allFinite(), InvalidInputError,
             "the source and target positions must be finite");
  PM_REQUIRE(m == 0 || (F.minCoeff() >= 0 && F.maxCoeff() < n), InvalidInputError,
             "a face has a vertex index outside [0, ", n, ")");

  // Connected parts (through faces); vertices in no face stay on the straight line.
  std::vector<Index> parent(n);
  std::iota(parent.begin(), parent.end(), 0);
  std::vector<char> in_face(n, 0);
  for (Index f = 0; f < m; ++f)
    for (int c = 0; c < 3; ++c) {
      in_face[F(f, c)] = 1;
      parent[find_root(parent, F(f, c))] = find_root(parent, F(f, (c + 1) % 3));
    }
  component_ = VectorXi::Constant(n, -1);
  std::vector<Index> anchors;
  unknown_ = VectorXi::Constant(n, -1);
  Index unknowns = 0;
  {
    std::unordered_map<Index, Index> part_of_root;
    for (Index v = 0; v < n; ++v) {
      if (!in_face[v]) continue;
      const auto [it, fresh] = part_of_root.emplace(find_root(parent, v), Index(anchors.size()));
      component_[v] = it->second;
      if (fresh) anchors.push_back(v);  // held at 0; the part's mean is set after the solve
      else unknown_[v] = unknowns++;
    }
  }
  anchor_of_ = Eigen::Map<VectorXi>(anchors.data(), Index(anchors.size()));
  vertex_face_start_.assign(n + 1, 0);
  for (Index f = 0; f < m; ++f)
    for (int c = 0; c < 3; ++c) ++vertex_face_start_[F(f, c) + 1];
  std::partial_sum(vertex_face_start_.begin(), vertex_face_start_.end(), vertex_face_start_.begin());
  vertex_faces_.resize(std::size_t(3) * m);
  {
    std::vector<Index> next(vertex_face_start_.begin(), vertex_face_start_.end() - 1);
    for (Index f = 0; f < m; ++f)
      for (int c = 0; c < 3; ++c) vertex_faces_[next[F(f, c)]++] = f;
  }

  // The shape's global rotation G (column convention), vertices weighted by
  // their faces' shares of each end's area (the ends' scales may differ) so
  // dense patches of a merged mesh do not outvote the rest.
  std::vector<double> area0(m), area1(m), scale0(m), scale1(m);
  std::vector<Eigen::Matrix3d> frame0(m), frame1(m);
  normal0_.resize(m);
  normal1_.resize(m);
  for (Index f = 0; f < m; ++f) {
    frame0[f] = face_frame(source, F, f, &area0[f], &scale0[f]);
    frame1[f] = face_frame(target, F, f, &area1[f], &scale1[f]);
    normal0_[f] = face_normal(source, F, f);
    normal1_[f] = face_normal(target, F, f);
  }
  report(0.1);
  const double total0 = std::accumulate(area0.begin(), area0.end(), 0.0);
  const double total1 = std::accumulate(area1.begin(), area1.end(), 0.0);
  std::vector<double> share(m);
  for (Index f = 0; f < m; ++f)
    share[f] = (total0 > 0 ? area0[f] / total0 : 0.0) + (total1 > 0 ? area1[f] / total1 : 0.0);
  VectorXd weight = VectorXd::Zero(n);
  for (Index f = 0; f < m; ++f)
    for (int c = 0; c < 3; ++c) weight[F(f, c)] += share[f];
  Eigen::Matrix3d G = Eigen::Matrix3d::Identity();
  if (m > 0 && weight.sum() > 0) {
    const Eigen::RowVector3d c0 = (weight.transpose() * source) / weight.sum();
    const Eigen::RowVector3d c1 = (weight.transpose() * target) / weight.sum();
    const MatrixX3d from = source.rowwise() - c0, to = target.rowwise() - c1;
    G = best_rotation(from, to, weight).transpose();  // rows p R  ->  columns R^T p
  }
  global_log_ = log_of(G);
  global_angle_ = global_log_.norm();

  // Per face: its deformation gradient without G.
  const double area_floor0 = 2e-12 * std::pow(bounding_box_diagonal(source), 2),
               area_floor1 = 2e-12 * std::pow(bounding_box_diagonal(target), 2);
  std::vector<Eigen::Matrix3d> gradient(m, Eigen::Matrix3d::Identity());
  face_degenerate_.assign(m, 0);
  for (Index f = 0; f < m; ++f) {
    // Zero area, or an angle below ~1e-6 rad: the frame cannot be inverted reliably.
    const bool degenerate = area0[f] <= area_floor0 || area1[f] <= area_floor1 || area0[f] <= 1e-6 * scale0[f] ||
                            area1[f] <= 1e-6 * scale1[f];
    if (degenerate) {
      face_degenerate_[f] = 1;
      ++degenerate_;
      continue;
    }
    gradient[f] = G.transpose() * frame1[f] * frame0[f].inverse();
  }

  // Faces across an edge (sound faces only): (edge, face) rows sorted by
  // edge, each run of one edge's faces made neighbours (a hash map of the
  // 1.1M edges of a 370k-face merged mesh took a second).
  std::vector<std::vector<Index>> neighbours(m);
  {
    auto key = [](Index a, Index b) {
      return (std::uint64_t(std::uint32_t(std::min(a, b))) << 32) | std::uint32_t(std::max(a, b));
    };
    std::vector<std::pair<std::uint64_t, Index>> edge_faces;
    edge_faces.reserve(std::size_t(3) * m);
    for (Index f = 0; f < m; ++f)
      if (!face_degenerate_[f])
        for (int c = 0; c < 3; ++c) edge_faces.emplace_back(key(F(f, c), F(f, (c + 1) % 3)), f);
    std::sort(edge_faces.begin(), edge_faces.end());
    for (std::size_t run = 0; run < edge_faces.size();) {
      std::size_t end = run;
      while (end < edge_faces.size() && edge_faces[end].first == edge_faces[run].first) ++end;
      for (std::size_t i = run; i < end; ++i)
        for (std::size_t j = run; j < end; ++j)
          if (i != j) neighbours[edge_faces[i].second].push_back(edge_faces[j].second);
      run = end;
    }
  }
  report(0.15);

  // R̄: the best rotation of the summed frame covariances over a few rings
  // (each sweep adds the neighbours' sums; rescaled so nothing overflows).
  std::vector<Eigen::Matrix3d> covariance(m, Eigen::Matrix3d::Zero());
  for (Index f = 0; f < m; ++f)
    if (!face_degenerate_[f]) covariance[f] = G.transpose() * frame1[f] * frame0[f].transpose();
  report(0.2);
  std::vector<Eigen::Matrix3d> next(m);
  for (int sweep = 0; sweep < kNeighbourhoodSweeps; ++sweep) {
    report(0.2 + 0.4 * double(sweep) / kNeighbourhoodSweeps);
    double largest = 0;
#pragma omp parallel for schedule(static) reduction(max : largest) if (worth_parallel(m))
    for (Index f = 0; f < m; ++f) {
      Eigen::Matrix3d sum = covariance[f];
      for (Index g : neighbours[f]) sum += covariance[g];
      next[f] = sum;
      largest = std::max(largest, sum.cwiseAbs().maxCoeff());
    }
    if (largest > 0)
#pragma omp parallel for schedule(static) if (worth_parallel(m))
      for (Index f = 0; f < m; ++f) next[f] /= largest;
    covariance.swap(next);
  }
  area_log_.assign(m, Eigen::Vector3d::Zero());
  area_rest_.assign(m, Eigen::Matrix3d::Identity());
  rest_turn_.assign(m, Eigen::Matrix3d::Identity());
  rest_axes_.assign(m, Eigen::Matrix3d::Identity());
  rest_log_stretch_.assign(m, Eigen::Vector3d::Zero());
  rest_straight_.assign(m, 1);
  own_log_.assign(m, Eigen::Vector3d::Zero());
  own_axes_.assign(m, Eigen::Matrix3d::Identity());
  own_log_stretch_.assign(m, Eigen::Vector3d::Zero());
  own_straight_.assign(m, 0);
  // Three small SVDs per face (1.5 s on 370k faces): in parallel (run once,
  // heavy items: common/parallel.h), in chunks with a report between them
  // (no report inside a parallel region).
  constexpr Index kChunk = 16384;
  for (Index first = 0; first < m; first += kChunk) {
    report(0.6 + 0.15 * double(first) / double(m));
    const Index last = std::min(m, first + kChunk);
#pragma omp parallel for schedule(static)
    for (Index f = first; f < last; ++f) {
      if (face_degenerate_[f]) continue;
      const Eigen::Matrix3d area_turn = nearest_rotation(covariance[f]);
      area_log_[f] = log_of(area_turn);
      area_rest_[f] = area_turn.transpose() * gradient[f];
      const Polar rest = polar(area_rest_[f]);
      if (rest.positive) {
        rest_turn_[f] = rest.turn;
        rest_axes_[f] = rest.axes;
        rest_log_stretch_[f] = rest.log_stretch;
        rest_straight_[f] = 0;
      }
      const Polar own = polar(gradient[f]);
      own_log_[f] = log_of(own.turn);
      own_log_stretch_[f] = own.log_stretch;
      own_straight_[f] = !own.positive;  // turned over between the ends: S mixed straight
      own_axes_[f] = own.positive ? own.axes : own.stretch;
    }
  }
  report(0.75);
  make_logs_consistent(area_log_, neighbours, face_degenerate_, area0);
  make_logs_consistent(own_log_, neighbours, face_degenerate_, area0);

  // Each face's edges weigh by the inverse of its size (squared edge lengths
  // relative to their mean, at the end where it is smaller) so the fit's
  // residual is spread in proportion to the faces rather than in absolute
  // lengths, and tiny faces beside large ones keep their shape. The floor
  // keeps the factor well conditioned.
  const double mean0 = std::accumulate(scale0.begin(), scale0.end(), 0.0) / std::max<Index>(m, 1);
  const double mean1 = std::accumulate(scale1.begin(), scale1.end(), 0.0) / std::max<Index>(m, 1);
  face_weight_.assign(m, 1.0);
  for (Index f = 0; f < m; ++f) {
    const double size = std::min(mean0 > 0 ? scale0[f] / mean0 : 1.0, mean1 > 0 ? scale1[f] / mean1 : 1.0);
    face_weight_[f] = (face_degenerate_[f] ? kDegenerateWeight : 1.0) / std::max(size, kSizeFloor);
  }

  // The fit's matrix: the edge graph's Laplacian over the unknown vertices.
  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(std::size_t(9) * m);
  for (Index f = 0; f < m; ++f) {
    const double w = face_weight_[f];
    for (int c = 0; c < 3; ++c) {
      if (F(f, c) == F(f, (c + 1) % 3)) continue;  // a repeated vertex: no edge
      const Index i = unknown_[F(f, c)], j = unknown_[F(f, (c + 1) % 3)];
      if (i >= 0) entries.emplace_back(i, i, w);
      if (j >= 0) entries.emplace_back(j, j, w);
      if (i >= 0 && j >= 0) entries.emplace_back(std::max(i, j), std::min(i, j), -w);
    }
  }
  if (unknowns > 0) {
    Eigen::SparseMatrix<double> H(unknowns, unknowns);
    H.setFromTriplets(entries.begin(), entries.end());
    report(0.8);
    factor(H, progress);
    PM_REQUIRE(factor_->llt.info() == Eigen::Success, ComputeError,
               "the in-between fit could not be factored (", unknowns, " vertices)");
  }
  report(1.0);
}

void ShapeInterpolation::factor(Eigen::SparseMatrix<double>& H, Progress* progress) {
  // The one factorisation cannot report (2.4 s for the 291k vertices of a
  // 97k-onto-48k-face morph): it runs beside a thread that reports, and a
  // cancelled setup leaves it to finish and drop the factor and the matrix,
  // which it owns with this object's share; it holds the BLAS lock until
  // then, so the next factorisation waits for it rather than sharing
  // OpenBLAS's buffers with it.
  auto matrix = std::make_shared<Eigen::SparseMatrix<double>>(std::move(H));
  report_while([factor = factor_, matrix] { factor->llt.compute(*matrix); }, progress, 0.9, "in-betweens: setup");
}

Eigen::Matrix3d ShapeInterpolation::wish(Index f, double t, bool neighbourhood) const {
  const Eigen::Matrix3d Gt = rotation_of(t * global_log_);
  if (neighbourhood) {
    if (rest_straight_[f])
      return Gt * rotation_of(t * area_log_[f]) * ((1.0 - t) * Eigen::Matrix3d::Identity() + t * area_rest_[f]);
    // The stretch's uniform scale straight, its shape (determinant 1) by its logarithm.
    const double log_scale = rest_log_stretch_[f].mean();
    const double scale = (1.0 - t) + t * std::exp(log_scale);
    const Eigen::Vector3d shape = (t * (rest_log_stretch_[f].array() - log_scale)).exp().matrix();
    return Gt * rotation_of(t * area_log_[f]) * ((1.0 - t) * Eigen::Matrix3d::Identity() + t * rest_turn_[f]) *
           (scale * rest_axes_[f] * shape.asDiagonal() * rest_axes_[f].transpose());
  }
  const Eigen::Matrix3d stretch =
      own_straight_[f] ? Eigen::Matrix3d((1.0 - t) * Eigen::Matrix3d::Identity() + t * own_axes_[f])
                       : Eigen::Matrix3d(own_axes_[f] * (t * own_log_stretch_[f]).array().exp().matrix().asDiagonal() *
                                         own_axes_[f].transpose());
  return Gt * rotation_of(t * own_log_[f]) * stretch;
}

namespace {

/// The edge (a -> b) of face f as face f wants it at t.
Eigen::Vector3d wanted_edge(const MatrixX3d& source, const MatrixX3d& target, Index a, Index b, bool degenerate,
                            const Eigen::Matrix3d& J, const Eigen::Matrix3d& G, const Eigen::Matrix3d& Gt, double t) {
  const Eigen::Vector3d e0 = (source.row(b) - source.row(a)).transpose();
  if (!degenerate) return J * e0;
  const Eigen::Vector3d e1 = (target.row(b) - target.row(a)).transpose();
  return Gt * ((1.0 - t) * e0 + t * (G.transpose() * e1));
}

}  // namespace

ShapeInterpolation::Sides ShapeInterpolation::sides_at(double t) const {
  const Eigen::Matrix3d Gt = rotation_of(t * global_log_), back = Gt * rotation_of(-global_log_);
  Sides sides{std::vector<Eigen::Vector3d>(F_.rows()), std::vector<Eigen::Vector3d>(F_.rows()), &normal0_, &normal1_};
  for (Index f = 0; f < Index(F_.rows()); ++f) {
    sides.from_source[f] = (Gt * normal0_[f]).normalized();
    sides.from_target[f] = (back * normal1_[f]).normalized();
  }
  return sides;
}

bool ShapeInterpolation::Sides::against_both(Index f, const Eigen::Vector3d& n) const {
  if (n.dot(from_source[f]) < 0 && n.dot(from_target[f]) < 0) return true;
  const Eigen::Vector3d &n0 = (*source)[f], &n1 = (*target)[f];
  return n.dot(n0) < 0 && n.dot(n1) < 0;
}

MatrixX3d ShapeInterpolation::at(double t) const {
  MatrixX3d X = fit(t);
  const Sides sides = sides_at(t);
  for (int k = 0; k < kRepairs; ++k)
    if (repair(t, k + 1, sides, X) == 0) break;
  for (int pass = 0; pass < kMirrorPasses; ++pass)
    if (mirror_apexes(t, sides, X) == 0) break;
  // Small moves first: the larger reaches then only take what the small
  // ones could not mend (measured on spot onto a horse, t = 1/2, judged
  // against the ends' own normals: 168 faces passing through others against
  // 288 with the full reach at once).
  for (double reach = kUntangleReach / 8; reach <= kUntangleReach; reach *= 2)
    for (int pass = 0; pass < kUntanglePasses; ++pass)
      if (untangle_vertices(t, reach, sides, X) == 0) break;
  return X;
}

Eigen::Vector3d ShapeInterpolation::wanted_side(Index f, double t, const Sides& sides) const {
  // Its neighbourhood's wish turns its normal at t = 0.
  Eigen::Vector3d reference = wish(f, t, true) * normal0_[f];
  if (!(reference.norm() > 0)) return Eigen::Vector3d::Zero();
  reference.normalize();
  // A face turning past a right angle between the ends may want a normal
  // against both: it takes the nearer end's instead.
  if (sides.against_both(f, reference)) {
    const Eigen::Vector3d &n0 = sides.from_source[f], &n1 = sides.from_target[f];
    reference = reference.dot(n0) > reference.dot(n1) ? n0 : n1;
  }
  return reference;
}

Index ShapeInterpolation::mirror_apexes(double t, const Sides& sides, MatrixX3d& X) const {
  const std::vector<Index> turned = turned_over(X, sides);
  Index fixed = 0;
  for (const Index f : turned) {
    if (!is_turned(f, X, sides)) continue;  // mended by an earlier move
    const Eigen::Vector3d reference = wanted_side(f, t, sides);
    if (!(reference.norm() > 0)) continue;
    // The corner nearest its opposite side (the apex of a thin piece), mirrored
    // across that side within the plane across `reference`: the smallest move.
    int best = -1;
    double best_height = std::numeric_limits<double>::infinity();
    Eigen::Vector3d best_direction;
    for (int c = 0; c < 3; ++c) {
      const Eigen::Vector3d a = X.row(F_(f, (c + 1) % 3)).transpose(), b = X.row(F_(f, (c + 2) % 3)).transpose();
      const Eigen::Vector3d apex = X.row(F_(f, c)).transpose();
      const Eigen::Vector3d along = (b - a).normalized(), across = reference.cross(along);
      if (!(across.norm() > 1e-12)) continue;
      const double height = (apex - a).dot(across.normalized());
      if (std::abs(height) < best_height) best_height = std::abs(height), best = c, best_direction = across.normalized();
    }
    if (best < 0) continue;
    // Thin pieces only: the move is at most a quarter of the face's longest side.
    double longest = 0;
    for (int c = 0; c < 3; ++c) longest = std::max(longest, (X.row(F_(f, c)) - X.row(F_(f, (c + 1) % 3))).norm());
    if (2.0 * best_height > 0.25 * longest) continue;
    const Index v = F_(f, best);
    const Eigen::RowVector3d old = X.row(v);
    const Index before = turned_around(v, X, sides);
    X.row(v) = old + 2.0 * best_height * best_direction.transpose();
    if (turned_around(v, X, sides) < before) {
      ++fixed;
    } else {
      X.row(v) = old;
    }
  }
  return fixed;
}

MatrixX3d ShapeInterpolation::fit(double t) const {
  const Index n = Index(source_.rows()), m = Index(F_.rows());
  const MatrixX3d straight = (1.0 - t) * source_ + t * target_;
  if (m == 0) return straight;
  const Eigen::Matrix3d G = rotation_of(global_log_), Gt = rotation_of(t * global_log_);
  const Index unknowns = factor_->llt.rows();
  RowsK<3> rhs = RowsK<3>::Zero(unknowns, 3);
  for (Index f = 0; f < m; ++f) {
    const double w = face_weight_[f];
    const Eigen::Matrix3d J = face_degenerate_[f] ? Eigen::Matrix3d::Identity() : wish(f, t, true);
    for (int c = 0; c < 3; ++c) {
      const Index a = F_(f, c), b = F_(f, (c + 1) % 3);
      if (a == b) continue;
      const Eigen::Vector3d wanted = wanted_edge(source_, target_, a, b, face_degenerate_[f], J, G, Gt, t);
      if (unknown_[b] >= 0) rhs.row(unknown_[b]) += w * wanted.transpose();
      if (unknown_[a] >= 0) rhs.row(unknown_[a]) -= w * wanted.transpose();
    }
  }
  RowsK<3> solved(unknowns, 3);
  if (unknowns > 0) solved = factor_->llt.solve(Eigen::MatrixXd(rhs));

  MatrixX3d X = straight;
  const Index parts = Index(anchor_of_.size());
  std::vector<Eigen::RowVector3d> shift(parts, Eigen::RowVector3d::Zero());
  std::vector<Index> count(parts, 0);
  for (Index v = 0; v < n; ++v) {
    const Index part = component_[v];
    if (part < 0) continue;
    X.row(v) = unknown_[v] >= 0 ? Eigen::RowVector3d(solved.row(unknown_[v])) : Eigen::RowVector3d::Zero();
    shift[part] += straight.row(v) - X.row(v);
    ++count[part];
  }
  for (Index v = 0; v < n; ++v)
    if (component_[v] >= 0) X.row(v) += shift[component_[v]] / double(count[component_[v]]);
  return X;
}

bool ShapeInterpolation::is_turned(Index f, const MatrixX3d& X, const Sides& sides) const {
  return !face_degenerate_[f] && sides.against_both(f, face_normal(X, F_, f));
}

Index ShapeInterpolation::turned_around(Index v, const MatrixX3d& X, const Sides& sides) const {
  Index count = 0;
  for (Index p = vertex_face_start_[v]; p < vertex_face_start_[v + 1]; ++p) count += is_turned(vertex_faces_[p], X, sides);
  return count;
}

std::vector<Index> ShapeInterpolation::turned_over(const MatrixX3d& X, const Sides& sides) const {
  std::vector<Index> out;
  for (Index f = 0; f < Index(F_.rows()); ++f)
    if (is_turned(f, X, sides)) out.push_back(f);
  return out;
}

Index ShapeInterpolation::repair(double t, int rings, const Sides& sides, MatrixX3d& X) const {
  const std::vector<Index> turned = turned_over(X, sides);
  if (turned.empty()) return 0;
  const Index n = Index(source_.rows());
  // The free vertices: those of the turned faces and `rings` rings around them.
  std::vector<Index> row(n, -1), free;
  for (Index f : turned)
    for (int c = 0; c < 3; ++c)
      if (row[F_(f, c)] < 0) {
        row[F_(f, c)] = Index(free.size());
        free.push_back(F_(f, c));
      }
  for (int ring = 0; ring < rings; ++ring) {
    const std::size_t end = free.size();
    for (std::size_t k = 0; k < end; ++k)
      for (Index p = vertex_face_start_[free[k]]; p < vertex_face_start_[free[k] + 1]; ++p)
        for (int c = 0; c < 3; ++c) {
          const Index v = F_(vertex_faces_[p], c);
          if (row[v] < 0) {
            row[v] = Index(free.size());
            free.push_back(v);
          }
        }
  }
  // The faces touching them, each asking for its own shape; held vertices
  // move their terms to the right-hand side.
  std::vector<char> taken(F_.rows(), 0);
  std::vector<Eigen::Triplet<double>> entries;
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(Index(free.size()), 3);
  const Eigen::Matrix3d G = rotation_of(global_log_), Gt = rotation_of(t * global_log_);
  bool held = false;
  for (Index v : free)
    for (Index p = vertex_face_start_[v]; p < vertex_face_start_[v + 1]; ++p) {
      const Index f = vertex_faces_[p];
      if (taken[f]) continue;
      taken[f] = 1;
      const double w = face_weight_[f];
      const Eigen::Matrix3d J = face_degenerate_[f] ? Eigen::Matrix3d::Identity() : wish(f, t, false);
      for (int c = 0; c < 3; ++c) {
        const Index a = F_(f, c), b = F_(f, (c + 1) % 3), i = row[a], j = row[b];
        if (a == b) continue;
        const Eigen::RowVector3d wanted =
            wanted_edge(source_, target_, a, b, face_degenerate_[f], J, G, Gt, t).transpose();
        // w |x_b - x_a - wanted|^2
        if (i >= 0) entries.emplace_back(i, i, w);
        if (j >= 0) entries.emplace_back(j, j, w);
        if (i >= 0 && j >= 0) {
          entries.emplace_back(i, j, -w);
          entries.emplace_back(j, i, -w);
        }
        if (j >= 0) rhs.row(j) += w * (wanted + (i < 0 ? Eigen::RowVector3d(X.row(a)) : Eigen::RowVector3d::Zero()));
        if (i >= 0) rhs.row(i) -= w * (wanted - (j < 0 ? Eigen::RowVector3d(X.row(b)) : Eigen::RowVector3d::Zero()));
        held = held || i < 0 || j < 0;
      }
    }
  if (!held) return Index(turned.size());  // a whole part turned over: nothing to hold it by
  // Every cluster of free vertices must touch a held one, or its fit is singular.
  {
    std::vector<Index> parent(free.size());
    std::iota(parent.begin(), parent.end(), 0);
    std::vector<char> anchored(free.size(), 0);
    for (const auto& e : entries) {
      if (e.row() == e.col()) continue;
      Index x = Index(e.row()), y = Index(e.col());
      while (parent[x] != x) x = parent[x] = parent[parent[x]];
      while (parent[y] != y) y = parent[y] = parent[parent[y]];
      parent[x] = y;
    }
    for (Index v : free)
      for (Index p = vertex_face_start_[v]; p < vertex_face_start_[v + 1]; ++p)
        for (int c = 0; c < 3; ++c)
          if (row[F_(vertex_faces_[p], c)] < 0) anchored[std::size_t(row[v])] = 1;
    std::vector<char> cluster_held(free.size(), 0);
    auto root = [&](Index x) {
      while (parent[x] != x) x = parent[x] = parent[parent[x]];
      return x;
    };
    for (std::size_t k = 0; k < free.size(); ++k)
      if (anchored[k]) cluster_held[std::size_t(root(Index(k)))] = 1;
    for (std::size_t k = 0; k < free.size(); ++k)
      if (!cluster_held[std::size_t(root(Index(k)))]) return Index(turned.size());
  }
  Eigen::SparseMatrix<double> H(Index(free.size()), Index(free.size()));
  H.setFromTriplets(entries.begin(), entries.end());
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(H);
  if (solver.info() != Eigen::Success) return Index(turned.size());
  const Eigen::MatrixXd solved = solver.solve(rhs);
  if (!solved.allFinite()) return Index(turned.size());
  // Kept only when fewer faces are turned over than before, counting with
  // them the faces around that pass through others (measured on a CAD box
  // onto a cow, t = 1/4: refits kept on turned faces alone took the faces
  // through others from 115 to 307; counting both, 184).
  MatrixX3d repaired = X;
  for (std::size_t k = 0; k < free.size(); ++k) repaired.row(free[k]) = solved.row(Index(k));
  const Index left = Index(turned_over(repaired, sides).size());
  if (left >= Index(turned.size())) return Index(turned.size());
  const auto [crossing_before, crossing_after] = crossing_faces(X, repaired, taken);
  if (left + crossing_after >= Index(turned.size()) + crossing_before) return Index(turned.size());
  X = std::move(repaired);
  return left;
}

std::pair<Index, Index> ShapeInterpolation::crossing_faces(const MatrixX3d& before, const MatrixX3d& after,
                                                           const std::vector<char>& moved) const {
  // The moved faces and a ring of faces around them, on their own vertices.
  std::vector<char> in(F_.rows(), 0);
  for (Index f = 0; f < Index(F_.rows()); ++f)
    if (moved[f])
      for (int c = 0; c < 3; ++c)
        for (Index p = vertex_face_start_[F_(f, c)]; p < vertex_face_start_[F_(f, c) + 1]; ++p)
          in[vertex_faces_[p]] = 1;
  std::vector<Index> local(source_.rows(), -1), vertices;
  std::vector<Eigen::Vector3i> faces;
  for (Index f = 0; f < Index(F_.rows()); ++f) {
    if (!in[f]) continue;
    Eigen::Vector3i face;
    for (int c = 0; c < 3; ++c) {
      Index& row = local[F_(f, c)];
      if (row < 0) {
        row = Index(vertices.size());
        vertices.push_back(F_(f, c));
      }
      face[c] = int(row);
    }
    faces.push_back(face);
  }
  MatrixX3i patch(Index(faces.size()), 3);
  for (std::size_t k = 0; k < faces.size(); ++k) patch.row(Index(k)) = faces[k].transpose();
  auto count = [&](const MatrixX3d& X) {
    MatrixX3d positions(Index(vertices.size()), 3);
    for (std::size_t k = 0; k < vertices.size(); ++k) positions.row(Index(k)) = X.row(vertices[k]);
    return self_intersections(positions, patch).intersecting_faces;
  };
  return {count(before), count(after)};
}

Index ShapeInterpolation::untangle_vertices(double t, double reach, const Sides& sides, MatrixX3d& X) const {
  const std::vector<Index> turned = turned_over(X, sides);
  if (turned.empty()) return 0;
  std::vector<char> visited(source_.rows(), 0);
  Index mended = 0;
  for (const Index f : turned)
    for (int corner = 0; corner < 3; ++corner) {
      const Index v = F_(f, corner);
      if (visited[v]) continue;
      visited[v] = 1;
      // Each face around v is linear in v: with (a, b) its side across v,
      // n · r = (a × b) · r + v · ((a − b) × r). Every face asks n · r >= its
      // floor with r the end normal it keeps (or, turned over, the one nearer
      // the side it wants), for both pairs of ends it is judged against: a
      // half-space g · v >= h per face and pair. (Asking for one pair only,
      // the moves mending one turned the face over against the other.)
      std::vector<Eigen::Vector3d> g;
      std::vector<double> h;
      Index turned_before = 0;
      double longest = 0;
      bool usable = true;
      for (Index p = vertex_face_start_[v]; p < vertex_face_start_[v + 1] && usable; ++p) {
        const Index face = vertex_faces_[p];
        if (face_degenerate_[face]) continue;
        int c = 0;
        while (F_(face, c) != v) ++c;
        const Eigen::Vector3d a = X.row(F_(face, (c + 1) % 3)).transpose(), b = X.row(F_(face, (c + 2) % 3)).transpose();
        const Eigen::Vector3d n = face_normal(X, F_, face);
        const double base = (a - b).squaredNorm();
        longest = std::max(longest, std::sqrt(base));
        turned_before += sides.against_both(face, n);
        const Eigen::Vector3d side = wanted_side(face, t, sides);
        // One half-space per pair of ends the face is judged against.
        const std::pair<Eigen::Vector3d, Eigen::Vector3d> ends[2] = {
            {sides.from_source[face], sides.from_target[face]},
            {(*sides.source)[face].normalized(), (*sides.target)[face].normalized()}};
        for (const auto& [n0, n1] : ends) {
          Eigen::Vector3d r;
          double floor = kUntangleHeight * base;
          if (n.dot(n0) < 0 && n.dot(n1) < 0) {
            r = side.dot(n0) >= side.dot(n1) ? n0 : n1;
          } else {
            r = n.dot(n0) >= n.dot(n1) ? n0 : n1;
            floor = std::min(floor, std::max(0.0, n.dot(r)));  // no thinner than it is
          }
          if (!r.allFinite()) usable = false;
          g.push_back((a - b).cross(r));
          h.push_back(floor - a.cross(b).dot(r));
        }
      }
      if (!usable || turned_before == 0) continue;
      // The nearest point of their intersection (Dykstra's alternating projections).
      const Eigen::Vector3d start = X.row(v).transpose();
      Eigen::Vector3d x = start;
      std::vector<Eigen::Vector3d> correction(g.size(), Eigen::Vector3d::Zero());
      for (int sweep = 0; sweep < kProjectionSweeps; ++sweep)
        for (std::size_t k = 0; k < g.size(); ++k) {
          const Eigen::Vector3d y = x + correction[k];
          const double gg = g[k].squaredNorm();
          const double shortfall = gg > 0 ? (h[k] - g[k].dot(y)) / gg : 0.0;
          x = shortfall > 0 ? Eigen::Vector3d(y + shortfall * g[k]) : y;
          correction[k] = y - x;
        }
      // Kept when it is a local move (within `reach` of the longest side
      // around) that leaves fewer faces around v turned over.
      if (!x.allFinite() || (x - start).norm() > reach * longest) continue;
      X.row(v) = x.transpose();
      const Index turned_after = turned_around(v, X, sides);
      if (turned_after < turned_before) {
        mended += turned_before - turned_after;
      } else {
        X.row(v) = start.transpose();
      }
    }
  return mended;
}

}  // namespace paramorph::morph
