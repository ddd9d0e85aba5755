// Arrangement of two sphere maps by walking cell to cell
// (morph/sphere_arrangement.h).
#include "morph/sphere_arrangement.h"

#include <Eigen/Geometry>
#include <stdexcept>

#include "morph/point_location.h"
#include "morph/sphere_predicates.h"

namespace paramorph::morph {

namespace {

// Local numbering inside a cell: edge i of a face runs from its corner i to
// corner i + 1, which is the edge opposite corner i + 2 in TriMesh's numbering.
inline int opposite(int i) {
  return (i + 2) % 3;
}

/// Builds the cell of one face of A and one face of B and names its vertices.
class CellBuilder {
 public:
  CellBuilder(const SphereMapTopology& a, const SphereMapTopology& b, SphereArrangement& out)
      : a_(a), b_(b), out_(out), head_(std::size_t(a.edges.rows()), -1) {}

  /// Appends the cell of (fa, fb) to the arrangement; calls across_a(fa2) for
  /// each side on an edge of A (fa2: the face of A beyond it) and across_b(fb2)
  /// for each side on an edge of B. Returns false when the faces do not overlap.
  template <typename AcrossA, typename AcrossB>
  bool build(Index fa, Index fb, AcrossA&& across_a, AcrossB&& across_b) {
    const Index* A = a_.F.row(fa).data();
    const Index* B = b_.F.row(fb).data();
    SpherePoint pa[3], pb[3];
    for (int k = 0; k < 3; ++k) {
      pa[k] = {a_.X.row(A[k]).data(), -1};
      pb[k] = {b_.X.row(B[k]).data(), B[k]};
    }
    // sb[j][i]: side of B's corner j from A's edge i; sa[i][j]: side of A's
    // corner i from B's edge j (> 0: left of the edge, inside its face).
    int sa[3][3], sb[3][3];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        sb[j][i] = perturbed_orientation(pa[i], pa[(i + 1) % 3], pb[j]);
        sa[i][j] = perturbed_orientation(pb[j], pb[(j + 1) % 3], pa[i]);
      }
    bool a_inside[3], b_inside[3];
    for (int k = 0; k < 3; ++k) {
      a_inside[k] = sa[k][0] > 0 && sa[k][1] > 0 && sa[k][2] > 0;
      b_inside[k] = sb[k][0] > 0 && sb[k][1] > 0 && sb[k][2] > 0;
    }
    // Arcs i of A and j of B cross when each has its ends on both sides of the
    // other's great circle, on the near intersection of the two circles (not
    // its antipode): sign det(a_i, a_i+1, b_j) = -sign det(b_j, b_j+1, a_i).
    // At a crossing either A leaves fb (its corner i inside edge j) or B leaves fa.
    int exit_a[3] = {-1, -1, -1};  // per edge i of A: the edge of B where it leaves fb
    int exit_b[3] = {-1, -1, -1};  // per edge j of B: the edge of A where it leaves fa
    int first_crossing = -1;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        const int i1 = (i + 1) % 3, j1 = (j + 1) % 3;
        if (sb[j][i] == sb[j1][i] || sa[i][j] == sa[i1][j] || sb[j][i] != -sa[i][j]) continue;
        if (first_crossing < 0) first_crossing = 6 + 3 * i + j;
        if (sa[i][j] > 0)
          exit_a[i] = j;
        else
          exit_b[j] = i;
      }

    // Events: 0..2 corners of A, 3..5 corners of B, 6 + 3 i + j crossings.
    int start = -1;
    for (int k = 0; k < 3 && start < 0; ++k)
      if (a_inside[k]) start = k;
    for (int k = 0; k < 3 && start < 0; ++k)
      if (b_inside[k]) start = 3 + k;
    if (start < 0) start = first_crossing;
    if (start < 0) return false;

    for (int k = 0; k < 3; ++k) {
      if (a_inside[k]) out_.face_b_of_a[A[k]] = fb;
      if (b_inside[k]) out_.face_a_of_b[B[k]] = fa;
    }
    // Walk the boundary counter-clockwise: along A's edge after a corner of A
    // or where A enters fb, along B's edge otherwise, to the next event.
    int event = start, steps = 0;
    do {
      if (++steps > 6) throw std::logic_error("overlay: a cell of the arrangement does not close");
      bool along_a;
      int i = -1, j = -1;
      if (event < 3) {
        along_a = true, i = event;
      } else if (event < 6) {
        along_a = false, j = event - 3;
      } else {
        i = (event - 6) / 3, j = (event - 6) % 3;
        along_a = sa[i][j] < 0;
      }
      out_.corner.push_back(vertex_id(fa, fb, event));
      int next;
      if (along_a) {
        out_.side.push_back(a_.face_edges(fa, opposite(i)));
        across_a(a_.neighbors(fa, opposite(i)));
        next = exit_a[i] >= 0 ? 6 + 3 * i + exit_a[i] : (i + 1) % 3;
      } else {
        out_.side.push_back(-1 - b_.face_edges(fb, opposite(j)));
        across_b(b_.neighbors(fb, opposite(j)));
        next = exit_b[j] >= 0 ? 6 + 3 * exit_b[j] + j : 3 + (j + 1) % 3;
      }
      event = next;
    } while (event != start);
    out_.cell_face_a.push_back(fa);
    out_.cell_face_b.push_back(fb);
    out_.cell_start.push_back(Index(out_.corner.size()));
    return true;
  }

