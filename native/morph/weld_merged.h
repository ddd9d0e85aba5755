// Welding a morph's merged mesh (issue 17, item 3; DESIGN.md §4.4 step 5).
// The overlay keeps every input vertex and crossing apart on the sphere, so
// where a vertex of B lies within a hair of a vertex or an edge of A the
// merged mesh has edges of nearly zero length and faces of nearly zero area
// at one end or both (slivers: the in-betweens cannot tell which way such a
// face points). Here:
//   1. an edge shorter than 1e-4 of the diagonal at either end is collapsed
//      where every face it leaves stays inside one face of A and one of B
//      within `tolerance` times the diagonal (so the carry still reads each
//      corner in its faces and both ends stay within that of A and B), the
//      old faces are covered as closely, no face around turns over (on the
//      sphere, exactly and no thinner than the overlay leaves them, or at
//      either end), the mesh stays a manifold, and never two vertices of one
//      input are joined; the vertex that stands for an input vertex is kept
//      at its exact place on that input;
//   2. a face of (nearly) zero area at either end inside one cell of the
//      overlay (its neighbour across its longest side in the same face of A
//      and of B: the four corners are coplanar at both ends) has that side
//      flipped where both new faces are better, which keeps both ends exact.
// What it cannot remove: whole tiny triangles (sides under 1e-4 of the
// diagonal) around an input vertex that lies a hair (1e-6 to 1e-5 of the
// diagonal) from the other input's edge: joining them would move an end
// further than the tolerance.
#pragma once

#include "common/progress.h"

#include "mesh/types.h"
#include "morph/spherical_overlay.h"

namespace paramorph::morph {

struct WeldStats {
  Index faces_before = 0, faces_after = 0;
  Index collapsed_edges = 0;  ///< short edges collapsed (vertices welded)
  Index flipped_edges = 0;    ///< edges flipped inside a cell
  Index slivers_before = 0;   ///< faces under kSliverArea at either end
  Index slivers_after = 0;
};

/// A face is a sliver when its area at an end is below this times that end's
/// squared diagonal (the measure).
constexpr double kSliverArea = 1e-12;

/// merged, source, target: a morph's merged topology and its vertices on A
/// and B, for A = (VA, FA) and B = (VB, FB) with FA, FB as the overlay saw
/// them (an inside-out file's faces turned). Updated in place.
/// progress: 0..1 over the collapses (a 100k-face morph spends 0.4 s here);
/// cancel throws Cancelled, leaving `merged` part-welded (the caller drops it).
WeldStats weld_merged(MergedTopology& merged, MatrixX3d& source, MatrixX3d& target, const MatrixX3d& VA,
                      const MatrixX3i& FA, const MatrixX3d& VB, const MatrixX3i& FB, double tolerance = 1e-6,
                      Progress* progress = nullptr);

}  // namespace paramorph::morph
