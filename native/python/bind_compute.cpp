// TEMPORARY empty binding so the module links while bind_compute is written.
#include "python/bindings.h"
namespace paramorph::python {
void bind_compute(pybind11::module_&) {}
}  // namespace paramorph::python
