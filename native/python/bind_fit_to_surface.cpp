// A kept topology fitted to the target's surface (morph/fit_to_surface.h).

#include <vector>

#include "morph/fit_to_surface.h"
#include "python/arrays.h"
#include "python/bindings.h"
#include "python/progress.h"

namespace paramorph::python {

void bind_fit_to_surface(py::module_& m) {
  py::class_<morph::FitToSurface>(m, "FitToSurface")
      .def_property_readonly("positions", [](const morph::FitToSurface& r) { return to_numpy(r.positions); },
                             "(n, 3) the fitted vertices")
      .def_readonly("rounds", &morph::FitToSurface::rounds, "rounds that stepped")
      .def_readonly("distance_before", &morph::FitToSurface::distance_before,
                    "sampled two-sided distance (the largest) at the start")
      .def_readonly("distance_after", &morph::FitToSurface::distance_after, "the same for positions")
      .def_readonly("facing_away_before", &morph::FitToSurface::facing_away_before,
                    "share of the faces whose normal points against the target's under their centre, at the start")
      .def_readonly("facing_away_after", &morph::FitToSurface::facing_away_after, "the same for positions")
      .def_readonly("pleat_moves", &morph::FitToSurface::pleat_moves,
                    "vertex moves the pleat smoothing kept (all passes; 0 when it found none or was off)")
      .def("__repr__", [](const morph::FitToSurface& r) {
        return "<FitToSurface rounds=" + std::to_string(r.rounds) + " distance " + std::to_string(r.distance_before) +
               " -> " + std::to_string(r.distance_after) + ">";
      });
  m.def(
      "fit_to_surface",
      [](const py::object& X, const py::object& F, const py::object& VB, const py::object& FB, const py::object& held,
         int rounds, int patience, double stiffness, double stiffness_decay, int smooth_pleats, int even_out_passes,
         double even_out_step, py::object progress) {
        const MatrixX3d x = to_vertices(X, "X"), vb = to_vertices(VB, "VB");
        const MatrixX3i f = to_faces(F, "F"), fb = to_faces(FB, "FB");
        const std::vector<Index> kept = to_indices(held, "held");
        const VectorXi h = Eigen::Map<const VectorXi>(kept.data(), Index(kept.size()));
        morph::FitToSurfaceOptions options;
        options.rounds = rounds;
        options.patience = patience;
        options.stiffness = stiffness;
        options.stiffness_decay = stiffness_decay;
        options.smooth_pleats = smooth_pleats;
        options.even_out_passes = even_out_passes;
        options.even_out_step = even_out_step;
        PythonProgress bridge(std::move(progress));
        return run_without_gil(bridge, [&] { return morph::fit_to_surface(x, f, vb, fb, h, options, bridge.get()); });
      },
      py::arg("X"), py::arg("F"), py::arg("VB"), py::arg("FB"), py::kw_only(), py::arg("held") = py::none(),
      py::arg("rounds") = 150, py::arg("patience") = 20, py::arg("stiffness") = 1.0, py::arg("stiffness_decay") = 0.95,
      py::arg("smooth_pleats") = 20, py::arg("even_out_passes") = 30, py::arg("even_out_step") = 0.5,
      py::arg("progress") = py::none(),
      R"doc(Moves a mesh of fixed connectivity lying on a target surface so the two lie close both ways
(Keep Source's Topology: A's vertices at their corresponding points on B, then fitted).

X, F: the mesh as it lies on the target; VB, FB: the target. Each round draws
samples of X's faces to their closest points on B and B's vertices to their
closest points on X (where the normals agree), with the change of each edge
penalised by `stiffness` (times `stiffness_decay` each round); after `rounds`,
rounds go on while the last `patience` came closer, up to 2 x rounds. Where
they end farther than 2 % of the target's diagonal, they run again from X's
faces evened out by `even_out_passes` passes (each moving a vertex
`even_out_step` of the way to its faces' area-weighted centroid along X; 0:
never), on a schedule of 2 x rounds (up to 4 x), and the closer end is kept.
held: vertices
that stay exactly where they are (pins, matched tips). A step that would turn
a face over is halved; one that cannot ends the fit. The round closest to B
both ways is kept (never farther than X); then up to `smooth_pleats` passes
move the vertices of faces folded over on B (normal against B's) along B's
surface, never ending farther from B (0: none). Returns FitToSurface. Turning, scaling or
moving both meshes moves the answer with them.)doc");
}

}  // namespace paramorph::python
