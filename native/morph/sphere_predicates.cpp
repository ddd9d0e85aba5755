// Exact and symbolically perturbed orientation on the sphere
// (morph/sphere_predicates.h). The only file of the overlay that includes
// CGAL (it is compiled with CGAL's -frounding-math, see CMakeLists.txt).
#include "morph/sphere_predicates.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

namespace paramorph::morph {

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;

/// Exact sign of x0 * y1 - x1 * y0: the 2D orientation of (0, (x0, y0), (x1, y1)).
int sign_of_minor(double x0, double y0, double x1, double y1) {
  return int(
      CGAL::orientation(Kernel::Point_2(0, 0), Kernel::Point_2(x0, y0), Kernel::Point_2(x1, y1)));
}

bool same_point(const double* p, const double* q) {
  return p[0] == q[0] && p[1] == q[1] && p[2] == q[2];
}

/// Exact signs of the components of a x b (0 at once for a repeated point,
/// where CGAL's filter would fail).
int cross_component_sign(const double* a, const double* b, int component) {
  if (same_point(a, b)) return 0;
  const int i = (component + 1) % 3, j = (component + 2) % 3;
  return sign_of_minor(a[i], a[j], b[i], b[j]);  // (a x b)_c = a_i b_j - a_j b_i
}

int sign_of(double x) {
  return (x > 0) - (x < 0);
}

/// det(p, q, r + delta_r), r ranked, p and q fixed, given det(p, q, r) == 0:
/// the expansion is sum_j delta_j (p x q)_j with delta_0 >> delta_1 >> delta_2.
int one_perturbed(const double* p, const double* q) {
  for (int j = 0; j < 3; ++j)
    if (const int s = cross_component_sign(p, q, j)) return s;
  return 0;  // p and q parallel: not an edge
}

/// det(u + du, w + dw, r), u and w ranked (ranks ru != rw), r fixed, given
/// det(u, w, r) == 0. Multilinear expansion: du_j (w x r)_j + dw_l (r x u)_l +
/// du_j dw_l (E_j x E_l) . r, taken in the order of the infinitesimals' sizes.
int two_perturbed(const double* u, Index ru, const double* w, Index rw, const double* r) {
  // (E_j x E_l) . r for the pair term: 0 on the diagonal, else +-r of the third axis.
  auto pair_sign = [&](int j, int l) {
    if (j == l) return 0;
    const int h = 3 - j - l;
    const bool even = (l == (j + 1) % 3);  // (0,1), (1,2), (2,0) give +r_h
    return even ? sign_of(r[h]) : -sign_of(r[h]);
  };
  if (ru < rw) {
    // du_0 >> du_1 >> du_2 >> dw_0 >> dw_0 du_0 >> dw_0 du_1 >> dw_0 du_2 >> dw_1 >> ...
    for (int j = 0; j < 3; ++j)
      if (const int s = cross_component_sign(w, r, j)) return s;
    for (int l = 0; l < 3; ++l) {
      if (const int s = cross_component_sign(r, u, l)) return s;
      for (int j = 0; j < 3; ++j)
        if (const int s = pair_sign(j, l)) return s;
    }
  } else {
    for (int l = 0; l < 3; ++l)
      if (const int s = cross_component_sign(r, u, l)) return s;
    for (int j = 0; j < 3; ++j) {
      if (const int s = cross_component_sign(w, r, j)) return s;
      for (int l = 0; l < 3; ++l)
        if (const int s = pair_sign(j, l)) return s;
    }
  }
  return 0;  // r == 0
}

}  // namespace

int orientation(const double* p, const double* q, const double* r) {
  return int(CGAL::orientation(Kernel::Point_3(0, 0, 0), Kernel::Point_3(p[0], p[1], p[2]),
                               Kernel::Point_3(q[0], q[1], q[2]),
                               Kernel::Point_3(r[0], r[1], r[2])));
}

int perturbed_orientation(const SpherePoint& p, const SpherePoint& q, const SpherePoint& r) {
  // A repeated point makes the determinant exactly 0 without asking CGAL,
  // whose filter would fail and fall back to exact arithmetic (the common
  // tie where a vertex of B sits on a vertex of A).
  const bool repeated =
      same_point(p.xyz, q.xyz) || same_point(q.xyz, r.xyz) || same_point(r.xyz, p.xyz);
  if (!repeated)
    if (const int s = orientation(p.xyz, q.xyz, r.xyz)) return s;
  const int ranked = (p.rank >= 0) + (q.rank >= 0) + (r.rank >= 0);
  // The determinant is invariant under cyclic shifts: rotate the arguments
  // into the canonical forms det(p, q, r*) and det(u*, w*, r).
  if (ranked == 1) {
    if (r.rank >= 0) return one_perturbed(p.xyz, q.xyz);
    if (p.rank >= 0) return one_perturbed(q.xyz, r.xyz);  // det(p*, q, r) = det(q, r, p*)
    return one_perturbed(r.xyz, p.xyz);                   // det(p, q*, r) = det(r, p, q*)
  }
  if (ranked == 2) {
    if (r.rank < 0) return two_perturbed(p.xyz, p.rank, q.xyz, q.rank, r.xyz);
    if (p.rank < 0) return two_perturbed(q.xyz, q.rank, r.xyz, r.rank, p.xyz);
    return two_perturbed(r.xyz, r.rank, p.xyz, p.rank, q.xyz);  // det(p*, q, r*) = det(r*, p*, q)
  }
  return 0;
}

}  // namespace paramorph::morph
