// Exact sign tests on the unit sphere for the spherical overlay (thesis 4.4;
// DESIGN.md §4.4 step 3): every decision of the overlay is the sign of one
// determinant det(p, q, r) of input points, evaluated exactly by CGAL's
// filtered predicates, with ties broken by Simulation of Simplicity
// (Edelsbrunner & Mücke 1990) so that the overlay never meets a degenerate
// case and all its decisions describe one (infinitesimally perturbed) input.
//
// det(p, q, r) > 0 says r lies left of the great circle running from p to q,
// seen from outside the sphere (p, q, r counter-clockwise); only the
// directions of the vectors matter, so they need not be normalised.
#pragma once

#include "mesh/types.h"

namespace paramorph::morph {

/// Sign of det(p, q, r) (+1, 0, -1), exact: CGAL::orientation(ORIGIN, p, q, r)
/// with the Exact_predicates_inexact_constructions_kernel (a floating-point
/// filter, exact arithmetic only when the filter cannot decide).
int orientation(const double* p, const double* q, const double* r);

/// A point for perturbed_orientation(): its coordinates and its rank in the
/// symbolic perturbation. rank < 0: the point stays put (the vertices of map
/// A); rank k >= 0: vertex k of map B, which is moved.
struct SpherePoint {
  const double* xyz = nullptr;
  Index rank = -1;
};

/// Sign of det(p, q, r) after moving every ranked point k by
/// (e^(2^(3k)), e^(2^(3k+1)), e^(2^(3k+2))) for an infinitesimal e > 0 (lower
/// ranks move by more): the exact sign where it is not 0, else the sign of the
/// first non-vanishing term of the perturbation's expansion (each term a 2 by 2
/// minor or a coordinate, also exact). Never 0 when one point is ranked and
/// the two fixed ones are independent, or two are ranked and independent:
/// every test between a vertex of one map and an edge of the other (the
/// vertex may coincide with an end of the edge). With none or three ranked it
/// is plain orientation(). Antisymmetric like the determinant, so the answers
/// of all tests are those of one perturbed configuration.
int perturbed_orientation(const SpherePoint& p, const SpherePoint& q, const SpherePoint& r);

}  // namespace paramorph::morph
