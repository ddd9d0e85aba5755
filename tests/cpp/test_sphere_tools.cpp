// The sphere-map tools the morph's correspondence is built from
// (param/spherical: isometric_sphere_map, balanced_sphere_map,
// map_through_proxy, untangle_sphere_map, smooth_sphere_map,
// relax_sphere_map) and the mesh helpers beside them (mesh/simplify,
// mesh/gaussian_curvature, mesh/edge_path_distances, mesh/signed_volume).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include <Eigen/Geometry>

#include "common/errors.h"
#include "mesh/edge_path_distances.h"
#include "mesh/gaussian_curvature.h"
#include "mesh/signed_volume.h"
#include "mesh/simplify.h"
#include "mesh/validate.h"
#include "param/spherical/balanced_sphere_map.h"
#include "param/spherical/isometric_sphere_map.h"
#include "param/spherical/map_through_proxy.h"
#include "param/spherical/relax_sphere_map.h"
#include "param/spherical/smooth_sphere_map.h"
#include "param/spherical/sphere_map.h"
#include "param/spherical/untangle_sphere_map.h"
#include "test_meshes.h"

using namespace paramorph;
using namespace paramorph::spherical;

namespace {

VectorXd triples(const MatrixX3d& X, const MatrixX3i& F) {
  VectorXd d(F.rows());
  for (Index f = 0; f < F.rows(); ++f) d[f] = X.row(F(f, 0)).dot(X.row(F(f, 1)).cross(X.row(F(f, 2))));
  return d;
}

/// An icosphere stretched along x: a long shape whose conformal sphere map
/// squeezes both ends by orders of magnitude.
std::pair<MatrixX3d, MatrixX3i> cigar(int levels, double length) {
  std::pair<MatrixX3d, MatrixX3i> mesh = test_meshes::icosphere(levels);
  mesh.first.col(0) *= length;
  return mesh;
}

}  // namespace

TEST(IsometricSphereMap, GradientMatchesFiniteDifferences) {
  auto [V, F] = test_meshes::lumpy_blob(1);
  MatrixX3d X = V.rowwise().normalized();
  const IsometricSphereRest rest = isometric_sphere_rest(V, F);
  MatrixX3d gradient;
  const double E = isometric_sphere_energy(rest, F, X, &gradient);
  ASSERT_TRUE(std::isfinite(E));
  std::mt19937 rng(3);
  std::uniform_int_distribution<Index> pick(0, V.rows() - 1);
  for (int trial = 0; trial < 12; ++trial) {
    const Index v = pick(rng);
    for (int d = 0; d < 3; ++d) {
      const double h = 1e-6;
      MatrixX3d plus = X, minus = X;
      plus(v, d) += h;
      minus(v, d) -= h;
      const double fd = (isometric_sphere_energy(rest, F, plus) - isometric_sphere_energy(rest, F, minus)) / (2 * h);
      EXPECT_NEAR(gradient(v, d), fd, 1e-5 * (1 + std::abs(fd))) << "vertex " << v << " coordinate " << d;
    }
  }
  // A face turned over has no finite energy.
  MatrixX3d turned = X;
  turned.row(F(0, 0)).swap(turned.row(F(0, 1)));
  EXPECT_EQ(isometric_sphere_energy(rest, F, turned), std::numeric_limits<double>::infinity());
}

TEST(IsometricSphereMap, LowersTheEnergyAndNeverFolds) {
  auto [V, F] = cigar(2, 3.0);
  const MatrixX3d start = V.rowwise().normalized();  // radial: fold-free for an ellipsoid
  ASSERT_GT(triples(start, F).minCoeff(), 0);
  const IsometricSphereResult r = isometric_sphere_map(V, F, start);
  EXPECT_LT(r.energy, r.start_energy);
  EXPECT_GT(triples(r.positions, F).minCoeff(), 0);
  for (Index v = 0; v < V.rows(); ++v) EXPECT_NEAR(r.positions.row(v).norm(), 1.0, 1e-12);
}

TEST(IsometricSphereMap, FixedVerticesStayBitForBit) {
  auto [V, F] = cigar(2, 2.0);
  const MatrixX3d start = V.rowwise().normalized();
  IsometricSphereOptions o;
  o.fixed = {0, 5, 17};
  const IsometricSphereResult r = isometric_sphere_map(V, F, start, o);
  for (const Index v : o.fixed) EXPECT_TRUE((r.positions.row(v).array() == start.row(v).array()).all());
  EXPECT_GT(r.steps, 0);
}

/// The spread of sphere area over surface area across the faces: the 99th
/// over the 1st percentile.
double area_spread(const MatrixX3d& V, const MatrixX3i& F, const MatrixX3d& X) {
  std::vector<double> ratio;
  const VectorXd det = triples(X, F);
  for (Index f = 0; f < F.rows(); ++f)
    ratio.push_back(det[f] / (V.row(F(f, 1)) - V.row(F(f, 0))).cross(V.row(F(f, 2)) - V.row(F(f, 0))).norm());
  std::sort(ratio.begin(), ratio.end());
  return ratio[ratio.size() * 99 / 100] / ratio[ratio.size() / 100];
}

TEST(BalancedSphereMap, AFoldFreeMapWhoseFacesTrackTheSurface) {
  auto [V, F] = cigar(4, 6.0);  // 5120 faces
  const MatrixX3d conformal = sphere_map(V, F).positions;
  const BalancedSphereResult balanced = balanced_sphere_map(V, F);
  EXPECT_GE(balanced.levels, 8);  // 4 vertices doubled up to 2562
  EXPECT_LE(balanced.energy, balanced.start_energy);
  EXPECT_GT(triples(balanced.positions, F).minCoeff(), 0);
  // Each part takes a share of the sphere close to its share of the surface:
  // far closer than in the conformal map, which squeezes the ends.
  EXPECT_LT(1.5 * area_spread(V, F, balanced.positions), area_spread(V, F, conformal));
}

