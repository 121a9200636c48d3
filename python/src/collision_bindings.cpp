// Collision detection alone (filled in below when the API is bound).
#include "bindings.hpp"

namespace penalty::python {

void bind_collision(py::module_&) {}

}  // namespace penalty::python
