// Topology (mesh/tri_mesh) and validators (mesh/validate). A validator that
// checks the wrong thing is a classic bug, so every check runs on a mesh that
// must trip it and on one that must not.
#include <gtest/gtest.h>

#include <array>
#include <random>
#include <thread>

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

/// Outward-oriented (counter-clockwise seen from outside) tetrahedron.
TriMesh tetrahedron() {
  return TriMesh(points({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}}),
                 faces({{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}}));
}

/// Outward-oriented octahedron: +x, -x, +y, -y, +z, -z.
TriMesh octahedron() {
  return TriMesh(points({{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}}),
                 faces({{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4},
                        {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}}));
}

/// Unit square split along its diagonal 0-2, counter-clockwise seen from +z.
TriMesh square() {
  return TriMesh(points({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}), faces({{0, 1, 2}, {0, 2, 3}}));
}

TriMesh torus(int n = 12, int m = 6) {
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
  return TriMesh(V, F);
}

TriMesh two_icospheres() {
  auto [V, F] = test_meshes::icosphere(1);
  MatrixX3d V2(2 * V.rows(), 3);
  V2 << V, V.rowwise() + Eigen::RowVector3d(3, 0, 0);
  MatrixX3i F2(2 * F.rows(), 3);
  F2 << F, F.array() + Index(V.rows());
  return TriMesh(V2, F2);
}

Index edge_index(const TriMesh& mesh, Index a, Index b) {
  const MatrixX2i& E = mesh.edges();
  for (Index e = 0; e < E.rows(); ++e)
    if (E(e, 0) == std::min(a, b) && E(e, 1) == std::max(a, b)) return e;
  return -1;
}

/// require_closed_genus0 must throw exactly `Error` (checked by type) with
/// `words` in its message.
template <typename Error>
void expect_rejected(const TriMesh& mesh, const std::string& words) {
  try {
    require_closed_genus0(validate(mesh));
    FAIL() << "accepted; expected an error containing '" << words << "'";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
    const MeshError* as_base = &e;  // the whole family is catchable as MeshError
    EXPECT_NE(dynamic_cast<const std::invalid_argument*>(as_base), nullptr);
  } catch (const MeshError& e) {
    FAIL() << "wrong MeshError subclass: " << e.what();
  }
}

/// Structural invariants that hold for any face list, broken or not.
void expect_consistent_topology(const TriMesh& mesh) {
  const MatrixX3i& F = mesh.F();
  const MatrixX2i& E = mesh.edges();
  for (Index e = 1; e < E.rows(); ++e)  // sorted, unique, a <= b
    EXPECT_TRUE(E(e - 1, 0) < E(e, 0) || (E(e - 1, 0) == E(e, 0) && E(e - 1, 1) < E(e, 1)));
  for (Index e = 0; e < E.rows(); ++e) EXPECT_LE(E(e, 0), E(e, 1));
  EXPECT_EQ(Index(mesh.edge_faces().items.size()), 3 * mesh.num_faces());
  EXPECT_EQ(Index(mesh.vertex_corners().items.size()), 3 * mesh.num_faces());
  for (Index f = 0; f < mesh.num_faces(); ++f)
    for (int k = 0; k < 3; ++k) {  // face_edges: the edge opposite corner k
      const Index e = mesh.face_edges()(f, k);
      const Index a = F(f, (k + 1) % 3), b = F(f, (k + 2) % 3);
      EXPECT_EQ(E(e, 0), std::min(a, b));
      EXPECT_EQ(E(e, 1), std::max(a, b));
      const Csr& ef = mesh.edge_faces();
      EXPECT_NE(std::find(ef.items.begin() + ef.begin(e), ef.items.begin() + ef.end(e), f),
                ef.items.begin() + ef.end(e));
    }
  const Csr& corners = mesh.vertex_corners();
  for (Index v = 0; v < mesh.num_vertices(); ++v)
    for (Index k = corners.begin(v); k < corners.end(v); ++k)
      EXPECT_EQ(F(corners.items[k] / 3, corners.items[k] % 3), v);
  const Csr& nbr = mesh.vertex_neighbors();
  const Csr& nbr_edges = mesh.vertex_neighbor_edges();
  ASSERT_EQ(nbr.offsets, nbr_edges.offsets);
  for (Index v = 0; v < mesh.num_vertices(); ++v)
    for (Index k = nbr.begin(v); k < nbr.end(v); ++k) {
      if (k > nbr.begin(v)) {
        EXPECT_LT(nbr.items[k - 1], nbr.items[k]) << "1-ring of " << v << " not sorted";
      }
      EXPECT_NE(nbr.items[k], v);
      const Index e = nbr_edges.items[k];
      EXPECT_EQ(E(e, 0), std::min(v, nbr.items[k]));
      EXPECT_EQ(E(e, 1), std::max(v, nbr.items[k]));
    }
  Index boundary_vertices = 0;
  for (const auto& loop : mesh.boundary_loops()) boundary_vertices += Index(loop.size());
  Index boundary_edges = 0;
  for (Index e = 0; e < E.rows(); ++e) boundary_edges += mesh.edge_faces().size(e) == 1;
  EXPECT_LE(boundary_vertices, boundary_edges);  // every boundary half-edge used at most once
}

}  // namespace

