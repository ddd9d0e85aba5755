// In-betweens of a morph and their checks: ShapeInterpolation
// (morph/shape_interpolation.h), self_intersections
// (mesh/self_intersections.h) and surface_distance (mesh/surface_distance.h).

#include <pybind11/stl.h>

#include <memory>
#include <vector>

#include "mesh/self_intersections.h"
#include "mesh/surface_distance.h"
#include "morph/shape_interpolation.h"
#include "python/arrays.h"
#include "python/bindings.h"
#include "python/progress.h"

namespace paramorph::python {

void bind_in_betweens(py::module_& m) {
  py::class_<morph::ShapeInterpolation>(m, "ShapeInterpolation", R"doc(As-rigid-as-possible in-betweens of
one mesh at two shapes (Alexa et al. 2000; Xu et al. 2005): per face, the
rotation from one end to the other is turned by t and the stretch
interpolated linearly, and the positions are fitted to those faces with one
sparse factor computed here, once; at(t) is then one solve. Exact at t = 0
and 1; each connected part's vertex mean moves on the straight line.

source, target: (n, 3) positions; F: (m, 3) faces. InvalidInputError for
mismatched or malformed arrays. progress(fraction, stage) as elsewhere
(the setup takes seconds on a merged mesh of a few 100k faces; returning
False cancels with Cancelled).)doc")
      .def(py::init([](const py::object& source, const py::object& target, const py::object& F,
                       py::object progress) {
             const MatrixX3d s = to_vertices(source, "source"), t = to_vertices(target, "target");
             const MatrixX3i f = to_faces(F, "F");
             PythonProgress bridge(std::move(progress));
             return run_without_gil(bridge,
                                    [&] { return std::make_unique<morph::ShapeInterpolation>(s, t, f, bridge.get()); });
           }),
           py::arg("source"), py::arg("target"), py::arg("F"), py::kw_only(), py::arg("progress") = py::none())
      .def(
          "at",
          [](const morph::ShapeInterpolation& self, double t) {
            MatrixX3d out;
            {
              py::gil_scoped_release release;
              out = self.at(t);
            }
            return to_numpy(out);
          },
          py::arg("t"), "(n, 3) positions at time t (0: source, 1: target).")
      .def_property_readonly("degenerate_faces", &morph::ShapeInterpolation::degenerate_faces,
                             "faces of zero area at either end (their edges interpolated straight)")
      .def_property_readonly("global_angle", &morph::ShapeInterpolation::global_angle,
                             "the whole shape's turn between the ends, radians");

  py::class_<SelfIntersections>(m, "SelfIntersections")
      .def_property_readonly("intersecting", [](const SelfIntersections& r) {
        std::vector<bool> flags(r.intersecting.begin(), r.intersecting.end());
        py::array_t<bool> out(py::ssize_t(flags.size()));
        auto w = out.mutable_unchecked<1>();
        for (std::size_t k = 0; k < flags.size(); ++k) w(py::ssize_t(k)) = flags[k];
        return out;
      }, "(m,) bool: the face passes through another face")
      .def_readonly("intersecting_faces", &SelfIntersections::intersecting_faces)
      .def_readonly("pairs", &SelfIntersections::pairs, "intersecting pairs of faces")
      .def_readonly("degenerate_faces", &SelfIntersections::degenerate_faces, "faces of zero area (not tested)")
      .def("__repr__", [](const SelfIntersections& r) {
        return "<SelfIntersections faces=" + std::to_string(r.intersecting_faces) +
               " pairs=" + std::to_string(r.pairs) + " degenerate=" + std::to_string(r.degenerate_faces) + ">";
      });
  m.def(
      "self_intersections",
      [](const py::object& V, const py::object& F) {
        const MatrixX3d v = to_vertices(V, "V");
        const MatrixX3i f = to_faces(F, "F");
        py::gil_scoped_release release;
        return self_intersections(v, f);
      },
      py::arg("V"), py::arg("F"),
      "Faces that pass through other faces (CGAL's exact test; faces meeting only at a shared edge or vertex do not count).");

  py::class_<SurfaceDistance>(m, "SurfaceDistance")
      .def_readonly("a_to_b", &SurfaceDistance::a_to_b, "largest distance from A's samples to B")
      .def_readonly("b_to_a", &SurfaceDistance::b_to_a, "largest distance from B's samples to A")
      .def_readonly("mean_a_to_b", &SurfaceDistance::mean_a_to_b)
      .def_readonly("mean_b_to_a", &SurfaceDistance::mean_b_to_a)
      .def_property_readonly("hausdorff", &SurfaceDistance::hausdorff, "max(a_to_b, b_to_a)")
      .def("__repr__", [](const SurfaceDistance& r) {
        return "<SurfaceDistance a_to_b=" + std::to_string(r.a_to_b) + " b_to_a=" + std::to_string(r.b_to_a) + ">";
      });
  m.def(
      "surface_distance",
      [](const py::object& VA, const py::object& FA, const py::object& VB, const py::object& FB,
         py::object progress) {
        const MatrixX3d va = to_vertices(VA, "VA"), vb = to_vertices(VB, "VB");
        const MatrixX3i fa = to_faces(FA, "FA"), fb = to_faces(FB, "FB");
        require_mesh(va, fa, "A");
        require_mesh(vb, fb, "B");
        PythonProgress bridge(std::move(progress));
        return run_without_gil(bridge, [&] { return surface_distance(va, fa, vb, fb, bridge.get()); });
      },
      py::arg("VA"), py::arg("FA"), py::arg("VB"), py::arg("FB"), py::kw_only(), py::arg("progress") = py::none(),
      "Sampled distances between two surfaces (vertices, edge midpoints, face centroids to the other's closest points).");
}

}  // namespace paramorph::python
