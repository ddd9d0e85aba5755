// Welding coincident vertices: the first step of repair() (issue 19). Meshes
// exported with their UV or normal seams split carry several vertices at one
// place; until they are one vertex the surface looks torn into parts.
#pragma once

#include "mesh/types.h"

namespace paramorph {

/// V: #V by 3 positions; tolerance: an absolute distance (>= 0, finite).
/// Returns #V: for each vertex the vertex it is welded into, the lowest index
/// of its cluster (itself when alone). Two vertices are in one cluster when a
/// chain of vertices each within `tolerance` of the next joins them;
/// tolerance 0 welds exactly equal positions only. Linear in #V on average
/// (a hash grid of cells `tolerance` wide).
VectorXi weld_vertices(const MatrixX3d& V, double tolerance);

}  // namespace paramorph
