// The .vdb writer lays out OpenVDB's file format itself (band by band, never holding the grids):
// OpenVDB, reading each file and writing it again through its own io::File with the same
// compression, must give the very same bytes (all but the UUID, which OpenVDB draws at random).
// This is the reference test of the writer: grids, metadata, transform, topology, leaf buffers,
// halves and Blosc blocks alike.
#include <gtest/gtest.h>
#include <openvdb/io/File.h>
#include <openvdb/io/Stream.h>
#include <openvdb/openvdb.h>

#include <unistd.h>

#include <atomic>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "ifsforge/io/ifs_json.h"
#include "ifsforge/io/vdb.h"
#include "ifsforge/core/error.h"
#include "ifsforge/volume/volume_jobs.h"
#include "ifsforge/volume/volume_renderer.h"
#include "../../cpp/src/io/vdb_srgb.h"
#include "ifsforge/core/color.h"
#include "test_systems.h"

using namespace ifsforge;
using namespace ifsforge::test_systems;

namespace {

constexpr std::size_t kUuidBegin = 21, kUuidEnd = 57;  // after magic, versions and the offsets flag

std::string stream_temp_path(const std::string& name) {
  return (std::filesystem::temp_directory_path() / ("ifsforge_stream_" + std::to_string(getpid()) + "_" + name)).string();
}

std::string bytes_of(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

/// The file OpenVDB writes for what it reads from `path`.
std::string rewritten_by_openvdb(const std::string& path, bool blosc) {
  openvdb::initialize();
  std::ifstream file(path, std::ios::binary);
  openvdb::io::Stream in(file, /*delayLoad=*/false);  // grids in the file's order (io::File sorts them by name)
  const openvdb::MetaMap::Ptr meta = in.getMetadata();
  const openvdb::GridPtrVecPtr grids = in.getGrids();
  const std::string again = path + ".openvdb";
  openvdb::io::File out(again);
  out.setCompression(openvdb::io::COMPRESS_ACTIVE_MASK | (blosc ? openvdb::io::COMPRESS_BLOSC : 0));
  out.write(*grids, *meta);
  out.close();
  const std::string bytes = bytes_of(again);
  std::remove(again.c_str());
  return bytes;
}

void expect_openvdb_writes_the_same(const Volume& v, VdbWriteOptions o, const std::string& what) {
  const std::string path = stream_temp_path("v.vdb");
  write_vdb(path, v, o);
  const std::string ours = bytes_of(path), theirs = rewritten_by_openvdb(path, o.compress);
  std::remove(path.c_str());
  ASSERT_EQ(ours.size(), theirs.size()) << what;
  ASSERT_GT(ours.size(), kUuidEnd) << what;
  std::size_t first = 0;
  while (first < ours.size() && (ours[first] == theirs[first] || (first >= kUuidBegin && first < kUuidEnd))) ++first;
  auto around = [&](const std::string& bytes) {
    std::string text;
    for (std::size_t i = first < 16 ? 0 : first - 16; i < std::min(bytes.size(), first + 32); ++i) {
      char hex[4];
      std::snprintf(hex, sizeof hex, "%02x ", static_cast<unsigned char>(bytes[i]));
      text += hex;
    }
    return text;
  };
  EXPECT_EQ(first, ours.size()) << what << ": the first byte that differs from OpenVDB's\n ours:   "
                                << around(ours) << "\n theirs: " << around(theirs);
}

/// A measure volume reaching past 4096 voxels in y and z: several root nodes, whose leaves the
/// file orders otherwise than x-bands do.
Volume wide_volume() {
  Volume v;
  v.grid.dims = {4200, 5000, 9000};
  v.grid.voxel_size = 0.5;
  v.density_mode = VolumeDensity::Measure;
  v.algorithm = "test";
  for (std::uint64_t k : {VoxelGrid::key(0, 0, 0), VoxelGrid::key(0, 0, 4097), VoxelGrid::key(0, 4500, 10),
                          VoxelGrid::key(3, 4500, 11), VoxelGrid::key(130, 4100, 8200), VoxelGrid::key(131, 7, 7),
                          VoxelGrid::key(4199, 1, 4097), VoxelGrid::key(4199, 4999, 8999)})
    v.keys.push_back(k);
  for (std::size_t i = 0; i < v.keys.size(); ++i) v.density.push_back(0.01f * float(i + 1));
  return v;
}

}  // namespace

TEST(VdbStream, OpenVdbWritesTheSameBytesForEveryEncoding) {
  const Ifs rgb = read_ifs_json(std::string(IFSFORGE_SOURCE_DIR) + "/samples/systems/volume_sierpinski_pyramid_rgb.json");
  VolumeOptions options;
  options.resolution = 96;
  const Volume binary = render_volume(rgb, "prr", options);
  options.density = VolumeDensity::Measure;
  const Volume measure = render_volume(rgb, "prr", options);
  ASSERT_GT(binary.size(), 10000u);
  for (const bool half : {true, false})
    for (const bool compress : {false, true}) {
      VdbWriteOptions o;
      o.half = half;
      o.compress = compress;
      o.system = &rgb;
      o.metadata = {{"frame", "12"}, {"note", "streamed"}};
      const std::string what = std::string(half ? "half" : "float") + (compress ? ", blosc" : "");
      expect_openvdb_writes_the_same(binary, o, "binary rgb, " + what);
      expect_openvdb_writes_the_same(measure, o, "measure rgb, " + what);
    }
}

TEST(VdbStream, OpenVdbWritesTheSameBytesForGrayAlphaEmptyAndWideVolumes) {
  std::vector<AffineMap> maps;
  for (int i = 0; i < 4; ++i) maps.push_back(corner_map(5, 0.5, kCorners[i], 0.5, {0.1 * i, 0.5}));
  const Ifs gray("ga", ChannelLayout("xyz+gray+alpha"), maps, {1, 1, 1, 1});
  VolumeOptions options;
  options.resolution = 40;
  expect_openvdb_writes_the_same(render_volume(gray, "prr", options), {}, "gray and alpha");
  options.bounds = Box3{10, 10, 10, 11, 11, 11};  // misses the attractor
  const Volume empty = render_volume(tetrahedron(true), "prr", options);
  ASSERT_EQ(empty.size(), 0u);
  expect_openvdb_writes_the_same(empty, {}, "empty");
  VdbWriteOptions blosc;
  blosc.compress = true;
  expect_openvdb_writes_the_same(empty, blosc, "empty, blosc");
  options.bounds.reset();
  options.resolution = 150;
  const Volume plain = render_volume(tetrahedron(), "prr", options);  // binary, no channels: its topology alone
  ASSERT_GT(plain.size(), 1000u);
  expect_openvdb_writes_the_same(plain, {}, "binary without channels");
  expect_openvdb_writes_the_same(plain, blosc, "binary without channels, blosc");
  expect_openvdb_writes_the_same(wide_volume(), {}, "several root nodes");
  expect_openvdb_writes_the_same(wide_volume(), blosc, "several root nodes, blosc");
}

// A volume given band by band (each band copied into the loader's scratch, as a merge of job
// results does) is the same file as the whole volume, UUID included.
TEST(VdbStream, BandsGivenOneByOneMakeTheWholeVolumesFile) {
  VolumeOptions options;
  options.resolution = 300;  // 3 bands
  const Volume v = render_volume(tetrahedron(true), "prr", options);
  const std::string whole = stream_temp_path("whole.vdb"), banded = stream_temp_path("banded.vdb");
  write_vdb(whole, v);
  Volume header = v;
  header.keys.clear();
  header.density.clear();
  header.channels.clear();
  const int nc = v.channel_count();
  std::atomic<int> calls{0};
  write_vdb(banded, header, 3, [&](std::size_t b, bool keys_only, Volume& scratch) {
    ++calls;
    scratch.keys.clear();
    scratch.density.clear();
    scratch.channels.clear();
    for (std::size_t i = 0; i < v.size(); ++i)
      if (static_cast<std::size_t>(VoxelGrid::coord(v.keys[i])[0]) / kVolumeBandRows == b) {
        scratch.keys.push_back(v.keys[i]);
        if (keys_only) continue;
        scratch.density.push_back(v.density[i]);
        scratch.channels.insert(scratch.channels.end(), v.channels.begin() + i * nc, v.channels.begin() + (i + 1) * nc);
      }
    return VoxelSpan{scratch.keys.data(), scratch.density.data(), scratch.channels.data(), scratch.keys.size()};
  });
  EXPECT_EQ(calls.load(), 6);  // the keys of each band, then all of it
  EXPECT_EQ(bytes_of(whole), bytes_of(banded));
  std::remove(whole.c_str());
  std::remove(banded.c_str());
}

// Rendering straight into a .vdb (PRR's jobs merged a band at a time; the other renderers write
// their whole volume) makes the file of rendering, then writing.
TEST(VdbStream, RenderingStraightIntoTheFileMakesTheRenderedVolumesFile) {
  const std::string samples = std::string(IFSFORGE_SOURCE_DIR) + "/samples/systems/";
  for (const Ifs& rgb : {read_ifs_json(samples + "volume_sierpinski_pyramid_rgb.json"), read_ifs_json(samples + "sierpinski_pyramid.json")})
  for (const char* algorithm : {"prr", "eta"})
    for (const VolumeDensity density : {VolumeDensity::Binary, VolumeDensity::Hits, VolumeDensity::Measure}) {
      if (density == VolumeDensity::Measure && std::string(algorithm) == "eta") continue;  // eta has no measure
      VolumeOptions options;
      options.resolution = 160;  // 2 bands
      options.density = density;
      VdbWriteOptions o;
      o.system = &rgb;
      const std::string rendered = stream_temp_path("rendered.vdb"), straight = stream_temp_path("straight.vdb");
      const Volume v = render_volume(rgb, algorithm, options);
      write_vdb(rendered, v, o);
      std::uint64_t voxels = 0;
      const Volume header = render_volume_to_vdb(straight, rgb, algorithm, options, o, &voxels);
      EXPECT_EQ(voxels, v.size()) << algorithm;
      EXPECT_EQ(header.size(), 0u) << algorithm;
      EXPECT_EQ(header.points, v.points) << algorithm;
      EXPECT_EQ(header.depth, v.depth) << algorithm;
      EXPECT_EQ(bytes_of(rendered), bytes_of(straight)) << rgb.name() << " " << algorithm << " " << name_of(density);
      std::remove(rendered.c_str());
      std::remove(straight.c_str());
    }
}

// Voxels outside the grid (a malformed volume, or a cluster's result for another grid) are
// InputError, and no file is left.
TEST(VdbStream, VoxelsOutsideTheGridAreInputErrorsAndLeaveNoFile) {
  const std::string path = stream_temp_path("outside.vdb");
  Volume v = wide_volume();
  v.grid.dims[2] = 8999;  // the last voxel's z is 8999
  EXPECT_THROW(write_vdb(path, v), InputError);
  const Ifs pyramid = read_ifs_json(std::string(IFSFORGE_SOURCE_DIR) + "/samples/systems/sierpinski_pyramid.json");
  VolumeOptions options;
  options.resolution = 200;
  const std::string bytes = volume_renderer("prr").run_jobs(pyramid, options, 0, ~std::uint64_t(0));
  const VolumeJobsBytes part(bytes);
  VoxelGrid small;
  small.dims = {100, 200, 200};  // the result reaches x = 199: past the grid's only band
  const Volume header = empty_volume(small, pyramid, ChannelQuantizer(), VolumeDensity::Binary);
  EXPECT_THROW(give_volume_jobs({part}, header, ChannelQuantizer(), 1.0,
                                [&](const Volume& h, std::size_t bands, const VolumeBandLoader& load) {
                                  write_vdb(path, h, bands, load);
                                }),
               InputError);
  small.dims = {200, 100, 200};  // y beyond the grid: found by the writer
  EXPECT_THROW(give_volume_jobs({part}, empty_volume(small, pyramid, ChannelQuantizer(), VolumeDensity::Binary),
                                ChannelQuantizer(), 1.0,
                                [&](const Volume& h, std::size_t bands, const VolumeBandLoader& load) {
                                  write_vdb(path, h, bands, load);
                                }),
               InputError);
  EXPECT_FALSE(std::filesystem::exists(path));
  for (const auto& entry : std::filesystem::directory_iterator(std::filesystem::path(path).parent_path()))
    EXPECT_EQ(entry.path().filename().string().rfind(std::filesystem::path(path).filename().string() + ".tmp", 0),
              std::string::npos);
}

// The writer's threads (bands in parallel, leaves written wherever they belong) never change the
// bytes, Blosc included.
TEST(VdbStream, TheThreadCountNeverChangesTheFile) {
  VolumeOptions options;
  options.resolution = 400;  // 4 bands
  const Volume v = render_volume(tetrahedron(true), "prr", options);
  for (const bool compress : {false, true}) {
    std::string first;
    for (const int threads : {1, 2, 3, 8}) {
      VdbWriteOptions o;
      o.compress = compress;
      o.threads = threads;
      const std::string path = stream_temp_path("threads.vdb");
      write_vdb(path, v, o);
      const std::string bytes = bytes_of(path);
      std::remove(path.c_str());
      if (first.empty()) first = bytes;
      EXPECT_EQ(bytes, first) << threads << " threads" << (compress ? ", blosc" : "");
    }
  }
}

// The colour grid's halves come from thresholds, not powf: for every float of the range where
// srgb_to_linear calls powf, and past both ends, the very half that powf's value rounds to.
// This is what makes the table exact: it holds where c -> half(srgb_to_linear(c)) never
// decreases, which is checked here for every float rather than assumed (about 40 M values).
TEST(VdbStream, TheColourGridsHalvesAreThoseOfPowfForEveryFloat) {
  const detail::LinearHalves& linear = detail::LinearHalves::get();
  ASSERT_TRUE(linear.in_use());
  auto bits = [](float f) {
    std::uint32_t x;
    std::memcpy(&x, &f, sizeof x);
    return x;
  };
  auto check = [&](float c) {
    const std::uint16_t expected = openvdb::math::half(srgb_to_linear(c)).bits();
    return linear(c) == expected && detail::LinearHalves::exact(c) == expected;
  };
  std::uint64_t wrong = 0;
  std::uint32_t first_wrong = 0;
  for (std::uint32_t x = bits(0.04f); x <= bits(1.0f) + 65536; ++x) {
    float c;
    std::memcpy(&c, &x, sizeof c);
    if (!check(c) && wrong++ == 0) first_wrong = x;
  }
  EXPECT_EQ(wrong, 0u) << "first at float bits " << std::hex << first_wrong;
  for (float c : {0.0f, -0.0f, 1e-30f, 0.04045f, -0.5f, 2.0f, INFINITY, -INFINITY}) EXPECT_TRUE(check(c)) << c;
  EXPECT_EQ(linear(NAN), openvdb::math::half(srgb_to_linear(NAN)).bits());
}