TEST(MapThroughProxy, TheModelOnItsProxysMapIsUntangledAndRelaxed) {
  auto [V, F] = cigar(4, 3.0);
  const SimplifiedMesh proxy = simplify(V, F, 600);
  const MatrixX3d proxy_map = balanced_sphere_map(proxy.V, proxy.F).positions;
  MatrixX3d X = map_through_proxy(V, proxy.V, proxy.F, proxy_map);
  const std::vector<char> none(std::size_t(V.rows()), 0);
  const SphereUntangleResult u = untangle_sphere_map(V, F, X, none);
  EXPECT_EQ(u.folded, 0);
  EXPECT_GT(triples(X, F).minCoeff(), 0);
  const RelaxPoorResult r = relax_poor_regions(V, F, X, none);
  EXPECT_LE(r.worst_after, r.worst_before + 1e-9);
  EXPECT_GT(triples(X, F).minCoeff(), 0);
}

TEST(UntangleSphereMap, RepairsFoldsAndKeepsFixedVertices) {
  auto [V, F] = test_meshes::icosphere(3);
  MatrixX3d X = V.rowwise().normalized();
  // Push one vertex across its neighbours: its faces fold.
  const Index v = 100;
  std::vector<char> fixed(std::size_t(V.rows()), 0);
  fixed[7] = 1;
  const TriMesh mesh(V, F);
  const Csr& ring = mesh.vertex_neighbors();
  const Eigen::RowVector3d across = X.row(ring.items[ring.begin(v)]);
  X.row(v) = (X.row(v) + 2.5 * (across - X.row(v))).normalized();
  const Eigen::RowVector3d kept = X.row(7);
  ASSERT_LT(triples(X, F).minCoeff(), 0);
  const SphereUntangleResult r = untangle_sphere_map(V, F, X, fixed);
  EXPECT_GT(r.folded_before, 0);
  EXPECT_EQ(r.folded, 0);
  EXPECT_GT(triples(X, F).minCoeff(), 0);
  EXPECT_TRUE((X.row(7).array() == kept.array()).all());
}

TEST(SmoothSphereMap, ThickensASliverAndNeverFolds) {
  auto [V, F] = test_meshes::icosphere(3);
  MatrixX3d X = V.rowwise().normalized();
  const TriMesh mesh(V, F);
  // Squash face 0: its first corner moved almost onto the opposite edge.
  const Eigen::RowVector3d a = X.row(F(0, 1)), b = X.row(F(0, 2));
  X.row(F(0, 0)) = (X.row(F(0, 0)) + 0.97 * (0.5 * (a + b) - X.row(F(0, 0)))).normalized();
  const VectorXd before = triples(X, F);
  ASSERT_GT(before.minCoeff(), 0);
  smooth_sphere_map(mesh, X, vertices_near_faces(mesh, {0}, 1), {}, 3);
  const VectorXd after = triples(X, F);
  EXPECT_GT(after.minCoeff(), 0);
  EXPECT_GT(after.minCoeff(), 2 * before.minCoeff());
}

TEST(Simplify, KeepsTheTopologyAndMapsEveryVertex) {
  auto [V, F] = test_meshes::lumpy_blob(4);
  const SimplifiedMesh s = simplify(V, F, 500);
  EXPECT_LE(s.F.rows(), 502);
  EXPECT_GE(s.F.rows(), 400);
  const MeshReport report = validate(TriMesh(s.V, s.F));
  EXPECT_TRUE(report.is_closed_genus0);
  ASSERT_EQ(s.proxy_of.size(), V.rows());
  EXPECT_GE(s.proxy_of.minCoeff(), 0);
  EXPECT_LT(s.proxy_of.maxCoeff(), s.V.rows());
  EXPECT_GT(signed_volume(s.V, s.F), 0);  // orientation kept
  // Small enough already: returned as it is.
  const SimplifiedMesh same = simplify(V, F, Index(F.rows()));
  EXPECT_TRUE(same.F == F);
}

TEST(MeshQuantities, GaussianCurvatureIntegratesToFourPiAndDistancesGrow) {
  auto [V, F] = test_meshes::lumpy_blob(3);
  const TriMesh mesh(V, F);
  const VectorXd K = smoothed_gaussian_curvature(mesh, 0);
  VectorXd area = VectorXd::Zero(V.rows());
  for (Index f = 0; f < F.rows(); ++f) {
    const double a = 0.5 * (V.row(F(f, 1)) - V.row(F(f, 0))).cross(V.row(F(f, 2)) - V.row(F(f, 0))).norm();
    for (int k = 0; k < 3; ++k) area[F(f, k)] += a / 3;
  }
  EXPECT_NEAR(K.dot(area), 4 * M_PI, 1e-9);  // Gauss-Bonnet, exact for angle defects
  const VectorXd smooth = smoothed_gaussian_curvature(mesh, 5);
  EXPECT_LT((smooth.array() - smooth.mean()).abs().maxCoeff(), (K.array() - K.mean()).abs().maxCoeff());
  const VectorXd d = edge_path_distances(mesh, {0});
  EXPECT_EQ(d[0], 0);
  EXPECT_GT(d.maxCoeff(), (V.row(0) - V.colwise().mean()).norm());
  EXPECT_THROW(edge_path_distances(mesh, {Index(V.rows())}), InvalidInputError);
  // Inside-out: the enclosed volume turns negative.
  MatrixX3i turned = F;
  turned.col(1).swap(turned.col(2));
  EXPECT_NEAR(signed_volume(V, turned), -signed_volume(V, F), 1e-12);
}
