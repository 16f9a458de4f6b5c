// POV-Ray density files from volumes.
#include "bindings.h"

#include "ifsforge/io/df3.h"

namespace ifsforge::python {
namespace {

void bind_df3(py::module_& m) {
  m.def("write_df3",
        [](const std::string& path, const Volume& volume, int bits) {
          py::gil_scoped_release release;
          write_df3(path, volume, bits);
        },
        py::arg("path"), py::arg("volume"), py::arg("bits") = 8,
        "Write the volume's density as a POV-Ray .df3 (atomically): big-endian uint16 sizes x, y, z, then "
        "8/16/32-bit big-endian voxels, x fastest, density / max density scaled to the full range.");
}

const Binding registered(46, &bind_df3);

}  // namespace
}  // namespace ifsforge::python
