// Uniform Loop refinement of a mesh region (paste/refine_region, thesis 5.2):
// watertight stitching, unchanged outside, flat positions on their base faces,
// limit positions and normals of the whole mesh, typed errors.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <random>
#include <set>

#include "common/errors.h"
#include "mesh/tri_mesh.h"
#include "mesh/validate.h"
#include "paste/refine_region.h"
#include "test_meshes.h"

using namespace paramorph;
using namespace paramorph::paste;

namespace {

/// Faces whose centroid has z above `height` (a cap of a sphere).
std::vector<Index> cap(const MatrixX3d& V, const MatrixX3i& F, double height) {
  std::vector<Index> region;
  for (Index f = 0; f < Index(F.rows()); ++f)
    if ((V.row(F(f, 0)) + V.row(F(f, 1)) + V.row(F(f, 2)))(2) / 3 > height) region.push_back(f);
  return region;
}

/// A scattered random set: its neighbours have 1, 2 and 3 split edges.
std::vector<Index> scattered(Index faces, unsigned seed, double fraction) {
  std::mt19937 rng(seed);
  std::bernoulli_distribution pick(fraction);
  std::vector<Index> region;
  for (Index f = 0; f < faces; ++f)
    if (pick(rng)) region.push_back(f);
  return region;
}

/// A flat (n+1)^2 grid over [0, 1]^2 in the plane z = 0.
std::pair<MatrixX3d, MatrixX3i> plane(int n) {
  auto [V, F] = test_meshes::bumpy_grid(n);
  V.col(2).setZero();
  return {V, F};
}

/// The invariants every result keeps, whatever the mesh and region.
void check_result(const MatrixX3d& V, const MatrixX3i& F, const std::vector<Index>& region, int level,
                  const RefinedRegion& r) {
  const Index nv = Index(V.rows()), n = Index(r.V.rows());
  ASSERT_EQ(r.base_face.size(), n);
  ASSERT_EQ(r.bary.rows(), n);
  ASSERT_EQ(r.limit.rows(), n);
  ASSERT_EQ(r.limit_normal.rows(), n);
  ASSERT_EQ(r.region_interior.size(), n);
  // Original vertices unchanged, in their order.
  EXPECT_EQ(r.V.topRows(nv), V);
  // Topology: same Euler characteristic and boundary loops, manifold, oriented.
  const MeshReport before = validate(TriMesh(V, F)), after = validate(TriMesh(r.V, r.F));
  EXPECT_EQ(after.euler_characteristic, before.euler_characteristic);
  EXPECT_EQ(after.boundary_loops, before.boundary_loops);
  EXPECT_TRUE(after.non_manifold_edges.empty());  // every edge has 1 or 2 faces
  EXPECT_TRUE(after.non_manifold_vertices.empty());
  EXPECT_TRUE(after.inconsistent_orientation_edges.empty());
  EXPECT_TRUE(after.degenerate_faces.empty());
  EXPECT_TRUE(after.isolated_vertices.empty());
  // Faces outside the region not touching it by an edge: unchanged and first.
  std::set<Index> in(region.begin(), region.end());
  const TriMesh mesh(V, F);
  std::vector<char> split(mesh.edges().rows(), 0);
  for (const Index f : in)
    for (int k = 0; k < 3; ++k) split[mesh.face_edges()(f, k)] = 1;
  Index row = 0;
  for (Index f = 0; f < Index(F.rows()); ++f) {
    if (in.count(f)) continue;
    if (split[mesh.face_edges()(f, 0)] || split[mesh.face_edges()(f, 1)] || split[mesh.face_edges()(f, 2)])
      continue;
    ASSERT_LT(row, r.F.rows());
    EXPECT_EQ(r.F.row(row), F.row(f)) << "face " << f;
    ++row;
  }
  ASSERT_EQ(r.new_faces.size(), r.F.rows() - row);
  for (Index k = 0; k < r.new_faces.size(); ++k) EXPECT_EQ(r.new_faces(k), row + k);
  // At least 4^level triangles per region face.
  EXPECT_GE(r.new_faces.size(), Index(in.size()) << (2 * level));
  // Every flat position lies on its base face.
  for (Index i = 0; i < n; ++i) {
    const Index f = r.base_face(i);
    ASSERT_GE(f, 0);
    EXPECT_NEAR(r.bary.row(i).sum(), 1.0, 1e-12);
    EXPECT_GE(r.bary.row(i).minCoeff(), -1e-12);
    const Eigen::RowVector3d p =
        r.bary(i, 0) * V.row(F(f, 0)) + r.bary(i, 1) * V.row(F(f, 1)) + r.bary(i, 2) * V.row(F(f, 2));
    EXPECT_LE((p - r.V.row(i)).norm(), 1e-12) << "vertex " << i;
    EXPECT_NEAR(r.limit_normal.row(i).norm(), 1.0, 1e-12);
  }
}

}  // namespace

