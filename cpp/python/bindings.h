#pragma once
// Shared by the bind_<area>.cpp files: one function per area, called from module.cpp.
#include <pybind11/functional.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "ifsforge/core/error.h"
#include "ifsforge/core/progress.h"
#include "ifsforge/io/axes.h"
#include "ifsforge/model/ifs.h"
#include "ifsforge/render/image.h"

namespace ifsforge::python {

namespace py = pybind11;

/// @brief One function per cpp/src area, in bind_<area>.cpp; module.cpp calls them in this
/// order (types before the functions that take or return them).
void bind_core(py::module_& m);
void bind_model(py::module_& m);
void bind_render(py::module_& m);
void bind_texture(py::module_& m);
void bind_vector(py::module_& m);
void bind_volume(py::module_& m);
void bind_io(py::module_& m);
void bind_terrain(py::module_& m);
void bind_pifs(py::module_& m);
void bind_design(py::module_& m);
void bind_inverse(py::module_& m);

/// @brief A C++ progress callback around a Python callable f(fraction) -> bool | None
/// (False cancels). Ctrl-C also cancels. Empty when `callback` is None.
ProgressCallback wrap_progress(const py::object& callback);

/// @brief An `up` argument: None (the format's default: none), "y", "z" or ifsforge.Up.
std::optional<Up> up_argument(const py::object& up);

/// @brief {'positions', 'normals', 'triangles'} numpy arrays (copies) of a mesh.
py::dict mesh_dict(const TriangleMesh& mesh);

/// @brief A float32 numpy array (copy) of shape `shape` from contiguous data.
py::array_t<float> to_numpy(const std::vector<float>& data, std::vector<py::ssize_t> shape);

/// @brief An Image from a (h, w) or (h, w, c) array: floats in [0, 1], or uint8 / uint16.
Image image_from_numpy(const py::array& array);
/// @brief (h, w) for one channel, else (h, w, c), float32.
py::array_t<float> image_to_numpy(const Image& image);

/// A count a Python caller gives as an int: negative values are an InputError naming the
/// option (not pybind's TypeError for an unsigned parameter).
inline std::uint64_t count_argument(long long value, const char* name) {
  if (value < 0) throw InputError(std::string(name) + ": expects 0 or more, got " + std::to_string(value));
  return static_cast<std::uint64_t>(value);
}

}  // namespace ifsforge::python
