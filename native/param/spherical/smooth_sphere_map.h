// Fold-free local smoothing of a sphere map: each chosen vertex moves
// towards the centre of its neighbours (Laplacian smoothing on the sphere)
// as far as its faces stay turned the right way. Untangling leaves slivers
// (a face three hundredths of a degree thick and a degree long), which the
// slightest shear of a later flow turns over; smoothing round them gives the
// flow room (morph/flow_sphere_map, param/spherical/untangle_sphere_map).
#pragma once

#include <vector>

#include "mesh/tri_mesh.h"

namespace paramorph::spherical {

/// mesh: the model (its topology); X: #V by 3 unit vectors, modified in
/// place; vertices: the ones to smooth (fixed ones are skipped); rounds:
/// sweeps over them. A move is halved until the thinnest face of the vertex
/// is no thinner than before (so a sliver only gets thicker, and nothing
/// folds). Returns the moves made.
Index smooth_sphere_map(const TriMesh& mesh, MatrixX3d& X, const std::vector<Index>& vertices,
                        const std::vector<char>& fixed, int rounds = 3);

/// The vertices within `rings` edge rings of the given faces' corners.
std::vector<Index> vertices_near_faces(const TriMesh& mesh, const std::vector<Index>& faces, int rings);

}  // namespace paramorph::spherical
