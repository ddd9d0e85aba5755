// Gaussian curvature per vertex (angle defect over the vertex's area),
// smoothed over its neighbourhood: an intrinsic descriptor (a re-posed
// model keeps it) that tells a bump from a flank and a saddle; the morph's
// correspondence score compares it across the models (morph/correspondence).
#pragma once

#include "mesh/tri_mesh.h"

namespace paramorph {

/// #V: (2 pi - sum of corner angles) / (a third of the incident faces'
/// area), then `smoothing` rounds of area-weighted averaging over each
/// vertex and its 1-ring (0: raw). Closed manifold meshes; a vertex without
/// area gets 0.
VectorXd smoothed_gaussian_curvature(const TriMesh& mesh, int smoothing);

}  // namespace paramorph
