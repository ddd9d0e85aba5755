// devices(): the OpenCL platforms/devices found (compute/device.h).
#include "compute/device.h"
#include "python/bindings.h"

namespace paramorph::python {

namespace py = pybind11;

void bind_compute(py::module_& m) {
  m.def(
      "devices",
      [] {
        const auto found = compute::list_devices();
        auto selected = compute::default_device();
        py::list out;
        bool marked = false;
        for (const auto& d : found) {
          py::dict entry;
          entry["platform"] = d.platform;
          entry["name"] = d.name;
          entry["type"] = d.type;
          entry["version"] = d.version;
          entry["usable"] = d.usable;
          entry["reason"] = d.reason;
          entry["global_memory"] = d.global_memory;
          entry["compute_units"] = d.compute_units;
          const bool is_selected = !marked && selected && selected->info().platform == d.platform &&
                                   selected->info().name == d.name;
          marked = marked || is_selected;
          entry["selected"] = is_selected;
          out.append(entry);
        }
        return out;
      },
      "OpenCL devices found, as dicts (platform, name, type, version, usable, reason,\n"
      "global_memory, compute_units, selected). Rejected devices say why in 'reason'.\n"
      "The selected one is what backend='auto'/'opencl' uses (PARAMORPH_OPENCL_DEVICE picks).\n"
      "Empty where no OpenCL driver is installed: opencl_error() then says so, and every\n"
      "function runs on its CPU path.");
  m.def("opencl_available", [] { return compute::default_device() != nullptr; },
        "True when a usable OpenCL device was selected.");
  m.def("opencl_error", &compute::default_device_error,
        "Why no OpenCL device is used (empty when one is).");
}

}  // namespace paramorph::python