// --- topology -------------------------------------------------------------------

TEST(TriMesh, TetrahedronCounts) {
  const TriMesh mesh = tetrahedron();
  EXPECT_EQ(mesh.num_vertices(), 4);
  EXPECT_EQ(mesh.num_faces(), 4);
  EXPECT_EQ(mesh.edges().rows(), 6);
  for (Index e = 0; e < 6; ++e) EXPECT_EQ(mesh.edge_faces().size(e), 2);
  for (Index v = 0; v < 4; ++v) {
    EXPECT_EQ(mesh.vertex_neighbors().size(v), 3);
    EXPECT_EQ(mesh.vertex_corners().size(v), 3);
  }
  EXPECT_TRUE(mesh.boundary_loops().empty());
  EXPECT_EQ(mesh.num_components(), 1);
  expect_consistent_topology(mesh);
  const MeshReport r = validate(mesh);
  EXPECT_EQ(r.euler_characteristic, 2);
  EXPECT_EQ(r.genus, 0);
  EXPECT_EQ(r.boundary_edges, 0);
  EXPECT_TRUE(r.is_closed_genus0);
  EXPECT_NO_THROW(require_closed_genus0(r));
}

TEST(TriMesh, OctahedronCounts) {
  const TriMesh mesh = octahedron();
  EXPECT_EQ(mesh.edges().rows(), 12);
  for (Index v = 0; v < 6; ++v) EXPECT_EQ(mesh.vertex_neighbors().size(v), 4);
  // +x (0) is adjacent to everything except -x (1).
  const Csr& nbr = mesh.vertex_neighbors();
  EXPECT_EQ(std::vector<Index>(nbr.items.begin() + nbr.begin(0), nbr.items.begin() + nbr.end(0)),
            (std::vector<Index>{2, 3, 4, 5}));
  expect_consistent_topology(mesh);
  const MeshReport r = validate(mesh);
  EXPECT_EQ((std::array<Index, 4>{r.vertices, r.edges, r.faces, r.euler_characteristic}),
            (std::array<Index, 4>{6, 12, 8, 2}));
  EXPECT_EQ(r.genus, 0);
  EXPECT_TRUE(r.is_closed_genus0);
}

TEST(TriMesh, EdgeFacesListsBothFacesInAscendingOrder) {
  const TriMesh mesh = square();
  const Index diagonal = edge_index(mesh, 0, 2), side = edge_index(mesh, 0, 1);
  const Csr& ef = mesh.edge_faces();
  ASSERT_EQ(ef.size(diagonal), 2);
  EXPECT_EQ(ef.items[ef.begin(diagonal)], 0);
  EXPECT_EQ(ef.items[ef.begin(diagonal) + 1], 1);
  ASSERT_EQ(ef.size(side), 1);
  EXPECT_EQ(ef.items[ef.begin(side)], 0);
}

TEST(TriMesh, IcosphereTopologyIsConsistent) {
  auto [V, F] = test_meshes::icosphere(2);
  const TriMesh mesh(V, F);
  expect_consistent_topology(mesh);
  EXPECT_EQ(mesh.edges().rows(), 3 * mesh.num_faces() / 2);
  EXPECT_EQ(validate(mesh).genus, 0);
}

TEST(TriMesh, BoundaryLoopOfASquareFollowsFaceOrientation) {
  const TriMesh mesh = square();
  ASSERT_EQ(mesh.boundary_loops().size(), 1u);
  EXPECT_EQ(mesh.boundary_loops()[0], (std::vector<Index>{0, 1, 2, 3}));
  // Both faces flipped: the same cycle, walked the other way.
  const TriMesh flipped(mesh.V(), faces({{0, 2, 1}, {0, 3, 2}}));
  ASSERT_EQ(flipped.boundary_loops().size(), 1u);
  EXPECT_EQ(flipped.boundary_loops()[0], (std::vector<Index>{0, 3, 2, 1}));
  const MeshReport r = validate(mesh);
  EXPECT_EQ(r.boundary_loops, 1);
  EXPECT_EQ(r.boundary_edges, 4);
  EXPECT_EQ(r.genus, 0);  // a disc: chi = 1 = 2 - 0 - 1
  EXPECT_FALSE(r.is_closed_genus0);
  expect_rejected<NotClosedError>(mesh, "1 boundary loop (hole) with 4 boundary edges");
}

