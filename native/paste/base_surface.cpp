#include "paste/base_surface.h"

#include <Eigen/Geometry>
#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>

#include "common/errors.h"
#include "common/supernodal_cholesky.h"
#include "mesh/cotangent_weights.h"

namespace paramorph::paste {

MatrixX3d base_surface(const TriMesh& mesh, const SelectionPatch& patch) {
  const Index nv = mesh.num_vertices();
  const Index ns = Index(patch.vertices.size());
  MatrixX3d base(ns, 3);
  for (Index i = 0; i < ns; ++i) base.row(i) = mesh.V().row(patch.vertices[i]);

  std::vector<char> on_boundary(ns, 0);
  for (const auto& loop : patch.boundary_loops)
    for (Index v : loop) on_boundary[v] = 1;
  // Unknowns: the selection's interior vertices, numbered 0..nu.
  std::vector<Index> unknown(ns, -1);
  Index nu = 0;
  for (Index i = 0; i < ns; ++i)
    if (!on_boundary[i]) unknown[i] = nu++;
  if (nu == 0) return base;

  // The extended patch: selection + ring, vertices renumbered (selection first).
  std::vector<Index> ext(nv, -1);
  std::vector<Index> ext_vertices(patch.vertices.data(), patch.vertices.data() + ns);
  for (Index i = 0; i < ns; ++i) ext[patch.vertices[i]] = i;
  const Index nsel = Index(patch.faces.size()), nring = Index(patch.ring_faces.size());
  MatrixX3i FE(nsel + nring, 3);
  for (Index f = 0; f < nsel + nring; ++f) {
    const Index src = f < nsel ? patch.faces[f] : patch.ring_faces[f - nsel];
    for (int k = 0; k < 3; ++k) {
      const Index v = mesh.F()(src, k);
      if (ext[v] < 0) ext[v] = Index(ext_vertices.size()), ext_vertices.push_back(v);
      FE(f, k) = ext[v];
    }
  }
  const Index ne = Index(ext_vertices.size());
  MatrixX3d VE(ne, 3);
  for (Index i = 0; i < ne; ++i) VE.row(i) = mesh.V().row(ext_vertices[i]);
  const TriMesh extended(VE, FE);
  const VectorXd w = clamped_cotangent_weights(extended);
  const MatrixX2i& E = extended.edges();
  VectorXd area = VectorXd::Zero(ne);
  for (Index f = 0; f < Index(FE.rows()); ++f) {
    const Eigen::Vector3d a = VE.row(FE(f, 0)), b = VE.row(FE(f, 1)), c = VE.row(FE(f, 2));
    const double third = (b - a).cross(c - a).norm() / 6.0;
    for (int k = 0; k < 3; ++k) area[FE(f, k)] += third;
  }

  // A = the selection's rows of L (ns by ne), split into unknown columns A_u
  // and known columns A_k; minimise |M^-1/2 (A_u x_u + A_k x_k)|².
  using Sparse = Eigen::SparseMatrix<double>;
  std::vector<Eigen::Triplet<double>> tu, tk;
  auto add = [&](Index row, Index col, double value) {
    if (row >= ns) return;  // ring vertices' own rows are not in the energy
    if (col < ns && unknown[col] >= 0)
      tu.emplace_back(row, unknown[col], value);
    else
      tk.emplace_back(row, col, value);
  };
  for (Index e = 0; e < Index(E.rows()); ++e) {
    const Index a = E(e, 0), b = E(e, 1);
    if (a == b) continue;
    add(a, b, w[e]), add(b, a, w[e]);
    add(a, a, -w[e]), add(b, b, -w[e]);
  }
  Sparse Au(ns, nu), Ak(ns, ne);
  Au.setFromTriplets(tu.begin(), tu.end());
  Ak.setFromTriplets(tk.begin(), tk.end());
  VectorXd inv_mass(ns);
  for (Index i = 0; i < ns; ++i) inv_mass[i] = 1.0 / area[i];
  const Sparse WAu = inv_mass.asDiagonal() * Au;
  const Sparse Q = Sparse(Au.transpose()) * WAu;
  MatrixX3d known = MatrixX3d::Zero(ne, 3);
  for (Index i = 0; i < ne; ++i)
    if (i >= ns || unknown[i] < 0) known.row(i) = VE.row(i);
  const Eigen::MatrixXd rhs = -(Sparse(WAu.transpose()) * (Ak * known));
  // CHOLMOD's supernodal Cholesky (BLAS 3): the thin-plate matrix has two
  // rings of fill per row, and Eigen's simplicial LDLT spent 3 s, without a
  // chance to report progress, on an 80 % selection of an 82k-face mesh.
  const SupernodalCholesky<Sparse> solver(Q);
  PM_REQUIRE(solver.info() == Eigen::Success, ConstraintError,
             "the base surface's thin-plate system is singular (degenerate selection)");
  const Eigen::MatrixXd x = solver.solve(rhs);
  PM_REQUIRE(solver.info() == Eigen::Success && x.allFinite(), ConstraintError,
             "the base surface's thin-plate solve failed");
  for (Index i = 0; i < ns; ++i)
    if (unknown[i] >= 0) base.row(i) = x.row(unknown[i]);
  return base;
}

}  // namespace paramorph::paste
