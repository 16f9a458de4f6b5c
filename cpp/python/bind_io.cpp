// File formats: ifsforge/1 JSON, Fractint .ifs, PNG.
#include "bindings.h"
#include "ifsforge/core/error.h"
#include "ifsforge/io/fractint.h"
#include "ifsforge/io/system_file.h"
#include "ifsforge/io/ifs_json.h"
#include "ifsforge/io/png.h"

namespace ifsforge::python {

Image image_from_numpy(const py::array& array) {
  if (array.ndim() != 2 && array.ndim() != 3) throw InputError("an image array must be (h, w) or (h, w, c)");
  const int h = static_cast<int>(array.shape(0)), w = static_cast<int>(array.shape(1));
  const int c = array.ndim() == 3 ? static_cast<int>(array.shape(2)) : 1;
  if (c < 1 || c > 4) throw InputError("an image has 1 to 4 channels");
  double scale = 1.0;
  if (py::isinstance<py::array_t<std::uint8_t>>(array)) scale = 1.0 / 255.0;
  if (py::isinstance<py::array_t<std::uint16_t>>(array)) scale = 1.0 / 65535.0;
  auto values = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(array);
  if (!values) throw InputError("an image array must hold numbers");
  Image image(w, h, c);
  const float* src = values.data();
  for (std::size_t i = 0; i < image.pixels.size(); ++i) image.pixels[i] = static_cast<float>(src[i] * scale);
  return image;
}

py::array_t<float> image_to_numpy(const Image& image) {
  if (image.channels == 1) return to_numpy(image.pixels, {image.height, image.width});
  return to_numpy(image.pixels, {image.height, image.width, image.channels});
}

namespace {

void bind_io(py::module_& m) {
  m.attr("FORMAT_VERSION") = kFormatVersion;
  m.def("load", &load_system, py::arg("spec"),
        "A system from 'file.json', 'file.ifs' (first entry) or 'file.ifs:entry'.");
  m.def("read_json", &read_ifs_json, py::arg("path"));
  m.def("parse_json", &parse_ifs_json, py::arg("text"), py::arg("source") = "<json>");
  m.def("to_json", &to_ifs_json, py::arg("ifs"));
  m.def("write_json", &write_ifs_json, py::arg("path"), py::arg("ifs"), "Atomic write of the canonical JSON.");
  m.def("read_fractint", &read_fractint, py::arg("path"), "Every entry of a Fractint .ifs file.");
  m.def("parse_fractint", &parse_fractint, py::arg("text"), py::arg("source") = "<ifs>");
  m.def("write_png", [](const std::string& path, const py::array& array, int bit_depth) {
    Image image = image_from_numpy(array);
    py::gil_scoped_release release;
    write_png(path, image, bit_depth);
  }, py::arg("path"), py::arg("image"), py::arg("bit_depth") = 8,
     "Write (h, w[, c]) floats in [0, 1] (or uint8/uint16) as an 8- or 16-bit PNG, atomically.");
  m.def("read_png", [](const std::string& path) { return image_to_numpy(read_png(path)); }, py::arg("path"),
        "A PNG as float32 in [0, 1], shape (h, w) or (h, w, c).");
}

const Binding registered(20, &bind_io);

}  // namespace
}  // namespace ifsforge::python
