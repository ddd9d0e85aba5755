// Tips of two models paired by what they are (issue 29): each protrusion tip
// (features/protrusion_tips) is described by the path from its model's core
// out to it, sampled at equal steps and measured in the model's own spread
// (each coordinate over the model's area-weighted standard deviation along
// it, at least half the largest, so a long lion and a short cow compare body
// for body), and the tips
// are assigned at least cost (features/min_cost_assignment). What the
// paths cannot tell apart the mirror does: a tip that is its own mirror image
// (a muzzle, a tail) costs more against one of a mirrored pair (an ear, a
// horn, a foot) by mirror_weight times the difference in their loneliness
// (features/mirror_plane); a grazing cow's muzzle points down and its ears
// forward-up like a cat's muzzle (cat -> horned cow: muzzle 16.7 % -> 2.3 %
// of the diagonal as placed). A tail is then
// the tip whose path leaves the body at its back end, whether it is raised
// (a cat) or hangs to the hocks (a cow); a front leg's path runs down from
// the chest, a muzzle's forward from the neck. Comparing where the tips
// themselves are paired the cat's raised tail with nothing on the cow, and
// the sphere maps' tip layout turned a cow 150 degrees onto a cat.
#pragma once

#include <array>
#include <vector>

#include "features/protrusion_tips.h"
#include "mesh/types.h"

namespace paramorph::morph {

struct TipPathPair {
  Index a = -1, b = -1;  ///< vertices of A and of B (the tips)
  double cost = 0;       ///< root mean square distance of the sampled paths, in spreads
};

/// VA, area_a: A's vertices (in the frame both are compared in) and their
/// areas (the spread is area-weighted); tips_a: A's protrusion tips; the same
/// for B, with VB already turned into A's frame. samples >= 2 points per
/// path, from the core to the tip. loneliness_a, loneliness_b: per tip, how
/// alone it is under its model's mirror (features::mirror_loneliness), both
/// empty for no mirror term, weighed by mirror_weight >= 0. Returns the
/// assigned pairs cheaper than max_cost, cheapest first.
std::vector<TipPathPair> tip_path_pairs(const MatrixX3d& VA, const VectorXd& area_a, const features::ProtrusionTips& tips_a,
                                        const MatrixX3d& VB, const VectorXd& area_b, const features::ProtrusionTips& tips_b,
                                        int samples, double max_cost, const VectorXd& loneliness_a = VectorXd(),
                                        const VectorXd& loneliness_b = VectorXd(), double mirror_weight = 0);

}  // namespace paramorph::morph
