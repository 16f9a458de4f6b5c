// The process-wide default thread count (what threads=0 means in every call).
#include "bindings.h"

#include "ifsforge/core/default_threads.h"
#include "ifsforge/core/parallel.h"

namespace ifsforge::python {
namespace {

void bind_parallel(py::module_& m) {
  m.def("set_default_threads", &set_default_threads, py::arg("threads"),
        "Threads used by every call given threads=0 (0: all cores). Results do not depend on it.");
  m.def("default_threads", [] { return resolve_threads(0); }, "Threads a call given threads=0 uses.");
}

const Binding registered(5, &bind_parallel);

}  // namespace
}  // namespace ifsforge::python
