#include "morph/pin_order.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <utility>

#include <Eigen/Geometry>

#include "common/errors.h"
#include "mesh/validate.h"

namespace paramorph::morph {

namespace {

/// det(a, b, c) over the product of the chord lengths: the turning sense of
/// three points and how far they are from lying on one great circle.
double shape_orientation(const Eigen::RowVector3d& a, const Eigen::RowVector3d& b, const Eigen::RowVector3d& c) {
  const double scale = (a - b).norm() * (b - c).norm() * (c - a).norm();
  return scale > 0 ? a.dot(b.cross(c)) / scale : 0.0;
}

}  // namespace

PinOrder pin_order(const MatrixX3d& on_b, const MatrixX3d& on_a) {
  PinOrder order;
  const Index k = on_a.rows();
  PM_REQUIRE(on_b.rows() == k, InvalidInputError, "pin_order: ", on_b.rows(), " and ", k, " pins");
  std::map<Index, Index> count;
  auto judge = [&](Index i, Index j, Index l) {
    const double a = shape_orientation(on_a.row(i), on_a.row(j), on_a.row(l));
    const double b = shape_orientation(on_b.row(i), on_b.row(j), on_b.row(l));
    if (std::abs(a) < 0.05 || std::abs(b) < 0.05) return;
    ++order.oriented;
    if ((a > 0) != (b > 0)) {
      ++order.disagreeing;
      ++count[i], ++count[j], ++count[l];
    }
  };
  constexpr Index kAllUpTo = 60;     // 34,220 triples
  constexpr int kSampled = 34220;    // beyond: as many triples, drawn with a fixed seed (the same verdict every run)
  if (k <= kAllUpTo) {
    for (Index i = 0; i < k; ++i)
      for (Index j = i + 1; j < k; ++j)
        for (Index l = j + 1; l < k; ++l) judge(i, j, l);
  } else {
    std::mt19937_64 draw(20161);
    std::uniform_int_distribution<Index> any(0, k - 1);
    for (int s = 0; s < kSampled; ++s) {
      Index t[3] = {any(draw), any(draw), any(draw)};
      if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) continue;
      std::sort(t, t + 3);  // the same sense as the enumeration (i < j < l)
      judge(t[0], t[1], t[2]);
    }
  }
  std::vector<std::pair<Index, Index>> ranked;
  for (const auto& [pin, n] : count) ranked.emplace_back(-n, pin);
  std::sort(ranked.begin(), ranked.end());
  for (const auto& [n, pin] : ranked) order.pins.push_back(pin);
  return order;
}

std::string mirrored_pins_message(const PinOrder& order) {
  std::vector<Index> named(order.pins.begin(), order.pins.begin() + std::min<std::size_t>(order.pins.size(), 8));
  return detail::concat("the pins are in mirrored order: ", order.disagreeing, " of ", order.oriented,
                        " clearly oriented triples of pins turn the other way on one mesh than on the other (pins ",
                        format_indices(named), "); are left and right swapped, or is one file mirrored?");
}

}  // namespace paramorph::morph
