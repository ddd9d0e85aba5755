// Spherical overlay (thesis 4.4): the perturbed predicates against an exact
// evaluation of the perturbation, walking point location, the cell
// triangulation, and the merged topology's invariants.
#include <gtest/gtest.h>

// Boost's rational type as the exact reference (its headers trip GCC's
// maybe-uninitialized analysis, hence the pragma).
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include <boost/multiprecision/cpp_int.hpp>
#pragma GCC diagnostic pop
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <set>

#include "common/errors.h"
#include "mesh/face_neighbors.h"
#include "mesh/tri_mesh.h"
#include "mesh/validate.h"
#include "morph/point_location.h"
#include "morph/sphere_predicates.h"
#include "morph/spherical_overlay.h"
#include "morph/triangulate_spherical_polygon.h"
#include "test_meshes.h"

using namespace paramorph;
using namespace paramorph::morph;
using Rational = boost::multiprecision::cpp_rational;

namespace {

/// det(p + dp, q + dq, r + dr) evaluated exactly for the concrete e = 2^-20,
/// each ranked point k moved by (e^(2^(3k)), e^(2^(3k+1)), e^(2^(3k+2))):
/// small integer coordinates keep every later term far below the first.
int exact_perturbed_sign(const Eigen::Vector3d* P, const int* rank) {
  const Rational e = Rational(1) / Rational(1 << 20);
  Rational m[3][3];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      m[i][j] = Rational(P[i][j]);
      if (rank[i] >= 0) {
        Rational d = 1;
        for (int power = 0; power < (1 << (3 * rank[i] + j)); ++power) d *= e;
        m[i][j] += d;
      }
    }
  const Rational det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
                       m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
                       m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
  return det > 0 ? 1 : (det < 0 ? -1 : 0);
}

Eigen::Matrix3d rotation(unsigned seed, double angle) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal;
  const Eigen::Vector3d axis = Eigen::Vector3d(normal(rng), normal(rng), normal(rng)).normalized();
  return Eigen::AngleAxisd(angle, axis).toRotationMatrix();
}

double total_area(const MatrixX3d& V, const MatrixX3i& F) {
  double area = 0;
  for (Index f = 0; f < F.rows(); ++f)
    area += spherical_triangle_area(V.row(F(f, 0)), V.row(F(f, 1)), V.row(F(f, 2)));
  return area;
}

/// Checks the invariants every merged topology promises.
void expect_valid(const MergedTopology& r, const MatrixX3d& A, const MatrixX3i& FA,
                  const MatrixX3d& B, const MatrixX3i& FB) {
  EXPECT_EQ(r.stats.folded, 0);
  EXPECT_EQ(r.stats.open_edges, 0);
  EXPECT_EQ(r.stats.degenerate_cells, 0);
  EXPECT_NEAR(total_area(r.V, r.F), 4 * M_PI, 1e-9);
  for (Index t = 0; t < r.F.rows(); ++t)
    ASSERT_GT(orientation(r.V.row(r.F(t, 0)).data(), r.V.row(r.F(t, 1)).data(),
                          r.V.row(r.F(t, 2)).data()),
              0)
        << "triangle " << t;
  // Euler characteristic 2 of a closed triangle mesh: V - 3F/2 + F.
  EXPECT_EQ(r.V.rows() - r.F.rows() / 2, 2);
  std::set<Index> seen_a(r.vertex_of_a.data(), r.vertex_of_a.data() + r.vertex_of_a.size());
  std::set<Index> seen_b(r.vertex_of_b.data(), r.vertex_of_b.data() + r.vertex_of_b.size());
  EXPECT_EQ(Index(seen_a.size()), A.rows());
  EXPECT_EQ(Index(seen_b.size()), B.rows());
  const double moved = std::max(1e-9, r.stats.max_merge_distance);
  for (Index m = 0; m < r.V.rows(); ++m) {
    Eigen::RowVector3d pa = Eigen::RowVector3d::Zero(), pb = pa;
    for (int k = 0; k < 3; ++k) {
      pa += r.bary_a(m, k) * A.row(FA(r.face_a[m], k));
      pb += r.bary_b(m, k) * B.row(FB(r.face_b[m], k));
    }
    EXPECT_LE((pa.normalized() - r.V.row(m)).norm(), moved + 1e-14) << m;
    EXPECT_LE((pb.normalized() - r.V.row(m)).norm(), moved + 1e-14) << m;
  }
}

