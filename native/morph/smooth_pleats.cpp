// Pleats of a kept topology smoothed along the target (morph/smooth_pleats.h).
#include "morph/smooth_pleats.h"

#include <cstddef>

#include "mesh/tri_mesh.h"
#include "mesh/vertex_normals.h"

namespace paramorph::morph {

namespace {

/// The share of the umbrella step taken per pass (a full step overshoots
/// where the ring is uneven).
constexpr double kStep = 0.5;
/// A moved vertex's snap back onto B may be at most this share of its mean
/// ring edge (longer: the step left B's sheet, across a crease).
constexpr double kLongestSnap = 0.5;
/// B's normals before and after a move must agree this much (cosine):
/// never onto the other side of a thin part.
constexpr double kSameSheet = 0.5;
/// Times the farthest sample's distance: the radius around it in which moved
/// vertices go back when a pass went past the limit.
constexpr double kRevertRadius = 3.0;
constexpr int kMostReverts = 20;

MatrixX3d rows_of(const MatrixX3d& P, const std::vector<Index>& rows) {
  MatrixX3d out(rows.size(), 3);
  for (std::size_t i = 0; i < rows.size(); ++i) out.row(Index(i)) = P.row(rows[i]);
  return out;
}

}  // namespace

std::vector<char> faces_facing_away(const MatrixX3d& P, const MatrixX3i& F, const ClosestPointTree& target,
                                    const MatrixX3d& VB, const MatrixX3i& FB, double source_side) {
  MatrixX3d centres(F.rows(), 3);
  for (Index f = 0; f < Index(F.rows()); ++f) centres.row(f) = (P.row(F(f, 0)) + P.row(F(f, 1)) + P.row(F(f, 2))) / 3.0;
  const ClosestPoints under = target.query(centres);
  std::vector<char> away(F.rows(), 0);
  for (Index f = 0; f < Index(F.rows()); ++f)
    away[f] = source_side * face_normal(P, F, f).dot(face_normal(VB, FB, under.face(f))) < 0;
  return away;
}

SmoothedPleats smooth_pleats(MatrixX3d& P, const MatrixX3i& F, const ClosestPointTree& target, const MatrixX3d& VB,
                             const MatrixX3i& FB, const MatrixX3d& target_normals, double source_side,
                             std::vector<char>& fixed,
                             const std::function<Farthest(const MatrixX3d&)>& farthest, int passes,
                             Progress* progress) {
  const TriMesh topology(P, F);  // its connectivity only: the passes do not change it
  const Csr& ring = topology.vertex_neighbors();
  // B's normal at a closest point, blended from its vertex normals.
  auto normal_at = [&](const ClosestPoints& on, Index i) {
    const Index f = on.face(i);
    Eigen::RowVector3d n = Eigen::RowVector3d::Zero();
    for (int c = 0; c < 3; ++c) n += on.bary(i, c) * target_normals.row(FB(f, c));
    return Eigen::RowVector3d(n.normalized());
  };

  SmoothedPleats out;
  for (int pass = 0; pass < passes; ++pass) {
    if (progress) progress->report(0.99, "smoothing the pleats along the target");
    const std::vector<char> away = faces_facing_away(P, F, target, VB, FB, source_side);
    std::vector<char> in_region(P.rows(), 0);
    for (Index f = 0; f < Index(F.rows()); ++f)
      if (away[f])
        for (int k = 0; k < 3; ++k) in_region[F(f, k)] = 1;
    // One ring more: a pleat's fold is undone by its neighbours moving too.
    std::vector<char> grown = in_region;
    for (Index v = 0; v < Index(P.rows()); ++v)
      if (in_region[v])
        for (Index j = ring.begin(v); j < ring.end(v); ++j) grown[ring.items[j]] = 1;
    // A vertex with no neighbour (in no face, or only in faces of it alone)
    // has nowhere to move to.
    std::vector<Index> moving;
    for (Index v = 0; v < Index(P.rows()); ++v)
      if (grown[v] && !fixed[v] && ring.size(v) > 0) moving.push_back(v);
    if (moving.empty()) break;

    const MatrixX3d previous = P;
    const ClosestPoints before = target.query(rows_of(P, moving));
    MatrixX3d proposal(moving.size(), 3);
    VectorXd ring_edge(moving.size());
    for (std::size_t i = 0; i < moving.size(); ++i) {
      const Index v = moving[i];
      Eigen::RowVector3d centroid = Eigen::RowVector3d::Zero();
      double edge = 0.0;
      for (Index j = ring.begin(v); j < ring.end(v); ++j) {
        centroid += P.row(ring.items[j]);
        edge += (P.row(ring.items[j]) - P.row(v)).norm();
      }
      const double count = double(ring.size(v));
      ring_edge(Index(i)) = edge / count;
      // The umbrella step in B's tangent plane where the vertex lies.
      const Eigen::RowVector3d n = normal_at(before, Index(i));
      Eigen::RowVector3d step = centroid / count - P.row(v);
      step -= step.dot(n) * n;
      proposal.row(Index(i)) = P.row(v) + kStep * step;
    }
    const ClosestPoints onto = target.query(proposal);
    Index kept = 0;
    for (std::size_t i = 0; i < moving.size(); ++i) {
      const Index v = moving[i];
      const double edge = ring_edge(Index(i));
      if (!(edge > 0)) continue;
      if (onto.distance(Index(i)) > kLongestSnap * edge) continue;
      if (normal_at(onto, Index(i)).dot(normal_at(before, Index(i))) < kSameSheet) continue;
      if ((onto.points.row(Index(i)) - P.row(v)).norm() > edge) continue;
      P.row(v) = onto.points.row(Index(i));
      ++kept;
    }
    if (kept == 0) break;  // the next pass would propose the same

    // Never past the bounds: the moved vertices around the farthest sample go
    // back and stay there; if none moved there, the cause is elsewhere and
    // the whole pass goes back.
    bool within = false;
    for (int revert = 0; revert < kMostReverts; ++revert) {
      const Farthest worst = farthest(P);
      if (worst.over <= 1.0) {
        within = true;
        break;
      }
      const double radius = kRevertRadius * worst.distance;
      Index reverted = 0;
      for (Index v = 0; v < Index(P.rows()); ++v)
        if ((P.row(v) - worst.where).norm() < radius || (previous.row(v) - worst.where).norm() < radius) {
          fixed[v] = 1;
          if (P.row(v) != previous.row(v)) {
            P.row(v) = previous.row(v);
            ++reverted;
          }
        }
      if (reverted == 0) break;
    }
    if (!within) {
      P = previous;
      break;
    }
    // All moves gone back: the next pass proposes others (more are fixed).
    Index moved = 0;
    for (const Index v : moving) moved += P.row(v) != previous.row(v);
    if (moved == 0) continue;
    ++out.passes;
    out.moves += moved;
  }
  return out;
}

}  // namespace paramorph::morph
