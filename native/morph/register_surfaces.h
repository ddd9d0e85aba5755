// Feature-guided 3D registration of model B onto model A (thesis ch. 4:
// the correspondence the morph's maps must encode; DESIGN.md §4.4 step 2).
//
// The aligned sphere map of B (align_sphere_map) needs, for every vertex of
// B, where its partner on A is on A's map. Warping on the sphere from a few
// feature pairs cannot give that: a smooth deformation of the model moves
// radial directions by amounts that jump with the radius at bumps. This
// fits a smooth map T: R^3 -> R^3 taking B onto A instead; each vertex of B
// is then read on A's map at the closest point of A to T(v) (the morph does
// that). T is a polynomial (degree 1: affine, 2, 3) in B's normalised
// coordinates, fitted by point-to-plane ICP: repeatedly, every vertex of B
// is moved by T, its closest point on A (and that face's normal) found, and
// T refitted to the planes by weighted least squares (weights: B's vertex
// areas; closest points farther than `max_distance` ignored; a small
// damping towards the previous T keeps tangential motion on smooth parts,
// which the planes do not fix, where it was). Degrees are raised one at a
// time (coarse to fine), so the affine fit places the features before the
// bends are fitted.
//
// Starts: the caller's (e.g. the feature match's similarity, and the
// identity rotation — the objects' own placement); each is run and the one
// with the lowest final cost wins, the first unless another is lower by
// more than 5 per cent.
#pragma once

#include <vector>

#include "common/progress.h"
#include "mesh/types.h"

namespace paramorph::morph {

/// x -> phi((x - centre) / scale) coefficients, phi the monomials of
/// degree <= `degree` in (x, y, z): 1, x, y, z (4), then x^2, y^2, z^2, xy,
/// yz, zx (10), then the 10 cubic ones (20).
struct PolynomialWarp {
  Eigen::RowVector3d centre = Eigen::RowVector3d::Zero();
  double scale = 1.0;
  int degree = 1;
  Eigen::MatrixXd coefficients;  ///< basis_size(degree) by 3

  /// A similarity: x -> to_centre + to_scale * rotation * (x - centre) / scale.
  static PolynomialWarp similarity(const Eigen::RowVector3d& centre, double scale,
                                   const Eigen::Matrix3d& rotation,
                                   const Eigen::RowVector3d& to_centre, double to_scale);
  static int basis_size(int degree);
  /// #X by 3 warped points.
  MatrixX3d operator()(const MatrixX3d& X) const;
};

struct RegisterOptions {
  int max_degree = 3;         ///< 1 (affine) .. 3
  int iterations = 8;         ///< ICP rounds per degree
  /// Closest points farther than this share of A's bounding-box diagonal are
  /// left out of a fit (and count as this far in the cost).
  double max_distance = 0.1;
  double damping = 1e-3;      ///< pull towards the previous T, relative to the fit's scale
};

struct Registration {
  PolynomialWarp warp;
  std::size_t start = 0;      ///< which start won
  /// Area-weighted mean distance of T(B) from A (capped at max_distance), as a
  /// share of A's bounding-box diagonal: per start, and the winner's.
  std::vector<double> start_costs;
  double cost = 0;
};

/// VA, FA / VB, FB: the two triangle meshes (closed or not); starts: one or
/// more warps of B onto A (any degree <= max_degree; InvalidInputError when
/// none). Raises InvalidInputError for bad options, Cancelled.
Registration register_surfaces(const MatrixX3d& VA, const MatrixX3i& FA, const MatrixX3d& VB,
                               const MatrixX3i& FB, const std::vector<PolynomialWarp>& starts,
                               const RegisterOptions& options = {}, Progress* progress = nullptr);

}  // namespace paramorph::morph
