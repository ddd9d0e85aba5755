// Shape signature and similarity (thesis 3.5.3, DESIGN.md §4.3): the
// histogram of the area stretch of a conformal map onto the sphere.
//
// A conformal sphere map shrinks protruding parts (limbs) and keeps the body,
// largely whatever the pose, so the distribution of log area stretch
// describes the shape: similar shapes give similar histograms. Each face's
// log stretch is weighted by its share of the surface area, which is the
// histogram of a uniform sampling of the surface, so the signature does not
// depend on the tessellation.
#pragma once

#include <optional>

#include "common/progress.h"
#include "mesh/types.h"

namespace paramorph::features {

struct SignatureOptions {
  int bins = 32;           ///< histogram bins, >= 1
  double log_range = 4.0;  ///< bins cover log stretch in [-log_range, log_range]; > 0
  /// #V by 3 positions on the unit sphere (e.g. SphereMapResult::positions);
  /// computed with spherical::sphere_map (conformal weights) when absent.
  std::optional<MatrixX3d> sphere;
};

/// Signature of a closed genus-0 mesh: #bins weights summing to 1.
///
/// Per face f, stretch s_f = (A_f / A) / (a_f / a) with A_f the face's area,
/// a_f the area of its chord triangle on the sphere, A and a their totals
/// (> 1 where the map shrinks the surface, Def. 3.1). Face f adds the weight
/// A_f / A at x = ln s_f. Bin k covers [-L + k w, -L + (k + 1) w), w = 2L/bins,
/// L = log_range; x beyond the range counts in the end bins. Light smoothing:
/// the weight is split linearly between the two bins whose centres bracket x
/// (so a small shift of x moves a little weight, never a whole face's).
///
/// V: #V by 3, F: #F by 3 (counter-clockwise seen from outside). Without
/// options.sphere the mesh must be closed, connected, manifold and genus 0
/// (sphere_map's checks and errors); with it only the arrays are checked.
/// Throws InvalidInputError for bad options or arrays (a sphere of the wrong
/// shape, a mesh or sphere of zero area), the sphere map's MeshError
/// subclasses, and Cancelled when `progress` says so.
VectorXd shape_signature(const MatrixX3d& V, const MatrixX3i& F,
                         const SignatureOptions& options = {}, Progress* progress = nullptr);

/// Distance between two signatures made with the same bins and log_range:
/// the earth mover's distance in log-stretch units, i.e. the L1 distance
/// between their cumulative sums times the bin width 2 log_range / bins.
/// A whole histogram shifted by one bin is one bin width away, whatever its
/// shape, so small shifts give small distances (unlike a bin-by-bin norm).
/// Each input is normalised to sum 1 first. Symmetric, 0 for equal inputs,
/// at most 2 log_range. Throws InvalidInputError when the sizes differ or a
/// histogram is empty, has negative or non-finite entries, or sums to 0.
double signature_distance(const VectorXd& a, const VectorXd& b, double log_range = 4.0);

}  // namespace paramorph::features