/// B with up to `count` vertices moved `d` radians off the nearest arc of A
/// (alternating sides, the foot inside the arc), those already within 0.02.
MatrixX3d near_arcs(const MatrixX3d& A, const MatrixX3i& FA, MatrixX3d B, double d, int count) {
  const TriMesh mesh(A, FA);
  const MatrixX2i& E = mesh.edges();
  int moved = 0;
  for (Index v = 0; v < B.rows() && moved < count; ++v) {
    const Eigen::Vector3d P = B.row(v);
    double best = 0.02;
    Eigen::Vector3d foot, normal;
    for (Index e = 0; e < E.rows(); ++e) {
      const Eigen::Vector3d p0 = A.row(E(e, 0)), p1 = A.row(E(e, 1));
      const Eigen::Vector3d n = p0.cross(p1).normalized();
      const Eigen::Vector3d f = (P - P.dot(n) * n).normalized();
      if (n.cross(p0).dot(f) < 0 || p1.cross(n).dot(f) < 0) continue;
      if (std::abs(P.dot(n)) < best) best = std::abs(P.dot(n)), foot = f, normal = n;
    }
    if (best >= 0.02) continue;
    B.row(v) = (foot + (moved % 2 ? d : -d) * normal).normalized().transpose();
    ++moved;
  }
  return B;
}

/// B with each vertex within 0.02 of a vertex of A moved to `d` radians from it.
MatrixX3d near_vertices(const MatrixX3d& A, MatrixX3d B, double d) {
  std::mt19937 rng(4);
  std::normal_distribution<double> normal;
  for (Index v = 0; v < B.rows(); ++v) {
    Index u;
    (A * B.row(v).transpose()).maxCoeff(&u);
    const Eigen::Vector3d p = A.row(u);
    if ((B.row(v).transpose() - p).norm() > 0.02) continue;
    Eigen::Vector3d t(normal(rng), normal(rng), normal(rng));
    t = (t - t.dot(p) * p).normalized();
    B.row(v) = (p + d * t).normalized().transpose();
  }
  return B;
}

/// Each merged vertex on a mesh V, F from its face and barycentric
/// coordinates, as morph() places it.
MatrixX3d positions_on(const MatrixX3d& V, const MatrixX3i& F, const VectorXi& face,
                       const MatrixX3d& bary) {
  MatrixX3d P(face.size(), 3);
  for (Index m = 0; m < face.size(); ++m)
    P.row(m) = bary(m, 0) * V.row(F(face[m], 0)) + bary(m, 1) * V.row(F(face[m], 1)) +
               bary(m, 2) * V.row(F(face[m], 2));
  return P;
}

/// Smallest altitude (twice the area over the longest side) of the triangles.
double thinnest(const MatrixX3d& V, const MatrixX3i& F) {
  double h = std::numeric_limits<double>::infinity();
  for (Index t = 0; t < F.rows(); ++t) {
    const Eigen::Vector3d a = V.row(F(t, 0)), b = V.row(F(t, 1)), c = V.row(F(t, 2));
    const double longest =
        std::sqrt(std::max({(b - a).squaredNorm(), (c - b).squaredNorm(), (a - c).squaredNorm()}));
    h = std::min(h, (b - a).cross(c - a).norm() / longest);
  }
  return h;
}

}  // namespace

TEST(SpherePredicates, ExactOrientation) {
  const double x[3] = {1, 0, 0}, y[3] = {0, 1, 0}, z[3] = {0, 0, 1}, xy[3] = {1, 1, 0};
  EXPECT_EQ(orientation(x, y, z), 1);
  EXPECT_EQ(orientation(y, x, z), -1);
  EXPECT_EQ(orientation(x, y, xy), 0);
  // A difference far below the double's rounding of a plain triple product.
  const double tiny[3] = {1, 1, 1e-300};
  EXPECT_EQ(orientation(x, y, tiny), 1);
}

