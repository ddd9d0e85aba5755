// sphere_map(): fold-free spherical parameterization (param/spherical/sphere_map.h);
// isometric_sphere_map and balanced_sphere_map (param/spherical/), the morph's maps.
#include <pybind11/stl.h>

#include "param/spherical/balanced_sphere_map.h"
#include "param/spherical/isometric_sphere_map.h"
#include "param/spherical/progressive_sphere_map.h"
#include "mesh/validate.h"
#include "param/spherical/sphere_map.h"
#include "python/arrays.h"
#include "python/bindings.h"
#include "python/progress.h"

namespace paramorph::python {

using spherical::SphereMapOptions;
using spherical::SphereMapResult;

void def_isometric_sphere_map(py::module_& m) {
  using spherical::IsometricSphereResult;
  py::class_<IsometricSphereResult>(m, "IsometricSphereMap", "Result of isometric_sphere_map().")
      .def_property_readonly("positions", [](const IsometricSphereResult& r) { return to_numpy(r.positions); })
      .def_readonly("steps", &IsometricSphereResult::steps)
      .def_readonly("start_energy", &IsometricSphereResult::start_energy)
      .def_readonly("energy", &IsometricSphereResult::energy)
      .def_readonly("converged", &IsometricSphereResult::converged);
  m.def(
      "isometric_sphere_map",
      [](const py::object& V, const py::object& F, const py::object& start, int max_steps, double tol,
         py::object progress) {
        const MatrixX3d v = to_vertices(V), s = to_vertices(start, "start");
        const MatrixX3i f = to_faces(F);
        require_mesh(v, f);
        require_directions(s, "start", v.rows());
        spherical::IsometricSphereOptions o;
        o.max_steps = max_steps;
        o.tol = tol;
        PythonProgress bridge(std::move(progress));
        return run_without_gil(bridge, [&] {
          return spherical::isometric_sphere_map(v, f, s, o, ProgressWindow(bridge.get()));
        });
      },
      py::arg("V"), py::arg("F"), py::arg("start"), py::kw_only(), py::arg("max_steps") = 40,
      py::arg("tol") = 1e-5, py::arg("progress") = py::none(),
      R"doc(Sphere map minimising the isometric (symmetric Dirichlet) energy of every
face, from a fold-free start whose faces all have positive triple products.)doc");
}

void def_balanced_sphere_map(py::module_& m) {
  using spherical::BalancedSphereResult;
  py::class_<BalancedSphereResult>(m, "BalancedSphereMap", "Result of balanced_sphere_map().")
      .def_property_readonly("positions", [](const BalancedSphereResult& r) { return to_numpy(r.positions); })
      .def_readonly("levels", &BalancedSphereResult::levels)
      .def_readonly("steps", &BalancedSphereResult::steps)
      .def_readonly("start_energy", &BalancedSphereResult::start_energy)
      .def_readonly("energy", &BalancedSphereResult::energy);
  m.def(
      "balanced_sphere_map",
      [](const py::object& V, const py::object& F, double level_ratio, int max_steps, double polish_face_steps,
         py::object progress) {
        const MatrixX3d v = to_vertices(V);
        const MatrixX3i f = to_faces(F);
        spherical::BalancedSphereOptions o;
        o.progressive.level_ratio = level_ratio;
        o.isometric.max_steps = max_steps;
        o.polish_face_steps = polish_face_steps;
        PythonProgress bridge(std::move(progress));
        return run_without_gil(bridge, [&] { return spherical::balanced_sphere_map(v, f, o, bridge.get()); });
      },
      py::arg("V"), py::arg("F"), py::kw_only(), py::arg("level_ratio") = 2.0, py::arg("max_steps") = 100,
      py::arg("polish_face_steps") = 300000.0, py::arg("progress") = py::none(),
      R"doc(Fold-free sphere map giving every part a share of the sphere close to its
share of the surface: the progressive embedding (fold-free by construction,
relaxed level by level; level_ratio: vertices of a level over the one before),
then at most min(max_steps, polish_face_steps / faces) Newton steps on the
isometric energy of the whole model.)doc");
}

void def_progressive_sphere_map(py::module_& m) {
  using spherical::ProgressiveSphereResult;
  py::class_<ProgressiveSphereResult>(m, "ProgressiveSphereMap", "Result of progressive_sphere_map().")
      .def_property_readonly("positions", [](const ProgressiveSphereResult& r) { return to_numpy(r.positions); })
      .def_readonly("levels", &ProgressiveSphereResult::levels)
      .def_readonly("vertex_steps", &ProgressiveSphereResult::vertex_steps)
      .def_readonly("geometric_refusals", &ProgressiveSphereResult::geometric_refusals)
      .def_readonly("min_triple", &ProgressiveSphereResult::min_triple)
      .def_readonly("collapse_seconds", &ProgressiveSphereResult::collapse_seconds)
      .def_readonly("embed_seconds", &ProgressiveSphereResult::embed_seconds);
  m.def(
      "progressive_sphere_map",
      [](const py::object& V, const py::object& F, double level_ratio, double level_work, int min_sweeps,
         int max_sweeps, int insert_steps, py::object progress) {
        const MatrixX3d v = to_vertices(V);
        const MatrixX3i f = to_faces(F);
        spherical::ProgressiveSphereOptions o;
        o.level_ratio = level_ratio;
        o.level_work = level_work;
        o.min_sweeps = min_sweeps;
        o.max_sweeps = max_sweeps;
        o.insert_steps = insert_steps;
        PythonProgress bridge(std::move(progress));
        return run_without_gil(bridge, [&] {
          validate_arrays(v, f);
          const TriMesh mesh(v, f);
          require_closed_genus0(validate(mesh));
          return spherical::progressive_sphere_map(mesh, o, ProgressWindow(bridge.get()));
        });
      },
      py::arg("V"), py::arg("F"), py::kw_only(), py::arg("level_ratio") = 2.0, py::arg("level_work") = 40000.0,
      py::arg("min_sweeps") = 2, py::arg("max_sweeps") = 60, py::arg("insert_steps") = 4,
      py::arg("progress") = py::none(),
      R"doc(Fold-free sphere map by construction (Praun & Hoppe 2003): the mesh
collapsed to a tetrahedron, then its vertices put back one at a time, each
inside its ring, with local isometric relaxation level by level (sweeps per
level: level_work / vertices, within [min_sweeps, max_sweeps]; level_ratio:
vertices of a level over those of the one before).)doc");
}

void bind_sphere(py::module_& m) {
  def_isometric_sphere_map(m);
  def_progressive_sphere_map(m);
  def_balanced_sphere_map(m);
  py::class_<SphereMapResult>(m, "SphereMap",
                              "Result of sphere_map(): unit-sphere positions and solver statistics.")
      .def_property_readonly("positions", [](const SphereMapResult& r) { return to_numpy(r.positions); },
                             "(n, 3) float64 unit vectors, in the input's vertex order")
      .def_readonly("flipped", &SphereMapResult::flipped, "faces folded on the sphere (0 on success)")
      .def_readonly("residual", &SphereMapResult::residual,
                    "relative residual of the last saddle-point solve")
      .def_readonly("outer_iterations", &SphereMapResult::outer_iterations)
      .def_readonly("inner_iterations", &SphereMapResult::inner_iterations,
                    "inner iterations summed over the outer iterations")
      .def_readonly("inner_per_outer", &SphereMapResult::inner_per_outer)
      .def_property_readonly("energy_history",
                             [](const SphereMapResult& r) { return to_numpy(r.energy_history); },
                             "spring energy of the start and after each outer iteration")
      .def_readonly("energy_increased", &SphereMapResult::energy_increased)
      .def_readonly("stop_reason", &SphereMapResult::stop_reason,
                    "\"converged\", \"max_outer_iterations\", \"fold\", \"energy\" or \"inner_stalled\"\n"
                    "(the last solve did not reach tol: Jacobi on a mesh it does not converge on)")
      .def_readonly("relaxation_sweeps", &SphereMapResult::relaxation_sweeps)
      .def_readonly("initial_map", &SphereMapResult::initial_map,
                    "the start used: \"stereographic\" (Tutte), \"progressive\" (fold-free by construction) or "
                    "\"relaxation\"")
      .def_readonly("squeezed_start", &SphereMapResult::squeezed_start,
                    "faces of the Tutte start with triple products within rounding of 0 (<= 1e-13)")
      .def_readonly("partial_steps", &SphereMapResult::partial_steps,
                    "outer steps cut short so that no face folds or reaches rounding")
      .def_property_readonly("area_stretch",
                             [](const SphereMapResult& r) { return to_numpy(r.area_stretch); },
                             "(n,) area stretch factor per vertex (thesis Def. 3.1)")
      .def_readonly("weights", &SphereMapResult::weights)
      .def_readonly("solver", &SphereMapResult::solver)
      .def_readonly("backend", &SphereMapResult::backend)
      .def_readonly("device", &SphereMapResult::device)
      .def_readonly("backend_note", &SphereMapResult::backend_note)
      .def_readonly("seconds", &SphereMapResult::seconds)
      .def_property_readonly("timings", [](const SphereMapResult& r) {
        py::dict d;
        for (const auto& [stage, seconds] : r.timings) d[py::str(stage)] = seconds;
        return d;
      })
      .def("__repr__", [](const SphereMapResult& r) {
        return "<SphereMap n=" + std::to_string(r.positions.rows()) +
               " flipped=" + std::to_string(r.flipped) + " residual=" + std::to_string(r.residual) +
               " outer=" + std::to_string(r.outer_iterations) +
               " inner=" + std::to_string(r.inner_iterations) + " backend=" + r.backend + ">";
      });

  m.def(
      "sphere_map",
      [](const py::object& V, const py::object& F, const std::string& weights, double tol,
         int max_iterations, const std::string& solver, const std::string& backend,
         py::object progress, int max_outer_iterations, double outer_tol, const std::string& init,
         int check_every, double omega, bool reorder) {
        const MatrixX3d v = to_vertices(V);
        const MatrixX3i f = to_faces(F);
        SphereMapOptions o;
        o.weights = spherical::parse_weights(weights);
        o.solver = spherical::parse_inner_solver(solver);
        o.backend = compute::parse_backend(backend);
        o.init = spherical::parse_initial_map(init);
        o.tol = tol;
        o.max_iterations = max_iterations;
        o.max_outer_iterations = max_outer_iterations;
        o.outer_tol = outer_tol;
        o.check_every = check_every;
        o.omega = omega;
        o.reorder = reorder;
        PythonProgress bridge(std::move(progress));
        return run_without_gil(bridge, [&] { return spherical::sphere_map(v, f, o, bridge.get()); });
      },
      py::arg("V"), py::arg("F"), py::kw_only(), py::arg("weights") = "conformal",
      py::arg("tol") = 1e-7, py::arg("max_iterations") = 200000, py::arg("solver") = "auto",
      py::arg("backend") = "auto", py::arg("progress") = py::none(),
      py::arg("max_outer_iterations") = 4, py::arg("outer_tol") = 1e-3, py::arg("init") = "auto",
      py::arg("check_every") = 50, py::arg("omega") = 0.9, py::arg("reorder") = true,
      R"doc(Fold-free map of a closed genus-0 triangle mesh onto the unit sphere (thesis ch. 3).

V: (n, 3) float64 or float32 vertex positions. F: (m, 3) int32 or int64 triangles,
counter-clockwise seen from outside.
weights: "conformal" (cotangent, angles clamped to [5°, 85°]) or "barycentric".
tol: relative residual each tangent-plane saddle-point solve must reach (at most
1e-2 after a progressive start, whose steps are cut short where limbs squeeze).
max_iterations: inner iterations allowed per saddle-point solve.
solver: "auto" (= "pcg"), "pcg", "cholesky" or "jacobi" (thesis Algorithm 3).
backend: "auto" (OpenCL on a GPU that builds the kernels, else C++: on a CPU device the C++ path is faster), "opencl", "cpu".
progress: callable(fraction, stage) -> bool; returning False raises Cancelled.
max_outer_iterations, outer_tol: outer loop limits (stops when the relative energy
decrease drops below outer_tol; a step that would fold a face or squeeze one to
rounding is cut short; at most 2 after a progressive start). init: "auto" (the Tutte start where no face of it is within
rounding of 0, else the progressive one: never fails), "stereographic" (Tutte,
repaired by relaxation), "progressive" (built fold-free coarse to fine) or
"relaxation" (the thesis' radial projection).
check_every, omega: Jacobi residual-test period and damping.
Raises NotClosedError, NotGenusZeroError, DisconnectedError, NonManifoldError,
DegenerateFaceError, InvalidInputError (all MeshError), Cancelled, ComputeError (its subclass
DeviceError when the OpenCL device fails).)doc");
}

}  // namespace paramorph::python
