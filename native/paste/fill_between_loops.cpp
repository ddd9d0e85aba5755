#include "paste/fill_between_loops.h"

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_face_base_with_info_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>
#include <deque>

namespace paramorph::paste {

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using VertexBase = CGAL::Triangulation_vertex_base_with_info_2<Index, Kernel>;
/// Face info: how many loops enclose the face (-1 until reached).
using FaceInfoBase = CGAL::Triangulation_face_base_with_info_2<int, Kernel>;
using FaceBase = CGAL::Constrained_triangulation_face_base_2<Kernel, FaceInfoBase>;
using Tds = CGAL::Triangulation_data_structure_2<VertexBase, FaceBase>;
// Exact_predicates_tag: crossing constraints are split at a constructed
// point (which is how a crossing shows: one vertex more than given).
using Cdt = CGAL::Constrained_Delaunay_triangulation_2<Kernel, Tds, CGAL::Exact_predicates_tag>;

/// Depth of every finite face: flood fill from the infinite face, a
/// constraint crossed adds one.
void mark_depths(Cdt& cdt) {
  for (auto f = cdt.all_faces_begin(); f != cdt.all_faces_end(); ++f) f->info() = -1;
  std::deque<std::pair<Cdt::Face_handle, int>> next{{cdt.infinite_face(), 0}};
  while (!next.empty()) {
    std::deque<Cdt::Face_handle> same{next.front().first};
    const int depth = next.front().second;
    next.pop_front();
    if (same.front()->info() != -1) continue;
    while (!same.empty()) {  // the component reachable without crossing a constraint
      const Cdt::Face_handle f = same.front();
      same.pop_front();
      if (f->info() != -1) continue;
      f->info() = depth;
      for (int i = 0; i < 3; ++i) {
        const Cdt::Face_handle g = f->neighbor(i);
        if (g->info() != -1) continue;
        if (cdt.is_constrained({f, i}))
          next.emplace_back(g, depth + 1);
        else
          same.push_back(g);
      }
    }
  }
}

}  // namespace

std::optional<MatrixX3i> fill_between_loops(const std::vector<Eigen::Vector2d>& points,
                                            const std::vector<std::array<Index, 2>>& segments) {
  Cdt cdt;
  std::vector<Cdt::Vertex_handle> handles(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    handles[i] = cdt.insert(Kernel::Point_2(points[i].x(), points[i].y()));
    handles[i]->info() = Index(i);
  }
  if (cdt.number_of_vertices() != points.size()) return std::nullopt;  // a point given twice
  for (const auto& s : segments) cdt.insert_constraint(handles[s[0]], handles[s[1]]);
  // A crossing is split at a constructed point: one more vertex.
  if (cdt.number_of_vertices() != points.size()) return std::nullopt;
  mark_depths(cdt);
  std::vector<Index> rows;
  for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f)
    if (f->info() % 2 == 1)
      for (int k = 0; k < 3; ++k) rows.push_back(f->vertex(k)->info());
  MatrixX3i out(Index(rows.size() / 3), 3);
  for (Index r = 0; r < out.rows(); ++r)
    for (int k = 0; k < 3; ++k) out(r, k) = rows[std::size_t(3 * r + k)];
  return out;
}

}  // namespace paramorph::paste
