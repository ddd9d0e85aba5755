// Starting maps for the planar solver (thesis 2.3; DESIGN.md §4.1).
//
// tutte_map: the longest boundary loop on the unit circle (spaced by edge
//   length), interior vertices as positive-weight averages of their neighbours
//   (clamped cotangent weights): fold-free for a disc (Tutte/Floater).
// blend_pins: moves a start onto hard pins smoothly (before untangling).
// lscm_map: free boundary, least-squares conformal map (conformal energy =
//   Dirichlet energy minus the boundary's signed area) with two boundary
//   vertices pinned, true cotangent weights, solved with a sparse LDLᵀ.
#pragma once

#include <vector>

#include "mesh/tri_mesh.h"

namespace paramorph::planar {

/// Positions of the vertices not `pinned` solving L_ff X_f = -L_fp X_p with
/// edge weights w (#E, positive for Floater's guarantee); pinned rows of X kept.
MatrixX2d harmonic_fill(const TriMesh& mesh, const VectorXd& w, const std::vector<char>& pinned,
                        MatrixX2d X);

/// `start` moved so every pinned vertex lands exactly on its row of
/// `targets` (#V by 2; only pinned rows are read), by the smoothest
/// displacement: D = argmin ∫|ΔD|² (bi-Laplacian L M⁻¹ L, clamped cotangent
/// L with natural boundary conditions, lumped areas M) with D = target - start
/// at the pins. Unlike harmonic interpolation, a biharmonic field has no
/// spike at a point constraint, so sparse interior pins that follow a smooth
/// warp leave few or no folds for untangling.
MatrixX2d blend_pins(const TriMesh& mesh, const MatrixX2d& start, const std::vector<char>& pinned,
                     const MatrixX2d& targets);

/// #V by 2. Needs at least one boundary loop.
MatrixX2d tutte_map(const TriMesh& mesh);

/// #V by 2; pins the two boundary vertices farthest apart at (0, 0) and
/// (d, 0), d their 3D distance, so the map has the surface's scale.
MatrixX2d lscm_map(const TriMesh& mesh);

}  // namespace paramorph::planar