TEST(TriMesh, HolesTouchingAtOneVertexStayTwoLoops) {
  // Two squares sharing only vertex 0: a bow-tie whose two boundaries pass
  // through 0. Following fans keeps them apart (and the walk terminates).
  const TriMesh mesh(points({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {-1, 0, 0}, {-1, -1, 0}, {0, -1, 0}}),
                     faces({{0, 1, 2}, {0, 2, 3}, {0, 4, 5}, {0, 5, 6}}));
  ASSERT_EQ(mesh.boundary_loops().size(), 2u);
  EXPECT_EQ(mesh.boundary_loops()[0], (std::vector<Index>{0, 1, 2, 3}));
  EXPECT_EQ(mesh.boundary_loops()[1], (std::vector<Index>{0, 4, 5, 6}));
  expect_consistent_topology(mesh);
  EXPECT_EQ(validate(mesh).non_manifold_vertices, (std::vector<Index>{0}));
}

TEST(TriMesh, BrokenFaceSoupBuildsWithoutHangingOrCrashing) {
  // Random triangles over few vertices: non-manifold edges, repeated indices,
  // inconsistent orientation, isolated vertices all at once.
  std::mt19937 rng(7);
  std::uniform_int_distribution<Index> pick(0, 29);
  MatrixX3i F(400, 3);
  for (Index f = 0; f < F.rows(); ++f) F.row(f) << pick(rng), pick(rng), pick(rng);
  MatrixX3d V = MatrixX3d::Random(32, 3);
  const TriMesh mesh(V, F);
  expect_consistent_topology(mesh);
  const MeshReport r = validate(mesh);
  EXPECT_FALSE(r.non_manifold_edges.empty());
  EXPECT_FALSE(r.degenerate_faces.empty());
  EXPECT_EQ(r.isolated_vertices, (std::vector<Index>{30, 31}));
  EXPECT_EQ(r.genus, -1);
  EXPECT_FALSE(r.is_closed_genus0);
  // Faces naming a vertex twice are among the causes of the shared edges:
  // they are named first (their fix is plain).
  EXPECT_FALSE(r.repeated_vertex_faces.empty());
  EXPECT_THROW(require_closed_genus0(r), DegenerateFaceError);
}

TEST(TriMesh, ConcurrentFirstUseBuildsOneTopology) {
  auto [V, F] = test_meshes::icosphere(3);
  const TriMesh mesh(V, F);
  std::vector<const MatrixX2i*> seen(4);
  std::vector<std::thread> threads;
  for (int t = 0; t < 4; ++t) threads.emplace_back([&, t] { seen[t] = &mesh.edges(); });
  for (auto& t : threads) t.join();
  for (int t = 1; t < 4; ++t) EXPECT_EQ(seen[t], seen[0]);
  EXPECT_EQ(seen[0]->rows(), 3 * mesh.num_faces() / 2);
}

TEST(TriMesh, ComponentsLabelIsolatedVerticesSeparately) {
  const TriMesh two = two_icospheres();
  EXPECT_EQ(two.num_components(), 2);
  EXPECT_EQ(two.vertex_component()(0), 0);
  EXPECT_EQ(two.vertex_component()(two.num_vertices() - 1), 1);
  const TriMesh loose(points({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {5, 5, 5}}),
                      tetrahedron().F());
  EXPECT_EQ(loose.num_components(), 2);
  EXPECT_EQ(loose.vertex_component()(4), 1);
}

// --- validators: each must fire on its case and stay silent on a good mesh -----

TEST(Validate, NonManifoldEdge) {
  // Three triangles on edge (0, 1).
  const TriMesh mesh(points({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}}),
                     faces({{0, 1, 2}, {1, 0, 3}, {0, 1, 4}}));
  const MeshReport r = validate(mesh);
  ASSERT_EQ(r.non_manifold_edges, (std::vector<Index>{edge_index(mesh, 0, 1)}));
  ASSERT_EQ(r.non_manifold_edge_vertices.rows(), 1);
  EXPECT_EQ(r.non_manifold_edge_vertices(0, 0), 0);
  EXPECT_EQ(r.non_manifold_edge_vertices(0, 1), 1);
  EXPECT_EQ(mesh.edge_faces().size(edge_index(mesh, 0, 1)), 3);
  EXPECT_EQ(r.genus, -1);
  EXPECT_FALSE(r.is_closed_genus0);
  expect_rejected<NonManifoldError>(mesh, "between vertices (0, 1)");
  EXPECT_TRUE(validate(tetrahedron()).non_manifold_edges.empty());
  EXPECT_TRUE(validate(square()).non_manifold_edges.empty());
}

