// Topology (mesh/tri_mesh) and validators (mesh/validate): each check is
// exercised on a mesh that must pass and on one that must fail.
#include <gtest/gtest.h>

#include "common/errors.h"
#include "mesh/tri_mesh.h"
#include "mesh/validate.h"
#include "test_meshes.h"

using namespace paramorph;

namespace {

MatrixX3d points(std::initializer_list<std::array<double, 3>> rows) {
  MatrixX3d V(rows.size(), 3);
  Index i = 0;
  for (const auto& r : rows) V.row(i++) << r[0], r[1], r[2];
  return V;
}
MatrixX3i faces(std::initializer_list<std::array<Index, 3>> rows) {
  MatrixX3i F(rows.size(), 3);
  Index i = 0;
  for (const auto& r : rows) F.row(i++) << r[0], r[1], r[2];
  return F;
}

TriMesh tetrahedron() {
  return TriMesh(points({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}}),
                 faces({{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}}));
}

template <typename Error>
void expect_rejected(const TriMesh& mesh, const std::string& words) {
  try {
    require_closed_genus0(validate(mesh));
    FAIL() << "accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
  }
}

}  // namespace

TEST(TriMesh, TetrahedronCounts) {
  const TriMesh mesh = tetrahedron();
  EXPECT_EQ(mesh.edges().rows(), 6);
  for (Index e = 0; e < 6; ++e) EXPECT_EQ(mesh.edge_faces().size(e), 2);
  for (Index v = 0; v < 4; ++v) {
    EXPECT_EQ(mesh.vertex_neighbors().size(v), 3);
    EXPECT_EQ(mesh.vertex_corners().size(v), 3);
  }
  EXPECT_TRUE(mesh.boundary_loops().empty());
  EXPECT_EQ(mesh.num_components(), 1);
  const MeshReport r = validate(mesh);
  EXPECT_EQ(r.euler_characteristic, 2);
  EXPECT_EQ(r.genus, 0);
  EXPECT_TRUE(r.is_closed_genus0);
  EXPECT_NO_THROW(require_closed_genus0(r));
}

TEST(TriMesh, NeighborsSortedAndEdgesConsistent) {
  auto [V, F] = test_meshes::icosphere(2);
  const TriMesh mesh(V, F);
  const Csr& nbr = mesh.vertex_neighbors();
  const Csr& nbr_edges = mesh.vertex_neighbor_edges();
  for (Index v = 0; v < mesh.num_vertices(); ++v)
    for (Index k = nbr.begin(v); k < nbr.end(v); ++k) {
      if (k > nbr.begin(v)) EXPECT_LT(nbr.items[k - 1], nbr.items[k]);
      const Index e = nbr_edges.items[k];
      EXPECT_EQ(std::min(v, nbr.items[k]), mesh.edges()(e, 0));
      EXPECT_EQ(std::max(v, nbr.items[k]), mesh.edges()(e, 1));
    }
  for (Index f = 0; f < mesh.num_faces(); ++f)
    for (int k = 0; k < 3; ++k) {  // face_edges: edge opposite corner k
      const Index e = mesh.face_edges()(f, k);
      const Index a = F(f, (k + 1) % 3), b = F(f, (k + 2) % 3);
      EXPECT_EQ(mesh.edges()(e, 0), std::min(a, b));
      EXPECT_EQ(mesh.edges()(e, 1), std::max(a, b));
    }
}

TEST(TriMesh, BoundaryLoopOfASquare) {
  const TriMesh mesh(points({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}),
                     faces({{0, 1, 2}, {0, 2, 3}}));
  ASSERT_EQ(mesh.boundary_loops().size(), 1u);
  EXPECT_EQ(mesh.boundary_loops()[0], (std::vector<Index>{0, 1, 2, 3}));
  expect_rejected<NotClosedError>(mesh, "1 boundary loops");
}

TEST(Validate, NonManifoldEdge) {
  const TriMesh mesh(points({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}}),
                     faces({{0, 1, 2}, {1, 0, 3}, {0, 1, 4}}));
  const MeshReport r = validate(mesh);
  ASSERT_EQ(r.non_manifold_edges.size(), 1u);
  EXPECT_FALSE(r.is_closed_genus0);
  expect_rejected<NonManifoldError>(mesh, "more than two faces");
}

