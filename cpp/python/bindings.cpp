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

py::array_t<float> to_numpy(const std::vector<float>& data, std::vector<py::ssize_t> shape) {
  py::array_t<float> out(shape);
  std::copy(data.begin(), data.end(), out.mutable_data());
  return out;
}

py::dict mesh_dict(const TriangleMesh& mesh) {
  py::dict out;
  const auto n = static_cast<py::ssize_t>(mesh.positions.size()), t = static_cast<py::ssize_t>(mesh.triangles.size());
  py::array_t<float> positions({n, py::ssize_t(3)}), normals({static_cast<py::ssize_t>(mesh.normals.size()), py::ssize_t(3)});
  py::array_t<std::uint32_t> triangles({t, py::ssize_t(3)});
  std::memcpy(positions.mutable_data(), mesh.positions.data(), n * 12);
  std::memcpy(normals.mutable_data(), mesh.normals.data(), mesh.normals.size() * 12);
  std::memcpy(triangles.mutable_data(), mesh.triangles.data(), t * 12);
  out["positions"] = positions;
  out["normals"] = normals;
  out["triangles"] = triangles;
  return out;
}

}  // namespace ifsforge::python
