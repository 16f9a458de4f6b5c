// The compiled half of the `ifsforge` Python package.
#include "bindings.h"

#include <algorithm>
#include <utility>
#include <vector>

#include "ifsforge/core/error.h"

namespace ifsforge::python {

namespace {
std::vector<std::pair<int, void (*)(py::module_&)>>& bindings() {
  static std::vector<std::pair<int, void (*)(py::module_&)>> list;
  return list;
}
}  // namespace

Binding::Binding(int order, void (*bind)(py::module_&)) { bindings().emplace_back(order, bind); }

void bind_all(py::module_& m) {
  auto list = bindings();
  std::stable_sort(list.begin(), list.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  for (const auto& entry : list) entry.second(m);
}

ProgressCallback wrap_progress(const py::object& callback) {
  // Ctrl-C must stop long work even without a callback.
  return [callback](double fraction) {
    py::gil_scoped_acquire gil;
    if (PyErr_CheckSignals() != 0) throw py::error_already_set();
    if (callback.is_none()) return true;
    py::object answer = callback(fraction);
    return answer.is_none() ? true : answer.cast<bool>();
  };
}

py::array_t<float> to_numpy(const std::vector<float>& data, std::vector<py::ssize_t> shape) {
  py::array_t<float> out(shape);
  std::copy(data.begin(), data.end(), out.mutable_data());
  return out;
}

}  // namespace ifsforge::python

PYBIND11_MODULE(_core, m) {
  using namespace ifsforge::python;
  m.doc() = "ifsforge core: iterated function systems in n dimensions, their analysis and rendering";
  bind_all(m);
}
