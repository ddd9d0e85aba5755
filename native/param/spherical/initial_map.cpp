#include "param/spherical/initial_map.h"

#include <Eigen/SparseCholesky>
#include <Eigen/Dense>
#include <cmath>

#include "common/errors.h"
#include "common/parallel.h"
#include "param/spherical/sphere_quality.h"

namespace paramorph::spherical {

VectorXd vertex_areas(const TriMesh& mesh) {
  const VectorXd A = face_areas(mesh.V(), mesh.F());
  VectorXd out = VectorXd::Zero(mesh.num_vertices());
  for (Index f = 0; f < mesh.num_faces(); ++f)
    for (int k = 0; k < 3; ++k) out[mesh.F()(f, k)] += A[f] / 3.0;
  return out;
}

namespace {

/// The 1-ring of p in the faces' orientation order.
std::vector<Index> ordered_ring(const TriMesh& mesh, Index p) {
  const Csr& corners = mesh.vertex_corners();
  const MatrixX3i& F = mesh.F();
  std::vector<std::pair<Index, Index>> next;  // a -> b for each face (p, a, b)
  for (Index k = corners.begin(p); k < corners.end(p); ++k) {
    const Index f = corners.items[k] / 3, c = corners.items[k] % 3;
    next.emplace_back(F(f, (c + 1) % 3), F(f, (c + 2) % 3));
  }
  std::vector<Index> ring{next.front().first};
  for (std::size_t step = 0; step + 1 < next.size(); ++step) {
    const Index a = ring.back();
    Index b = -1;
    for (const auto& e : next)
      if (e.first == a) b = e.second;
    PM_REQUIRE(b >= 0, NonManifoldError, "the faces around vertex ", p, " do not form one fan");
    ring.push_back(b);
  }
  return ring;
}

Index pick_puncture(const TriMesh& mesh) {
  const VectorXd areas = vertex_areas(mesh);
  Index best = 0;
  for (Index v = 1; v < mesh.num_vertices(); ++v)
    if (areas[v] > areas[best]) best = v;
  return best;
}

}  // namespace

std::shared_ptr<const PuncturedLaplacian> factor_punctured_laplacian(const TriMesh& mesh,
                                                                     const SpringGraph& graph,
                                                                     Index puncture) {
  auto out = std::make_shared<PuncturedLaplacian>();
  const Index n = mesh.num_vertices();
  out->puncture = puncture >= 0 ? puncture : pick_puncture(mesh);
  out->ring = ordered_ring(mesh, out->puncture);
  out->interior_index.assign(n, 0);
  out->interior_index[out->puncture] = -1;
  for (Index r : out->ring) out->interior_index[r] = -1;
  for (Index v = 0; v < n; ++v)
    if (out->interior_index[v] >= 0) out->interior_index[v] = out->interior_count++;

  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(graph.neighbors.size());
  for (Index v = 0; v < n; ++v) {
    const Index r = out->interior_index[v];
    if (r < 0) continue;
    triplets.emplace_back(r, r, graph.degree[v]);
    for (Index k = graph.offsets[v]; k < graph.offsets[v + 1]; ++k) {
      const Index c = out->interior_index[graph.neighbors[k]];
      if (c >= 0 && c < r) triplets.emplace_back(r, c, -graph.weights[k]);  // lower part only
    }
  }
  Eigen::SparseMatrix<double> A(out->interior_count, out->interior_count);
  A.setFromTriplets(triplets.begin(), triplets.end());
  out->factor = std::make_unique<PuncturedLaplacian::Factor>(A);
  PM_REQUIRE(out->factor->info() == Eigen::Success, DegenerateFaceError,
             "the Laplacian of the punctured mesh could not be factored (degenerate weights)");
  return out;
}

MatrixX3d stereographic_tutte_map(const TriMesh& mesh, const SpringGraph& graph,
                                  const PuncturedLaplacian& laplacian) {
  const Index n = mesh.num_vertices();
  const Index p = laplacian.puncture;
  const std::vector<Index>& ring = laplacian.ring;

  // Ring on the unit circle, spaced by the 3D lengths of the ring's edges.
  std::vector<double> cumulative{0.0};
  const MatrixX3d& V = mesh.V();
  for (std::size_t k = 0; k < ring.size(); ++k)
    cumulative.push_back(cumulative.back() +
                         (V.row(ring[(k + 1) % ring.size()]) - V.row(ring[k])).norm());
  MatrixX2d Z = MatrixX2d::Zero(n, 2);
  for (std::size_t k = 0; k < ring.size(); ++k) {
    const double angle = 2.0 * M_PI * cumulative[k] / cumulative.back();
    Z(ring[k], 0) = std::cos(angle);
    Z(ring[k], 1) = std::sin(angle);
  }
  // Dirichlet problem L_II Z_I = sum over ring neighbours w_ir z_r.
  if (laplacian.interior_count > 0) {
    Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(laplacian.interior_count, 2);
    for (Index v = 0; v < n; ++v) {
      const Index r = laplacian.interior_index[v];
      if (r < 0) continue;
      for (Index k = graph.offsets[v]; k < graph.offsets[v + 1]; ++k) {
        const Index j = graph.neighbors[k];
        if (laplacian.interior_index[j] < 0) rhs.row(r) += graph.weights[k] * Z.row(j);
      }
    }
    const Eigen::MatrixXd ZI = laplacian.factor->solve(rhs);
    for (Index v = 0; v < n; ++v)
      if (laplacian.interior_index[v] >= 0) Z.row(v) = ZI.row(laplacian.interior_index[v]);
  }

  // Lift: the fan of p covers the polar cap whose area share equals the fan's
  // share of the surface, a good start for Möbius balancing.
  const VectorXd A = face_areas(mesh.V(), mesh.F());
  double fan_area = 0.0;
  const Csr& corners = mesh.vertex_corners();
  for (Index k = corners.begin(p); k < corners.end(p); ++k) fan_area += A[corners.items[k] / 3];
  const double cap_height = std::clamp(1.0 - 2.0 * fan_area / A.sum(), -0.9, 0.9);
  const double scale = std::sqrt((1.0 + cap_height) / (1.0 - cap_height));

  MatrixX3d X(n, 3);
  for (Index v = 0; v < n; ++v) {
    if (v == p) {
      X.row(v) << 0.0, 0.0, 1.0;
      continue;
    }
    const double qx = scale * Z(v, 0), qy = scale * Z(v, 1);
    const double q2 = qx * qx + qy * qy;
    X.row(v) << 2.0 * qx / (q2 + 1.0), 2.0 * qy / (q2 + 1.0), (q2 - 1.0) / (q2 + 1.0);
  }
  // The ring's direction decides the handedness; mirror when most faces face inwards.
  Index negative = Index(flipped_faces(X, mesh.F()).size());
  if (2 * negative > mesh.num_faces()) X.col(0) = -X.col(0);
  return X;
}

MatrixX3d radial_projection(const TriMesh& mesh) {
  const VectorXd w = vertex_areas(mesh);
  const Eigen::RowVector3d center = (w.transpose() * mesh.V()) / w.sum();
  MatrixX3d X = mesh.V().rowwise() - center;
  X.rowwise().normalize();
  return X;
}

int centroid_relaxation(const TriMesh& mesh, MatrixX3d& X, int max_sweeps, int check_every,
                        ProgressWindow progress) {
  const MatrixX3i& F = mesh.F();
  const Csr& corners = mesh.vertex_corners();
  const Index n = mesh.num_vertices(), m = mesh.num_faces();
  MatrixX3d weighted(m, 3);  // area * centroid per face
  for (int sweep = 0; sweep < max_sweeps; ++sweep) {
    if (sweep % check_every == 0) {
      if (flipped_faces(X, F).empty()) return sweep;
      progress.report(double(sweep) / max_sweeps, "relaxation");
    }
#pragma omp parallel for schedule(static) if (worth_parallel(m))
    for (Index f = 0; f < m; ++f) {
      const Eigen::Vector3d a = X.row(F(f, 0)), b = X.row(F(f, 1)), c = X.row(F(f, 2));
      const double area = 0.5 * (b - a).cross(c - a).norm();
      weighted.row(f) = area * (a + b + c) / 3.0;
    }
#pragma omp parallel for schedule(static) if (worth_parallel(n))
    for (Index v = 0; v < n; ++v) {
      Eigen::RowVector3d s = Eigen::RowVector3d::Zero();
      for (Index k = corners.begin(v); k < corners.end(v); ++k) s += weighted.row(corners.items[k] / 3);
      const double norm = s.norm();
      if (norm > 0) X.row(v) = s / norm;
    }
  }
  return max_sweeps;
}

double mobius_center(MatrixX3d& X, const MatrixX3i& F, const VectorXd& vertex_weights,
                     int max_steps, double tolerance) {
  const double total = vertex_weights.sum();
  const Index n = Index(X.rows());
  std::size_t folds = flipped_faces(X, F).size();
  double norm = 0.0;
  for (int step = 0; step < max_steps; ++step) {
    const Eigen::RowVector3d c = (vertex_weights.transpose() * X) / total;
    norm = c.norm();
    if (norm < tolerance) break;
    // The ball automorphism sending c to 0, restricted to the sphere:
    // x -> ((1 - |c|^2)(x - c) - |x - c|^2 c) / |x - c|^2.
    MatrixX3d Y(n, 3);
    const double c2 = c.squaredNorm();
#pragma omp parallel for schedule(static) if (worth_parallel(n))
    for (Index v = 0; v < n; ++v) {
      const Eigen::RowVector3d d = X.row(v) - c;
      const double d2 = d.squaredNorm();
      Eigen::RowVector3d y = ((1.0 - c2) * d - d2 * c) / d2;
      Y.row(v) = y.normalized();
    }
    const std::size_t new_folds = flipped_faces(Y, F).size();
    if (new_folds > folds) break;  // a huge triangle turned over: keep the last good map
    folds = new_folds;
    X.swap(Y);
  }
  return norm;
}

}  // namespace paramorph::spherical