TEST(RefineRegion, ClosedMeshStaysAClosedManifold) {
  const auto [V, F] = test_meshes::icosphere(2);
  for (int level : {1, 2, 3}) {
    for (const auto& region : {cap(V, F, 0.3), scattered(Index(F.rows()), 1, 0.3)}) {
      const RefinedRegion r = refine_region(V, F, region, level);
      check_result(V, F, region, level, r);
      EXPECT_EQ(validate(TriMesh(r.V, r.F)).boundary_edges, 0);
    }
  }
}

TEST(RefineRegion, OpenPlaneKeepsItsBoundaryAndHasNoTJunctions) {
  const auto [V, F] = plane(6);
  // A region touching the boundary, and a scattered one.
  std::vector<Index> corner_region;
  for (Index f = 0; f < Index(F.rows()); ++f)
    if ((V.row(F(f, 0)) + V.row(F(f, 1)) + V.row(F(f, 2))).maxCoeff() / 3 < 0.45) corner_region.push_back(f);
  for (const auto& region : {corner_region, scattered(Index(F.rows()), 2, 0.35)}) {
    const int level = 2;
    const RefinedRegion r = refine_region(V, F, region, level);
    check_result(V, F, region, level, r);
    // The boundary is the same square: its length is 4.
    const TriMesh out(r.V, r.F);
    EXPECT_EQ(validate(out).boundary_loops, 1);
    double length = 0.0;
    for (const auto& loop : out.boundary_loops())
      for (std::size_t k = 0; k < loop.size(); ++k)
        length += (r.V.row(loop[k]) - r.V.row(loop[(k + 1) % loop.size()])).norm();
    EXPECT_NEAR(length, 4.0, 1e-12);
    // Geometrically: no vertex lies inside an edge of the output.
    Index t_junctions = 0;
    for (Index e = 0; e < Index(out.edges().rows()); ++e) {
      const Eigen::RowVector3d a = r.V.row(out.edges()(e, 0)), b = r.V.row(out.edges()(e, 1));
      const Eigen::RowVector3d d = b - a;
      for (Index i = 0; i < Index(r.V.rows()); ++i) {
        if (i == out.edges()(e, 0) || i == out.edges()(e, 1)) continue;
        const Eigen::RowVector3d p = r.V.row(i) - a;
        const double t = p.dot(d) / d.squaredNorm();
        if (t > 1e-9 && t < 1 - 1e-9 && (p - t * d).norm() < 1e-9 * d.norm()) ++t_junctions;
      }
    }
    EXPECT_EQ(t_junctions, 0);
    // Limit surface of a plane: the plane itself, normal +z.
    EXPECT_LE(r.limit.col(2).cwiseAbs().maxCoeff(), 1e-12);
    for (Index i = 0; i < Index(r.V.rows()); ++i)
      EXPECT_LE((r.limit_normal.row(i) - Eigen::RowVector3d(0, 0, 1)).norm(), 1e-9) << "vertex " << i;
    // Region interior: refined vertices off the rim exist, and none on the square's boundary.
    EXPECT_GT(r.region_interior.sum(), 0);
    for (const auto& loop : out.boundary_loops())
      for (const Index v : loop) EXPECT_EQ(r.region_interior(v), 0);
  }
}