TEST(Validate, BowTieVertex) {
  // Two triangles sharing only vertex 0.
  const TriMesh mesh(points({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {-1, 0, 0}, {-1, -1, 0}}),
                     faces({{0, 1, 2}, {0, 3, 4}}));
  const MeshReport r = validate(mesh);
  EXPECT_EQ(r.non_manifold_vertices, (std::vector<Index>{0}));
  EXPECT_TRUE(validate(tetrahedron()).non_manifold_vertices.empty());
}

TEST(Validate, FlippedFaceBreaksOrientation) {
  auto [V, F] = test_meshes::icosphere(1);
  std::swap(F(3, 1), F(3, 2));
  const MeshReport r = validate(TriMesh(V, F));
  EXPECT_EQ(r.inconsistent_orientation_edges.size(), 3u);
  expect_rejected<NonManifoldError>(TriMesh(V, F), "consistently oriented");
}

TEST(Validate, DegenerateAndDisconnectedAndGenus) {
  auto [V, F] = test_meshes::icosphere(1);
  MatrixX3d W = V;
  W.row(F(4, 2)) = 0.5 * (V.row(F(4, 0)) + V.row(F(4, 1)));
  EXPECT_EQ(validate(TriMesh(W, F)).degenerate_faces, (std::vector<Index>{4}));
  expect_rejected<DegenerateFaceError>(TriMesh(W, F), "4");

  MatrixX3d V2(2 * V.rows(), 3);
  V2 << V, V.rowwise() + Eigen::RowVector3d(3, 0, 0);
  MatrixX3i F2(2 * F.rows(), 3);
  F2 << F, F.array() + Index(V.rows());
  EXPECT_EQ(validate(TriMesh(V2, F2)).components, 2);
  expect_rejected<DisconnectedError>(TriMesh(V2, F2), "2 connected components");
}

TEST(Validate, TorusHasGenusOne) {
  const int n = 12, m = 6;
  MatrixX3d V(n * m, 3);
  MatrixX3i F(2 * n * m, 3);
  auto id = [&](int a, int b) { return Index((a % n) * m + (b % m)); };
  for (int a = 0; a < n; ++a)
    for (int b = 0; b < m; ++b) {
      const double u = 2 * M_PI * a / n, v = 2 * M_PI * b / m;
      V.row(id(a, b)) << (1 + 0.3 * std::cos(v)) * std::cos(u), (1 + 0.3 * std::cos(v)) * std::sin(u),
          0.3 * std::sin(v);
      F.row(2 * id(a, b)) << id(a, b), id(a + 1, b), id(a + 1, b + 1);
      F.row(2 * id(a, b) + 1) << id(a, b), id(a + 1, b + 1), id(a, b + 1);
    }
  const MeshReport r = validate(TriMesh(V, F));
  EXPECT_EQ(r.genus, 1);
  expect_rejected<NotGenusZeroError>(TriMesh(V, F), "genus 1");
}

TEST(ValidateArrays, NonFiniteAndOutOfRange) {
  auto [V, F] = test_meshes::icosphere(0);
  MatrixX3d W = V;
  W(5, 1) = std::nan("");
  try {
    validate_arrays(W, F);
    FAIL();
  } catch (const InvalidInputError& e) {
    EXPECT_NE(std::string(e.what()).find("vertices: 5"), std::string::npos) << e.what();
  }
  MatrixX3i G = F;
  G(7, 2) = 99;
  EXPECT_THROW(validate_arrays(V, G), InvalidInputError);
  EXPECT_NO_THROW(validate_arrays(V, F));
}

TEST(Validate, LooseVerticesAreNamedNotCountedAsSurfaces) {
  const TriMesh mesh(points({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {5, 5, 5}}),
                     faces({{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}}));
  const MeshReport r = validate(mesh);
  EXPECT_EQ(r.isolated_vertices, (std::vector<Index>{4}));
  EXPECT_FALSE(r.is_closed_genus0);
  expect_rejected<DisconnectedError>(mesh, "1 loose vertices that belong to no face (4)");
}
