#include "param/spherical/untangle_sphere_map.h"

#include <algorithm>
#include <cmath>
#include <unordered_map>

#include <Eigen/Geometry>

#include "common/errors.h"
#include "mesh/face_neighbors.h"
#include "mesh/tri_mesh.h"
#include "param/planar/isometric_energy.h"
#include "param/planar/untangle.h"
#include "param/planar/untangle_continuation.h"
#include "param/spherical/smooth_sphere_map.h"

namespace paramorph::spherical {

namespace {

double triple(const MatrixX3d& X, const MatrixX3i& F, Index f) {
  return X.row(F(f, 0)).dot(X.row(F(f, 1)).cross(X.row(F(f, 2))));
}

/// The faces within `rings` rings of `seeds` (faces sharing a vertex count
/// as neighbours), ascending.
std::vector<Index> grow(const TriMesh& mesh, const std::vector<Index>& seeds, int rings) {
  const MatrixX3i& F = mesh.F();
  const Csr& corners = mesh.vertex_corners();
  std::vector<char> in(std::size_t(F.rows()), 0);
  std::vector<Index> front = seeds;
  for (const Index f : seeds) in[std::size_t(f)] = 1;
  for (int r = 0; r < rings && !front.empty(); ++r) {
    std::vector<Index> next;
    for (const Index f : front)
      for (int k = 0; k < 3; ++k) {
        const Index v = F(f, k);
        for (Index c = corners.begin(v); c < corners.end(v); ++c) {
          const Index g = corners.items[c] / 3;
          if (!in[std::size_t(g)]) in[std::size_t(g)] = 1, next.push_back(g);
        }
      }
    front.swap(next);
  }
  // Rings around a thin part (a leg) close into an annulus: the pieces of
  // the rest of the surface other than the largest (the leg's end) join the
  // patch, which makes it a disc again.
  const MatrixX3i neighbors = face_neighbors(mesh);
  std::vector<Index> piece(std::size_t(F.rows()), -1), piece_size;
  for (Index f = 0; f < F.rows(); ++f) {
    if (in[std::size_t(f)] || piece[std::size_t(f)] >= 0) continue;
    const Index id = Index(piece_size.size());
    piece_size.push_back(0);
    std::vector<Index> stack{f};
    piece[std::size_t(f)] = id;
    while (!stack.empty()) {
      const Index g = stack.back();
      stack.pop_back();
      ++piece_size.back();
      for (int k = 0; k < 3; ++k) {
        const Index h = neighbors(g, k);
        if (h >= 0 && !in[std::size_t(h)] && piece[std::size_t(h)] < 0) piece[std::size_t(h)] = id, stack.push_back(h);
      }
    }
  }
  const Index largest = piece_size.empty() ? -1
                        : Index(std::max_element(piece_size.begin(), piece_size.end()) - piece_size.begin());
  std::vector<Index> faces;
  for (Index f = 0; f < F.rows(); ++f)
    if (in[std::size_t(f)] || piece[std::size_t(f)] != largest) faces.push_back(f);
  return faces;
}

/// Untangles the patch `faces` of X in the gnomonic plane; writes X back and
/// returns true when every patch face ends turned the right way.
bool untangle_patch(const MatrixX3d& V, const MatrixX3i& F, MatrixX3d& X, const std::vector<char>& fixed,
                    const std::vector<Index>& faces, double max_angle) {
  // Local numbering.
  std::unordered_map<Index, Index> local;
  std::vector<Index> global;
  MatrixX3i PF(Index(faces.size()), 3);
  for (std::size_t i = 0; i < faces.size(); ++i)
    for (int k = 0; k < 3; ++k) {
      const Index v = F(faces[i], k);
      const auto [at, inserted] = local.emplace(v, Index(global.size()));
      if (inserted) global.push_back(v);
      PF(Index(i), k) = at->second;
    }
  const Index n = Index(global.size());
  MatrixX3d PV(n, 3);
  Eigen::RowVector3d centre = Eigen::RowVector3d::Zero();
  for (Index i = 0; i < n; ++i) {
    PV.row(i) = V.row(global[std::size_t(i)]);
    centre += X.row(global[std::size_t(i)]);
  }
  if (!(centre.norm() > 0)) return false;
  centre.normalize();
  const TriMesh patch(PV, PF);
  if (patch.boundary_loops().size() != 1 || n - Index(patch.edges().rows()) + PF.rows() != 1)
    return false;  // not a disc
  std::vector<char> pinned(std::size_t(n), 0);
  for (Index i = 0; i < n; ++i) pinned[std::size_t(i)] = fixed[std::size_t(global[std::size_t(i)])];
  for (const Index v : patch.boundary_loops()[0]) pinned[std::size_t(v)] = 1;

  // Gnomonic coordinates in the plane tangent at the centre.
  const Eigen::RowVector3d axis = std::abs(centre.x()) < 0.9 ? Eigen::RowVector3d::UnitX() : Eigen::RowVector3d::UnitY();
  const Eigen::RowVector3d e1 = (axis - axis.dot(centre) * centre).normalized(), e2 = centre.cross(e1);
  MatrixX2d uv(n, 2);
  const double min_cos = std::cos(max_angle);
  for (Index i = 0; i < n; ++i) {
    const Eigen::RowVector3d p = X.row(global[std::size_t(i)]);
    const double height = p.dot(centre);
    if (!(height > min_cos)) return false;  // too wide for the projection
    uv.row(i) << p.dot(e1) / height, p.dot(e2) / height;
  }
  planar::untangle(PF, uv, pinned);
  if (!planar::folded_faces(PF, uv).empty())
    planar::untangle_continuation(planar::isometric_factors(PV, PF), PF, uv, pinned);
  if (!planar::folded_faces(PF, uv).empty()) return false;
  for (Index i = 0; i < n; ++i)
    if (!pinned[std::size_t(i)])
      X.row(global[std::size_t(i)]) = (centre + uv(i, 0) * e1 + uv(i, 1) * e2).normalized();
  for (const Index f : faces)
    if (!(triple(X, F, f) > 0)) return false;  // rounding back onto the sphere
  return true;
}

/// The free vertices of a patch (its faces' corners not on its boundary).
std::vector<Index> inner_vertices(const TriMesh& mesh, const std::vector<Index>& faces) {
  std::vector<char> in(std::size_t(mesh.num_faces()), 0);
  for (const Index f : faces) in[std::size_t(f)] = 1;
  std::vector<Index> out;
  std::vector<char> seen(std::size_t(mesh.num_vertices()), 0);
  const Csr& corners = mesh.vertex_corners();
  for (const Index f : faces)
    for (int k = 0; k < 3; ++k) {
      const Index v = mesh.F()(f, k);
      if (seen[std::size_t(v)]) continue;
      seen[std::size_t(v)] = 1;
      bool inner = true;
      for (Index c = corners.begin(v); c < corners.end(v) && inner; ++c) inner = in[std::size_t(corners.items[c] / 3)];
      if (inner) out.push_back(v);
    }
  return out;
}

}  // namespace

SphereUntangleResult untangle_sphere_map(const MatrixX3d& V, const MatrixX3i& F, MatrixX3d& X,
                                         const std::vector<char>& fixed, const SphereUntangleOptions& o) {
  PM_REQUIRE(X.rows() == V.rows() && fixed.size() == std::size_t(V.rows()) &&
                 (F.size() == 0 || (F.minCoeff() >= 0 && F.maxCoeff() < V.rows())),
             InvalidInputError, "untangle_sphere_map: X and fixed need one row per vertex (", V.rows(),
             "), faces within range");
  SphereUntangleResult result;
  const TriMesh mesh(V, F);
  auto folded_faces = [&] {
    std::vector<Index> out;
    for (Index f = 0; f < F.rows(); ++f)
      if (!(triple(X, F, f) > 0) && !(fixed[F(f, 0)] && fixed[F(f, 1)] && fixed[F(f, 2)])) out.push_back(f);
    return out;
  };
  std::vector<Index> folded = folded_faces();
  result.folded_before = Index(folded.size());
  std::vector<char> given_up(std::size_t(F.rows()), 0);
  while (true) {
    // The first folded face not given up on, and its cluster (folded faces
    // joined through shared vertices).
    const auto seed = std::find_if(folded.begin(), folded.end(), [&](Index f) { return !given_up[std::size_t(f)]; });
    if (seed == folded.end()) break;
    std::vector<char> is_folded(std::size_t(F.rows()), 0);
    for (const Index f : folded) is_folded[std::size_t(f)] = 1;
    std::vector<Index> cluster{*seed}, stack{*seed};
    std::vector<char> seen(std::size_t(F.rows()), 0);
    seen[std::size_t(*seed)] = 1;
    const Csr& corners = mesh.vertex_corners();
    while (!stack.empty()) {
      const Index f = stack.back();
      stack.pop_back();
      for (int k = 0; k < 3; ++k)
        for (Index c = corners.begin(F(f, k)); c < corners.end(F(f, k)); ++c) {
          const Index g = corners.items[c] / 3;
          if (is_folded[std::size_t(g)] && !seen[std::size_t(g)]) seen[std::size_t(g)] = 1, cluster.push_back(g), stack.push_back(g);
        }
    }
    bool done = false;
    std::size_t last_patch = 0;
    for (int rings = o.first_rings; rings <= o.max_rings && !done; ++rings) {
      const std::vector<Index> patch = grow(mesh, cluster, rings);
      // Once the patch holds its whole piece of the surface, another ring
      // would try the same patch again (and a huge max_rings would spin).
      if (patch.size() == last_patch) break;
      last_patch = patch.size();
      MatrixX3d trial = X;
      if (untangle_patch(V, F, trial, fixed, patch, o.max_patch_angle)) {
        // Untangling leaves slivers (a later flow turns them over at the
        // slightest shear): smooth the patch's free vertices.
        smooth_sphere_map(mesh, trial, inner_vertices(mesh, patch), fixed, 3);
        X.swap(trial);
        done = true;
        ++result.patches;
        result.largest_rings = std::max(result.largest_rings, rings);
      }
    }
    if (!done)
      for (const Index f : cluster) given_up[std::size_t(f)] = 1;
    folded = folded_faces();
  }
  result.folded = Index(folded.size());
  return result;
}

}  // namespace paramorph::spherical
