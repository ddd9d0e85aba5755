// Best-shaped positive triangulation of a small spherical polygon
// (morph/triangulate_spherical_polygon.h).
#include "morph/triangulate_spherical_polygon.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <limits>
#include <stdexcept>

#include "morph/sphere_predicates.h"

namespace paramorph::morph {

namespace {

/// Quality of triangle (a, b, c) when positively oriented, else -1.
double score(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  if (orientation(a.data(), b.data(), c.data()) <= 0) return -1.0;
  const double det = a.dot(b.cross(c));
  const double edges = (a - b).squaredNorm() + (b - c).squaredNorm() + (c - a).squaredNorm();
  return std::max(det / edges, std::numeric_limits<double>::min());  // > 0: it is positive
}

}  // namespace

bool triangulate_spherical_polygon(const Eigen::Vector3d* P, int n, std::array<int, 3>* out) {
  if (n < 3 || n > kMaxPolygonCorners)
    throw std::logic_error("overlay: cell polygon with an unexpected number of corners");
  if (n == 3) {
    out[0] = {0, 1, 2};
    return score(P[0], P[1], P[2]) > 0;
  }
  // best[i][j]: the best worst-triangle score of the sub-polygon i, i+1, ..., j
  // closed by the diagonal (j, i); split[i][j]: its apex k.
  double best[kMaxPolygonCorners][kMaxPolygonCorners];
  int split[kMaxPolygonCorners][kMaxPolygonCorners];
  constexpr double kOpen = std::numeric_limits<double>::infinity();
  for (int i = 0; i + 1 < n; ++i) best[i][i + 1] = kOpen;
  for (int length = 2; length < n; ++length)
    for (int i = 0; i + length < n; ++i) {
      const int j = i + length;
      best[i][j] = -std::numeric_limits<double>::infinity();
      for (int k = i + 1; k < j; ++k) {
        const double s = std::min({score(P[i], P[k], P[j]), best[i][k], best[k][j]});
        if (s > best[i][j]) best[i][j] = s, split[i][j] = k;
      }
    }
  // Unfold the choices into triangles.
  int count = 0;
  std::array<std::pair<int, int>, kMaxPolygonCorners> stack;
  int top = 0;
  stack[top++] = {0, n - 1};
  while (top > 0) {
    const auto [i, j] = stack[--top];
    if (j - i < 2) continue;
    const int k = split[i][j];
    out[count++] = {i, k, j};
    stack[top++] = {i, k};
    stack[top++] = {k, j};
  }
  return best[0][n - 1] > 0;
}

}  // namespace paramorph::morph