 private:
  Index vertex_id(Index fa, Index fb, int event) {
    if (event < 3) return a_.F(fa, event);
    if (event < 6) return out_.num_a + b_.F(fb, event - 3);
    const int i = (event - 6) / 3, j = (event - 6) % 3;
    return out_.num_a + out_.num_b +
           crossing(a_.face_edges(fa, opposite(i)), b_.face_edges(fb, opposite(j)));
  }

  /// The crossing of edge ea of A with edge eb of B: found in ea's short list
  /// (an edge of A crosses a few edges of B), else added.
  Index crossing(Index ea, Index eb) {
    for (Index c = head_[ea]; c >= 0; c = next_[c])
      if (out_.crossing_edge_b[c] == eb) return c;
    const Index c = out_.num_crossings();
    out_.crossing_edge_a.push_back(ea);
    out_.crossing_edge_b.push_back(eb);
    next_.push_back(head_[ea]);
    head_[ea] = c;
    const Eigen::Vector3d p0 = a_.X.row(a_.edges(ea, 0)), p1 = a_.X.row(a_.edges(ea, 1));
    const Eigen::Vector3d q0 = b_.X.row(b_.edges(eb, 0)), q1 = b_.X.row(b_.edges(eb, 1));
    const Eigen::Vector3d n = p0.cross(p1);
    const double s0 = n.dot(q0), s1 = n.dot(q1);
    Eigen::Vector3d x = std::abs(s1) * q0 + std::abs(s0) * q1;
    if (!(x.squaredNorm() > 0)) x = q0 + q1;  // both ends on A's circle: B is along it
    out_.crossing_position.push_back(x.normalized());
    return c;
  }

  const SphereMapTopology& a_;
  const SphereMapTopology& b_;
  SphereArrangement& out_;
  std::vector<Index> head_;  // per edge of A: its latest crossing
  std::vector<Index> next_;  // per crossing: the previous one on the same edge of A
};

/// A face of B at vertex v (the first that names it).
Index face_at_vertex(const MatrixX3i& F, Index v) {
  for (Index f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k)
      if (F(f, k) == v) return f;
  return -1;
}

}  // namespace

SphereArrangement arrange_sphere_maps(const SphereMapTopology& a, const SphereMapTopology& b,
                                      ProgressWindow progress) {
  SphereArrangement out;
  out.num_a = Index(a.X.rows());
  out.num_b = Index(b.X.rows());
  out.face_b_of_a = VectorXi::Constant(out.num_a, -1);
  out.face_a_of_b = VectorXi::Constant(out.num_b, -1);
  out.cell_start.push_back(0);
  const Index faces_a = Index(a.F.rows()), faces_b = Index(b.F.rows());
  // About |FA| + |FB| cells and as many crossings for maps of similar size.
  out.cell_face_a.reserve(std::size_t(2 * (faces_a + faces_b)));
  out.cell_face_b.reserve(out.cell_face_a.capacity());
  out.corner.reserve(4 * out.cell_face_a.capacity());
  out.side.reserve(out.corner.capacity());

  // Seed: vertex 0 of B, located in A; its cell with any face of B around it.
  const Index fb0 = face_at_vertex(b.F, 0);
  const Index fa0 = locate_on_sphere(a.X, a.F, a.neighbors, false, {b.X.row(0).data(), 0}, 0);
  if (fa0 < 0 || fb0 < 0)
    throw std::logic_error("overlay: the first vertex of B is in no face of A");

  // Face by face of A (breadth first); inside each, a flood over the faces of
  // B that overlap it. seed_b[fa] >= 0 once fa is queued; stamp[fb] == fa
  // once (fa, fb) is queued.
  CellBuilder builder(a, b, out);
  VectorXi seed_b = VectorXi::Constant(faces_a, -1);
  VectorXi stamp = VectorXi::Constant(faces_b, -1);
  std::vector<Index> queue_a{fa0}, stack_b;
  seed_b[fa0] = fb0;
  for (std::size_t head = 0; head < queue_a.size(); ++head) {
    const Index fa = queue_a[head];
    stack_b.assign(1, seed_b[fa]);
    stamp[seed_b[fa]] = fa;
    while (!stack_b.empty()) {
      const Index fb = stack_b.back();
      stack_b.pop_back();
      builder.build(
          fa, fb,
          [&](Index fa2) {
            if (fa2 >= 0 && seed_b[fa2] < 0) seed_b[fa2] = fb, queue_a.push_back(fa2);
          },
          [&](Index fb2) {
            if (fb2 >= 0 && stamp[fb2] != fa) stamp[fb2] = fa, stack_b.push_back(fb2);
          });
    }
    if ((head & 1023) == 0) progress.report(double(head) / double(faces_a), "overlay: arrangement");
  }
  if (Index(queue_a.size()) != faces_a)
    throw std::logic_error("overlay: the walk did not reach every face of A");
  return out;
}

}  // namespace paramorph::morph
