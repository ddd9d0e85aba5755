// Internals of the spherical solver (param/spherical): weights, Laplacian,
// starting maps, Möbius balancing, Proposition 3.1, inner solvers.
#include <gtest/gtest.h>

#include "mesh/reorder.h"
#include "mesh/tri_mesh.h"
#include "param/spherical/initial_map.h"
#include "param/spherical/saddle_point.h"
#include "param/spherical/sphere_kernels.h"
#include "param/spherical/sphere_map.h"
#include "param/spherical/sphere_quality.h"
#include "param/spherical/spring_graph.h"
#include "test_meshes.h"

using namespace paramorph;
using namespace paramorph::spherical;

TEST(SpringGraph, ConformalWeightsArePositiveAndRowsSumToZero) {
  auto [V, F] = test_meshes::lumpy_blob(2);
  const TriMesh mesh(V, F);
  for (Weights kind : {Weights::Conformal, Weights::Barycentric}) {
    const VectorXd w = edge_weights(mesh, kind);
    EXPECT_GT(w.minCoeff(), 0.0);
    const SpringGraph g = build_spring_graph(mesh, w);
    MatrixX3d ones = MatrixX3d::Ones(mesh.num_vertices(), 3), out;
    g.apply(ones, out);
    EXPECT_LT(out.cwiseAbs().maxCoeff(), 1e-12);
    const auto L = g.matrix();
    EXPECT_LT((Eigen::SparseMatrix<double>(L.transpose()) - L).norm(), 1e-12);
  }
}

TEST(SpringGraph, ClampedCotangentWeightsMatchTheFormulaOnAnEquilateralMesh) {
  // Equilateral icosahedron: every angle is 60°, so w = cot 60° (two halves).
  auto [V, F] = test_meshes::icosphere(0);
  const TriMesh mesh(V, F);
  const VectorXd w = edge_weights(mesh, Weights::Conformal);
  EXPECT_NEAR(w.minCoeff(), 1.0 / std::sqrt(3.0), 1e-12);
  EXPECT_NEAR(w.maxCoeff(), 1.0 / std::sqrt(3.0), 1e-12);
}

TEST(InitialMap, StereographicTutteIsFoldFreeOnTheSphere) {
  auto [V, F] = test_meshes::lumpy_blob(3);
  const TriMesh mesh(V, F);
  for (Weights kind : {Weights::Conformal, Weights::Barycentric}) {
    const SpringGraph g = build_spring_graph(mesh, edge_weights(mesh, kind));
    MatrixX3d X = stereographic_tutte_map(mesh, g, *factor_punctured_laplacian(mesh, g));
    EXPECT_LT((X.rowwise().norm().array() - 1.0).abs().maxCoeff(), 1e-12);
    EXPECT_TRUE(flipped_faces(X, F).empty());
  }
}

TEST(InitialMap, MobiusCenteringMovesTheCentroidToTheOrigin) {
  auto [V, F] = test_meshes::lumpy_blob(3);
  const TriMesh mesh(V, F);
  const SpringGraph g = build_spring_graph(mesh, edge_weights(mesh, Weights::Conformal));
  MatrixX3d X = stereographic_tutte_map(mesh, g, *factor_punctured_laplacian(mesh, g));
  const VectorXd w = vertex_areas(mesh);
  const double before = ((w.transpose() * X) / w.sum()).norm();
  const double after = mobius_center(X, F, w);
  EXPECT_LT(after, before);
  EXPECT_LT(((w.transpose() * X) / w.sum()).norm(), 1e-6);
  EXPECT_TRUE(flipped_faces(X, F).empty());
}

TEST(InitialMap, CentroidRelaxationUnfoldsTheRadialProjection) {
  // The radial projection of a non-star-shaped blob folds; relaxation (4.3.2) repairs it.
  auto [V, F] = test_meshes::lumpy_blob(3);
  for (Index i = 0; i < V.rows(); ++i)
    if (V(i, 0) > 0.3) V(i, 0) = 0.3 - 0.5 * (V(i, 0) - 0.3);  // dent: not star-shaped
  const TriMesh mesh(V, F);
  MatrixX3d X = radial_projection(mesh);
  ASSERT_FALSE(flipped_faces(X, F).empty()) << "the test needs a folded start";
  const int sweeps = centroid_relaxation(mesh, X, 5000);
  EXPECT_LT(sweeps, 5000);
  EXPECT_TRUE(flipped_faces(X, F).empty());
}

TEST(Orientation, DetectsAFoldedTriangle) {
  const Eigen::Vector3d a(1, 0, 0), b(0, 1, 0), c(0, 0, 1);
  EXPECT_GT(sphere_orientation(a, b, c), 0.0);
  EXPECT_LT(sphere_orientation(a, c, b), 0.0);
  EXPECT_EQ(sphere_orientation(a, a, b), 0.0);
}