TEST(RefineRegion, LimitOfAnIcosphereIsNearTheSphere) {
  // Loop's limit of the level-3 icosphere shrinks slightly inside the unit
  // sphere (measured 0.67% of the radius): within 1%; its normals are within
  // 1 degree of radial (measured 0.46), while the flat faces' normals are off
  // by several degrees, so the normals really come from the limit surface.
  const auto [V, F] = test_meshes::icosphere(3);
  std::vector<Index> all(F.rows());
  for (Index f = 0; f < Index(F.rows()); ++f) all[f] = f;
  const RefinedRegion r = refine_region(V, F, all, 2);
  check_result(V, F, all, 2, r);
  double worst_radius = 0.0, worst_angle = 0.0, worst_flat_angle = 0.0;
  const auto angle = [](const Eigen::RowVector3d& a, const Eigen::RowVector3d& b) {
    return std::acos(std::min(1.0, a.normalized().dot(b.normalized())));
  };
  for (Index i = 0; i < Index(r.V.rows()); ++i) {
    const Eigen::RowVector3d p = r.limit.row(i);
    worst_radius = std::max(worst_radius, std::abs(p.norm() - 1.0));
    worst_angle = std::max(worst_angle, angle(r.limit_normal.row(i), p));
    const Index f = r.base_face(i);
    const Eigen::RowVector3d face_normal =
        (V.row(F(f, 1)) - V.row(F(f, 0))).cross(V.row(F(f, 2)) - V.row(F(f, 0)));
    worst_flat_angle = std::max(worst_flat_angle, angle(face_normal, r.V.row(i)));
  }
  EXPECT_LE(worst_radius, 0.01);
  EXPECT_LE(worst_angle, M_PI / 180);
  EXPECT_GT(worst_flat_angle, 3 * worst_angle);
  // The limit points are smooth-surface points, not the flat ones.
  EXPECT_GT((r.limit - r.V).rowwise().norm().maxCoeff(), 1e-3);
}

TEST(RefineRegion, LevelZeroReturnsTheInput) {
  const auto [V, F] = test_meshes::icosphere(1);
  const RefinedRegion r = refine_region(V, F, cap(V, F, 0.0), 0);
  EXPECT_EQ(r.V, V);
  EXPECT_EQ(r.F, F);
  EXPECT_EQ(r.new_faces.size(), 0);
  EXPECT_EQ(r.region_interior.sum(), 0);
  for (Index i = 0; i < Index(V.rows()); ++i)
    EXPECT_GT(r.limit_normal.row(i).dot(V.row(i)), 0.99);
  // An empty region is the same at any level.
  const RefinedRegion empty = refine_region(V, F, {}, 3);
  EXPECT_EQ(empty.F, F);
  EXPECT_EQ(empty.V, V);
}

TEST(RefineRegion, TypedErrors) {
  const auto [V, F] = test_meshes::icosphere(1);
  EXPECT_THROW(refine_region(V, F, {0, Index(F.rows())}, 1), InvalidInputError);
  EXPECT_THROW(refine_region(V, F, {-1}, 1), InvalidInputError);
  EXPECT_THROW(refine_region(V, F, {0}, -1), InvalidInputError);
  EXPECT_THROW(refine_region(V, F, {0}, 9), InvalidInputError);
  // A third face on an edge.
  MatrixX3d V2(V.rows() + 1, 3);
  V2 << V, Eigen::RowVector3d(2, 2, 2);
  MatrixX3i F2(F.rows() + 1, 3);
  F2 << F, F(0, 0), F(0, 1), Index(V.rows());
  EXPECT_THROW(refine_region(V2, F2, {0}, 1), NonManifoldError);
  // A face with a repeated index.
  MatrixX3i F3 = F;
  F3(4, 2) = F3(4, 1);
  EXPECT_THROW(refine_region(V, F3, {0}, 1), MeshError);
  // Non-finite coordinates.
  MatrixX3d V4 = V;
  V4(3, 0) = NAN;
  EXPECT_THROW(refine_region(V4, F, {0}, 1), InvalidInputError);
}