TEST(Validate, BowTieVertex) {
  // Two triangles sharing only vertex 0.
  const TriMesh mesh(points({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {-1, 0, 0}, {-1, -1, 0}}),
                     faces({{0, 1, 2}, {0, 3, 4}}));
  const MeshReport r = validate(mesh);
  EXPECT_EQ(r.non_manifold_vertices, (std::vector<Index>{0}));
  EXPECT_TRUE(r.non_manifold_edges.empty());
  expect_rejected<NonManifoldError>(mesh, "vertices 0");
  // Negative cases: closed fans, and open fans on a boundary, are manifold.
  EXPECT_TRUE(validate(tetrahedron()).non_manifold_vertices.empty());
  EXPECT_TRUE(validate(square()).non_manifold_vertices.empty());
}

TEST(Validate, TwoClosedSurfacesPinchedAtOneVertex) {
  // Two tetrahedra sharing vertex 0: every edge has two faces, yet vertex 0
  // has two separate closed fans.
  const TriMesh mesh(points({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {-1, 0, 0}, {0, -1, 0}, {0, 0, -1}}),
                     faces({{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2},
                            {0, 5, 4}, {0, 4, 6}, {4, 5, 6}, {0, 6, 5}}));
  const MeshReport r = validate(mesh);
  EXPECT_TRUE(r.non_manifold_edges.empty());
  EXPECT_EQ(r.non_manifold_vertices, (std::vector<Index>{0}));
  EXPECT_EQ(r.components, 1);
  EXPECT_EQ(r.boundary_loops, 0);
  expect_rejected<NonManifoldError>(mesh, "single fan");
}

TEST(Validate, FlippedFaceBreaksOrientation) {
  auto [V, F] = test_meshes::icosphere(1);
  EXPECT_TRUE(validate(TriMesh(V, F)).inconsistent_orientation_edges.empty());
  MatrixX3i G = F;
  G.row(3) << F(3, 0), F(3, 2), F(3, 1);  // flip face 3
  const TriMesh mesh(V, G);
  const MeshReport r = validate(mesh);
  ASSERT_EQ(r.inconsistent_orientation_edges.size(), 3u);
  for (int k = 0; k < 3; ++k)  // exactly the three edges of face 3
    EXPECT_NE(std::find(r.inconsistent_orientation_edges.begin(), r.inconsistent_orientation_edges.end(),
                        mesh.face_edges()(3, k)),
              r.inconsistent_orientation_edges.end());
  EXPECT_EQ(r.inconsistent_orientation_edge_vertices.rows(), 3);
  EXPECT_EQ(r.genus, 0);  // still a topological sphere, just not oriented
  EXPECT_FALSE(r.is_closed_genus0);
  expect_rejected<NonManifoldError>(mesh, "consistently oriented");
  // Flipping every face is consistent again (inward normals are not an orientation error).
  MatrixX3i H(F.rows(), 3);
  H << F.col(0), F.col(2), F.col(1);
  EXPECT_TRUE(validate(TriMesh(V, H)).is_closed_genus0);
}

TEST(Validate, DegenerateFaces) {
  auto [V, F] = test_meshes::icosphere(1);
  EXPECT_TRUE(validate(TriMesh(V, F)).degenerate_faces.empty());
  // Zero area: a corner moved onto the midpoint of the opposite edge.
  MatrixX3d W = V;
  W.row(F(4, 2)) = 0.5 * (V.row(F(4, 0)) + V.row(F(4, 1)));
  EXPECT_EQ(validate(TriMesh(W, F)).degenerate_faces, (std::vector<Index>{4}));
  expect_rejected<DegenerateFaceError>(TriMesh(W, F), "faces 4");
  // Repeated index.
  const TriMesh repeated(points({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}), faces({{0, 1, 2}, {0, 1, 1}}));
  EXPECT_EQ(validate(repeated).degenerate_faces, (std::vector<Index>{1}));
  // The tolerance is relative: a tiny but well-shaped mesh is fine.
  EXPECT_TRUE(validate(TriMesh(1e-6 * V, F)).degenerate_faces.empty());
  EXPECT_TRUE(validate(TriMesh(1e6 * V, F)).degenerate_faces.empty());
}

