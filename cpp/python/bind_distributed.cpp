// Scale-out: the job API a cluster (ifsforge.distributed, on Dask) drives. Options travel as
// plain dicts (picklable, the same names as render / render_volume); job results as bytes.
#include "bindings.h"
#include "ifsforge/render/parameters.h"
#include "ifsforge/render/renderer.h"
#include "ifsforge/volume/volume_jobs.h"
#include "ifsforge/volume/volume_renderer.h"

namespace ifsforge::python {
namespace {

const Renderer& distributable_renderer(const std::string& algorithm) {
  const Renderer& r = renderer(algorithm);
  if (!r.distributable())
    throw InputError("the " + r.name() + " renderer does not split into independent jobs: distribute chaos or prr");
  return r;
}

}  // namespace

void bind_distributed(py::module_& m) {
  m.def("run_volume_jobs",
        [](const Ifs& ifs, const std::string& algorithm, const py::dict& options, std::uint64_t first,
           std::uint64_t last) {
          const VolumeOptions o = options_from<VolumeOptions>("render_volume", options);
          const VolumeRenderer& r = volume_renderer(algorithm);
          std::string bytes;
          {
            py::gil_scoped_release release;
            bytes = r.run_jobs(ifs, o, first, last);
          }
          return py::bytes(bytes);
        },
        py::arg("ifs"), py::arg("algorithm"), py::arg("options"), py::arg("first"), py::arg("last"),
        "A worker's part of a distributed volume: jobs [first, last) (prr: address prefixes, ria: (seed, job) "
        "streams) as compact bytes of integer voxel sums. options: render_volume's keywords as a dict.");
  m.def("render_volume_distributed",
        [](const Ifs& ifs, const std::string& algorithm, const py::dict& options, const py::object& distribute,
           const py::object& progress) {
          VolumeOptions o = options_from<VolumeOptions>("render_volume", options);
          o.progress = wrap_progress(progress);
          o.distribute = BytesRunner(distribute);
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
          check_parameters(r, o);
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
          o.distribute = BytesRunner(distribute);
          const Renderer& r = distributable_renderer(algorithm);
          check_parameters(r, o);
          py::gil_scoped_release release;
          return r.render(ifs, o);
        },
        py::arg("ifs"), py::arg("algorithm"), py::arg("options"), py::arg("distribute"),
        py::arg("progress") = py::none(),
        "render with its jobs run by distribute(first, last) -> [bytes of run_render_jobs, ...] and merged here "
        "exactly: the same raster as render.");
}

}  // namespace ifsforge::python
