// TEMPORARY empty binding so the module links while bind_sphere is written.
#include "python/bindings.h"
namespace paramorph::python {
void bind_sphere(pybind11::module_&) {}
}  // namespace paramorph::python
