// Scale-out: the job API a cluster (ifsforge.distributed, on Dask) drives. Options travel as
// plain dicts (picklable, the same names as render / render_volume); job results as bytes.
#include "bindings.h"
#include "ifsforge/render/renderer.h"
#include "ifsforge/volume/volume_jobs.h"
#include "ifsforge/volume/volume_renderer.h"

namespace ifsforge::python {
namespace {

template <typename T>
T option(const py::dict& options, const char* name, T fallback) {
  return options.contains(name) && !options[name].is_none() ? options[name].cast<T>() : fallback;
}

/// Rejects names the job API does not know (a typo would otherwise render something else).
void check_names(const py::dict& options, std::initializer_list<const char*> known, const char* what) {
  for (const auto& item : options) {
    const std::string name = py::str(item.first);
    bool found = false;
    for (const char* k : known) found = found || name == k;
    if (!found) throw InputError(std::string(what) + ": unknown option '" + name + "'");
  }
}

VolumeOptions volume_options(const py::dict& d) {
  check_names(d, {"resolution", "bounds", "density", "depth", "iterations", "escape_bound", "escape_norm",
                  "escape_pick_max", "seed", "threads"}, "volume options");
  VolumeOptions o;
  o.resolution = option(d, "resolution", o.resolution);
  if (d.contains("bounds") && !d["bounds"].is_none()) o.bounds = d["bounds"].cast<Box3>();
  o.density = volume_density_from_string(option<std::string>(d, "density", "binary"));
  o.depth = option(d, "depth", o.depth);
  o.iterations = count_argument(option<long long>(d, "iterations", 0), "iterations");
  o.escape_bound = option(d, "escape_bound", o.escape_bound);
  o.escape_norm = escape_norm_from_string(option<std::string>(d, "escape_norm", "euclidean"));
  o.escape_pick_max = option(d, "escape_pick_max", o.escape_pick_max);
  o.seed = option(d, "seed", o.seed);
  o.threads = option(d, "threads", o.threads);
  return o;
}

RenderOptions render_options(const py::dict& d) {
  check_names(d, {"width", "height", "window", "view", "iterations", "depth", "seed", "threads", "binary",
                  "points_per_pixel", "skip", "parameters"}, "render options");
  RenderOptions o;
  o.width = option(d, "width", o.width);
  o.height = option(d, "height", o.width);
  if (d.contains("window") && !d["window"].is_none()) {
    const auto w = d["window"].cast<std::array<double, 4>>();
    o.window = Window{w[0], w[1], w[2], w[3]};
  }
  if (d.contains("view") && !d["view"].is_none()) {
    const auto v = d["view"].cast<std::array<double, 2>>();
    o.view = View{v[0], v[1]};
  }
  o.iterations = count_argument(option<long long>(d, "iterations", 0), "iterations");
  o.depth = option(d, "depth", o.depth);
  o.seed = option(d, "seed", o.seed);
  o.threads = option(d, "threads", o.threads);
  o.binary = option(d, "binary", o.binary);
  o.points_per_pixel = option(d, "points_per_pixel", o.points_per_pixel);
  o.skip = count_argument(option<long long>(d, "skip", 100), "skip");
  if (d.contains("parameters") && !d["parameters"].is_none())
    for (const auto& item : d["parameters"].cast<py::dict>())
      o.parameters[py::str(item.first)] = py::str(item.second);
  return o;
}

const Renderer& distributable_renderer(const std::string& algorithm) {
  const Renderer& r = renderer(algorithm);
  if (!r.distributable())
    throw InputError("the " + r.name() + " renderer does not split into independent jobs: distribute chaos or prr");
  return r;
}

/// A C++ job runner around a Python callable distribute(first, last) -> list of bytes.
std::function<std::vector<std::string>(std::uint64_t, std::uint64_t)> bytes_runner(const py::object& distribute) {
  return [distribute](std::uint64_t first, std::uint64_t last) {
    py::gil_scoped_acquire gil;
    std::vector<std::string> out;
    for (const auto& item : distribute(first, last)) out.push_back(item.cast<std::string>());
    return out;
  };
}

}  // namespace

void bind_distributed(py::module_& m) {
  m.def("run_volume_jobs",
        [](const Ifs& ifs, const std::string& algorithm, const py::dict& options, std::uint64_t first,
           std::uint64_t last) {
          const VolumeOptions o = volume_options(options);
          const VolumeRenderer& r = volume_renderer(algorithm);
          std::string bytes;
          {
            py::gil_scoped_release release;
            bytes = encode_volume_jobs(r.run_jobs(ifs, o, first, last), o.density);
          }
          return py::bytes(bytes);
        },
        py::arg("ifs"), py::arg("algorithm"), py::arg("options"), py::arg("first"), py::arg("last"),
        "A worker's part of a distributed volume: jobs [first, last) (prr: address prefixes, ria: (seed, job) "
        "streams) as compact bytes of integer voxel sums. options: render_volume's keywords as a dict.");
  m.def("render_volume_distributed",
        [](const Ifs& ifs, const std::string& algorithm, const py::dict& options, const py::object& distribute,
           const py::object& progress) {
          VolumeOptions o = volume_options(options);
          o.progress = wrap_progress(progress);
          const auto runner = bytes_runner(distribute);
          o.distribute = [runner](std::uint64_t first, std::uint64_t last) {
            std::vector<VolumeJobsResult> results;
            for (const std::string& bytes : runner(first, last)) results.push_back(decode_volume_jobs(bytes));
            return results;
          };
          const VolumeRenderer& r = volume_renderer(algorithm);
          py::gil_scoped_release release;
          return r.render(ifs, o);
        },
        py::arg("ifs"), py::arg("algorithm"), py::arg("options"), py::arg("distribute"),
        py::arg("progress") = py::none(),
        "render_volume with its jobs run by distribute(first, last) -> [bytes of run_volume_jobs, ...] and merged "
        "here exactly: the same volume as render_volume.");
  m.def("run_render_jobs",
        [](const Ifs& ifs, const std::string& algorithm, const py::dict& options, std::uint64_t first,
           std::uint64_t last) {
          const RenderOptions o = render_options(options);
          const Renderer& r = distributable_renderer(algorithm);
          std::string bytes;
          {
            py::gil_scoped_release release;
            bytes = r.run_jobs(ifs, o, first, last);
          }
          return py::bytes(bytes);
        },
        py::arg("ifs"), py::arg("algorithm"), py::arg("options"), py::arg("first"), py::arg("last"),
        "A worker's part of a distributed image: jobs [first, last) (chaos: sparse histogram tiles of integer "
        "sums; prr: address-ordered leaves) as bytes. options: render's keywords as a dict.");
  m.def("render_distributed",
        [](const Ifs& ifs, const std::string& algorithm, const py::dict& options, const py::object& distribute,
           const py::object& progress) {
          RenderOptions o = render_options(options);
          o.progress = wrap_progress(progress);
          o.distribute = bytes_runner(distribute);
          const Renderer& r = distributable_renderer(algorithm);
          py::gil_scoped_release release;
          return r.render(ifs, o);
        },
        py::arg("ifs"), py::arg("algorithm"), py::arg("options"), py::arg("distribute"),
        py::arg("progress") = py::none(),
        "render with its jobs run by distribute(first, last) -> [bytes of run_render_jobs, ...] and merged here "
        "exactly: the same raster as render.");
}

}  // namespace ifsforge::python