// The solver object: one refiner, many regions; each refine() equals the
// one-shot function, replaced_faces lists exactly the rows that left, and
// LimitAt restricts Bfr's work to where the caller needs it.
TEST(RegionRefiner, RepeatedRefinementsMatchTheOneShotFunction) {
  const auto [V, F] = test_meshes::icosphere(3);
  const RegionRefiner refiner(V, F);
  for (const double height : {0.6, 0.2, -0.5}) {
    const std::vector<Index> region = cap(V, F, height);
    const RefinedRegion once = refine_region(V, F, region, 2);
    const RefinedRegion again = refiner.refine(region, 2);
    EXPECT_EQ(again.V, once.V);
    EXPECT_EQ(again.F, once.F);
    EXPECT_EQ(again.limit, once.limit);
    EXPECT_EQ(again.region_interior, once.region_interior);
    // replaced_faces + the untouched rows make up F exactly.
    std::vector<char> replaced(F.rows(), 0);
    for (Index k = 0; k < again.replaced_faces.size(); ++k) replaced[again.replaced_faces(k)] = 1;
    Index row = 0;
    for (Index f = 0; f < Index(F.rows()); ++f)
      if (!replaced[f]) {
        EXPECT_EQ(again.F.row(row++), F.row(f));
      }
    EXPECT_EQ(row, Index(F.rows()) - again.replaced_faces.size());
    EXPECT_EQ(again.new_faces.size(), again.F.rows() - row);

    const RefinedRegion nowhere = refiner.refine(region, 2, LimitAt::Nowhere);
    EXPECT_EQ(nowhere.V, once.V);
    EXPECT_EQ(nowhere.limit, nowhere.V);
    EXPECT_EQ(nowhere.limit_normal.norm(), 0.0);
    const RefinedRegion local = refiner.refine(region, 2, LimitAt::RegionVertices);
    std::vector<char> corner(V.rows(), 0);
    for (const Index f : region)
      for (int k = 0; k < 3; ++k) corner[F(f, k)] = 1;
    for (Index i = 0; i < local.V.rows(); ++i) {
      const bool wanted = i >= V.rows() || corner[i];
      if (wanted) {
        EXPECT_EQ(local.limit.row(i), once.limit.row(i)) << "vertex " << i;
      } else {
        EXPECT_EQ(local.limit.row(i), local.V.row(i)) << "vertex " << i;
      }
    }
  }
}

TEST(RegionRefiner, LimitAtPointsMatchesTheRefinedVertices) {
  const auto [V, F] = test_meshes::icosphere(2);
  const RegionRefiner refiner(V, F);
  const RefinedRegion r = refiner.refine(cap(V, F, 0.3), 3);
  MatrixX3d normals;
  const MatrixX3d P = refiner.limit(r.base_face, r.bary, &normals);
  EXPECT_LE((P - r.limit).cwiseAbs().maxCoeff(), 1e-14);
  EXPECT_LE((normals - r.limit_normal).cwiseAbs().maxCoeff(), 1e-14);
  EXPECT_THROW(refiner.limit(VectorXi::Constant(1, Index(F.rows())), MatrixX3d::Constant(1, 3, 1.0 / 3)),
               InvalidInputError);
  EXPECT_THROW(refiner.refine({0}, 9), InvalidInputError);
}

