// TEMPORARY empty binding so the module links while bind_mesh is written.
#include "python/bindings.h"
namespace paramorph::python {
void bind_mesh(pybind11::module_&) {}
}  // namespace paramorph::python
