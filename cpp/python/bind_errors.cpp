// C++ exceptions become the Python classes of ifsforge.errors (which also derive from
// ValueError, MemoryError, OSError where that is what a Python user would catch).
#include "bindings.h"
#include "ifsforge/core/error.h"

namespace ifsforge::python {

namespace {

void bind_errors(py::module_& m) {
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
}

const Binding registered(0, &bind_errors);

}  // namespace
}  // namespace ifsforge::python
