#include "paste/selection_patch.h"

#include <algorithm>

#include "common/errors.h"
#include "mesh/validate.h"

namespace paramorph::paste {

SelectionPatch selection_patch(const TriMesh& mesh, const std::vector<Index>& selected) {
  const Index nf = mesh.num_faces(), nv = mesh.num_vertices();
  PM_REQUIRE(!selected.empty(), EmptySelectionError, "the selection is empty: select the feature's faces");
  std::vector<char> in(nf, 0);
  for (Index f : selected) {
    PM_REQUIRE(f >= 0 && f < nf, InvalidInputError, "selected face ", f, " is out of range for ", nf,
               " faces");
    PM_REQUIRE(!in[f], InvalidInputError, "selected face ", f, " is given twice");
    in[f] = 1;
  }
  PM_REQUIRE(Index(selected.size()) < nf, WholeMeshSelectedError, "all ", nf,
             " faces are selected: a feature needs surface left around it");

  // Edge-connected: flood across edges with two selected faces.
  const MatrixX3i& FE = mesh.face_edges();
  const Csr& EF = mesh.edge_faces();
  std::vector<char> reached(nf, 0);
  std::vector<Index> stack{selected.front()};
  reached[selected.front()] = 1;
  Index count = 0;
  while (!stack.empty()) {
    const Index f = stack.back();
    stack.pop_back();
    ++count;
    for (int k = 0; k < 3; ++k) {
      const Index e = FE(f, k);
      for (Index i = EF.begin(e); i < EF.end(e); ++i) {
        const Index g = EF.items[i];
        if (in[g] && !reached[g]) reached[g] = 1, stack.push_back(g);
      }
    }
  }
  PM_REQUIRE(count == Index(selected.size()), SelectionTopologyError, "the selection is not connected: ",
             selected.size() - count, " of its ", selected.size(),
             " faces do not share an edge path with the rest; select one piece");

  SelectionPatch patch;
  std::vector<Index> faces = selected;
  std::sort(faces.begin(), faces.end());
  patch.faces = Eigen::Map<const VectorXi>(faces.data(), Index(faces.size()));
  std::vector<Index> local(nv, -1);
  for (Index f : faces)
    for (int k = 0; k < 3; ++k) local[mesh.F()(f, k)] = 0;
  std::vector<Index> vertices;
  for (Index v = 0; v < nv; ++v)
    if (local[v] == 0) local[v] = Index(vertices.size()), vertices.push_back(v);
  patch.vertices = Eigen::Map<const VectorXi>(vertices.data(), Index(vertices.size()));
  patch.F.resize(Index(faces.size()), 3);
  MatrixX3d V(Index(vertices.size()), 3);
  for (Index i = 0; i < Index(vertices.size()); ++i) V.row(i) = mesh.V().row(vertices[i]);
  for (Index i = 0; i < Index(faces.size()); ++i)
    for (int k = 0; k < 3; ++k) patch.F(i, k) = local[mesh.F()(faces[i], k)];

  // Topology of the selection as a surface of its own.
  const TriMesh sub(V, patch.F);
  const MeshReport r = validate(sub, 0.0);
  PM_REQUIRE(r.non_manifold_vertices.empty(), SelectionTopologyError,
             "the selection is pinched at vertices ", [&] {
               std::vector<Index> src;
               for (Index v : r.non_manifold_vertices) src.push_back(vertices[v]);
               return format_indices(src);
             }(), " (its faces meet there only at a corner); select a piece without pinches");
  const Index b = r.boundary_loops, chi = r.euler_characteristic;
  const Index twice_genus = 2 - b - chi;
  PM_REQUIRE(twice_genus <= 0, SelectionTopologyError, "the selection has handles (genus ", twice_genus / 2,
             ", ", b, " boundary loops); select a disc or an annulus");
  PM_REQUIRE(b == 1 || b == 2, SelectionTopologyError, "the selection has ", b,
             " boundary loops; select a disc (1 loop) or an annulus (2 loops)");
  patch.boundary_loops = sub.boundary_loops();

  // The ring: unselected source faces around the boundary vertices.
  std::vector<char> ring(nf, 0);
  const Csr& VC = mesh.vertex_corners();
  for (const auto& loop : patch.boundary_loops)
    for (Index v : loop) {
      const Index s = vertices[v];
      for (Index i = VC.begin(s); i < VC.end(s); ++i)
        if (!in[VC.items[i] / 3]) ring[VC.items[i] / 3] = 1;
    }
  std::vector<Index> ring_faces;
  for (Index f = 0; f < nf; ++f)
    if (ring[f]) ring_faces.push_back(f);
  patch.ring_faces = Eigen::Map<const VectorXi>(ring_faces.data(), Index(ring_faces.size()));
  return patch;
}

}  // namespace paramorph::paste
