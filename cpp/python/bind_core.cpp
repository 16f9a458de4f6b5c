// The core: C++ exceptions become the Python classes of ifsforge.errors (which also derive from
// ValueError, MemoryError, OSError where that is what a Python user would catch), the default
// thread count, and the sRGB transfer function every writer shares.
#include "bindings.h"
#include "ifsforge/core/color.h"
#include "ifsforge/core/default_threads.h"
#include "ifsforge/core/error.h"
#include "ifsforge/core/memory.h"
#include "ifsforge/core/parallel.h"

namespace ifsforge::python {

void bind_core(py::module_& m) {
  py::register_exception_translator([](std::exception_ptr p) {
    auto raise = [](const char* name, const char* what) {
      py::object cls = py::module_::import("ifsforge.errors").attr(name);
      PyErr_SetString(cls.ptr(), what);
    };
    try {
      if (p) std::rethrow_exception(p);
    } catch (const DivergentSystemError& e) {
      raise("DivergentSystemError", e.what());
    } catch (const InputError& e) {
      raise("InputError", e.what());
    } catch (const MemoryBudgetError& e) {
      raise("MemoryBudgetError", e.what());
    } catch (const FileError& e) {
      raise("FileError", e.what());
    } catch (const Cancelled& e) {
      raise("Cancelled", e.what());
    } catch (const Error& e) {
      raise("Error", e.what());
    }
  });

  m.def("set_default_threads", &set_default_threads, py::arg("threads"),
        "Threads used by every call given threads=0 (0: all cores). Results do not depend on it.");
  m.def("default_threads", [] { return resolve_threads(0); }, "Threads a call given threads=0 uses.");
  m.def("memory_budget", &memory_budget,
        "Bytes one job may allocate: IFSFORGE_MEMORY_BUDGET_MB if set, else 75% of the physical memory.");
  m.def("check_memory", &check_memory, py::arg("bytes"), py::arg("what"),
        "MemoryBudgetError naming `what` when `bytes` exceeds memory_budget() (estimate before allocating).");
  m.def("srgb_to_linear", py::vectorize([](double c) { return srgb_to_linear<double>(c); }), py::arg("c"),
        "Display (sRGB-encoded) color values in [0, 1] to linear light (IEC 61966-2-1), clamped first: what "
        "glTF COLOR_0/baseColorFactor, the .vdb color grid and Blender color attributes hold.");
  m.def("linear_to_srgb", py::vectorize([](double c) { return linear_to_srgb(c); }), py::arg("c"),
        "The inverse of srgb_to_linear on [0, 1].");
}

}  // namespace ifsforge::python
