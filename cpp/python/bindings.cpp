// The helpers every binding module shares (ifsforge._core and ifsforge._vdb).
#include "bindings.h"

#include <algorithm>
#include <cstring>

#include "ifsforge/io/mesh.h"

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

py::dict mesh_dict(TriangleMesh mesh) {
  py::dict out;
  out["positions"] = rows_array(std::move(mesh.positions));
  out["normals"] = rows_array(std::move(mesh.normals));
  out["triangles"] = rows_array(std::move(mesh.triangles));
  return out;
}

std::vector<std::string_view> BytesRunner::operator()(std::uint64_t first, std::uint64_t last, int depth) const {
  py::gil_scoped_acquire gil;
  *held_ = py::list(depth ? distribute_(first, last, depth) : distribute_(first, last));
  std::vector<std::string_view> out;
  for (const auto& item : *held_) {
    char* data = nullptr;
    Py_ssize_t size = 0;
    if (!PyBytes_Check(item.ptr()) || PyBytes_AsStringAndSize(item.ptr(), &data, &size) != 0)
      throw InputError("a distributed job returned " + std::string(py::str(py::type::of(item))) +
                       ", not the bytes of run_volume_jobs or run_render_jobs");
    out.emplace_back(data, static_cast<std::size_t>(size));
  }
  return out;
}

}  // namespace ifsforge::python
