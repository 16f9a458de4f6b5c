// Fractal image compression with partitioned IFS (seed 3.3.2): encode, decode at any size, files.
#include <optional>

#include "bindings.h"
#include "ifsforge/core/error.h"
#include "ifsforge/io/pifs_file.h"
#include "ifsforge/pifs/decoder.h"
#include "ifsforge/pifs/encoder.h"
#include "ifsforge/pifs/plane_coding.h"

namespace ifsforge::python {
namespace {

py::bytes to_bytes(const PifsCode& code) {
  std::vector<std::uint8_t> b;
  {
    py::gil_scoped_release release;
    b = pifs_to_bytes(code);
  }
  return py::bytes(reinterpret_cast<const char*>(b.data()), b.size());
}

/// Bits spent on each part of the file, summed over the planes.
py::dict cost(const PifsCode& code) {
  PifsPlaneCost total;
  std::size_t leaves = 0, flat = 0;
  for (const PifsPlane& p : code.planes) {
    PifsPlaneCost c;
    encode_plane(code, p, &c);
    total.quadtree += c.quadtree;
    total.contrast += c.contrast;
    total.mean += c.mean;
    total.isometry += c.isometry;
    total.domain += c.domain;
    leaves += p.leaves.size();
    for (const PifsLeaf& l : p.leaves) flat += l.s == 0;
  }
  py::dict d;
  d["bytes"] = pifs_to_bytes(code).size();
  d["header_bits"] = 8.0 * double(pifs_header_size(code) + 4);
  d["quadtree_bits"] = total.quadtree;
  d["contrast_bits"] = total.contrast;
  d["mean_bits"] = total.mean;
  d["isometry_bits"] = total.isometry;
  d["domain_bits"] = total.domain;
  d["leaves"] = leaves;
  d["flat_leaves"] = flat;
  return d;
}

}  // namespace

void bind_pifs(py::module_& m) {
  add_choices<PifsDecoder>(m, "decoder");
  add_choices<PifsColor>(m, "color");
  py::class_<PifsCode>(m, "PifsCode", "A partitioned IFS code of an image (seed 3.3.2); decodes at any size.")
      .def_readonly("width", &PifsCode::width)
      .def_readonly("height", &PifsCode::height)
      .def_readonly("channels", &PifsCode::channels)
      .def_property_readonly("color", [](const PifsCode& c) {
        return std::string(name_of(c.color));
      })
      .def_property_readonly("min_block", [](const PifsCode& c) { return 1 << c.min_log; })
      .def_property_readonly("max_block", [](const PifsCode& c) { return 1 << c.max_log; })
      .def_readonly("s_bits", &PifsCode::s_bits)
      .def_readonly("dc_step", &PifsCode::dc_step)
      .def_property_readonly("plane_sizes", [](const PifsCode& c) {
        std::vector<std::pair<int, int>> out;
        for (const auto& p : c.planes) out.push_back({p.width, p.height});
        return out;
      }, "(width, height) of each coded plane")
      .def_property_readonly("leaf_counts", [](const PifsCode& c) {
        std::vector<std::size_t> out;
        for (const auto& p : c.planes) out.push_back(p.leaves.size());
        return out;
      }, "range cells per plane")
      .def("decode", [](const PifsCode& code, double scale, std::optional<std::pair<int, int>> size,
                        const std::string& decoder, int iterations, bool deblock, int threads) {
        PifsDecodeOptions o;
        o.scale = scale;
        if (size) {
          if (size->first < 1 || size->second < 1) throw InputError("size must be two positive integers (width, height)");
          o.width = size->first;
          o.height = size->second;
        }
        o.decoder = parse_name<PifsDecoder>(decoder);
        o.iterations = iterations;
        o.deblock = deblock;
        o.threads = threads;
        Image image;
        {
          py::gil_scoped_release release;
          image = pifs_decode(code, o);
        }
        return image_to_numpy(image);
      }, py::arg("scale") = PifsDecodeOptions{}.scale, py::arg("size") = py::none(),
         py::arg("decoder") = "hierarchical", py::arg("iterations") = PifsDecodeOptions{}.iterations,
         py::arg("deblock") = PifsDecodeOptions{}.deblock, py::arg("threads") = PifsDecodeOptions{}.threads,
         "The image (float32 in [0, 1], (h, w) or (h, w, c)) at scale × the size, or at size=(width, height). "
         "decoder: 'hierarchical' (Baharav) or 'iterative' (DIA); iterations 0 = the default.")
      .def("to_bytes", &to_bytes, "The .pifs file's bytes.")
      .def("cost", &cost, "Bytes of the file and bits spent on each part (measured).")
      .def("__repr__", [](const PifsCode& c) {
        return "PifsCode(" + std::to_string(c.width) + "x" + std::to_string(c.height) + ", " +
               std::to_string(c.channels) + " channels, " + std::to_string(pifs_to_bytes(c).size()) + " bytes)";
      });

  m.def("pifs_encode", [](const py::array& array, std::optional<double> ratio, std::optional<std::size_t> bytes,
                          std::optional<double> quality, int min_block, int max_block, int s_bits, int dc_step,
                          bool ycbcr, int threads, const py::object& progress) {
    if (py::isinstance<py::array_t<std::uint16_t>>(array))
      py::module_::import("warnings").attr("warn")("16-bit image reduced to 8 bits for PIFS coding");
    Image image = image_from_numpy(array);
    PifsEncodeOptions o;
    if (ratio) {
      if (!(*ratio > 0)) throw InputError("ratio must be positive");
      o.ratio = *ratio;
    }
    if (bytes) {
      if (*bytes == 0) throw InputError("bytes must be positive");
      o.bytes = *bytes;
    }
    if (quality) o.quality = *quality;
    o.min_block = min_block;
    o.max_block = max_block;
    o.s_bits = s_bits;
    o.dc_step = dc_step;
    o.ycbcr = ycbcr;
    o.threads = threads;
    ProgressCallback callback = wrap_progress(progress);
    py::gil_scoped_release release;
    return pifs_encode(image, o, callback);
  }, py::arg("image"), py::arg("ratio") = py::none(), py::arg("bytes") = py::none(), py::arg("quality") = py::none(),
     py::arg("min_block") = PifsEncodeOptions{}.min_block, py::arg("max_block") = PifsEncodeOptions{}.max_block,
     py::arg("s_bits") = PifsEncodeOptions{}.s_bits, py::arg("dc_step") = PifsEncodeOptions{}.dc_step,
     py::arg("ycbcr") = PifsEncodeOptions{}.ycbcr, py::arg("threads") = PifsEncodeOptions{}.threads,
     py::arg("progress") = py::none(),
     "PIFS code of an image array ((h, w) or (h, w, c), c = 1-4; uint8, uint16 or floats in [0, 1]). Rate: "
     "bytes (file <= bytes), ratio (raw bytes / ratio) or quality (collage RMS threshold, 8-bit levels; default "
     "8). Identical for any thread count.");
  m.def("pifs_from_bytes", [](const py::bytes& data) {
    const std::string s = data;
    return pifs_from_bytes(reinterpret_cast<const std::uint8_t*>(s.data()), s.size());
  }, py::arg("data"), "A code from .pifs bytes (InputError when truncated or corrupt).");
  m.def("read_pifs", &read_pifs, py::arg("path"), py::call_guard<py::gil_scoped_release>());
  m.def("write_pifs", &write_pifs, py::arg("path"), py::arg("code"), py::call_guard<py::gil_scoped_release>(),
        "Atomic write of a .pifs file.");
}

}  // namespace ifsforge::python
