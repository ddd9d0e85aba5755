#include "mesh/repair.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <set>
#include <utility>
#include <vector>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/border.h>
#include <CGAL/Polygon_mesh_processing/connected_components.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/repair_degeneracies.h>
#include <CGAL/Polygon_mesh_processing/shape_predicates.h>
#include <CGAL/Polygon_mesh_processing/triangulate_hole.h>
#include <CGAL/Surface_mesh.h>

#include "common/errors.h"
#include "mesh/closest_points.h"
#include "mesh/validate.h"
#include "mesh/weld_vertices.h"

namespace paramorph {

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Surface = CGAL::Surface_mesh<Point>;
using VertexId = Surface::Vertex_index;
using FaceId = Surface::Face_index;
using Polygon = std::vector<std::size_t>;
namespace PMP = CGAL::Polygon_mesh_processing;

/// Records what orient_polygon_soup changes (CGAL copies the visitor, so it
/// holds pointers).
struct OrientRecord : PMP::Default_orientation_visitor {
  std::vector<char>* reversed = nullptr;        // per polygon
  std::vector<Index>* point_source = nullptr;   // per soup point: its input vertex
  std::set<std::pair<std::size_t, std::size_t>>* non_manifold_edges = nullptr;
  Index* non_manifold_vertices = nullptr;
  void non_manifold_edge(std::size_t a, std::size_t b, std::size_t) {
    non_manifold_edges->emplace(std::min(a, b), std::max(a, b));
  }
  void non_manifold_vertex(std::size_t, std::size_t) { ++*non_manifold_vertices; }
  void duplicated_vertex(std::size_t old_id, std::size_t new_id) {
    if (point_source->size() <= new_id) point_source->resize(new_id + 1, -1);
    (*point_source)[new_id] = (*point_source)[old_id];
  }
  void polygon_orientation_reversed(std::size_t p) { (*reversed)[p] ^= 1; }
};

std::string count(Index n, const char* one, const char* many) {
  return std::to_string(n) + " " + (n == 1 ? one : many);
}

}  // namespace

std::vector<std::string> RepairReport::changes() const {
  std::vector<std::string> out;
  if (welded_vertices)
    out.push_back("merged " + count(welded_vertices, "vertex", "vertices") +
                  " that sat on another one (unwelded seams)");
  if (degenerate_faces_removed)
    out.push_back("removed " + count(degenerate_faces_removed, "degenerate face", "degenerate faces") +
                  " (a repeated corner or no area)");
  if (duplicate_faces_removed)
    out.push_back("removed " + count(duplicate_faces_removed, "duplicate face", "duplicate faces"));
  if (isolated_vertices_removed)
    out.push_back("left out " + count(isolated_vertices_removed, "loose vertex", "loose vertices") +
                  " (in no face)");
  if (parts_turned_outward)
    out.push_back("turned " + count(parts_turned_outward, "inside-out part", "inside-out parts") +
                  " the right way out");
  if (faces_reversed)
    out.push_back("turned " + count(faces_reversed, "face", "faces") + " to face the same way as their neighbours");
  if (non_manifold_edges)
    out.push_back("cut apart " + count(non_manifold_edges, "edge", "edges") + " shared by more than two faces");
  if (non_manifold_vertices_split)
    out.push_back("split " + count(non_manifold_vertices_split, "vertex", "vertices") +
                  " where separate fans of faces met (bow-ties)");
  if (holes_filled)
    out.push_back("filled " + count(holes_filled, "hole", "holes") + " (" +
                  count(fill_faces_added, "face", "faces") + " added)");
  if (fairing_failed)
    out.push_back(count(fairing_failed, "filled hole is", "filled holes are") + " flat (the smoothing failed)");
  if (holes_not_filled)
    out.push_back("could not fill " + count(holes_not_filled, "hole", "holes") + "; left open");
  if (single_faces_left_open)
    out.push_back("left " + count(single_faces_left_open, "lone triangle", "lone triangles") +
                  " open (one face cannot enclose anything)");
  if (components_removed)
    out.push_back("removed " + count(components_removed, "smaller part", "smaller parts") + " (" +
                  count(faces_removed_with_components, "face", "faces") + "), kept the largest");
  return out;
}

