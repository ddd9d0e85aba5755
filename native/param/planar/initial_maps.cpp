#include "param/planar/initial_maps.h"

#include <Eigen/Geometry>
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <cmath>

#include "common/fill_reducing_ordering.h"
#include "common/errors.h"
#include "mesh/cotangent_weights.h"
#include "param/planar/laplacian_preconditioner.h"

namespace paramorph::planar {

namespace {

const std::vector<Index>& longest_loop(const TriMesh& mesh) {
  const auto& loops = mesh.boundary_loops();
  PM_REQUIRE(!loops.empty(), NotClosedError,
             "the mesh has no boundary: a planar map needs an open surface (cut it first)");
  return *std::max_element(loops.begin(), loops.end(),
                           [](const auto& a, const auto& b) { return a.size() < b.size(); });
}

}  // namespace

MatrixX2d harmonic_fill(const TriMesh& mesh, const VectorXd& w, const std::vector<char>& pinned,
                        MatrixX2d X) {
  const FreeVertices free = free_vertices(pinned);
  if (free.vertices.empty()) return X;
  // L_ff X_f = -L_fp X_p: the pinned neighbours' weighted positions.
  const Csr& nbr = mesh.vertex_neighbors();
  const Csr& nbr_edges = mesh.vertex_neighbor_edges();
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(Index(free.vertices.size()), 2);
  for (Index v : free.vertices)
    for (Index k = nbr.begin(v); k < nbr.end(v); ++k)
      if (pinned[nbr.items[k]]) rhs.row(free.slot[v]) += w[nbr_edges.items[k]] * X.row(nbr.items[k]);
  Eigen::SimplicialLLT<Eigen::SparseMatrix<double>, Eigen::Lower, FillReducingOrdering<int>> solver(
      free_laplacian(mesh, w, free));
  PM_REQUIRE(solver.info() == Eigen::Success, DisconnectedError,
             "the Tutte system is singular: a part of the mesh does not reach the boundary");
  const Eigen::MatrixXd Y = solver.solve(rhs);
  for (Index v : free.vertices) X.row(v) = Y.row(free.slot[v]);
  return X;
}

MatrixX2d blend_pins(const TriMesh& mesh, const MatrixX2d& start, const std::vector<char>& pinned,
                     const MatrixX2d& targets) {
  const Index n = mesh.num_vertices();
  const FreeVertices free = free_vertices(pinned);
  MatrixX2d out = start;
  for (Index v = 0; v < n; ++v)
    if (pinned[v]) out.row(v) = targets.row(v);
  if (free.vertices.size() == std::size_t(n) || free.vertices.empty()) return out;

  // Full Laplacian (every vertex free) and lumped areas.
  const Eigen::SparseMatrix<double> L = Eigen::SparseMatrix<double>(
      free_laplacian(mesh, clamped_cotangent_weights(mesh), free_vertices(std::vector<char>(n, 0)))
          .selfadjointView<Eigen::Lower>());
  VectorXd inverse_area = VectorXd::Zero(n);
  const MatrixX3d& V = mesh.V();
  const MatrixX3i& F = mesh.F();
  for (Index f = 0; f < mesh.num_faces(); ++f) {
    const double area = 0.5 * (V.row(F(f, 1)) - V.row(F(f, 0)))
                                  .cross(V.row(F(f, 2)) - V.row(F(f, 0)))
                                  .norm();
    for (int k = 0; k < 3; ++k) inverse_area[F(f, k)] += area / 3.0;
  }
  inverse_area = inverse_area.cwiseInverse();
  const Eigen::SparseMatrix<double> Q = L * inverse_area.asDiagonal() * L;

  // Q_ff D_f = -Q_fp D_p.
  const Index nf = Index(free.vertices.size());
  std::vector<Eigen::Triplet<double>> triplets;
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(nf, 2);
  for (Index col = 0; col < Q.outerSize(); ++col)
    for (Eigen::SparseMatrix<double>::InnerIterator it(Q, col); it; ++it) {
      const Index row = free.slot[it.row()];
      if (row < 0) continue;
      const Index c = free.slot[col];
      if (c >= 0) {
        if (c <= row) triplets.emplace_back(row, c, it.value());
      } else {
        rhs.row(row) -= it.value() * (targets.row(col) - start.row(col));
      }
    }
  Eigen::SparseMatrix<double> A(nf, nf);
  A.setFromTriplets(triplets.begin(), triplets.end());
  Eigen::SimplicialLLT<Eigen::SparseMatrix<double>, Eigen::Lower, FillReducingOrdering<int>> llt(A);
  PM_REQUIRE(llt.info() == Eigen::Success, DisconnectedError,
             "the pin blending system is singular: a part of the mesh holds no pin");
  const Eigen::MatrixXd D = llt.solve(rhs);
  for (Index v : free.vertices) out.row(v) += D.row(free.slot[v]);
  return out;
}

MatrixX2d tutte_map(const TriMesh& mesh) {
  const std::vector<Index>& loop = longest_loop(mesh);
  const MatrixX3d& V = mesh.V();
  std::vector<double> cumulative{0.0};
  for (std::size_t k = 0; k < loop.size(); ++k)
    cumulative.push_back(cumulative.back() +
                         (V.row(loop[(k + 1) % loop.size()]) - V.row(loop[k])).norm());
  MatrixX2d X = MatrixX2d::Zero(mesh.num_vertices(), 2);
  std::vector<char> pinned(mesh.num_vertices(), 0);
  for (std::size_t k = 0; k < loop.size(); ++k) {
    const double angle = 2.0 * M_PI * cumulative[k] / cumulative.back();
    X.row(loop[k]) << std::cos(angle), std::sin(angle);
    pinned[loop[k]] = 1;
  }
  return harmonic_fill(mesh, clamped_cotangent_weights(mesh), pinned, std::move(X));
}

MatrixX2d lscm_map(const TriMesh& mesh) {
  const std::vector<Index>& loop = longest_loop(mesh);
  const MatrixX3d& V = mesh.V();
  // Two far-apart boundary vertices (two sweeps of "farthest from").
  auto farthest = [&](Index from) {
    return *std::max_element(loop.begin(), loop.end(), [&](Index a, Index b) {
      return (V.row(a) - V.row(from)).squaredNorm() < (V.row(b) - V.row(from)).squaredNorm();
    });
  };
  const Index a = farthest(loop.front());
  const Index b = farthest(a);
  const double distance = (V.row(a) - V.row(b)).norm();

  // Unknowns x = (u, v) of the non-pinned vertices, interleaved so the
  // ordering sees the mesh graph; Q = [[L, -B], [-Bᵀ, L]] in (u; v) blocks,
  // B from the signed area of every boundary loop (½ Σ u_i v_j - u_j v_i).
  const Index n = mesh.num_vertices();
  std::vector<Index> slot(n, -1);
  Index free_count = 0;
  for (Index v = 0; v < n; ++v)
    if (v != a && v != b) slot[v] = free_count++;
  Eigen::Vector2d pin_a(0.0, 0.0), pin_b(distance, 0.0);
  auto pinned_value = [&](Index v, int c) { return v == a ? pin_a[c] : pin_b[c]; };

  // True (unclamped) cotangents: the conformal energy is exact, so a flat
  // mesh maps to itself; positivity is not needed for a start that untangling
  // may repair.
  const VectorXd w = clamped_cotangent_weights(mesh, 1e-9, 180.0 - 1e-9);
  const Csr& nbr = mesh.vertex_neighbors();
  const Csr& nbr_edges = mesh.vertex_neighbor_edges();
  std::vector<Eigen::Triplet<double>> triplets;
  VectorXd rhs = VectorXd::Zero(2 * free_count);
  // Adds q * x_row * x_col (row, col: vertex, component) to ½ xᵀQx's gradient system.
  auto add = [&](Index vr, int cr, Index vc, int cc, double q) {
    if (slot[vr] < 0) return;
    const Index row = 2 * slot[vr] + cr;
    if (slot[vc] >= 0)
      triplets.emplace_back(row, 2 * slot[vc] + cc, q);
    else
      rhs[row] -= q * pinned_value(vc, cc);
  };
  for (Index v = 0; v < n; ++v) {
    double degree = 0.0;
    for (Index k = nbr.begin(v); k < nbr.end(v); ++k) {
      const double wk = w[nbr_edges.items[k]];
      degree += wk;
      for (int c = 0; c < 2; ++c) add(v, c, nbr.items[k], c, -wk);
    }
    for (int c = 0; c < 2; ++c) add(v, c, v, c, degree);
  }
  for (const auto& boundary : mesh.boundary_loops())
    for (std::size_t k = 0; k < boundary.size(); ++k) {
      const Index i = boundary[k], j = boundary[(k + 1) % boundary.size()];
      // Area ½(u_i v_j - u_j v_i): symmetric Hessian entries ±½ between (u_i, v_j), (u_j, v_i).
      add(i, 0, j, 1, -0.5);
      add(j, 1, i, 0, -0.5);
      add(j, 0, i, 1, 0.5);
      add(i, 1, j, 0, 0.5);
    }
  Eigen::SparseMatrix<double> Q(2 * free_count, 2 * free_count);
  Q.setFromTriplets(triplets.begin(), triplets.end());
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>, Eigen::Lower, FillReducingOrdering<int>> solver(Q);
  PM_REQUIRE(solver.info() == Eigen::Success, DisconnectedError,
             "the conformal map system is singular (is the mesh connected?)");
  const VectorXd x = solver.solve(rhs);
  MatrixX2d X(n, 2);
  for (Index v = 0; v < n; ++v) {
    if (slot[v] >= 0)
      X.row(v) << x[2 * slot[v]], x[2 * slot[v] + 1];
    else
      X.row(v) = (v == a ? pin_a : pin_b).transpose();
  }
  return X;
}

}  // namespace paramorph::planar
