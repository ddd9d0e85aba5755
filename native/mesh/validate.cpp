#include "mesh/validate.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <sstream>

#include "common/errors.h"

namespace paramorph {

std::string format_indices(const std::vector<Index>& indices, std::size_t max_shown) {
  std::ostringstream out;
  for (std::size_t k = 0; k < indices.size() && k < max_shown; ++k) out << (k ? ", " : "") << indices[k];
  if (indices.size() > max_shown) out << " (and " << indices.size() - max_shown << " more)";
  return out.str();
}

void validate_arrays(const MatrixX3d& V, const MatrixX3i& F) {
  PM_REQUIRE(V.rows() > 0 && F.rows() > 0, InvalidInputError, "the mesh is empty (", V.rows(),
             " vertices, ", F.rows(), " faces)");
  std::vector<Index> bad_vertices;
  for (Index v = 0; v < Index(V.rows()); ++v)
    if (!V.row(v).allFinite()) bad_vertices.push_back(v);
  PM_REQUIRE(bad_vertices.empty(), InvalidInputError, "non-finite (NaN or inf) coordinates at ",
             bad_vertices.size(), " vertices: ", format_indices(bad_vertices));
  for (Index f = 0; f < Index(F.rows()); ++f)
    for (int k = 0; k < 3; ++k)
      PM_REQUIRE(F(f, k) >= 0 && F(f, k) < V.rows(), InvalidInputError, "face ", f,
                 " has vertex index ", F(f, k), ", out of range for ", V.rows(), " vertices");
}

namespace {

/// True when the faces around v form one fan, connected across shared edges.
bool single_fan(const TriMesh& mesh, Index v) {
  const Csr& corners = mesh.vertex_corners();
  const MatrixX3i& F = mesh.F();
  const Index begin = corners.begin(v), count = corners.size(v);
  if (count <= 1) return true;
  // Union faces that share an edge through v (same "other" vertex).
  std::vector<std::pair<Index, Index>> spokes;  // (other vertex, local face)
  for (Index k = 0; k < count; ++k) {
    const Index f = corners.items[begin + k] / 3, c = corners.items[begin + k] % 3;
    spokes.emplace_back(F(f, (c + 1) % 3), k);
    spokes.emplace_back(F(f, (c + 2) % 3), k);
  }
  std::sort(spokes.begin(), spokes.end());
  std::vector<Index> parent(count);
  for (Index k = 0; k < count; ++k) parent[k] = k;
  auto root = [&](Index x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  Index groups = count;
  for (std::size_t i = 1; i < spokes.size(); ++i)
    if (spokes[i].first == spokes[i - 1].first) {
      const Index a = root(spokes[i].second), b = root(spokes[i - 1].second);
      if (a != b) {
        parent[a] = b;
        --groups;
      }
    }
  return groups == 1;
}

}  // namespace

MeshReport validate(const TriMesh& mesh, double relative_area_tolerance) {
  MeshReport r;
  const MatrixX3d& V = mesh.V();
  const MatrixX3i& F = mesh.F();
  r.vertices = mesh.num_vertices();
  r.faces = mesh.num_faces();
  r.edges = Index(mesh.edges().rows());
  r.components = mesh.num_components();
  r.boundary_loops = Index(mesh.boundary_loops().size());
  r.euler_characteristic = r.vertices - r.edges + r.faces;

  const Csr& edge_faces = mesh.edge_faces();
  for (Index e = 0; e < r.edges; ++e)
    if (edge_faces.size(e) > 2) r.non_manifold_edges.push_back(e);

  // Orientation: the two faces of an interior edge must run it in opposite directions.
  const MatrixX2i& E = mesh.edges();
  for (Index e = 0; e < r.edges; ++e) {
    if (edge_faces.size(e) != 2) continue;
    int forward = 0;
    for (Index k = edge_faces.begin(e); k < edge_faces.end(e); ++k) {
      const Index f = edge_faces.items[k];
      for (int c = 0; c < 3; ++c)
        if (F(f, c) == E(e, 0) && F(f, (c + 1) % 3) == E(e, 1)) ++forward;
    }
    if (forward != 1) r.inconsistent_orientation_edges.push_back(e);
  }

  const Csr& corners = mesh.vertex_corners();
  for (Index v = 0; v < r.vertices; ++v) {
    if (corners.size(v) == 0)
      r.isolated_vertices.push_back(v);
    else if (!single_fan(mesh, v))
      r.non_manifold_vertices.push_back(v);
  }

  const double diagonal = (V.colwise().maxCoeff() - V.colwise().minCoeff()).norm();
  const double min_area = relative_area_tolerance * diagonal * diagonal;
  for (Index f = 0; f < r.faces; ++f) {
    const Index a = F(f, 0), b = F(f, 1), c = F(f, 2);
    const Eigen::Vector3d e1 = (V.row(b) - V.row(a)).transpose();
    const Eigen::Vector3d e2 = (V.row(c) - V.row(a)).transpose();
    if (a == b || b == c || a == c || 0.5 * e1.cross(e2).norm() <= min_area)
      r.degenerate_faces.push_back(f);
  }

  const bool manifold = r.non_manifold_edges.empty() && r.non_manifold_vertices.empty();
  if (manifold && r.components == 1 && r.isolated_vertices.empty()) {
    const Index twice_genus = 2 - r.boundary_loops - r.euler_characteristic;
    r.genus = twice_genus >= 0 && twice_genus % 2 == 0 ? twice_genus / 2 : -1;
  }
  r.is_closed_genus0 = manifold && r.components == 1 && r.isolated_vertices.empty() &&
                       r.boundary_loops == 0 && r.genus == 0 && r.degenerate_faces.empty() &&
                       r.inconsistent_orientation_edges.empty();
  return r;
}

void require_closed_genus0(const MeshReport& r) {
  if (!r.non_manifold_edges.empty())
    throw NonManifoldError(detail::concat(
        "mesh is not manifold: ", r.non_manifold_edges.size(),
        " edges have more than two faces (edge indices ", format_indices(r.non_manifold_edges), ")"));
  if (!r.non_manifold_vertices.empty())
    throw NonManifoldError(detail::concat(
        "mesh is not manifold: the faces around ", r.non_manifold_vertices.size(),
        " vertices do not form one fan (vertices ", format_indices(r.non_manifold_vertices), ")"));
  if (!r.degenerate_faces.empty())
    throw DegenerateFaceError(detail::concat(
        "mesh has ", r.degenerate_faces.size(), " degenerate (zero-area) faces: ",
        format_indices(r.degenerate_faces), "; merge or dissolve them first"));
  const Index surfaces = r.components - Index(r.isolated_vertices.size());
  if (surfaces > 1)
    throw DisconnectedError(detail::concat(
        "mesh has ", surfaces, " connected components; one connected surface is required: "
        "separate the parts first"));
  if (r.boundary_loops > 0)
    throw NotClosedError(detail::concat("mesh is not closed: it has ", r.boundary_loops,
                                        " boundary loops (holes); fill the holes first"));
  if (!r.isolated_vertices.empty())
    throw DisconnectedError(detail::concat(
        "mesh has ", r.isolated_vertices.size(), " loose vertices that belong to no face (",
        format_indices(r.isolated_vertices), "); delete them (Mesh > Clean Up > Delete Loose)"));
  if (!r.inconsistent_orientation_edges.empty())
    throw NonManifoldError(detail::concat(
        "mesh is not consistently oriented: ", r.inconsistent_orientation_edges.size(),
        " edges are used in the same direction by both faces (edge indices ",
        format_indices(r.inconsistent_orientation_edges), "); recalculate normals first"));
  if (r.genus != 0)
    throw NotGenusZeroError(detail::concat(
        "mesh has genus ", r.genus, " (", r.genus, r.genus == 1 ? " handle" : " handles",
        "); a closed genus-0 (sphere-like) mesh is required"));
}

}  // namespace paramorph
