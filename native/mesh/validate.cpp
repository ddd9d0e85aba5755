// Mesh validation (mesh/validate.h). Every check reads the shared TriMesh
// topology; require_closed_genus0 turns a report into the one error an artist
// should fix first, naming the elements so they can be selected in Blender.
#include "mesh/validate.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <sstream>

#include "common/errors.h"

namespace paramorph {

namespace {
constexpr double kLargestCoordinate = 1e150;
constexpr double kSmallestExtent = 1e-150;
}  // namespace

std::string format_indices(const std::vector<Index>& indices, std::size_t max_shown) {
  std::ostringstream out;
  for (std::size_t k = 0; k < indices.size() && k < max_shown; ++k) out << (k ? ", " : "") << indices[k];
  if (indices.size() > max_shown) out << " (and " << indices.size() - max_shown << " more)";
  return out.str();
}

std::string format_vertex_pairs(const MatrixX2i& pairs, std::size_t max_shown) {
  std::ostringstream out;
  const std::size_t count = std::size_t(pairs.rows());
  for (std::size_t k = 0; k < count && k < max_shown; ++k)
    out << (k ? ", " : "") << "(" << pairs(k, 0) << ", " << pairs(k, 1) << ")";
  if (count > max_shown) out << " (and " << count - max_shown << " more)";
  return out.str();
}

namespace {

/// "1 face" / "3 faces".
std::string count_of(std::size_t n, const char* singular, const char* plural) {
  return std::to_string(n) + " " + (n == 1 ? singular : plural);
}

MatrixX2i edge_rows(const MatrixX2i& E, const std::vector<Index>& edges) {
  MatrixX2i out(Index(edges.size()), 2);
  for (std::size_t k = 0; k < edges.size(); ++k) out.row(Index(k)) = E.row(edges[k]);
  return out;
}

/// Counts the fans of faces around each vertex: faces around v are joined when
/// they share an edge through v, and one fan means one group. Scratch buffers
/// are reused across vertices (this runs once per vertex on 1M-face meshes).
class FanCounter {
 public:
  explicit FanCounter(const TriMesh& mesh) : mesh_(mesh) {}

  bool single_fan(Index v) {
    const Csr& corners = mesh_.vertex_corners();
    const MatrixX3i& FE = mesh_.face_edges();
    const Index begin = corners.begin(v), count = corners.size(v);
    if (count <= 1) return true;
    // Spokes: the two edges of each incident face that touch v (the edges
    // opposite the other two corners), tagged with the face's local number.
    spokes_.clear();
    for (Index k = 0; k < count; ++k) {
      const Index f = corners.items[begin + k] / 3, c = corners.items[begin + k] % 3;
      spokes_.emplace_back(FE(f, (c + 1) % 3), k);
      spokes_.emplace_back(FE(f, (c + 2) % 3), k);
    }
    std::sort(spokes_.begin(), spokes_.end());
    parent_.resize(std::size_t(count));
    for (Index k = 0; k < count; ++k) parent_[k] = k;
    Index groups = count;
    for (std::size_t i = 1; i < spokes_.size(); ++i)
      if (spokes_[i].first == spokes_[i - 1].first) {
        const Index a = root(spokes_[i].second), b = root(spokes_[i - 1].second);
        if (a != b) parent_[a] = b, --groups;
      }
    return groups == 1;
  }

