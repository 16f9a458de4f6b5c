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

}  // namespace ifsforge::python
