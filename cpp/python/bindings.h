#pragma once
// Shared by the bind_<area>.cpp files: one function per area, called from module.cpp.
#include <pybind11/functional.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <string>
#include <type_traits>

#include "ifsforge/core/error.h"
#include "ifsforge/core/names.h"
#include "ifsforge/core/progress.h"
#include "ifsforge/geometry/axes.h"
#include "ifsforge/model/ifs.h"
#include "ifsforge/render/frame.h"
#include "ifsforge/render/renderer.h"
#include "ifsforge/core/image.h"

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
void bind_distributed(py::module_& m);

/// @brief Publishes the names of enum E (EnumNames) as `_core.choices[key]`, a list in table
/// order: the CLI's choices and the property setters read the same table.
template <typename E>
void add_choices(py::module_& m, const char* key) {
  if (!py::hasattr(m, "choices")) m.attr("choices") = py::dict();
  py::dict choices = m.attr("choices");
  choices[key] = names_of<E>();
}

/// @brief A C++ progress callback around a Python callable f(fraction) -> bool | None
/// (False cancels). Ctrl-C also cancels. Empty when `callback` is None.
ProgressCallback wrap_progress(const py::object& callback);

/// @brief The core's job runner (images and volumes) around distribute(first, last) -> list of
/// bytes of each range's job results: the bytes are read in place (a large volume's results
/// run to hundreds of MB: no copy), held until the next call or the end of the render (whose binding
/// holds the GIL again before the runner goes). An image's runner passes distribute a third
/// argument, the depth, when a point-recursive render fell back to a fixed one.
class BytesRunner {
 public:
  explicit BytesRunner(const py::object& distribute)
      : distribute_(distribute), held_(std::make_shared<py::list>()) {}
  std::vector<std::string_view> operator()(std::uint64_t first, std::uint64_t last) const {
    return (*this)(first, last, 0);
  }
  std::vector<std::string_view> operator()(std::uint64_t first, std::uint64_t last, int depth) const;

 private:
  py::object distribute_;
  std::shared_ptr<py::list> held_;
};

/// @brief An `up` argument: None (the format's default: none), "y", "z" or ifsforge.Up.
std::optional<Up> up_argument(const py::object& up);

/// @brief An (n, N) numpy array that takes over `rows` (no copy: a capsule owns the vector).
template <typename T, std::size_t N>
py::array_t<T> rows_array(std::vector<std::array<T, N>>&& rows) {
  auto* owned = new std::vector<std::array<T, N>>(std::move(rows));
  py::capsule owner(owned, [](void* p) { delete static_cast<std::vector<std::array<T, N>>*>(p); });
  return py::array_t<T>({static_cast<py::ssize_t>(owned->size()), static_cast<py::ssize_t>(N)},
                        reinterpret_cast<const T*>(owned->data()), owner);
}

/// @brief A 1-D numpy array that takes over `values` (no copy).
template <typename T>
py::array_t<T> vector_array(std::vector<T>&& values) {
  auto* owned = new std::vector<T>(std::move(values));
  py::capsule owner(owned, [](void* p) { delete static_cast<std::vector<T>*>(p); });
  return py::array_t<T>(static_cast<py::ssize_t>(owned->size()), owned->data(), owner);
}

/// @brief {'positions', 'normals', 'triangles'} numpy arrays of a mesh, which they take over.
py::dict mesh_dict(TriangleMesh mesh);

/// @brief A float32 numpy array (copy) of shape `shape` from contiguous data.
template <class Floats>
py::array_t<float> to_numpy(const Floats& data, std::vector<py::ssize_t> shape) {
  py::array_t<float> out(shape);
  std::copy(data.begin(), data.end(), out.mutable_data());
  return out;
}

/// @brief An Image from a (h, w) or (h, w, c) array: floats in [0, 1], or uint8 / uint16.
Image image_from_numpy(const py::array& array);
/// @brief (h, w) for one channel, else (h, w, c), float32.
py::array_t<float> image_to_numpy(const Image& image);

template <typename T, typename = void>
struct has_progress : std::false_type {};
template <typename T>
struct has_progress<T, std::void_t<decltype(T::progress)>> : std::true_type {};

/// @brief A `T` options struct from keyword arguments. The defaults are a default-constructed
/// T's (the one place they are written); each keyword is set through T's bound Python class,
/// whose properties convert and check it; None keeps the default. An unknown keyword is a
/// TypeError naming `function`. A struct with a progress callback always gets one, so Ctrl-C
/// stops the work even when the caller passed none.
template <typename T>
T options_from(const char* function, const py::dict& kwargs) {
  py::object options = py::cast(T{});
  for (const auto& item : kwargs) {
    const std::string name = py::str(item.first);
    if (name.empty() || name[0] == '_' || !py::hasattr(options, name.c_str()))
      throw py::type_error(std::string(function) + "() got an unexpected keyword argument '" + name + "'");
    if (!item.second.is_none()) py::setattr(options, item.first, item.second);
  }
  T result = options.cast<T>();
  if constexpr (has_progress<T>::value)
    if (!result.progress) result.progress = wrap_progress(py::none());
  return result;
}

/// @brief render()'s RenderOptions from its keywords (options_from; height defaults to width).
RenderOptions render_options(const py::dict& given);

/// @brief Binds `T` as a Python class constructible with keyword arguments (see options_from).
template <typename T>
py::class_<T> options_class(py::module_& m, const char* name, const char* doc) {
  py::class_<T> cls(m, name, doc);
  cls.def(py::init([name](const py::kwargs& kwargs) { return options_from<T>(name, kwargs); }));
  return cls;
}

/// @brief Sets `key` in `kwargs` when `value` is not None: a leading positional argument that
/// is also an option field.
inline void add_option(py::dict& kwargs, const char* key, const py::object& value) {
  if (!value.is_none()) kwargs[key] = value;
}

/// @brief A window (xmin, ymin, xmax, ymax) between Python and C++.
inline std::optional<Window> window_argument(const std::optional<std::array<double, 4>>& w) {
  if (!w) return std::nullopt;
  return Window{(*w)[0], (*w)[1], (*w)[2], (*w)[3]};
}
inline std::optional<std::array<double, 4>> window_tuple(const std::optional<Window>& w) {
  if (!w) return std::nullopt;
  return std::array<double, 4>{w->xmin, w->ymin, w->xmax, w->ymax};
}

/// A count a Python caller gives as an int: negative values are an InputError naming the
/// option (not pybind's TypeError for an unsigned parameter).
inline std::uint64_t count_argument(long long value, const char* name) {
  if (value < 0) throw InputError(std::string(name) + ": expects 0 or more, got " + std::to_string(value));
  return static_cast<std::uint64_t>(value);
}

}  // namespace ifsforge::python
