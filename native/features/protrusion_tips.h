// Protrusion tips (issue 29): the points a limb, a tail, a muzzle, a horn or
// an ear ends in, found as the local maxima of the average geodesic distance
// (the mean edge-path distance to samples spread over the surface; a
// protrusion's far end is the farthest from everything else), with the path
// from the shape's core (the vertex of least average distance) out to each.
// Unlike extremity_tips this needs no segmentation: on a scanned cow whose
// short front legs the conformal segmentation folded into the body, its tips
// are still on all four hooves, the tail's hanging end and the muzzle. The
// paths say what a tip is (morph/tip_path_pairs): a tail leaves the body at
// its back end, a leg below it, whatever way the tip itself then points.
#pragma once

#include <cstddef>
#include <vector>

#include "mesh/types.h"

namespace paramorph::features {

struct ProtrusionTips {
  VectorXd average_distance;             ///< per vertex: mean edge-path distance to the samples
  Index core = -1;                       ///< the vertex of least average distance
  std::vector<Index> vertices;           ///< the tips, highest average distance first
  std::vector<std::vector<Index>> paths; ///< per tip: the vertices of a shortest edge path from the core to it
};

struct ProtrusionOptions {
  /// A tip is the highest vertex (by average distance) within this edge-path
  /// distance of itself (units of V): about the width of the thinnest limb
  /// that should count as its own (0.15 for a model scaled to unit area).
  double radius = 0.15;
  std::size_t samples = 100;   ///< farthest-point samples the average is over
  std::size_t max_tips = 24;   ///< the highest kept
};

/// V, F: a connected mesh (a proxy of a few thousand faces: one Dijkstra per
/// sample). Tips are only sought above the median average distance. Raises
/// InvalidInputError for a non-positive radius or no samples.
ProtrusionTips protrusion_tips(const MatrixX3d& V, const MatrixX3i& F, const ProtrusionOptions& options = {});

}  // namespace paramorph::features
