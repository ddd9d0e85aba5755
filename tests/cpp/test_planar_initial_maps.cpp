// Starting maps of the planar solver: Tutte on a circle, LSCM with two pins.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "mesh/tri_mesh.h"
#include "param/planar/initial_maps.h"
#include "param/planar/untangle.h"

using namespace paramorph;
using namespace paramorph::planar;

namespace {
/// A bumpy disc: rings of a polar grid lifted by a height field.
TriMesh bumpy_disc(int rings, int sectors, double bump) {
  MatrixX3d V(1 + rings * sectors, 3);
  V.row(0) << 0, 0, bump;
  for (int r = 1; r <= rings; ++r)
    for (int s = 0; s < sectors; ++s) {
      const double rho = double(r) / rings, phi = 2 * M_PI * (s + 0.5 * r) / sectors;
      const double x = rho * std::cos(phi), y = 0.6 * rho * std::sin(phi);
      V.row(1 + (r - 1) * sectors + s) << x, y, bump * std::cos(3 * x) * std::cos(4 * y);
    }
  std::vector<Eigen::Vector3i> faces;
  auto id = [&](int r, int s) { return r == 0 ? 0 : 1 + (r - 1) * sectors + ((s % sectors) + sectors) % sectors; };
  for (int s = 0; s < sectors; ++s) faces.push_back({0, id(1, s), id(1, s + 1)});
  for (int r = 1; r < rings; ++r)
    for (int s = 0; s < sectors; ++s) {
      faces.push_back({id(r, s), id(r + 1, s), id(r + 1, s + 1)});
      faces.push_back({id(r, s), id(r + 1, s + 1), id(r, s + 1)});
    }
  MatrixX3i F(faces.size(), 3);
  for (std::size_t f = 0; f < faces.size(); ++f) F.row(f) = faces[f].transpose().cast<Index>();
  return TriMesh(V, F);
}
}  // namespace

TEST(TutteMap, FoldFreeWithTheBoundaryOnTheUnitCircle) {
  const TriMesh mesh = bumpy_disc(12, 40, 0.5);
  const MatrixX2d X = tutte_map(mesh);
  EXPECT_TRUE(folded_faces(mesh.F(), X).empty());
  for (Index v : mesh.boundary_loops()[0]) EXPECT_NEAR(X.row(v).norm(), 1.0, 1e-12);
}

TEST(LscmMap, ReproducesAFlatMeshUpToSimilarity) {
  const TriMesh flat = bumpy_disc(8, 24, 0.0);  // already planar (z = 0)
  const MatrixX2d X = lscm_map(flat);
  // A conformal map of a flat mesh is a similarity; with the pins' distance
  // preserved it is a rigid motion: all pairwise distances match.
  const MatrixX3d& V = flat.V();
  double worst = 0.0;
  for (Index i = 0; i < V.rows(); i += 7)
    for (Index j = i + 1; j < V.rows(); j += 11)
      worst = std::max(worst, std::abs((X.row(i) - X.row(j)).norm() - (V.row(i) - V.row(j)).norm()));
  EXPECT_LT(worst, 1e-9);
  EXPECT_TRUE(folded_faces(flat.F(), X).empty());
}

TEST(LscmMap, FoldFreeOnABumpyDisc) {
  const TriMesh mesh = bumpy_disc(12, 40, 0.3);
  EXPECT_TRUE(folded_faces(mesh.F(), lscm_map(mesh)).empty());
}

TEST(InitialMaps, ClosedMeshIsRejected) {
  MatrixX3d V(4, 3);
  V << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1;
  MatrixX3i F(4, 3);
  F << 0, 2, 1, 0, 1, 3, 1, 2, 3, 0, 3, 2;
  EXPECT_THROW(tutte_map(TriMesh(V, F)), NotClosedError);
}

TEST(BlendPins, SparsePinsOfASmoothWarpLeaveNoFoldsAndFollowTheWarp) {
  // Tutte map twisted by up to 45° about its centre; boundary + every 37th
  // vertex pinned on the twist. Harmonic interpolation between such sparse
  // point pins spikes at each pin; the biharmonic blend has no spikes.
  const TriMesh mesh = bumpy_disc(30, 120, 0.3);
  const MatrixX2d tutte = tutte_map(mesh);
  const Index n = mesh.num_vertices();
  MatrixX2d warped(n, 2);
  for (Index v = 0; v < n; ++v) {
    const Eigen::Vector2d p = tutte.row(v);
    const double theta = 0.25 * M_PI * std::clamp((1.0 - p.norm()) / 0.5, 0.0, 1.0);
    warped.row(v) << std::cos(theta) * p.x() - std::sin(theta) * p.y(),
        std::sin(theta) * p.x() + std::cos(theta) * p.y();
  }
  ASSERT_TRUE(folded_faces(mesh.F(), warped).empty());
  std::vector<char> pinned(n, 0);
  for (const auto& loop : mesh.boundary_loops())
    for (Index v : loop) pinned[v] = 1;
  for (Index v = 0; v < n; v += 37) pinned[v] = 1;

  const MatrixX2d blended = blend_pins(mesh, tutte, pinned, warped);
  for (Index v = 0; v < n; ++v)
    if (pinned[v]) EXPECT_EQ(blended.row(v), warped.row(v)) << v;  // exact
  EXPECT_TRUE(folded_faces(mesh.F(), blended).empty());
  MatrixX2d dropped = tutte;  // pins dropped in, the rest harmonic
  for (Index v = 0; v < n; ++v)
    if (pinned[v]) dropped.row(v) = warped.row(v);
  const MatrixX2d harmonic = harmonic_fill(mesh, VectorXd::Ones(mesh.edges().rows()), pinned, dropped);
  // Each dropped-in pin pulls a spike into its 1-ring: the harmonic start folds.
  EXPECT_GT(folded_faces(mesh.F(), harmonic).size(), 10u);
}
