#include "mesh/simplify.h"

#include <algorithm>
#include <numeric>
#include <boost/optional.hpp>
#include <vector>

#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/Surface_mesh_simplification/Edge_collapse_visitor_base.h>
#include <CGAL/Surface_mesh_simplification/Policies/Edge_collapse/Count_stop_predicate.h>
#include <CGAL/Surface_mesh_simplification/edge_collapse.h>

#include "common/errors.h"

namespace paramorph {

namespace {

using Kernel = CGAL::Simple_cartesian<double>;
using Surface = CGAL::Surface_mesh<Kernel::Point_3>;
using VertexId = Surface::Vertex_index;
namespace SMS = CGAL::Surface_mesh_simplification;

/// Union-find over the surface's vertex indices: every collapse joins its two
/// ends into the vertex that stays.
struct CollapseRecord : SMS::Edge_collapse_visitor_base<Surface> {
  std::vector<Index>* parent = nullptr;
  Progress* progress = nullptr;
  std::size_t collected = 0, selected = 0, edges = 1, stop_edges = 0;
  // Collecting costs every edge (a tenth of the time), collapsing the rest.
  void OnCollected(const SMS::Edge_profile<Surface>&, const boost::optional<double>&) {
    if (progress && ++collected % 1024 == 0)
      progress->report(0.1 * double(collected) / double(edges), "simplify");
  }
  void OnSelected(const SMS::Edge_profile<Surface>&, const boost::optional<double>&, std::size_t initial,
                  std::size_t current) {
    if (progress && ++selected % 128 == 0 && initial > stop_edges)
      progress->report(0.1 + 0.9 * double(initial - current) / double(initial - stop_edges), "simplify");
  }
  void OnCollapsed(const SMS::Edge_profile<Surface>& profile, const VertexId& kept) {
    (*parent)[std::size_t(profile.v0())] = Index(kept);
    (*parent)[std::size_t(profile.v1())] = Index(kept);
    (*parent)[std::size_t(kept)] = Index(kept);
  }
};

Index root(std::vector<Index>& parent, Index v) {
  while (parent[std::size_t(v)] != v) v = parent[std::size_t(v)] = parent[std::size_t(parent[std::size_t(v)])];
  return v;
}

}  // namespace

SimplifiedMesh simplify(const MatrixX3d& V, const MatrixX3i& F, Index target_faces, Progress* progress) {
  PM_REQUIRE(target_faces > 0, InvalidInputError, "target_faces must be positive");
  SimplifiedMesh out;
  if (F.rows() <= target_faces) {
    out.V = V;
    out.F = F;
    out.proxy_of.resize(V.rows());
    std::iota(out.proxy_of.data(), out.proxy_of.data() + V.rows(), 0);
    return out;
  }
  Surface surface;
  std::vector<VertexId> ids(std::size_t(V.rows()));
  for (Index v = 0; v < V.rows(); ++v) ids[std::size_t(v)] = surface.add_vertex({V(v, 0), V(v, 1), V(v, 2)});
  for (Index f = 0; f < F.rows(); ++f) {
    const auto face = surface.add_face(ids[std::size_t(F(f, 0))], ids[std::size_t(F(f, 1))], ids[std::size_t(F(f, 2))]);
    PM_REQUIRE(face != Surface::null_face(), InvalidInputError, "simplify: face ", f,
               " makes the mesh non-manifold or turns against its neighbours");
  }
  std::vector<Index> parent(std::size_t(V.rows()));
  std::iota(parent.begin(), parent.end(), Index(0));
  CollapseRecord record;
  record.parent = &parent;
  record.progress = progress;
  record.edges = std::max<std::size_t>(surface.number_of_edges(), 1);
  // Closed triangle meshes have 3/2 edges per face.
  record.stop_edges = std::size_t(3 * target_faces / 2);
  const SMS::Count_stop_predicate<Surface> stop{record.stop_edges};
  SMS::edge_collapse(surface, stop, CGAL::parameters::visitor(record));

  // Surviving vertices in index order, then each input vertex's survivor.
  std::vector<Index> proxy(std::size_t(V.rows()), -1);
  Index count = 0;
  for (const VertexId v : surface.vertices()) proxy[std::size_t(v)] = count++;
  out.V.resize(count, 3);
  for (const VertexId v : surface.vertices()) {
    const auto& p = surface.point(v);
    out.V.row(proxy[std::size_t(v)]) << p.x(), p.y(), p.z();
  }
  out.F.resize(Index(surface.number_of_faces()), 3);
  Index f = 0;
  for (const auto face : surface.faces()) {
    int k = 0;
    for (const VertexId v : CGAL::vertices_around_face(surface.halfedge(face), surface))
      out.F(f, k++) = proxy[std::size_t(v)];
    ++f;
  }
  out.proxy_of.resize(V.rows());
  for (Index v = 0; v < V.rows(); ++v) out.proxy_of[v] = proxy[std::size_t(root(parent, v))];
  return out;
}

}  // namespace paramorph
