// Merging the vertices of a sphere arrangement that stand for one point
// (thesis 4.4; DESIGN.md §4.4 step 3). The perturbed arrangement
// (sphere_arrangement.h) is exact, so a vertex of B on a vertex of A comes out
// as two vertices and a few crossings at one point, and an edge of B along an
// edge of A as a strip of zero width; near-degenerate inputs (B turned by
// 1e-12) give the same at 1e-12. Such groups become one vertex here.
//
// Rule: vertices are merged into one point P when P lies within `tolerance`
// (radians) of each merged vertex of A or B and of both arcs through each
// merged crossing, P being the merged vertex of A if there is one, else the
// vertex of B, else one of the crossings; and only where may_merge() allows:
// never two vertices of A or two of B (every input vertex stays one vertex),
// nor crossings on two edges of A (of B) without the edges' common vertex.
// Candidates are the pairs of vertices on one cell (cell sides and, by
// distance alone, cell diagonals), taken in order of the distance they move a
// vertex off its arcs, each taken if the grown group still meets the rule;
// pairs refused are tried again until nothing changes (a refusal may lapse
// once a group holds a vertex). A crossing of two nearly parallel arcs is
// merged with a neighbour along one arc that lies within tolerance of the
// other, however far along the arcs it is: its own position is ill-defined,
// and the strip between the arcs has no width to keep.
//
// Groups of vertices spread over about the tolerance can still leave two
// vertices closer than it that the rule cannot join, and moving a vertex by up
// to the tolerance can turn such a tiny cell over. The overlay finds those
// cells (no positive triangulation) and asks again with `forced` pairs, which
// are merged after the rule's merges whatever their distance (still only
// where may_merge() allows).
#pragma once

#include <utility>
#include <vector>

#include "morph/sphere_arrangement.h"

namespace paramorph::morph {

/// What ties a group of vertices down: its vertex of A and of B, and (when it
/// has no such vertex) the one edge of A and of B its crossings lie on; -1 none.
struct ClusterAnchors {
  Index vertex_a = -1, vertex_b = -1, edge_a = -1, edge_b = -1;
};

/// Whether two groups may become one: not two vertices of A or of B, and a
/// group without a vertex of A lies on at most one edge of A (else two arcs
/// of A would share a piece beside their common vertex), the same for B.
bool may_merge(const ClusterAnchors& p, const ClusterAnchors& q);

struct VertexClusters {
  VectorXi cluster;    ///< per arrangement vertex: its cluster, in [0, #clusters)
  MatrixX3d position;  ///< #clusters by 3: the unit vector each cluster stands for
  VectorXi vertex_a;   ///< per cluster: its vertex of A, or -1
  VectorXi vertex_b;   ///< per cluster: its vertex of B, or -1
  /// Per cluster: an edge of A through it (that of a crossing in it) when it
  /// has no vertex of A, else -1; edge_b the same for B.
  VectorXi edge_a, edge_b;
  VectorXi representative;  ///< per cluster: the arrangement vertex whose position it takes
  Index merged = 0;         ///< arrangement vertices merged into another (vertices - clusters)
  /// Largest distance from a merged cluster's position to the input vertices
  /// and arcs its members stand for (<= tolerance without forced pairs).
  double max_deviation = 0;

  Index size() const { return Index(position.rows()); }
  ClusterAnchors anchors(Index k) const;
};

/// tolerance: angular distance in radians (> 0). forced: pairs of
/// arrangement vertices to merge as well (see above).
VertexClusters merge_close_vertices(const SphereArrangement& arrangement,
                                    const SphereMapTopology& a, const SphereMapTopology& b,
                                    double tolerance,
                                    const std::vector<std::pair<Index, Index>>& forced = {});

}  // namespace paramorph::morph
