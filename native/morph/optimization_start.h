// The start of optimize_sphere_map in morph (thesis 4.3.2–4.3.3; DESIGN.md
// §4.4 step 1): the conformal sphere map, unless it squeezes faces, then the
// thesis' own start, the radial projection relaxed until no face folds.
//
// Why: a conformal map shrinks long protrusions (tentacles, a bunny's ears)
// exponentially, to triple products of 1e-12..1e-17, and the optimization
// then has far to go. The relaxed projection starts near its targets there:
// optimize_sphere_map on tentacle_sphere(4) (18.7k faces) 4 s against 34 s,
// on the closed bunny (69.7k faces) 40 s against 140 s. Where the conformal
// map is not squeezed it is as good or better: the 20k-face octopus 11 s
// against 19 s (the relaxed start's larger smallest face raises epsilon).
#pragma once

#include "common/progress.h"
#include "mesh/types.h"

namespace paramorph::morph {

/// A conformal map whose smallest face triple product is under this share of
/// the mean counts as squeezed (measured: spot 2.5e-5, the octopus 0.03,
/// pair20k's Suzanne 1e-4; the bunny 4e-9, tentacles 1e-17 and below).
constexpr double kSqueezedShare = 1e-6;

/// #V by 3 unit vectors, a fold-free map of the closed genus-0 mesh (V, F):
/// spherical::sphere_map's conformal map, or the relaxed radial projection
/// (sphere_map with init Relaxation and no outer steps) where the conformal
/// one is squeezed and the relaxation unfolds the projection.
MatrixX3d optimization_start(const MatrixX3d& V, const MatrixX3i& F, Progress* progress = nullptr);

}  // namespace paramorph::morph
