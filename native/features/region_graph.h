// Region adjacency graph with geodesic edge lengths, and its reduction
// (thesis 4.5, Fig. 4.5; DESIGN.md §4.3).
//
// Nodes are the regions of a Segmentation, edges join regions that share a
// mesh edge. Each region is stood for by its anchor, the region's vertex
// nearest its centroid (the centroid of a curved region lies off the
// surface; its nearest vertex is its projection onto the region). An edge's
// length is the geodesic distance between the two anchors, approximated by
// the shortest path along mesh edges (Dijkstra, stopped once every
// neighbour's anchor is reached; it overestimates the true geodesic by a few
// per cent, more on coarse or grid-aligned triangulations).
//
// Reduction: "edges that correspond to large geodesic distances" are
// dropped so matching sees local neighbourhoods. An edge is long when its
// length exceeds `long_edge_factor` times the median length of all edges
// of the graph (a scale-free rule), and it is dropped unless it is the
// shortest edge of one of its two regions, so the reduction never isolates
// a region that had neighbours.
#pragma once

#include <utility>
#include <vector>

#include "features/segmentation.h"

namespace paramorph::features {

struct RegionGraphOptions {
  /// Edges longer than this many times the median edge length are dropped
  /// (except a region's shortest edge). Must be > 0; infinity keeps all.
  double long_edge_factor = 2.0;
};

struct RegionGraph {
  /// The reduced graph: (a, b) with a < b, sorted; a subset of the adjacency.
  std::vector<std::pair<Index, Index>> edges;
  /// Per edge, the geodesic distance between the anchors, in the units of V.
  std::vector<double> lengths;
  /// Per region, its number of edges in the reduced graph.
  std::vector<int> degree;
  /// The long edges removed by the reduction, sorted, and their lengths.
  std::vector<std::pair<Index, Index>> dropped;
  std::vector<double> dropped_lengths;
  /// Per region, the vertex standing for its centroid (a vertex of its faces).
  std::vector<Index> anchors;
};

/// V: #V by 3 positions; F: #F by 3 triangles (0-based); regions: a
/// segmentation of F (e.g. feature_regions(V, F)) with its summary filled
/// (face_labels, seeds, centroid, adjacency as summarise_regions makes them).
/// Throws InvalidInputError for malformed arrays, a segmentation that does
/// not fit the mesh, or a bad option.
RegionGraph region_graph(const MatrixX3d& V, const MatrixX3i& F, const Segmentation& regions,
                         const RegionGraphOptions& options = {});

}  // namespace paramorph::features
