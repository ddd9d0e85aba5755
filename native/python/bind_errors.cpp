// Python exception classes mirroring common/errors.h, and their translation.
#include <pybind11/pybind11.h>

#include "common/errors.h"
#include "compute/opencl.h"
#include "python/bindings.h"

namespace paramorph::python {

namespace py = pybind11;

void bind_errors(py::module_& m) {
  static py::exception<MeshError> mesh_error(m, "MeshError", PyExc_ValueError);
  static py::exception<NotClosedError> not_closed(m, "NotClosedError", mesh_error.ptr());
  static py::exception<NotOpenError> not_open(m, "NotOpenError", mesh_error.ptr());
  static py::exception<NotGenusZeroError> not_genus0(m, "NotGenusZeroError", mesh_error.ptr());
  static py::exception<DisconnectedError> disconnected(m, "DisconnectedError", mesh_error.ptr());
  static py::exception<NonManifoldError> non_manifold(m, "NonManifoldError", mesh_error.ptr());
  static py::exception<DegenerateFaceError> degenerate(m, "DegenerateFaceError", mesh_error.ptr());
  static py::exception<InvalidInputError> invalid(m, "InvalidInputError", mesh_error.ptr());
  static py::exception<ConstraintError> constraint(m, "ConstraintError", mesh_error.ptr());
  static py::exception<TargetTooSmallError> too_small(m, "TargetTooSmallError", mesh_error.ptr());
  static py::exception<EmptySelectionError> empty_selection(m, "EmptySelectionError", mesh_error.ptr());
  static py::exception<WholeMeshSelectedError> whole_mesh(m, "WholeMeshSelectedError", mesh_error.ptr());
  static py::exception<SelectionTopologyError> selection_topology(m, "SelectionTopologyError",
                                                                  mesh_error.ptr());
  static py::exception<Cancelled> cancelled(m, "Cancelled", PyExc_RuntimeError);
  static py::exception<ComputeError> compute(m, "ComputeError", PyExc_RuntimeError);
  static py::exception<DeviceError> device(m, "DeviceError", compute.ptr());

  // Most derived first: pybind11 tries translators in reverse registration order,
  // and one translator that checks derived types first keeps the mapping explicit.
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const NotClosedError& e) {
      not_closed(e.what());
    } catch (const NotOpenError& e) {
      not_open(e.what());
    } catch (const NotGenusZeroError& e) {
      not_genus0(e.what());
    } catch (const DisconnectedError& e) {
      disconnected(e.what());
    } catch (const NonManifoldError& e) {
      non_manifold(e.what());
    } catch (const DegenerateFaceError& e) {
      degenerate(e.what());
    } catch (const InvalidInputError& e) {
      invalid(e.what());
    } catch (const ConstraintError& e) {
      constraint(e.what());
    } catch (const TargetTooSmallError& e) {
      too_small(e.what());
    } catch (const EmptySelectionError& e) {
      empty_selection(e.what());
    } catch (const WholeMeshSelectedError& e) {
      whole_mesh(e.what());
    } catch (const SelectionTopologyError& e) {
      selection_topology(e.what());
    } catch (const MeshError& e) {
      mesh_error(e.what());
    } catch (const Cancelled& e) {
      cancelled(e.what());
    } catch (const DeviceError& e) {
      device(e.what());
    } catch (const ComputeError& e) {
      compute(e.what());
    } catch (const cl::Error& e) {  // a device failing mid-run (out of resources, lost)
      device((std::string("OpenCL error in ") + e.what() + " (code " + std::to_string(e.err()) +
               "); run with backend=\"cpu\"").c_str());
    }
  });
}

}  // namespace paramorph::python
