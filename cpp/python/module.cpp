// The compiled half of the `ifsforge` Python package.
#include "bindings.h"

#include <algorithm>
#include <vector>

#include "ifsforge/core/error.h"

namespace ifsforge::python {

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
  bind_core(m);
  bind_model(m);
  bind_render(m);
  bind_texture(m);
  bind_vector(m);
  bind_volume(m);
  bind_io(m);
  bind_terrain(m);
  bind_pifs(m);
  bind_design(m);
  bind_inverse(m);
}