 private:
  Index root(Index x) {
    while (parent_[x] != x) x = parent_[x] = parent_[parent_[x]];
    return x;
  }
  const TriMesh& mesh_;
  std::vector<std::pair<Index, Index>> spokes_;  // (edge, local face)
  std::vector<Index> parent_;
};

}  // namespace

void validate_arrays(const MatrixX3d& V, const MatrixX3i& F) {
  PM_REQUIRE(V.rows() > 0 && F.rows() > 0, InvalidInputError, "the mesh is empty (", V.rows(),
             " vertices, ", F.rows(), " faces); a triangle mesh with faces is required");
  std::vector<Index> bad_vertices;
  for (Index v = 0; v < Index(V.rows()); ++v)
    if (!V.row(v).allFinite()) bad_vertices.push_back(v);
  PM_REQUIRE(bad_vertices.empty(), InvalidInputError, "non-finite (NaN or inf) coordinates at ",
             count_of(bad_vertices.size(), "vertex", "vertices"), ": ", format_indices(bad_vertices));
  // Areas are products of two coordinate differences: beyond ~1e150 they
  // overflow to inf, below ~1e-150 they round to 0 (and every face reads as
  // degenerate, which would be the wrong advice).
  const double largest = V.cwiseAbs().maxCoeff();
  const double extent = (V.colwise().maxCoeff() - V.colwise().minCoeff()).maxCoeff();
  PM_REQUIRE(largest <= kLargestCoordinate && (extent == 0 || extent >= kSmallestExtent), InvalidInputError,
             "the mesh's coordinates reach ", largest, " and it spans ", extent,
             ": face areas would ", largest > kLargestCoordinate ? "overflow" : "round to zero",
             " in double precision; scale the mesh (e.g. to metres) first");
  std::vector<Index> bad_faces;
  Index first_face = -1, first_value = 0;
  for (Index f = 0; f < Index(F.rows()); ++f)
    for (int k = 0; k < 3; ++k)
      if (F(f, k) < 0 || F(f, k) >= V.rows()) {
        if (bad_faces.empty()) first_face = f, first_value = F(f, k);
        if (bad_faces.empty() || bad_faces.back() != f) bad_faces.push_back(f);
      }
  PM_REQUIRE(bad_faces.empty(), InvalidInputError, "face ", first_face, " has vertex index ",
             first_value, ", out of range for ", V.rows(), " vertices (indices are 0-based); ",
             count_of(bad_faces.size(), "face has", "faces have"), " bad indices: ",
             format_indices(bad_faces));
}

MeshReport validate(const TriMesh& mesh, double relative_area_tolerance) {
  MeshReport r;
  const MatrixX3d& V = mesh.V();
  const MatrixX3i& F = mesh.F();
  const MatrixX2i& E = mesh.edges();
  const Csr& edge_faces = mesh.edge_faces();
  r.vertices = mesh.num_vertices();
  r.faces = mesh.num_faces();
  r.edges = Index(E.rows());
  r.components = mesh.num_components();
  r.boundary_loops = Index(mesh.boundary_loops().size());
  r.euler_characteristic = r.vertices - r.edges + r.faces;

  for (Index e = 0; e < r.edges; ++e) {
    const Index faces = edge_faces.size(e);
    if (faces == 1) ++r.boundary_edges;
    if (faces > 2) r.non_manifold_edges.push_back(e);
    // Orientation: the two faces of an interior edge must run it in opposite
    // directions, so exactly one of them goes a -> b.
    if (faces == 2) {
      int forward = 0;
      for (Index k = edge_faces.begin(e); k < edge_faces.end(e); ++k) {
        const Index f = edge_faces.items[k];
        for (int c = 0; c < 3; ++c) forward += F(f, c) == E(e, 0) && F(f, (c + 1) % 3) == E(e, 1);
      }
      if (forward != 1) r.inconsistent_orientation_edges.push_back(e);
    }
  }
  r.non_manifold_edge_vertices = edge_rows(E, r.non_manifold_edges);
  r.inconsistent_orientation_edge_vertices = edge_rows(E, r.inconsistent_orientation_edges);

  const Csr& corners = mesh.vertex_corners();
  FanCounter fans(mesh);
  for (Index v = 0; v < r.vertices; ++v) {
    if (corners.size(v) == 0)
      r.isolated_vertices.push_back(v);
    else if (!fans.single_fan(v))
      r.non_manifold_vertices.push_back(v);
  }

  // Relative to the bounding box so the test is unchanged when the mesh is scaled.
  const double diagonal = (V.colwise().maxCoeff() - V.colwise().minCoeff()).norm();
  const double min_area = relative_area_tolerance * diagonal * diagonal;
  for (Index f = 0; f < r.faces; ++f) {
    const Index a = F(f, 0), b = F(f, 1), c = F(f, 2);
    const Eigen::Vector3d e1 = (V.row(b) - V.row(a)).transpose();
    const Eigen::Vector3d e2 = (V.row(c) - V.row(a)).transpose();
    const bool repeated = a == b || b == c || a == c;
    if (repeated) r.repeated_vertex_faces.push_back(f);
    if (repeated || 0.5 * e1.cross(e2).norm() <= min_area) r.degenerate_faces.push_back(f);
  }
  {
    std::map<std::array<Index, 3>, Index> first_on;
    for (Index f = 0; f < r.faces; ++f) {
      std::array<Index, 3> key{F(f, 0), F(f, 1), F(f, 2)};
      std::sort(key.begin(), key.end());
      if (!first_on.emplace(key, f).second) r.duplicate_faces.push_back(f);
    }
  }

  // chi = 2 - 2g - b holds per connected orientable surface; isolated vertices
  // add 1 each to V (and to the component count) without being surface.
  const Index isolated = Index(r.isolated_vertices.size());
  const bool manifold = r.non_manifold_edges.empty() && r.non_manifold_vertices.empty();
  if (manifold && r.components - isolated == 1) {
    const Index twice_genus = 2 - r.boundary_loops - (r.euler_characteristic - isolated);
    r.genus = twice_genus >= 0 && twice_genus % 2 == 0 ? twice_genus / 2 : -1;
  }
  r.is_closed_genus0 = manifold && r.components == 1 && isolated == 0 && r.boundary_loops == 0 &&
                       r.boundary_edges == 0 && r.genus == 0 && r.degenerate_faces.empty() &&
                       r.duplicate_faces.empty() &&
                       r.inconsistent_orientation_edges.empty();
  return r;
}

namespace {

const char* const kSelectHint = " (Select > Select All by Trait > Non Manifold shows them)";

void require_no_duplicate_faces(const MeshReport& r) {
  if (!r.duplicate_faces.empty())
    throw NonManifoldError(detail::concat(
        "mesh has ", count_of(r.duplicate_faces.size(), "duplicate face", "duplicate faces"),
        " (on the same three vertices as another face, enclosing nothing with it): faces ",
        format_indices(r.duplicate_faces), "; delete the extra copies (select them, Mesh > Delete > Faces)"));
}

void require_fans(const MeshReport& r) {
  // Faces naming a vertex twice and duplicated faces make edges look shared
  // by three faces; said as what they are, the fix is plain.
  if (!r.non_manifold_edges.empty() && !r.repeated_vertex_faces.empty())
    throw DegenerateFaceError(detail::concat(
        "mesh has ", count_of(r.repeated_vertex_faces.size(), "face", "faces"),
        " naming one vertex twice: faces ", format_indices(r.repeated_vertex_faces),
        "; remove them first (Mesh > Clean Up > Degenerate Dissolve)"));
  if (!r.non_manifold_edges.empty()) require_no_duplicate_faces(r);
  if (!r.non_manifold_edges.empty())
    throw NonManifoldError(detail::concat(
        "mesh is not manifold: ", count_of(r.non_manifold_edges.size(), "edge is", "edges are"),
        " shared by more than two faces, between vertices ",
        format_vertex_pairs(r.non_manifold_edge_vertices), kSelectHint,
        "; delete or separate the extra faces"));
  if (!r.non_manifold_vertices.empty())
    throw NonManifoldError(detail::concat(
        "mesh is not manifold: the faces around ",
        count_of(r.non_manifold_vertices.size(), "vertex", "vertices"),
        " do not form a single fan (surfaces touching at one point): vertices ",
        format_indices(r.non_manifold_vertices), kSelectHint, "; split or merge them"));
}

void require_oriented(const MeshReport& r) {
  if (!r.inconsistent_orientation_edges.empty())
    throw NonManifoldError(detail::concat(
        "mesh is not consistently oriented: ",
        count_of(r.inconsistent_orientation_edges.size(), "edge is", "edges are"),
        " run in the same direction by both of its faces, between vertices ",
        format_vertex_pairs(r.inconsistent_orientation_edge_vertices),
        "; recalculate normals first (Mesh > Normals > Recalculate Outside)"));
}

}  // namespace

void require_manifold(const MeshReport& r) {
  require_fans(r);
  require_oriented(r);
}

void require_closed_genus0(const MeshReport& r) {
  require_fans(r);
  // Also duplicates that share no edge with a third face: two faces on the
  // same three vertices closing on each other (a "pillow") pass every count
  // but enclose nothing; no sphere map can start from them.
  require_no_duplicate_faces(r);
  if (!r.degenerate_faces.empty())
    throw DegenerateFaceError(detail::concat(
        "mesh has ", count_of(r.degenerate_faces.size(), "degenerate face", "degenerate faces"),
        " (zero area or a repeated vertex): faces ", format_indices(r.degenerate_faces),
        "; remove them first (Mesh > Clean Up > Degenerate Dissolve)"));
  const Index isolated = Index(r.isolated_vertices.size());
  const Index surfaces = r.components - isolated;
  if (surfaces > 1)
    throw DisconnectedError(detail::concat(
        "mesh has ", surfaces, " connected components; one connected surface is required: "
        "separate the parts first (Mesh > Separate > By Loose Parts)"));
  if (r.boundary_loops > 0 || r.boundary_edges > 0)
    throw NotClosedError(detail::concat(
        "mesh is not closed: it has ", count_of(std::size_t(r.boundary_loops), "boundary loop (hole)", "boundary loops (holes)"),
        " with ", count_of(std::size_t(r.boundary_edges), "boundary edge", "boundary edges"),
        "; fill the holes first (select the boundary, Face > Fill)"));
  if (isolated > 0)
    throw DisconnectedError(detail::concat(
        "mesh has ", count_of(std::size_t(isolated), "loose vertex", "loose vertices"),
        " in no face (", format_indices(r.isolated_vertices),
        "); delete them (Mesh > Clean Up > Delete Loose)"));
  require_oriented(r);
  if (r.genus != 0) {
    if (r.genus < 0)
      throw NotGenusZeroError(
          "mesh is not a sphere-like surface (its Euler characteristic does not match an orientable "
          "surface); a closed genus-0 (sphere-like) mesh is required");
    throw NotGenusZeroError(detail::concat(
        "mesh has genus ", r.genus, " (", count_of(std::size_t(r.genus), "handle", "handles"),
        "); a closed genus-0 (sphere-like) mesh is required: close the handles first"));
  }
}

}  // namespace paramorph
