// The base surface under a feature (thesis 5.1/5.2: the "base surface" the
// detail is stored against; DESIGN.md §4.5 step 1): the smooth surface that
// spans the feature's boundary and meets the surroundings with matching
// tangents.
//
// Same connectivity as the selection. Its boundary vertices stay where they
// are; its interior vertices minimise the thin-plate energy
//   Σ_i |(L x)_i|² / M_i   over the selection's vertices i (boundary included),
// L the cotangent Laplacian (corner angles clamped to [5°, 85°] so every
// weight is positive) and M the lumped (barycentric) vertex areas of the
// selection plus the one ring of source faces just outside it. The rows of the
// boundary vertices reach into that ring, whose vertices are held fixed too:
// this is the biharmonic fill with two rings of boundary conditions, so the
// base continues the surroundings with matching tangents (C1 across the
// boundary). An annulus is the same, with both boundaries and both outer rings
// fixed. Weights and areas come from the source's own positions (the base is
// not known yet); they only set how the interior is distributed, not the
// boundary data it interpolates, and the energy is invariant to scale.
#pragma once

#include "mesh/tri_mesh.h"
#include "paste/selection_patch.h"

namespace paramorph::paste {

/// mesh: the source mesh; patch: selection_patch(mesh, ...).
/// Returns #Vs by 3 base positions, row i for local vertex i of the patch
/// (boundary rows equal the source positions exactly). Solved with CHOLMOD's
/// supernodal Cholesky (one factorisation, three right-hand sides).
MatrixX3d base_surface(const TriMesh& mesh, const SelectionPatch& patch);

}  // namespace paramorph::paste
