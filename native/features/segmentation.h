// A segmentation of a mesh into face regions, and what every consumer of one
// needs (thesis 3.5.1, 4.5; DESIGN.md §4.3): the add-on colours and selects
// regions, feature matching builds the region graph from the adjacency.
#pragma once

#include <functional>
#include <utility>
#include <vector>

#include "mesh/tri_mesh.h"

namespace paramorph::features {

struct Segmentation {
  VectorXi face_labels;               ///< #F, region of each face, 0 .. regions - 1
  std::vector<Index> seeds;           ///< per region, the vertex it grew from
  VectorXd area;                      ///< per region, 3D surface area
  MatrixX3d centroid;                 ///< per region, area-weighted face centroid
  std::vector<std::pair<Index, Index>> adjacency;  ///< (a, b), a < b, regions sharing an edge
  Index regions() const { return Index(seeds.size()); }
};

/// Fills area, centroid and adjacency from face_labels and seeds (every face
/// labelled, labels 0 .. seeds.size() - 1).
void summarise_regions(const TriMesh& mesh, Segmentation& segmentation);

/// Splits every region into the pieces its faces form when two faces of it
/// count as joined only across an edge where `joined(f, g)` holds (always
/// true: its edge-connected pieces). A piece keeps its region's seed if it
/// holds it (the first such piece), else it is seeded at its vertex of
/// highest `level`. Pieces are numbered in their regions' order, the one
/// with the seed first; the summary is recomputed.
void split_regions(const TriMesh& mesh, const VectorXd& level, Segmentation& segmentation,
                   const std::function<bool(Index, Index)>& joined = {});

}  // namespace paramorph::features
