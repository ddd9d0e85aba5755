// isometric_map(): constrained isometric planar parameterization (param/planar/isometric_map.h).
#include <pybind11/stl.h>

#include "compute/device.h"
#include "param/planar/isometric_map.h"
#include "python/arrays.h"
#include "python/bindings.h"
#include "python/progress.h"

namespace paramorph::python {

using planar::PlanarMapOptions;
using planar::PlanarMapResult;

namespace {

MatrixX2d to_uv(const py::object& obj, const char* name, std::size_t rows) {
  if (obj.is_none()) {
    PM_REQUIRE(rows == 0, InvalidInputError, name, " is required with its indices");
    return MatrixX2d(0, 2);
  }
  py::array arr = py::array::ensure(obj);
  PM_REQUIRE(arr && arr.ndim() == 2 && arr.shape(1) == 2 &&
                 (arr.dtype().kind() == 'f' || arr.dtype().kind() == 'i'),
             InvalidInputError, name, " must be a numeric (k, 2) array");
  auto data = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(arr);
  MatrixX2d out(arr.shape(0), 2);
  std::copy(data.data(), data.data() + data.size(), out.data());
  return out;
}

py::dict metrics_dict(const planar::PlanarMetrics& m) {
  py::dict d;
  d["area_min"] = m.area_min;
  d["area_max"] = m.area_max;
  d["area_rms"] = m.area_rms;
  d["angular"] = m.angular;
  d["l2_min"] = m.l2_min;
  d["l2_max"] = m.l2_max;
  d["l2_rms"] = m.l2_rms;
  d["symmetric_dirichlet"] = m.symmetric_dirichlet;
  return d;
}

}  // namespace

void bind_planar(py::module_& m) {
  py::class_<PlanarMapResult>(m, "PlanarMap", "Result of isometric_map().")
      .def_property_readonly("uv", [](const PlanarMapResult& r) { return to_numpy(r.uv); })
      .def_readonly("flipped", &PlanarMapResult::flipped)
      .def_readonly("iterations", &PlanarMapResult::iterations)
      .def_readonly("energy_evaluations", &PlanarMapResult::energy_evaluations)
      .def_readonly("gradient_evaluations", &PlanarMapResult::gradient_evaluations)
      .def_readonly("untangle_iterations", &PlanarMapResult::untangle_iterations)
      .def_property_readonly("energy_history",
                             [](const PlanarMapResult& r) { return to_numpy(r.energy_history); })
      .def_property_readonly("metrics", [](const PlanarMapResult& r) { return metrics_dict(r.metrics); })
      .def_readonly("stop_reason", &PlanarMapResult::stop_reason)
      .def_readonly("init", &PlanarMapResult::init)
      .def_readonly("backend", &PlanarMapResult::backend)
      .def_readonly("device", &PlanarMapResult::device)
      .def_readonly("backend_note", &PlanarMapResult::backend_note)
      .def_readonly("seconds", &PlanarMapResult::seconds);

  m.def(
      "isometric_map",
      [](const py::object& V, const py::object& F, const py::object& pinned,
         const py::object& pinned_uv, const py::object& soft, const py::object& soft_uv,
         double soft_weight, const py::object& init, int max_iterations, double tol,
         const std::string& backend, bool allow_folds, py::object progress) {
        const MatrixX3d v = to_vertices(V);
        const MatrixX3i f = to_faces(F);
        PlanarMapOptions o;
        o.pinned = to_indices(pinned, "pinned");
        o.pinned_uv = to_uv(pinned_uv, "pinned_uv", o.pinned.size());
        o.soft = to_indices(soft, "soft");
        o.soft_uv = to_uv(soft_uv, "soft_uv", o.soft.size());
        o.soft_weight = soft_weight;
        if (py::isinstance<py::str>(init)) {
          o.init = planar::parse_planar_init(init.cast<std::string>());
        } else {
          o.init = planar::PlanarInit::Given;
          o.initial_uv = to_uv(init, "init", 1);
        }
        o.max_iterations = max_iterations;
        o.tol = tol;
        o.allow_folds = allow_folds;
        o.backend = compute::parse_backend(backend);
        PythonProgress bridge(std::move(progress));
        return run_without_gil(bridge, [&] { return planar::isometric_map(v, f, o, bridge.get()); });
      },
      py::arg("V"), py::arg("F"), py::kw_only(), py::arg("pinned") = py::none(),
      py::arg("pinned_uv") = py::none(), py::arg("soft") = py::none(),
      py::arg("soft_uv") = py::none(), py::arg("soft_weight") = 100.0, py::arg("init") = "auto",
      py::arg("max_iterations") = 1000, py::arg("tol") = 1e-6, py::arg("backend") = "auto",
      py::arg("allow_folds") = false, py::arg("progress") = py::none(),
      R"doc(Fold-free isometric map of an open genus-0 patch to the plane (thesis ch. 2).

pinned (k,) indices with pinned_uv (k, 2): hard constraints, met exactly.
soft / soft_uv / soft_weight: quadratic-penalty constraints.
init: "auto" (free boundary), "tutte" (boundary on a circle), "free" (LSCM) or an (n, 2) array.
Hard pins are blended into the start smoothly (similarity fit, then a biharmonic displacement).
tol: stop when the energy fell by less than tol (relative) over the last 10 iterations.
A folded start is untangled first (Algorithm 2); folds that cannot be removed raise
ConstraintError unless allow_folds=True. Raises NotOpenError for a closed mesh,
NotGenusZeroError for a patch with handles.
backend: "auto" (OpenCL on a GPU that builds the kernels, else C++: on a CPU device the C++ path is faster), "opencl", "cpu";
the energy, gradient and step bound run there (thesis 2.3.2).)doc");
}

}  // namespace paramorph::python
