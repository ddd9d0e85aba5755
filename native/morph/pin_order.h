// Whether pins can hold without turning a map inside out (issue 16): an
// orientation-preserving map keeps the turning sense of every clearly
// oriented triple of points; pins whose triples mostly turn the other way on
// one model than where they are pinned on the other (left and right swapped,
// a mirrored file) ask for a reflection.
#pragma once

#include <string>
#include <vector>

#include "mesh/types.h"

namespace paramorph::morph {

struct PinOrder {
  Index oriented = 0;      ///< triples clearly oriented on both sides (normalised determinant > 0.05)
  Index disagreeing = 0;   ///< of those, triples that turn the other way
  std::vector<Index> pins; ///< pins of the disagreeing triples, the most involved first
  /// More than half of the clearly oriented triples disagree.
  bool mirrored() const { return oriented > 0 && 2 * disagreeing > oriented; }
};

/// on_b, on_a: #k by 3 points of the pins on the two sides (unit vectors of
/// two sphere maps, or any directions from a centre). Every triple up to 60
/// pins; beyond, about 34k triples drawn with a fixed seed.
PinOrder pin_order(const MatrixX3d& on_b, const MatrixX3d& on_a);

/// The ConstraintError text for mirrored pins, naming the most involved ones.
std::string mirrored_pins_message(const PinOrder& order);

}  // namespace paramorph::morph