// Every new face lies in its parent: its corners' base faces are the parent
// or, for corners on the parent's edges and corners, share those points.
TEST(RegionRefiner, NewFacesKnowTheFaceTheyCameFrom) {
  const auto [V, F] = test_meshes::icosphere(2);
  const RefinedRegion r = RegionRefiner(V, F).refine(scattered(Index(F.rows()), 7, 0.2), 2);
  ASSERT_EQ(r.new_face_parents.size(), r.new_faces.size());
  std::vector<char> replaced(F.rows(), 0);
  for (Index k = 0; k < r.replaced_faces.size(); ++k) replaced[r.replaced_faces(k)] = 1;
  for (Index k = 0; k < r.new_faces.size(); ++k) {
    const Index parent = r.new_face_parents(k);
    ASSERT_TRUE(replaced[parent]) << "new face " << k;
    // The new face's centroid lies in its parent (barycentric coordinates >= 0).
    const Eigen::Vector3d a = V.row(F(parent, 0)), b = V.row(F(parent, 1)), c = V.row(F(parent, 2));
    const Eigen::Vector3d p = (r.V.row(r.F(r.new_faces(k), 0)) + r.V.row(r.F(r.new_faces(k), 1)) +
                               r.V.row(r.F(r.new_faces(k), 2))).transpose() / 3;
    const Eigen::Vector3d n = (b - a).cross(c - a);
    const double area = n.squaredNorm();
    const double l0 = (c - b).cross(p - b).dot(n) / area, l1 = (a - c).cross(p - c).dot(n) / area;
    EXPECT_GE(l0, -1e-12);
    EXPECT_GE(l1, -1e-12);
    EXPECT_GE(1 - l0 - l1, -1e-12);
    EXPECT_LE(std::abs((p - a).dot(n.normalized())), 1e-12);  // flat: in the parent's plane
  }
}

// A mesh vertex's limit comes from its limit mask (linear in the mesh), a
// point inside a face from the face's patch: the two agree where they meet,
// also at a high-valence vertex (the fan around it cost valence^3 through
// the faces' patches: 2000 -> 22 s).
TEST(RegionRefiner, VertexLimitsAgreeWithThePatchesNextToThem) {
  for (const int valence : {5, 7, 64}) {
    // A bipyramid: two poles of `valence`, a ring of valence-4 vertices, bumped.
    MatrixX3d V(valence + 2, 3);
    MatrixX3i F(2 * valence, 3);
    for (int i = 0; i < valence; ++i) {
      const double a = 2 * M_PI * i / valence;
      V.row(i) << std::cos(a), std::sin(a), 0.1 * std::sin(3 * a);
      F.row(i) << i, (i + 1) % valence, valence;
      F.row(valence + i) << (i + 1) % valence, i, valence + 1;
    }
    V.row(valence) << 0.1, 0, 1;
    V.row(valence + 1) << 0, -0.1, -1;
    const RegionRefiner refiner(V, F);
    const Index faces = Index(F.rows());
    VectorXi face(2 * faces);
    MatrixX3d bary(2 * faces, 3);
    const double near = 1e-7;
    for (Index f = 0; f < faces; ++f) {
      face(2 * f) = face(2 * f + 1) = f;
      bary.row(2 * f) << 1, 0, 0;                        // the corner: its vertex's mask
      bary.row(2 * f + 1) << 1 - near, near / 2, near / 2;  // next to it: the face's patch
    }
    MatrixX3d normals;
    const MatrixX3d P = refiner.limit(face, bary, &normals);
    for (Index f = 0; f < faces; ++f) {
      EXPECT_LE((P.row(2 * f) - P.row(2 * f + 1)).norm(), 1e-5) << "valence " << valence << " face " << f;
      EXPECT_GE(normals.row(2 * f).dot(normals.row(2 * f + 1)), 0.999) << "valence " << valence << " face " << f;
    }
  }
}
