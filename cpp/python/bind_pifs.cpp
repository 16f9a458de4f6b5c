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
  d["residual_bits"] = 8.0 * double(pifs_residual_bytes(code));
  d["leaves"] = leaves;
  d["flat_leaves"] = flat;
  return d;
}

}  // namespace

void bind_pifs(py::module_& m) {
  add_choices<PifsDecoder>(m, "decoder");
  add_choices<PifsZoom>(m, "zoom");
  add_choices<PifsDomainSearch>(m, "search");
  add_choices<PifsColor>(m, "color");
  add_choices<PifsChroma>(m, "chroma");
  options_class<PifsDecodeOptions>(m, "PifsDecodeOptions",
                                    "The settings of PifsCode.decode() (keywords of the same names).")
      .def_readwrite("scale", &PifsDecodeOptions::scale, "output size = the image's size × scale")
      .def_property("size", [](const PifsDecodeOptions& o) -> std::optional<std::pair<int, int>> {
                      if (o.width <= 0) return std::nullopt;
                      return std::make_pair(o.width, o.height);
                    },
                    [](PifsDecodeOptions& o, std::pair<int, int> size) {
                      if (size.first < 1 || size.second < 1)
                        throw InputError("size must be two positive integers (width, height)");
                      o.width = size.first;
                      o.height = size.second;
                    }, "(width, height) of the output instead of scale; None: not set")
      .def_property("decoder", [](const PifsDecodeOptions& o) { return std::string(name_of(o.decoder)); },
                    [](PifsDecodeOptions& o, const std::string& d) { o.decoder = parse_name<PifsDecoder>(d); },
                    "hierarchical (Baharav) or iterative (DIA)")
      .def_readwrite("iterations", &PifsDecodeOptions::iterations,
                     "fixed-point iterations (0: the default; coarsest level, or every level when iterative)")
      .def_readwrite("deblock", &PifsDecodeOptions::deblock, "smooth both sides of every range-block edge")
      .def_property("zoom", [](const PifsDecodeOptions& o) { return std::string(name_of(o.zoom)); },
                    [](PifsDecodeOptions& o, const std::string& z) { o.zoom = parse_name<PifsZoom>(z); },
                    "above 1x: hybrid (fractal detail on the bicubic upscale, back-projected onto the 1x "
                    "decode) or fractal (the plain fractal decode)")
      .def_readwrite("threads", &PifsDecodeOptions::threads, "0: every core; the image never depends on it");
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
      .def("decode", [](const PifsCode& code, const py::kwargs& kwargs) {
        const PifsDecodeOptions o = options_from<PifsDecodeOptions>("decode", kwargs);
        Image image;
        {
          py::gil_scoped_release release;
          image = pifs_decode(code, o);
        }
        return image_to_numpy(image);
      }, "The image (float32 in [0, 1], (h, w) or (h, w, c)) at scale × the size, or at size=(width, height): "
         "the PifsDecodeOptions given as keywords.")
      .def("to_bytes", &to_bytes, "The .pifs file's bytes.")
      .def("cost", &cost, "Bytes of the file and bits spent on each part (measured).")
      .def("__repr__", [](const PifsCode& c) {
        return "PifsCode(" + std::to_string(c.width) + "x" + std::to_string(c.height) + ", " +
               std::to_string(c.channels) + " channels, " + std::to_string(pifs_to_bytes(c).size()) + " bytes)";
      });

  options_class<PifsEncodeOptions>(m, "PifsEncodeOptions",
                                    "The settings of pifs_encode() (keywords of the same names).")
      .def_readwrite("min_block", &PifsEncodeOptions::min_block, "smallest range cell, pixels (power of two, >= 2; 0: 8 under bytes or ratio with the residual "
                     "layer, else 2 at ratios up to 16:1 or quality <= 2, else 4)")
      .def_readwrite("max_block", &PifsEncodeOptions::max_block, "largest range cell, pixels (power of two)")
      .def_readwrite("s_bits", &PifsEncodeOptions::s_bits, "contrast bits (Eq. 29's s quantised)")
      .def_readwrite("dc_step", &PifsEncodeOptions::dc_step, "range-mean quantisation, 8-bit levels")
      .def_property("bytes", [](const PifsEncodeOptions& o) { return o.bytes; },
                    [](PifsEncodeOptions& o, long long v) {
                      if (v < 1) throw InputError("bytes must be positive, got " + std::to_string(v));
                      o.bytes = static_cast<std::size_t>(v);
                    }, "rate: the file is at most this many bytes (0: not set; wins over ratio and quality)")
      .def_property("ratio", [](const PifsEncodeOptions& o) { return o.ratio; },
                    [](PifsEncodeOptions& o, double v) {
                      if (!(v > 0)) throw InputError("ratio must be positive");
                      o.ratio = v;
                    }, "rate: raw bytes / ratio (0: not set; wins over quality)")
      .def_readwrite("quality", &PifsEncodeOptions::quality, "rate: collage RMS threshold, 8-bit levels")
      .def_readwrite("ycbcr", &PifsEncodeOptions::ycbcr, "RGB(A) as YCbCr, else R, G, B as they are")
      .def_property("chroma", [](const PifsEncodeOptions& o) { return std::string(name_of(o.chroma)); },
                    [](PifsEncodeOptions& o, const std::string& v) { o.chroma = parse_name<PifsChroma>(v); },
                    "YCbCr chroma: half (4:2:0), full (4:4:4) or auto (full where half-size chroma would cap "
                    "a size target's quality)")
      .def_readwrite("residual", &PifsEncodeOptions::residual,
                     "under bytes or ratio: code what the fractal code misses as a DCT residual layer")
      .def_property("search", [](const PifsEncodeOptions& o) { return std::string(name_of(o.search.mode)); },
                    [](PifsEncodeOptions& o, const std::string& v) { o.search.mode = parse_name<PifsDomainSearch>(v); },
                    "domain search: tree (fast) or exhaustive (every domain and isometry; the reference)")
      .def_readwrite("threads", &PifsEncodeOptions::threads, "0: every core; the code never depends on it");
  m.def("pifs_encode", [](const py::array& array, const py::object& progress, const py::kwargs& kwargs) {
    if (py::isinstance<py::array_t<std::uint16_t>>(array))
      py::module_::import("warnings").attr("warn")("16-bit image reduced to 8 bits for PIFS coding");
    Image image = image_from_numpy(array);
    const PifsEncodeOptions o = options_from<PifsEncodeOptions>("pifs_encode", kwargs);
    ProgressCallback callback = wrap_progress(progress);
    py::gil_scoped_release release;
    return pifs_encode(image, o, callback);
  }, py::arg("image"), py::kw_only(), py::arg("progress") = py::none(),
     "PIFS code of an image array ((h, w) or (h, w, c), c = 1-4; uint8, uint16 or floats in [0, 1]): the "
     "PifsEncodeOptions given as keywords. Rate: bytes (file <= bytes), ratio (raw bytes / ratio) or quality "
     "(collage RMS threshold, 8-bit levels). Identical for any thread count.");
  m.def("pifs_from_bytes", [](const py::bytes& data) {
    const std::string s = data;
    return pifs_from_bytes(reinterpret_cast<const std::uint8_t*>(s.data()), s.size());
  }, py::arg("data"), "A code from .pifs bytes (InputError when truncated or corrupt).");
  m.def("read_pifs", &read_pifs, py::arg("path"), py::call_guard<py::gil_scoped_release>());
  m.def("write_pifs", &write_pifs, py::arg("path"), py::arg("code"), py::call_guard<py::gil_scoped_release>(),
        "Atomic write of a .pifs file.");
}

}  // namespace ifsforge::python