TEST(SpherePredicates, PerturbedSignsMatchAnExactPerturbation) {
  std::mt19937 rng(11);
  std::uniform_int_distribution<int> small(-3, 3);
  auto point = [&] { return Eigen::Vector3d(small(rng), small(rng), small(rng)); };
  int degenerate = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    // Three points with det 0 (the third a small integer combination of the
    // first two, or a repeat), one or two of them ranked.
    Eigen::Vector3d P[3] = {point(), point(), Eigen::Vector3d::Zero()};
    if (P[0].cross(P[1]).squaredNorm() == 0) continue;
    P[2] = trial % 7 == 0 ? P[trial % 2] : double(small(rng)) * P[0] + double(small(rng)) * P[1];
    if (P[2].squaredNorm() == 0) continue;
    int rank[3] = {-1, -1, -1};
    const int first = int(rng() % 3), flip = int(rng() % 2);
    if (trial % 2 == 0) {
      rank[first] = flip;  // one ranked point
    } else {               // two, in either order of rank
      rank[first] = flip;
      rank[(first + 1 + rng() % 2) % 3] = 1 - flip;
    }
    const int ranked = 1 + trial % 2;
    // The precondition: the two fixed points (one ranked) or the two ranked
    // points are independent (an edge of A, or of B).
    int i = -1, j = -1;
    for (int k = 0; k < 3; ++k)
      if ((rank[k] >= 0) == (ranked == 2)) (i < 0 ? i : j) = k;
    if (P[i].cross(P[j]).squaredNorm() == 0) continue;
    const int expected = exact_perturbed_sign(P, rank);
    const int got = perturbed_orientation({P[0].data(), rank[0]}, {P[1].data(), rank[1]},
                                          {P[2].data(), rank[2]});
    ASSERT_NE(got, 0) << trial;
    ASSERT_EQ(got, expected) << "trial " << trial;
    // Antisymmetric like the determinant.
    ASSERT_EQ(perturbed_orientation({P[1].data(), rank[1]}, {P[0].data(), rank[0]},
                                    {P[2].data(), rank[2]}),
              -got);
    ++degenerate;
  }
  EXPECT_GT(degenerate, 1000);
}

TEST(PointLocation, WalkFindsTheFaceHoldingEachPoint) {
  auto [X, F] = test_meshes::icosphere(3);
  const MatrixX3i N = face_neighbors(TriMesh(X, F));
  std::mt19937 rng(5);
  std::normal_distribution<double> normal;
  Index start = 0;
  for (int trial = 0; trial < 200; ++trial) {
    const Eigen::Vector3d p = Eigen::Vector3d(normal(rng), normal(rng), normal(rng)).normalized();
    const Index f = locate_on_sphere(X, F, N, false, {p.data(), -1}, start);
    ASSERT_GE(f, 0);
    for (int k = 0; k < 3; ++k)
      EXPECT_GE(
          orientation(X.row(F(f, (k + 1) % 3)).data(), X.row(F(f, (k + 2) % 3)).data(), p.data()),
          0);
    start = (start + 97) % Index(F.rows());
  }
  // A vertex of the mesh itself, perturbed as a vertex of B: one face only.
  const Eigen::Vector3d v = X.row(7);
  const Index f = locate_on_sphere(X, F, N, false, {v.data(), 0}, 0);
  ASSERT_GE(f, 0);
  for (int k = 0; k < 3; ++k)
    EXPECT_GT(perturbed_orientation({X.row(F(f, (k + 1) % 3)).data(), -1},
                                    {X.row(F(f, (k + 2) % 3)).data(), -1}, {v.data(), 0}),
              0);
}

TEST(TriangulateSphericalPolygon, FlatCornersGetNoZeroAreaTriangle) {
  // A triangle with two extra corners on one side (on its great circle) and
  // one on another: a fan from a corner would make zero-area triangles.
  const Eigen::Vector3d a(1, 0, 0), b(0, 1, 0), c = Eigen::Vector3d(1, 1, 1).normalized();
  auto on = [](const Eigen::Vector3d& p, const Eigen::Vector3d& q, double t) {
    return Eigen::Vector3d((1 - t) * p + t * q).normalized();
  };
  const Eigen::Vector3d P[6] = {a, on(a, b, 0.3), on(a, b, 0.7), b, on(b, c, 0.5), c};
  std::array<int, 3> tris[kMaxPolygonCorners];
  ASSERT_TRUE(triangulate_spherical_polygon(P, 6, tris));
  for (int t = 0; t < 4; ++t)
    EXPECT_GT(orientation(P[tris[t][0]].data(), P[tris[t][1]].data(), P[tris[t][2]].data()), 0);
  // All corners on one great circle: nothing positive to make.
  const Eigen::Vector3d Q[4] = {a, on(a, b, 0.25), on(a, b, 0.5), b};
  EXPECT_FALSE(triangulate_spherical_polygon(Q, 4, tris));
}