TEST(Proposition31, RenormalisingPointsOutsideTheSphereDoesNotRaiseTheEnergy) {
  auto [V, F] = test_meshes::lumpy_blob(2);
  const TriMesh mesh(V, F);
  const SpringGraph g = build_spring_graph(mesh, edge_weights(mesh, Weights::Conformal));
  MatrixX3d U = V;
  for (Index i = 0; i < U.rows(); ++i) U.row(i) *= (1.0 + 0.5 * std::abs(std::sin(i))) / U.row(i).norm();
  MatrixX3d X = U;
  X.rowwise().normalize();
  EXPECT_LE(g.energy(X), g.energy(U));
}

TEST(InnerSolvers, PcgCholeskyAndJacobiReachTheSameSaddlePoint) {
  auto [V, F] = test_meshes::lumpy_blob(2);
  const TriMesh mesh(V, F);
  const SpringGraph g = build_spring_graph(mesh, edge_weights(mesh, Weights::Conformal));
  MatrixX3d X = stereographic_tutte_map(mesh, g, *factor_punctured_laplacian(mesh, g));
  auto laplacian = factor_punctured_laplacian(mesh, g);
  auto kernels = make_cpu_kernels(g, F);
  InnerOptions o;
  o.tol = 1e-10;
  MatrixX3d reference;
  TangentPlaneSolver cholesky(g, InnerSolver::Cholesky, *kernels);
  const InnerResult rc = cholesky.solve(X, reference, o);
  EXPECT_LE(rc.residual, 1e-10);
  for (InnerSolver kind : {InnerSolver::Pcg, InnerSolver::Jacobi}) {
    TangentPlaneSolver solver(g, kind, *kernels, laplacian);
    MatrixX3d u;
    const InnerResult r = solver.solve(X, u, o);
    EXPECT_TRUE(r.converged) << to_string(kind);
    EXPECT_LT((u - reference).cwiseAbs().maxCoeff(), 1e-7) << to_string(kind);
    // The tangent-plane constraint x_i · u_i = 1 holds exactly.
    EXPECT_LT(((X.array() * u.array()).rowwise().sum() - 1.0).abs().maxCoeff(), 1e-12);
  }
}

TEST(Reordering, RoundTripsAndKeepsFaceOrientation) {
  auto [V, F] = test_meshes::lumpy_blob(2);
  const Reordering order = locality_order(V, F);
  const MatrixX3d V2 = order.apply_to_vertices(V);
  const MatrixX3i F2 = order.apply_to_faces(F);
  EXPECT_EQ((order.restore_vertices(V2) - V).cwiseAbs().maxCoeff(), 0.0);
  for (Index f = 0; f < F2.rows(); ++f) {
    const Index old = order.new_to_old_face[f];
    for (int k = 0; k < 3; ++k)  // same corners in the same cyclic order
      EXPECT_EQ(order.new_to_old_vertex[F2(f, k)], F(old, k));
  }
}

TEST(SphereMap, FoldFreeWithAndWithoutReordering) {
  auto [V, F] = test_meshes::lumpy_blob(3);
  for (bool reorder : {true, false}) {
    SphereMapOptions o;
    o.backend = compute::Backend::Cpu;
    o.reorder = reorder;
    const auto r = sphere_map(V, F, o);
    EXPECT_EQ(r.flipped, 0);
    EXPECT_TRUE(flipped_faces(r.positions, F).empty());  // input order restored
    EXPECT_LE(r.residual, o.tol);
  }
}

TEST(SphereMap, OpenClAndCpuBackendsAgree) {
  if (!compute::default_device()) GTEST_SKIP() << compute::default_device_error();
  auto [V, F] = test_meshes::lumpy_blob(4);
  for (InnerSolver solver : {InnerSolver::Pcg, InnerSolver::Jacobi}) {
    SphereMapOptions o;
    o.solver = solver;
    o.backend = compute::Backend::Cpu;
    const auto cpu = sphere_map(V, F, o);
    o.backend = compute::Backend::OpenCL;
    const auto ocl = sphere_map(V, F, o);
    EXPECT_EQ(ocl.backend, "opencl");
    EXPECT_EQ(ocl.flipped, 0);
    EXPECT_LE(ocl.residual, o.tol);
    const VectorXd cosines = (cpu.positions.array() * ocl.positions.array()).rowwise().sum();
    EXPECT_GT(cosines.minCoeff(), std::cos(1e-5)) << to_string(solver) << " on " << ocl.device;
  }
}
