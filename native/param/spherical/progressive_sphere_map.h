// A sphere map that is fold-free by construction, for any closed genus-0
// mesh (issue 28; Praun & Hoppe 2003, "Spherical parametrization and
// remeshing", coarse to fine by vertex splits).
//
//   1. collapse the mesh to a tetrahedron (mesh/collapse_sequence) and put
//      the tetrahedron on the sphere;
//   2. undo the collapses in reverse order: each vertex goes back into the
//      kernel of its ring (the spherical polygon of points that see every
//      ring edge positively; never empty, since the collapse left the kept
//      vertex inside it), at the centroid of that polygon, then moves to the
//      minimum of the isometric energy of its faces (isometric_sphere_map's,
//      the symmetric Dirichlet energy of each 3D triangle onto its chord
//      triangle, infinite for a face turned over) without leaving the kernel;
//   3. each time the vertex count has doubled, every vertex takes a few such
//      steps (Gauss-Seidel), so each part of the model keeps a share of the
//      sphere near its share of the surface at every level.
//
// Every step keeps every face's triple product positive, so the map is valid
// at every insertion. Why (issue 28): a Tutte start is fold-free only in
// exact arithmetic: along a long limb its faces shrink geometrically and
// underflow (a dancer: 295 faces folded after 40,000 relaxation sweeps), and
// a map read off a coarser level and repaired afterwards fails the same way.
// Here no face is ever squeezed: a limb gets its share at the level where it
// first appears. Cost: linear in the faces (local steps only, a few sweeps
// per level).
#pragma once

#include "common/progress.h"
#include "mesh/tri_mesh.h"

namespace paramorph::spherical {

struct ProgressiveSphereOptions {
  double level_ratio = 2.0;     ///< vertices at a relaxation checkpoint over those at the one before
  /// Vertex steps per checkpoint: sweeps = clamp(level_work / vertices,
  /// min_sweeps, max_sweeps) (coarse levels are cheap and set the layout).
  double level_work = 40000;
  int min_sweeps = 2;           ///< at least 1: without relaxation insertions squeeze each other to rounding
  int max_sweeps = 60;
  int insert_steps = 4;         ///< Newton steps for a vertex just inserted (at least 1)
};

struct ProgressiveSphereResult {
  MatrixX3d positions;          ///< #V by 3 unit vectors, every face's triple product > 0
  int levels = 0;               ///< relaxation checkpoints
  long long vertex_steps = 0;   ///< local Newton steps taken, insertions included
  Index geometric_refusals = 0; ///< collapses that turned a face over in 3D (taken last)
  double min_triple = 0;        ///< smallest face triple product
  double collapse_seconds = 0, embed_seconds = 0;
};

/// mesh: closed, connected, manifold, genus 0, no degenerate faces (validate
/// first). Throws Cancelled through progress, ComputeError if a vertex
/// finds no room in its ring (not seen; the message names it).
ProgressiveSphereResult progressive_sphere_map(const TriMesh& mesh, const ProgressiveSphereOptions& options = {},
                                               ProgressWindow progress = {});

}  // namespace paramorph::spherical
