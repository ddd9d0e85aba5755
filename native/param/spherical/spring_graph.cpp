#include "param/spherical/spring_graph.h"

#include <Eigen/Dense>
#include <cmath>

#include "common/errors.h"
#include "common/parallel.h"
#include "mesh/cotangent_weights.h"

namespace paramorph::spherical {

Weights parse_weights(const std::string& name) {
  if (name == "conformal") return Weights::Conformal;
  if (name == "barycentric") return Weights::Barycentric;
  throw InvalidInputError("weights must be \"conformal\" or \"barycentric\", got \"" + name + "\"");
}

std::string to_string(Weights weights) {
  return weights == Weights::Conformal ? "conformal" : "barycentric";
}

VectorXd edge_weights(const TriMesh& mesh, Weights kind, double min_angle_degrees,
                      double max_angle_degrees) {
  if (kind == Weights::Barycentric) return VectorXd::Ones(mesh.edges().rows());
  return clamped_cotangent_weights(mesh, min_angle_degrees, max_angle_degrees);
}

SpringGraph build_spring_graph(const TriMesh& mesh, const VectorXd& edge_weights) {
  const Csr& nbr = mesh.vertex_neighbors();
  const Csr& nbr_edges = mesh.vertex_neighbor_edges();
  SpringGraph g;
  g.offsets = nbr.offsets;
  g.neighbors = nbr.items;
  g.weights.resize(nbr.items.size());
  g.degree = VectorXd::Zero(mesh.num_vertices());
  for (Index i = 0; i < mesh.num_vertices(); ++i) {
    double d = 0.0;
    for (Index k = nbr.begin(i); k < nbr.end(i); ++k) {
      g.weights[k] = edge_weights[nbr_edges.items[k]];
      d += g.weights[k];
    }
    g.degree[i] = d;
  }
  return g;
}

void SpringGraph::apply(const MatrixX3d& u, MatrixX3d& out) const {
  const Index n = num_vertices();
  out.resize(n, 3);
#pragma omp parallel for schedule(static) if (worth_parallel(n))
  for (Index i = 0; i < n; ++i) {
    double sx = 0, sy = 0, sz = 0;
    for (Index k = offsets[i]; k < offsets[i + 1]; ++k) {
      const Index j = neighbors[k];
      const double w = weights[k];
      sx += w * u(j, 0);
      sy += w * u(j, 1);
      sz += w * u(j, 2);
    }
    const double d = degree[i];
    out(i, 0) = d * u(i, 0) - sx;
    out(i, 1) = d * u(i, 1) - sy;
    out(i, 2) = d * u(i, 2) - sz;
  }
}

double SpringGraph::energy(const MatrixX3d& u) const {
  const Index n = num_vertices();
  // Rows in parallel, summed in order: the same energy on every run (the
  // outer loop's stopping test compares energies).
  VectorXd row_energy(n);
#pragma omp parallel for schedule(static) if (worth_parallel(n))
  for (Index i = 0; i < n; ++i) {
    double e = 0.0;
    for (Index k = offsets[i]; k < offsets[i + 1]; ++k) {
      const Index j = neighbors[k];
      if (j > i) e += weights[k] * (u.row(i) - u.row(j)).squaredNorm();
    }
    row_energy[i] = e;
  }
  return 0.5 * row_energy.sum();
}

Eigen::SparseMatrix<double> SpringGraph::matrix(double diagonal_shift) const {
  const Index n = num_vertices();
  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(neighbors.size() + n);
  for (Index i = 0; i < n; ++i) {
    triplets.emplace_back(i, i, degree[i] * (1.0 + diagonal_shift));
    for (Index k = offsets[i]; k < offsets[i + 1]; ++k)
      triplets.emplace_back(i, neighbors[k], -weights[k]);
  }
  Eigen::SparseMatrix<double> L(n, n);
  L.setFromTriplets(triplets.begin(), triplets.end());
  return L;
}

}  // namespace paramorph::spherical
