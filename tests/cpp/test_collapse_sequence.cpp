// mesh/collapse_sequence: half-edge collapses down to a tetrahedron, recorded
// so they undo exactly; and param/spherical/progressive_sphere_map, which
// undoes them on the sphere.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>

#include <Eigen/Geometry>

#include "mesh/collapse_sequence.h"
#include "mesh/validate.h"
#include "param/spherical/progressive_sphere_map.h"
#include "test_meshes.h"

using namespace paramorph;

namespace {

/// The sphere stretched into a cigar 12 times as long as wide: its Tutte
/// start squeezes the ends to rounding.
TriMesh cigar() {
  auto [V, F] = test_meshes::icosphere(4);
  V.col(0) *= 12.0;
  return TriMesh(V, F);
}

/// Faces alive at a level, with their corners, as a sorted set (for comparing levels).
std::set<std::array<Index, 3>> faces_of(const MatrixX3i& F, const std::vector<char>& alive) {
  std::set<std::array<Index, 3>> out;
  for (Index f = 0; f < F.rows(); ++f)
    if (alive[std::size_t(f)]) out.insert({F(f, 0), F(f, 1), F(f, 2)});
  return out;
}

}  // namespace

TEST(CollapseSequence, ReachesATetrahedronAndEveryLevelIsAClosedSphere) {
  const TriMesh mesh = cigar();
  const CollapseSequence s = collapse_sequence(mesh);
  ASSERT_EQ(Index(s.removed.size()), mesh.num_vertices() - 4);
  MatrixX3i G = mesh.F();
  std::vector<char> alive(std::size_t(mesh.num_faces()), 1);
  std::vector<char> removed(std::size_t(mesh.num_vertices()), 0);
  for (Index c = 0; c < Index(s.removed.size()); ++c) {
    // The ring starts at the kept vertex, and the faces are (removed, ring[k], ring[k + 1]).
    const Index ring = s.rings.begin(c), degree = s.rings.size(c);
    ASSERT_EQ(s.rings.items[ring], s.kept[std::size_t(c)]);
    ASSERT_EQ(s.faces.size(c), degree);
    for (Index k = 0; k < degree; ++k) {
      const Index f = s.faces.items[s.faces.begin(c) + k];
      ASSERT_TRUE(alive[std::size_t(f)]);
      const std::array<Index, 3> want{s.removed[std::size_t(c)], s.rings.items[ring + k],
                                      s.rings.items[ring + (k + 1) % degree]};
      const std::array<Index, 3> got{G(f, 0), G(f, 1), G(f, 2)};
      ASSERT_TRUE(std::is_permutation(got.begin(), got.end(), want.begin())) << "collapse " << c;
    }
    apply_collapse(s, c, G, alive);
    removed[std::size_t(s.removed[std::size_t(c)])] = 1;
    // Every 97th level: still closed, manifold, genus 0, and without the removed vertices.
    if (c % 97 == 0 || c + 1 == Index(s.removed.size())) {
      std::vector<Index> rows;
      for (Index f = 0; f < G.rows(); ++f)
        if (alive[std::size_t(f)]) rows.push_back(f);
      MatrixX3i level(Index(rows.size()), 3);
      for (std::size_t r = 0; r < rows.size(); ++r) level.row(Index(r)) = G.row(rows[r]);
      for (Index f = 0; f < level.rows(); ++f)
        for (int k = 0; k < 3; ++k) ASSERT_FALSE(removed[std::size_t(level(f, k))]);
      // Only the level's own vertices, renumbered (removed ones would count as pieces).
      std::vector<Index> renumber(std::size_t(mesh.num_vertices()), -1);
      Index used = 0;
      for (Index f = 0; f < level.rows(); ++f)
        for (int k = 0; k < 3; ++k) {
          Index& to = renumber[std::size_t(level(f, k))];
          if (to < 0) to = used++;
          level(f, k) = to;
        }
      EXPECT_EQ(used, mesh.num_vertices() - c - 1);
      const MeshReport report = validate(TriMesh(MatrixX3d::Random(used, 3), level));
      EXPECT_TRUE(report.is_closed_genus0) << "level " << c;
    }
  }
  EXPECT_EQ(faces_of(G, alive).size(), 4u);
  for (const Index f : s.base_faces) EXPECT_TRUE(alive[std::size_t(f)]);
  // Undone in reverse, the collapses give back the input faces exactly.
  for (Index c = Index(s.removed.size()); c-- > 0;) undo_collapse(s, c, G, alive);
  EXPECT_TRUE((G.array() == mesh.F().array()).all());
  EXPECT_TRUE(std::all_of(alive.begin(), alive.end(), [](char a) { return a == 1; }));
}

TEST(ProgressiveSphereMap, FoldFreeAndOneSheetWhereTheTutteStartSqueezes) {
  const TriMesh mesh = cigar();
  const spherical::ProgressiveSphereResult r = spherical::progressive_sphere_map(mesh);
  const MatrixX3d& X = r.positions;
  ASSERT_EQ(X.rows(), mesh.num_vertices());
  double area = 0, smallest = 1;
  for (Index f = 0; f < mesh.num_faces(); ++f) {
    const Eigen::Vector3d a = X.row(mesh.F()(f, 0)), b = X.row(mesh.F()(f, 1)), c = X.row(mesh.F()(f, 2));
    const double det = a.dot(b.cross(c));
    smallest = std::min(smallest, det);
    // Signed area of the spherical triangle (Van Oosterom and Strackee).
    area += 2 * std::atan2(det, 1 + a.dot(b) + b.dot(c) + c.dot(a));
  }
  for (Index v = 0; v < X.rows(); ++v) EXPECT_NEAR(X.row(v).norm(), 1.0, 1e-12);
  // Every face well clear of rounding, and the faces cover the sphere once.
  EXPECT_GT(smallest, 1e-8);
  EXPECT_NEAR(area, 4 * M_PI, 1e-9);
  EXPECT_DOUBLE_EQ(r.min_triple, smallest);
  EXPECT_GT(r.levels, 5);
}
