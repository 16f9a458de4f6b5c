// OpenVDB files and iso-surfaces: the io area's OpenVDB part, built as its own extension module
// (ifsforge._vdb) that the package imports on first use, so a command that writes no .vdb does
// not pay for loading libopenvdb, which is slow.
#include "bindings.h"

#include <cstring>

#include "ifsforge/io/mesh.h"
#include "ifsforge/io/vdb.h"
#include "ifsforge/io/voxel_target.h"

namespace ifsforge::python {
namespace {

void bind_io_vdb(py::module_& m) {
  options_class<VoxelTargetOptions>(m, "VoxelTargetOptions", "The settings of read_voxel_target() (keywords of the same names).")
      .def_readwrite("resolution", &VoxelTargetOptions::resolution, "voxels along the shape's longest side")
      .def_readwrite("density_threshold", &VoxelTargetOptions::density_threshold,
                     ".vdb fog volumes: the density a voxel of the shape exceeds");
  m.def("read_voxel_target", [](const std::string& path, const py::kwargs& kwargs) {
    const VoxelTargetOptions o = options_from<VoxelTargetOptions>("read_voxel_target", kwargs);
    VoxelSet s;
    {
      py::gil_scoped_release release;
      s = read_voxel_target(path, o);
    }
    py::array_t<bool> mask({s.grid.dims[0], s.grid.dims[1], s.grid.dims[2]});
    bool* p = mask.mutable_data();
    for (int i = 0; i < s.grid.dims[0]; ++i)
      for (int j = 0; j < s.grid.dims[1]; ++j)
        for (int k = 0; k < s.grid.dims[2]; ++k) *p++ = s.cells[s.index(i, j, k)] != 0;
    py::dict d;
    d["mask"] = mask;
    d["origin"] = py::make_tuple(s.grid.origin[0], s.grid.origin[1], s.grid.origin[2]);
    d["voxel_size"] = s.grid.voxel_size;
    return d;
  }, py::arg("path"),
        "A 3D shape to fit as a dict: mask bool (nx, ny, nz), origin, voxel_size (fit_3d's keywords). .vdb: the "
        "'density' grid (else the first float grid), a level set's inside or a fog volume's voxels above "
        "density_threshold; .obj/.ply/.stl/.off: the mesh's inside (OpenVDB's mesh to level set); resampled to "
        "`resolution` voxels along the longest side, in the file's coordinates. The VoxelTargetOptions as keywords.");
  options_class<VdbWriteOptions>(m, "VdbWriteOptions", "The settings of write_vdb() (keywords of the same names).")
      .def_property("color_scale", [](const VdbWriteOptions& o) { return std::string(name_of(o.color_scale)); },
                    [](VdbWriteOptions& o, const std::string& s) { o.color_scale = parse_name<ColorScale>(s); },
                    "auto, range or clamp")
      .def_readwrite("metadata", &VdbWriteOptions::metadata, "extra file metadata (string values)")
      .def_readwrite("half", &VdbWriteOptions::half, "16-bit halves for the [0, 1] grids")
      .def_readwrite("compress", &VdbWriteOptions::compress, "Blosc-compress the leaf buffers")
      .def_readwrite("threads", &VdbWriteOptions::threads, "threads that write (0: every core); the file never depends on it")
      .def_readwrite("translation", &VdbWriteOptions::translation,
                     "(x, y, z) added to the grids' transform: the file's coordinates are the system's plus it")
      .def_property("progress", [](const VdbWriteOptions&) { return py::none(); },
                    [](VdbWriteOptions& o, const py::object& f) { o.progress = wrap_progress(f); },
                    "progress(fraction) returning False cancels (write-only)");
  m.def("write_vdb",
        [](const std::string& path, const Volume& volume, std::optional<Ifs> system, const py::kwargs& kwargs) {
          VdbWriteOptions o = options_from<VdbWriteOptions>("write_vdb", kwargs);
          if (system) o.system = &*system;
          py::gil_scoped_release release;
          write_vdb(path, volume, o);
        },
        py::arg("path"), py::arg("volume"), py::arg("system") = py::none(),
        "Write an OpenVDB file (atomically): FloatGrid 'density', Vec3fGrid 'color' (RGB in [0, 1]) when the "
        "layout has color, FloatGrids 'gray', 'alpha', ...; the transform puts the voxels where the system "
        "puts them; metadata describes the volume and, when given, the system (its JSON). half: store the "
        "[0, 1] grids (and a binary density) as 16-bit halves (relative error <= 2^-11); compress: Blosc "
        "(about a third smaller, slower to write); translation (x, y, z): added to the transform (minus the box's "
        "centre centres the grid on the file's origin).");

  m.def("render_volume_to_vdb",
        [](const std::string& path, const Ifs& ifs, const std::string& algorithm, const py::object& distribute,
           const py::kwargs& kwargs) {
          // Each keyword goes to the options struct that has it; progress and threads (both have
          // them) are the render's, and the writing follows them.
          py::dict volume_keywords, vdb_keywords;
          const py::object vdb_fields = py::cast(VdbWriteOptions{});
          for (const auto& item : kwargs) {
            const std::string name = py::str(item.first);
            (name != "progress" && name != "threads" && py::hasattr(vdb_fields, name.c_str()) ? vdb_keywords
                                                                                               : volume_keywords)[item.first] =
                item.second;
          }
          VolumeOptions o = options_from<VolumeOptions>("render_volume_to_vdb", volume_keywords);
          if (!distribute.is_none()) o.distribute = BytesRunner(distribute);
          VdbWriteOptions w = options_from<VdbWriteOptions>("render_volume_to_vdb", vdb_keywords);
          w.system = &ifs;
          std::uint64_t voxels = 0;
          Volume header;
          {
            py::gil_scoped_release release;
            header = render_volume_to_vdb(path, ifs, algorithm, o, w, &voxels);
          }
          py::dict out;
          out["voxels"] = voxels;
          out["dims"] = py::make_tuple(header.grid.dims[0], header.grid.dims[1], header.grid.dims[2]);
          out["voxel_size"] = header.grid.voxel_size;
          out["origin"] = py::make_tuple(header.grid.origin[0], header.grid.origin[1], header.grid.origin[2]);
          out["algorithm"] = header.algorithm;
          out["depth"] = header.depth;
          out["points"] = header.points;
          return out;
        },
        py::arg("path"), py::arg("ifs"), py::arg("algorithm") = "prr", py::arg("distribute") = py::none(),
        "render_volume straight into the .vdb at `path` (write_vdb's file, with the system's metadata): prr gives "
        "its volume band by band as it merges its jobs, so no more than a band is held (2048^3 and beyond); the "
        "other renderers render, then write. Keywords: render_volume's and write_vdb's. distribute(first, last): "
        "the jobs run elsewhere (ifsforge.distributed). Returns a dict: voxels, dims, voxel_size, origin, "
        "algorithm, depth, points.");

  m.def("read_vdb_info", [](const std::string& path) {
    const VdbFileInfo info = read_vdb_info(path);
    py::list grids;
    for (const auto& g : info.grids) {
      py::dict d;
      d["name"] = g.name;
      d["type"] = g.type;
      d["active_voxels"] = g.active_voxels;
      d["voxel_size"] = g.voxel_size;
      d["index_bounds"] = g.index_bounds;
      grids.append(d);
    }
    py::dict out;
    out["grids"] = grids;
    out["metadata"] = info.metadata;
    return out;
  }, py::arg("path"), "The grids (name, type, active_voxels, voxel_size, index_bounds) and metadata of a .vdb.");

  options_class<IsoSurfaceOptions>(m, "IsoSurfaceOptions", "The settings of volume_to_mesh() (keywords of the same names).")
      .def_readwrite("iso", &IsoSurfaceOptions::iso, "the surface's level of the occupancy (or density)")
      .def_readwrite("use_density", &IsoSurfaceOptions::use_density, "the density grid's level instead of the occupancy")
      .def_readwrite("adaptivity", &IsoSurfaceOptions::adaptivity, "0: every voxel-sized polygon; up to 1: merge flat areas")
      .def_property("color_scale", [](const IsoSurfaceOptions& o) { return std::string(name_of(o.color_scale)); },
                    [](IsoSurfaceOptions& o, const std::string& s) { o.color_scale = parse_name<ColorScale>(s); },
                    "auto, range or clamp")
      .def_readwrite("normals", &IsoSurfaceOptions::normals, "per-vertex normals (False: normals is None)")
      .def_property("progress", [](const IsoSurfaceOptions&) { return py::none(); },
                    [](IsoSurfaceOptions& o, const py::object& f) { o.progress = wrap_progress(f); },
                    "progress(fraction) returning False cancels (write-only)");
  m.def("volume_to_mesh",
        [](const Volume& volume, const py::kwargs& kwargs) {
          const IsoSurfaceOptions o = options_from<IsoSurfaceOptions>("volume_to_mesh", kwargs);
          TriangleMesh mesh;
          {
            py::gil_scoped_release release;
            mesh = volume_to_mesh(volume, o);
          }
          const bool normals = !mesh.normals.empty();
          py::object colors = py::none();
          if (!mesh.colors.empty()) colors = rows_array(std::move(mesh.colors));
          py::dict out = mesh_dict(std::move(mesh));
          out["colors"] = colors;
          if (!normals) out["normals"] = py::none();
          return out;
        },
        py::arg("volume"),
        "The iso-surface of the occupancy (or of the density) as a dict of arrays: positions, triangles, normals, "
        "colors (RGBA from the color grid, or None) -- ready for write_mesh(path, **mesh). normals=False leaves "
        "normals None; progress(fraction) returning False cancels.");
}

}  // namespace
}  // namespace ifsforge::python

PYBIND11_MODULE(_vdb, m) {
  m.doc() = "ifsforge's OpenVDB writer, reader and iso-surfaces (imported by ifsforge on first use)";
  pybind11::module_::import("ifsforge._core");  // the Volume and Ifs types, and the error translation
  ifsforge::python::bind_io_vdb(m);
}
