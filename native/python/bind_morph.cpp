// Morphing (native/morph/): optimize_sphere_map (morph/optimize_sphere_map.h).
#include "morph/optimize_sphere_map.h"
#include "python/arrays.h"
#include "python/bindings.h"
#include "python/progress.h"

namespace paramorph::python {

namespace {

void def_optimize_sphere_map(py::module_& m) {
  using morph::OptimizeSphereResult;
  py::class_<OptimizeSphereResult>(m, "OptimizedSphereMap", "Result of optimize_sphere_map().")
      .def_property_readonly("positions", [](const OptimizeSphereResult& r) { return to_numpy(r.positions); },
                             "(n, 3) float64 unit vectors, fold-free")
      .def_readonly("iterations", &OptimizeSphereResult::iterations, "Ipopt's iterations")
      .def_readonly("barrier_steps", &OptimizeSphereResult::barrier_steps,
                    "Newton steps of the log-barrier warm start (0: Ipopt alone)")
      .def_readonly("objective", &OptimizeSphereResult::objective,
                    "sum of w_i v_i^0 . v_i at the end (sum of w_i at best)")
      .def_readonly("start_objective", &OptimizeSphereResult::start_objective)
      .def_readonly("epsilon", &OptimizeSphereResult::epsilon, "the absolute triple-product bound used")
      .def_readonly("min_triple", &OptimizeSphereResult::min_triple)
      .def_readonly("flipped", &OptimizeSphereResult::flipped)
      .def_readonly("status", &OptimizeSphereResult::status, "Ipopt's return status")
      .def_readonly("seconds", &OptimizeSphereResult::seconds)
      .def("__repr__", [](const OptimizeSphereResult& r) {
        return "<OptimizedSphereMap n=" + std::to_string(r.positions.rows()) +
               " iterations=" + std::to_string(r.iterations) + " flipped=" + std::to_string(r.flipped) +
               " status=" + r.status + ">";
      });
  m.def(
      "optimize_sphere_map",
      [](const py::object& V, const py::object& F, const py::object& sphere, double epsilon,
         int max_iterations, double tol, const py::object& target, const py::object& weights,
         py::object progress) {
        morph::OptimizeSphereOptions o;
        o.epsilon = epsilon;
        o.max_iterations = max_iterations;
        o.tol = tol;
        if (!target.is_none()) o.target = to_vertices(target, "target");
        if (!weights.is_none()) o.weights = to_vector(weights, "weights");
        const MatrixX3d v = to_vertices(V);
        const MatrixX3i f = to_faces(F);
        const MatrixX3d s = to_vertices(sphere, "sphere");
        PythonProgress bridge(std::move(progress));
        return run_without_gil(bridge,
                               [&] { return morph::optimize_sphere_map(v, f, s, o, bridge.get()); });
      },
      py::arg("V"), py::arg("F"), py::arg("sphere"), py::kw_only(), py::arg("epsilon") = 0.05,
      py::arg("max_iterations") = 200, py::arg("tol") = 1e-6, py::arg("target") = py::none(),
      py::arg("weights") = py::none(), py::arg("progress") = py::none(),
      R"doc(Optimized sphere map for morphing (thesis 4.3.3): from a fold-free map
`sphere` (e.g. sphere_map(V, F).positions), every vertex moves as close as the
fold constraints allow to its radial projection from the centroid (or to
`target`): maximise sum w_i v_i^0 . v_i subject to |v_i| = 1 (4.9) and, per
face, det(v_a, v_b, v_c) >= epsilon x (mean start triple product) (4.10;
lowered to half the start's smallest when the start is tighter). weights: (n,)
non-negative per-vertex w_i (all 1 when None; thesis (4.12) weighs feature
points). Ipopt (MUMPS) with exact sparse derivatives, warm-started from a
log-barrier Newton path on the spheres; every accepted iterate is fold-free.

V: (n, 3) float64/float32; F: (m, 3) int32/int64, closed genus 0; sphere:
(n, 3). progress: callable(fraction, stage) -> bool; False raises Cancelled.
Returns OptimizedSphereMap (positions, iterations, barrier_steps, objective,
start_objective, epsilon, min_triple, flipped, status, seconds). Raises the MeshError
subclasses of a non-closed / non-genus-0 mesh, InvalidInputError for a folded
or mis-shaped start or bad weights, Cancelled.)doc");
}

}  // namespace

void bind_morph(py::module_& m) { def_optimize_sphere_map(m); }

}  // namespace paramorph::python