TEST(SphericalOverlay, DifferentMapsMakeAValidMergedTopology) {
  auto [A, FA] = test_meshes::icosphere(2);
  auto [B, FB] = test_meshes::icosphere(3);
  B = (B * rotation(3, 0.7).transpose()).eval();
  const MergedTopology r = overlay(A, FA, B, FB);
  expect_valid(r, A, FA, B, FB);
  EXPECT_GT(r.stats.crossings, 0);
  EXPECT_EQ(r.stats.merged_vertices, 0);
  // Generic position: M = VA + VB + crossings, K = 2 M - 4.
  EXPECT_EQ(r.V.rows(), A.rows() + B.rows() + r.stats.crossings);
  EXPECT_EQ(r.F.rows(), 2 * r.V.rows() - 4);
  for (Index i = 0; i < A.rows(); ++i) EXPECT_EQ(r.vertex_of_a[i], i);
}

TEST(SphericalOverlay, AMapWithItselfIsTheMap) {
  auto [A, FA] = test_meshes::icosphere(2);
  for (const double angle : {0.0, 1e-12}) {
    const MatrixX3d B = A * rotation(9, angle).transpose();
    const MergedTopology r = overlay(A, FA, B, FA);
    expect_valid(r, A, FA, B, FA);
    EXPECT_EQ(r.V.rows(), A.rows());
    EXPECT_EQ(r.F.rows(), FA.rows());
    EXPECT_TRUE((r.vertex_kind.array() == 2).all());
  }
}

TEST(SphericalOverlay, RejectsBadInput) {
  auto [A, FA] = test_meshes::icosphere(1);
  MatrixX3d folded = A;
  folded.row(FA(0, 0)) *= -1;
  EXPECT_THROW(overlay(A, FA, folded, FA), InvalidInputError);
  EXPECT_THROW(overlay(A * 2.0, FA, A, FA), InvalidInputError);
  const MatrixX3i open = FA.topRows(FA.rows() - 1);
  EXPECT_THROW(overlay(A, open, A, FA), NotClosedError);
  OverlayOptions bad;
  bad.merge_tolerance = std::nan("");
  EXPECT_THROW(overlay(A, FA, A, FA, bad), InvalidInputError);
}

TEST(SphericalOverlay, NearDegenerateInputsMakeNoSlivers) {
  // A vertex of B within d of an arc of A, within d of a vertex of A (their
  // crossings within ~d of each other), B = A turned by d: under the
  // tolerance they merge, over it they stay, and no merged triangle is
  // thinner than kMinAltitudeInTolerances tolerances on the sphere nor
  // degenerate (validate()) there or on the two ellipsoids the maps stand for.
  auto [A, FA] = test_meshes::icosphere(3);
  auto [G, FG] = test_meshes::icosphere(2);
  G = (G * rotation(3, 0.7).transpose()).eval();
  const Eigen::RowVector3d axes_a(1.0, 0.6, 1.4), axes_b(1.3, 0.9, 0.7);
  for (const double d : {1e-10, 1e-8, 1e-7, 1.5e-6, 3e-6})
    for (int which = 0; which < 3; ++which) {
      SCOPED_TRACE(testing::Message() << "d " << d << " case " << which);
      const MatrixX3d& B = which == 2 ? A : G;
      const MatrixX3i& FB = which == 2 ? FA : FG;
      const MatrixX3d moved = which == 0   ? near_arcs(A, FA, G, d, 30)
                              : which == 1 ? near_vertices(A, G, d)
                                           : MatrixX3d(A * rotation(8, d).transpose());
      const MergedTopology r = overlay(A, FA, moved, FB);
      expect_valid(r, A, FA, moved, FB);
      const double tolerance = r.stats.merge_tolerance;
      EXPECT_EQ(tolerance, OverlayOptions().merge_tolerance);
      if (d < tolerance) {
        EXPECT_GT(r.stats.merged_vertices, 0);
        EXPECT_LE(r.stats.max_merge_distance, tolerance);
      }
      EXPECT_EQ(r.stats.thin_triangles, 0);
      EXPECT_GE(thinnest(r.V, r.F), kMinAltitudeInTolerances * tolerance);
      EXPECT_NEAR(r.stats.min_altitude, thinnest(r.V, r.F), 1e-6 * r.stats.min_altitude);
      EXPECT_TRUE(validate(TriMesh(r.V, r.F)).degenerate_faces.empty());
      const MatrixX3d PA = positions_on(A.array().rowwise() * axes_a.array(), FA, r.face_a, r.bary_a);
      const MatrixX3d PB = positions_on(B.array().rowwise() * axes_b.array(), FB, r.face_b, r.bary_b);
      EXPECT_TRUE(validate(TriMesh(PA, r.F)).degenerate_faces.empty());
      EXPECT_TRUE(validate(TriMesh(PB, r.F)).degenerate_faces.empty());
    }
}
