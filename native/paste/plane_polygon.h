// Predicates on closed polygons in a plane (the feature plane of a paste;
// DESIGN.md §4.5): what the seam of a carried feature needs of the
// feature's boundary and the hole cut around it.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <vector>

namespace paramorph::paste {

inline double plane_cross(const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return a.x() * b.y() - a.y() * b.x(); }

/// Whether x lies inside the closed polygon (even-odd rule) or within
/// `tolerance` of its boundary.
inline bool inside_or_near(const std::vector<Eigen::Vector2d>& polygon, const Eigen::Vector2d& x, double tolerance) {
  bool inside = false;
  for (std::size_t i = 0, j = polygon.size() - 1; i < polygon.size(); j = i++) {
    const Eigen::Vector2d &a = polygon[i], &b = polygon[j];
    const Eigen::Vector2d d = b - a;
    const double len2 = d.squaredNorm();
    const double t = len2 > 0 ? std::clamp((x - a).dot(d) / len2, 0.0, 1.0) : 0.0;
    if ((a + t * d - x).norm() <= tolerance) return true;
    if ((a.y() > x.y()) != (b.y() > x.y()) && x.x() < a.x() + (x.y() - a.y()) * (b.x() - a.x()) / (b.y() - a.y()))
      inside = !inside;
  }
  return inside;
}

/// Whether segments [a, b] and [c, d] meet (touching counts).
inline bool segments_meet(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c,
                   const Eigen::Vector2d& d) {
  if (std::max(a.x(), b.x()) < std::min(c.x(), d.x()) || std::max(c.x(), d.x()) < std::min(a.x(), b.x()) ||
      std::max(a.y(), b.y()) < std::min(c.y(), d.y()) || std::max(c.y(), d.y()) < std::min(a.y(), b.y()))
    return false;
  const double d1 = plane_cross(b - a, c - a), d2 = plane_cross(b - a, d - a), d3 = plane_cross(d - c, a - c),
               d4 = plane_cross(d - c, b - c);
  return !((d1 > 0 && d2 > 0) || (d1 < 0 && d2 < 0) || (d3 > 0 && d4 > 0) || (d3 < 0 && d4 < 0));
}

/// Whether the closed loop of points crosses or touches itself.
inline bool self_crossing(const std::vector<Eigen::Vector2d>& loop) {
  const std::size_t k = loop.size();
  for (std::size_t i = 0; i < k; ++i)
    for (std::size_t j = i + 2; j < k; ++j) {
      if (i == 0 && j == k - 1) continue;  // neighbours share a point
      if (segments_meet(loop[i], loop[(i + 1) % k], loop[j], loop[(j + 1) % k])) return true;
    }
  return false;
}

}  // namespace paramorph::paste