RepairResult repair(const MatrixX3d& V, const MatrixX3i& F, const RepairOptions& options, Progress* progress) {
  validate_arrays(V, F);
  PM_REQUIRE(F.rows() > 0, InvalidInputError, "the mesh has no faces");
  PM_REQUIRE(std::isfinite(options.weld_tolerance) && options.weld_tolerance >= 0, InvalidInputError,
             "weld_tolerance must be finite and >= 0 (a fraction of the mesh size), got ",
             options.weld_tolerance);
  auto report = [&](double fraction, const char* stage) {
    if (progress) progress->report(fraction, stage);
  };
  report(0.0, "welding");
  const Index n_in = Index(V.rows());
  RepairResult out;
  RepairReport& rep = out.report;

  // 1. Weld, relative to the size of what the faces use.
  std::vector<char> referenced(static_cast<std::size_t>(n_in), 0);
  for (Index f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k) referenced[std::size_t(F(f, k))] = 1;
  Eigen::RowVector3d low = Eigen::RowVector3d::Constant(INFINITY), high = -low;
  for (Index v = 0; v < n_in; ++v)
    if (referenced[std::size_t(v)]) {
      low = low.cwiseMin(V.row(v));
      high = high.cwiseMax(V.row(v));
    }
  const VectorXi into = weld_vertices(V, options.weld_tolerance * (high - low).norm());
  for (Index v = 0; v < n_in; ++v) {
    if (!referenced[std::size_t(v)]) ++rep.isolated_vertices_removed;
    else if (into(v) != v) ++rep.welded_vertices;
  }

  // 2. Faces on the welded vertices: drop repeated corners and duplicates.
  std::vector<Polygon> polygons;
  std::vector<Index> polygon_source;
  std::map<std::array<Index, 3>, Index> seen;
  for (Index f = 0; f < F.rows(); ++f) {
    const std::array<Index, 3> c = {into(F(f, 0)), into(F(f, 1)), into(F(f, 2))};
    if (c[0] == c[1] || c[1] == c[2] || c[0] == c[2]) {
      ++rep.degenerate_faces_removed;
      continue;
    }
    std::array<Index, 3> key = c;
    std::sort(key.begin(), key.end());
    if (!seen.emplace(key, f).second) {
      ++rep.duplicate_faces_removed;
      continue;
    }
    polygons.push_back({std::size_t(c[0]), std::size_t(c[1]), std::size_t(c[2])});
    polygon_source.push_back(f);
  }
  PM_REQUIRE(!polygons.empty(), InvalidInputError,
             "every face is degenerate (its corners coincide): nothing is left to repair");

  // 3. The soup: only the vertices the kept faces use, in input order.
  std::vector<Index> soup_of(static_cast<std::size_t>(n_in), -1), point_source;
  for (const auto& polygon : polygons)
    for (std::size_t corner : polygon) soup_of[corner] = 0;
  std::vector<Point> points;
  for (Index v = 0; v < n_in; ++v)
    if (soup_of[std::size_t(v)] == 0) {
      soup_of[std::size_t(v)] = Index(points.size());
      points.emplace_back(V(v, 0), V(v, 1), V(v, 2));
      point_source.push_back(v);
    }
  for (auto& polygon : polygons)
    for (auto& corner : polygon) corner = std::size_t(soup_of[corner]);
  report(0.1, "orienting");

  // 4. One orientation per part; non-manifold vertices and edges cut apart.
  std::vector<char> reversed(polygons.size(), 0);
  Index non_manifold_vertices = 0;
  std::set<std::pair<std::size_t, std::size_t>> non_manifold_edges;
  OrientRecord record;
  record.reversed = &reversed;
  record.point_source = &point_source;
  record.non_manifold_edges = &non_manifold_edges;
  record.non_manifold_vertices = &non_manifold_vertices;
  PMP::orient_polygon_soup(points, polygons, CGAL::parameters::visitor(record));
  point_source.resize(points.size(), -1);
  rep.non_manifold_vertices_split = non_manifold_vertices;
  rep.non_manifold_edges = Index(non_manifold_edges.size());
  PM_REQUIRE(PMP::is_polygon_soup_a_polygon_mesh(polygons), ComputeError,
             "repair could not cut the mesh into manifold pieces");
  Surface mesh;
  PMP::polygon_soup_to_polygon_mesh(points, polygons, mesh);
  // polygon_soup_to_polygon_mesh adds vertex i for point i and face j for polygon j.
  auto vertex_source = mesh.add_property_map<VertexId, Index>("v:paramorph_source", -1).first;
  auto face_source = mesh.add_property_map<FaceId, Index>("f:paramorph_source", -1).first;
  auto face_reversed = mesh.add_property_map<FaceId, char>("f:paramorph_reversed", 0).first;
  for (std::size_t i = 0; i < points.size(); ++i) vertex_source[VertexId(Surface::size_type(i))] = point_source[i];
  for (std::size_t j = 0; j < polygons.size(); ++j) {
    face_source[FaceId(Surface::size_type(j))] = polygon_source[j];
    face_reversed[FaceId(Surface::size_type(j))] = reversed[j];
  }
  report(0.25, "removing degenerate faces");

  // 5. Faces of zero area on three distinct vertices (needles, caps): CGAL
  // collapses and flips them away with exact predicates.
  std::vector<FaceId> flat;
  PMP::degenerate_faces(mesh, std::back_inserter(flat));
  if (!flat.empty()) {
    rep.degenerate_faces_removed += Index(flat.size());
    PMP::remove_degenerate_faces(mesh);
  }

  // 6. Parts, by area: keep the largest if asked (before filling, so no time
  // goes into the holes of parts that are dropped).
  auto component = mesh.add_property_map<FaceId, std::size_t>("f:paramorph_component", 0).first;
  const std::size_t n_parts = PMP::connected_components(mesh, component);
  auto corners = [&](FaceId f) {
    std::array<Eigen::RowVector3d, 3> p;
    int k = 0;
    for (VertexId v : CGAL::vertices_around_face(mesh.halfedge(f), mesh)) {
      const Point& q = mesh.point(v);
      p[std::size_t(k++)] = Eigen::RowVector3d(q.x(), q.y(), q.z());
    }
    return p;
  };
  std::vector<double> area(n_parts, 0);
  std::vector<Index> input_faces(n_parts, 0);
  for (FaceId f : mesh.faces()) {
    const auto p = corners(f);
    area[component[f]] += 0.5 * (p[1] - p[0]).cross(p[2] - p[0]).norm();
    ++input_faces[component[f]];
  }
  const std::size_t largest = std::size_t(std::max_element(area.begin(), area.end()) - area.begin());
  std::vector<char> keep(n_parts, 1);
  if (options.keep_largest_component)
    for (std::size_t c = 0; c < n_parts; ++c)
      if (c != largest) {
        keep[c] = 0;
        ++rep.components_removed;
        rep.faces_removed_with_components += input_faces[c];
      }
  rep.components = Index(n_parts) - rep.components_removed;

  // 7. Holes: Liepa's triangulation, refined and faired (CGAL).
  if (options.fill_holes) {
    std::vector<Surface::Halfedge_index> cycles;
    PMP::extract_boundary_cycles(mesh, std::back_inserter(cycles));
    for (std::size_t h = 0; h < cycles.size(); ++h) {
      report(0.3 + 0.6 * double(h) / double(cycles.size()), "filling holes");
      const FaceId inside = mesh.face(mesh.opposite(cycles[h]));
      const std::size_t part = component[inside];
      if (!keep[part]) continue;
      // A lone triangle's "hole" is itself: filling it would make a two-sided pillow.
      const auto h1 = mesh.next(cycles[h]), h2 = mesh.next(h1);
      if (mesh.next(h2) == cycles[h] && mesh.face(mesh.opposite(h1)) == inside &&
          mesh.face(mesh.opposite(h2)) == inside) {
        ++rep.single_faces_left_open;
        continue;
      }
      std::vector<FaceId> new_faces;
      std::vector<VertexId> new_vertices;
      const bool faired = std::get<0>(PMP::triangulate_refine_and_fair_hole(
          mesh, cycles[h], std::back_inserter(new_faces), std::back_inserter(new_vertices),
          CGAL::parameters::use_delaunay_triangulation(true)));
      if (new_faces.empty()) {
        ++rep.holes_not_filled;
        continue;
      }
      ++rep.holes_filled;
      rep.fill_faces_added += Index(new_faces.size());
      rep.fill_vertices_added += Index(new_vertices.size());
      if (!faired) ++rep.fairing_failed;
      for (FaceId f : new_faces) {
        face_source[f] = -1;
        component[f] = part;
      }
      for (VertexId v : new_vertices) vertex_source[v] = -1;
    }
  }
  report(0.9, "orienting parts outward");

  // 8. Turn inside-out parts outward: the volume a part's faces enclose,
  // about its centre (exact for a closed part, a fair guess for an open one).
  std::vector<double> volume(n_parts, 0), filled_area(n_parts, 0);
  std::vector<Eigen::RowVector3d> centre(n_parts, Eigen::RowVector3d::Zero());
  std::vector<Index> part_faces(n_parts, 0), part_reversed(n_parts, 0);
  for (FaceId f : mesh.faces()) {
    const auto p = corners(f);
    const std::size_t c = component[f];
    centre[c] += (p[0] + p[1] + p[2]) / 3.0;
    filled_area[c] += 0.5 * (p[1] - p[0]).cross(p[2] - p[0]).norm();
    ++part_faces[c];
    if (face_source[f] >= 0 && face_reversed[f]) ++part_reversed[c];
  }
  for (std::size_t c = 0; c < n_parts; ++c) centre[c] /= double(std::max<Index>(part_faces[c], 1));
  for (FaceId f : mesh.faces()) {
    const auto p = corners(f);
    const std::size_t c = component[f];
    volume[c] += (p[0] - centre[c]).dot((p[1] - centre[c]).cross(p[2] - centre[c])) / 6.0;
  }
  std::vector<char> turn(n_parts, 0);
  for (std::size_t c = 0; c < n_parts; ++c) {
    if (!keep[c]) continue;
    // Only a clearly negative volume: a flat sheet's is roundoff either way.
    turn[c] = options.orient_outward && volume[c] < -1e-9 * std::pow(filled_area[c], 1.5);
    // Against the input's winding: a part mostly reversed was inside out,
    // and its faces that kept their winding were the misfits.
    const Index final_reversed = turn[c] ? input_faces[c] - part_reversed[c] : part_reversed[c];
    if (final_reversed * 2 > input_faces[c]) {
      ++rep.parts_turned_outward;
      rep.faces_reversed += input_faces[c] - final_reversed;
    } else {
      rep.faces_reversed += final_reversed;
    }
  }

  // 9. Out: kept faces, the vertices they use in order.
  std::size_t vertex_ids = 0;
  for (VertexId v : mesh.vertices()) vertex_ids = std::max(vertex_ids, std::size_t(v) + 1);
  std::vector<Index> output_of(std::max(vertex_ids, points.size()), -1);
  std::vector<std::array<Index, 3>> faces;
  std::vector<Index> faces_source;
  for (FaceId f : mesh.faces()) {
    if (!keep[component[f]]) continue;
    std::array<Index, 3> tri;
    int k = 0;
    for (VertexId v : CGAL::vertices_around_face(mesh.halfedge(f), mesh)) tri[std::size_t(k++)] = Index(v);
    if (turn[component[f]]) std::swap(tri[1], tri[2]);
    faces.push_back(tri);
    faces_source.push_back(face_source[f]);
  }
  Index n_out = 0;
  std::vector<Index> used;
  for (const auto& tri : faces)
    for (Index v : tri)
      if (output_of[std::size_t(v)] < 0) {
        output_of[std::size_t(v)] = 0;
        used.push_back(v);
      }
  std::sort(used.begin(), used.end());
  out.V.resize(Index(used.size()), 3);
  out.vertex_source.resize(Index(used.size()));
  for (Index v : used) {
    output_of[std::size_t(v)] = n_out;
    const Point& q = mesh.point(VertexId(Surface::size_type(v)));
    out.V.row(n_out) << q.x(), q.y(), q.z();
    out.vertex_source(n_out) = vertex_source[VertexId(Surface::size_type(v))];
    ++n_out;
  }
  out.F.resize(Index(faces.size()), 3);
  out.face_source.resize(Index(faces.size()));
  for (std::size_t f = 0; f < faces.size(); ++f) {
    for (int k = 0; k < 3; ++k) out.F(Index(f), k) = output_of[std::size_t(faces[f][std::size_t(k)])];
    out.face_source(Index(f)) = faces_source[f];
  }

  // Each input vertex goes where its welded representative's first copy went.
  out.input_vertex_target = VectorXi::Constant(n_in, -1);
  std::vector<Index> lost;  // used by kept faces but collapsed away by step 5
  for (Index v = 0; v < n_in; ++v) {
    const Index s = soup_of[std::size_t(into(v))];
    if (s < 0) continue;
    const VertexId mv{Surface::size_type(s)};
    if (!mesh.is_removed(mv)) {
      out.input_vertex_target(v) = output_of[std::size_t(s)];  // -1 when its part was dropped
    } else {
      lost.push_back(v);
    }
  }
  if (!lost.empty() && out.F.rows() > 0) {
    // A vertex of a collapsed needle goes to the nearest corner left.
    MatrixX3d where(Index(lost.size()), 3);
    for (std::size_t i = 0; i < lost.size(); ++i) where.row(Index(i)) = V.row(lost[i]);
    const ClosestPoints near = ClosestPointTree(out.V, out.F).query(where);
    for (std::size_t i = 0; i < lost.size(); ++i) {
      Index corner = 0;
      near.bary.row(Index(i)).maxCoeff(&corner);
      out.input_vertex_target(lost[i]) = out.F(near.face(Index(i)), corner);
    }
  }
  report(1.0, "repaired");
  return out;
}

}  // namespace paramorph