TEST(Validate, DisconnectedSurfaces) {
  const TriMesh mesh = two_icospheres();
  const MeshReport r = validate(mesh);
  EXPECT_EQ(r.components, 2);
  EXPECT_EQ(r.euler_characteristic, 4);
  EXPECT_EQ(r.genus, -1);
  expect_rejected<DisconnectedError>(mesh, "2 connected components");
  EXPECT_EQ(validate(tetrahedron()).components, 1);
}

TEST(Validate, LooseVerticesAreNamedNotCountedAsSurfaces) {
  const TriMesh mesh(points({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {5, 5, 5}}),
                     tetrahedron().F());
  const MeshReport r = validate(mesh);
  EXPECT_EQ(r.isolated_vertices, (std::vector<Index>{4}));
  EXPECT_EQ(r.genus, 0);  // the surface itself is a sphere
  EXPECT_FALSE(r.is_closed_genus0);
  expect_rejected<DisconnectedError>(mesh, "1 loose vertex in no face (4)");
  EXPECT_TRUE(validate(tetrahedron()).isolated_vertices.empty());
}

TEST(Validate, TorusHasGenusOne) {
  const MeshReport r = validate(torus());
  EXPECT_EQ(r.euler_characteristic, 0);
  EXPECT_EQ(r.genus, 1);
  EXPECT_EQ(r.boundary_loops, 0);
  EXPECT_FALSE(r.is_closed_genus0);
  expect_rejected<NotGenusZeroError>(torus(), "genus 1 (1 handle)");
}

TEST(Validate, ChecksComeInTheDocumentedOrder) {
  // A torus with a hole: the hole is reported first (fill it, then see the genus).
  const TriMesh t = torus();
  MatrixX3i F = t.F().topRows(t.num_faces() - 1);
  expect_rejected<NotClosedError>(TriMesh(t.V(), F), "1 boundary loop");
  // Non-manifold beats degenerate.
  const TriMesh both(points({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {2, 0, 0}}),
                     faces({{0, 1, 2}, {1, 0, 3}, {0, 1, 4}, {0, 1, 5}}));
  expect_rejected<NonManifoldError>(both, "more than two faces");
}

// --- raw arrays ------------------------------------------------------------------

TEST(ValidateArrays, NonFiniteCoordinatesNameTheVertices) {
  auto [V, F] = test_meshes::icosphere(0);
  EXPECT_NO_THROW(validate_arrays(V, F));
  MatrixX3d W = V;
  W(5, 1) = std::nan("");
  W(8, 0) = std::numeric_limits<double>::infinity();
  try {
    validate_arrays(W, F);
    FAIL();
  } catch (const InvalidInputError& e) {
    EXPECT_NE(std::string(e.what()).find("2 vertices: 5, 8"), std::string::npos) << e.what();
  }
}

TEST(ValidateArrays, IndexOutOfRangeNamesFaceAndValue) {
  auto [V, F] = test_meshes::icosphere(0);
  MatrixX3i G = F;
  G(7, 2) = 99;
  G(9, 0) = -1;
  try {
    validate_arrays(V, G);
    FAIL();
  } catch (const InvalidInputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("face 7 has vertex index 99, out of range for 12 vertices"), std::string::npos) << what;
    EXPECT_NE(what.find("2 faces have bad indices: 7, 9"), std::string::npos) << what;
  }
  G(7, 2) = 12;  // one past the end
  G(9, 0) = 0;
  EXPECT_THROW(validate_arrays(V, G), InvalidInputError);
  G(7, 2) = 11;
  EXPECT_NO_THROW(validate_arrays(V, G));
}

TEST(ValidateArrays, EmptyMesh) {
  EXPECT_THROW(validate_arrays(MatrixX3d(0, 3), MatrixX3i(0, 3)), InvalidInputError);
  EXPECT_THROW(validate_arrays(MatrixX3d::Zero(3, 3), MatrixX3i(0, 3)), InvalidInputError);
}

TEST(FormatIndices, ShortensLongLists) {
  EXPECT_EQ(format_indices({}), "");
  EXPECT_EQ(format_indices({0, 5, 17}), "0, 5, 17");
  EXPECT_EQ(format_indices({1, 2, 3, 4, 5}, 3), "1, 2, 3 (and 2 more)");
  MatrixX2i pairs(3, 2);
  pairs << 3, 7, 8, 12, 1, 2;
  EXPECT_EQ(format_vertex_pairs(pairs, 2), "(3, 7), (8, 12) (and 1 more)");
}
