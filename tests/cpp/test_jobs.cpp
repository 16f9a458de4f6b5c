// The job API a cluster drives: a render whose jobs run in ranges (as on workers), travel as
// bytes and merge in the renderer equals the render run here, bit for bit.
#include <gtest/gtest.h>

#include "ifsforge/core/error.h"
#include "ifsforge/core/varint.h"
#include "ifsforge/render/renderer.h"
#include "ifsforge/volume/volume_jobs.h"
#include "test_systems.h"

namespace ifsforge {
namespace {

/// Cuts [first, last) into `parts` ranges (some possibly empty), as a cluster driver does.
template <typename Run>
auto in_ranges(std::uint64_t first, std::uint64_t last, std::uint64_t parts, Run run) {
  std::vector<decltype(run(first, last))> out;
  for (std::uint64_t k = 0; k < parts; ++k) {
    const std::uint64_t a = first + (last - first) * k / parts, b = first + (last - first) * (k + 1) / parts;
    if (b > a) out.push_back(run(a, b));
  }
  return out;
}

void expect_same(const Volume& a, const Volume& b) {
  EXPECT_EQ(a.keys, b.keys);
  EXPECT_EQ(a.density, b.density);
  EXPECT_EQ(a.channels, b.channels);
  EXPECT_EQ(a.points, b.points);
  EXPECT_EQ(a.depth, b.depth);
}

TEST(Jobs, VolumeRangesThroughBytesEqualTheLocalVolume) {
  for (const char* algorithm : {"prr", "ria"})
  for (VolumeDensity density : {VolumeDensity::Binary, VolumeDensity::Hits, VolumeDensity::Measure})
  for (bool color : {false, true}) {
    VolumeOptions o;
    o.resolution = 32;
    o.density = density;
    o.iterations = 3u << 20;
    o.seed = 9;
    const Ifs system = test_systems::tetrahedron(color);
    const VolumeRenderer& r = volume_renderer(algorithm);
    const Volume local = r.render(system, o);
    VolumeOptions remote = o;
    std::uint64_t calls = 0;
    std::vector<std::string> held;  // the runner keeps its bytes until its next call
    remote.distribute = [&](std::uint64_t first, std::uint64_t last) {
      ++calls;
      held = in_ranges(first, last, 3, [&](std::uint64_t a, std::uint64_t b) {
        return r.run_jobs(system, o, a, b);
      });
      return std::vector<std::string_view>(held.begin(), held.end());
    };
    const Volume merged = r.render(system, remote);
    EXPECT_GT(calls, 0u) << algorithm;
    ASSERT_GT(local.size(), 100u) << algorithm;
    expect_same(local, merged);
  }
}

TEST(Jobs, ImageRangesEqualTheLocalImage) {
  const Ifs system("sierpinski", ChannelLayout("xy"),
                   {AffineMap(2, {0.5, 0, 0, 0.5}, {0, 0}), AffineMap(2, {0.5, 0, 0, 0.5}, {0.5, 0}),
                    AffineMap(2, {0.5, 0, 0, 0.5}, {0.25, 0.5})},
                   {1.0 / 3, 1.0 / 3, 1.0 / 3});
  for (const char* algorithm : {"chaos", "prr"}) {
    RenderOptions o;
    o.width = o.height = 96;
    const Renderer& r = renderer(algorithm);
    const Raster local = r.render(system, o);
    RenderOptions remote = o;
    std::vector<std::string> held;
    remote.distribute = [&](std::uint64_t first, std::uint64_t last, int) {
      held = in_ranges(first, last, 5, [&](std::uint64_t a, std::uint64_t b) { return r.run_jobs(system, o, a, b); });
      return std::vector<std::string_view>(held.begin(), held.end());
    };
    const Raster merged = r.render(system, remote);
    EXPECT_EQ(local.density, merged.density) << algorithm;
    EXPECT_EQ(local.points, merged.points) << algorithm;
  }
}

TEST(Jobs, ImageRangesFollowTheFallBackToAFixedDepth) {
  // Pieces that halve across and shrink by a tenth along: a 64-pixel tall piece needs 40 levels
  // (2^40 nodes) to fit a pixel, so the node budget runs out and PRR falls back to a fixed
  // depth, which the jobs must then run at wherever they run.
  const Ifs system("tall", ChannelLayout("xy"),
                   {AffineMap(2, {0.5, 0, 0, 0.9}, {0, 0}), AffineMap(2, {0.5, 0, 0, 0.9}, {0.5, 0.1})}, {0.5, 0.5});
  RenderOptions o;
  o.width = o.height = 64;
  const Renderer& r = renderer("prr");
  const Raster local = r.render(system, o);
  RenderOptions remote = o;
  std::vector<std::string> held;
  std::vector<int> depths;
  remote.distribute = [&](std::uint64_t first, std::uint64_t last, int depth) {
    depths.push_back(depth);
    RenderOptions jobs = o;
    jobs.depth = depth;
    held = in_ranges(first, last, 3, [&](std::uint64_t a, std::uint64_t b) { return r.run_jobs(system, jobs, a, b); });
    return std::vector<std::string_view>(held.begin(), held.end());
  };
  const Raster merged = r.render(system, remote);
  ASSERT_EQ(depths.size(), 2u);  // the pixel stop over budget, then the fixed depth
  EXPECT_EQ(depths[0], 0);
  EXPECT_GT(depths[1], 0);
  EXPECT_EQ(local.points, std::uint64_t(1) << depths[1]);  // every leaf of the fixed depth on the image
  EXPECT_EQ(local.density, merged.density);
  EXPECT_EQ(local.points, merged.points);
}

TEST(Jobs, ImageLeavesOutsideTheImageOrCutShortAreRefused) {
  RenderOptions o;
  o.width = o.height = 16;
  std::string bytes;
  o.distribute = [&](std::uint64_t, std::uint64_t, int) { return std::vector<std::string_view>{bytes}; };
  const Ifs system("square", ChannelLayout("xy"),
                   {AffineMap(2, {0.5, 0, 0, 0.5}, {0, 0}), AffineMap(2, {0.5, 0, 0, 0.5}, {0.5, 0.5})}, {0.5, 0.5});
  // No budget flag, no counted groups, then entries: a pixel step, the leaves summed and their
  // mass (float bits).
  const std::string head("\x00\x00", 2), one_half("\x01\x80\x80\x80\xf8\x03", 6);
  for (const std::string& leaves : {std::string("\x04") + one_half + std::string("\x05") + one_half,  // 2, then -1
                                    std::string("\x80\x04") + one_half,                                 // pixel 256
                                    std::string("\x04\x00") + one_half.substr(1),                       // no leaves
                                    std::string("\x04\x01\x80\x80")}) {                                // mass cut short
    bytes = head + leaves;
    EXPECT_THROW(renderer("prr").render(system, o), InputError);
  }
  // A result over its budget at a fixed depth (where there is none) is not followed for ever.
  bytes = std::string("\x01\x00", 2);
  RenderOptions fixed = o;
  fixed.depth = 4;
  EXPECT_THROW(renderer("prr").render(system, fixed), InputError);
  bytes = head + std::string("\x04\x03") + one_half.substr(1) + std::string("\x01") + one_half;  // 2 (3 leaves), 1
  const Raster raster = renderer("prr").render(system, o);
  EXPECT_EQ(raster.points, 4u);
  EXPECT_EQ(raster.density[1], 0.5f);
  EXPECT_EQ(raster.density[2], 0.5f);
}

TEST(Jobs, RenderersWithoutJobsAndForeignBytesAreRefused) {
  VolumeOptions o;
  o.resolution = 8;
  o.distribute = [](std::uint64_t, std::uint64_t) { return std::vector<std::string_view>(); };
  EXPECT_THROW(volume_renderer("dia").render(test_systems::tetrahedron(), o), InputError);
  EXPECT_FALSE(renderer("dia").distributable());
  EXPECT_THROW(decode_volume_jobs("not a job"), InputError);
  VolumeJobsResult r;
  r.voxels.keys = {5, 9};
  r.voxels.hits = {1, 2};
  r.voxels.mass = {3, 4};
  std::string bytes = encode_volume_jobs(r);
  EXPECT_EQ(decode_volume_jobs(bytes).voxels.keys, r.voxels.keys);
  bytes.pop_back();
  EXPECT_THROW(decode_volume_jobs(bytes), InputError);
}

/// A job result of `keys` (one hit each, no channels), encoded.
std::string job_bytes(std::vector<std::uint64_t> keys) {
  VolumeJobsResult r;
  r.voxels.hits.assign(keys.size(), 1);
  r.voxels.mass.assign(keys.size(), 0);
  r.voxels.keys = std::move(keys);
  return encode_volume_jobs(r, VolumeDensity::Hits);
}

TEST(Jobs, ResultsAreCutIntoXSlabsThatDecodeOnTheirOwn) {
  // x = 0, 7 | 8 | (none) | 30: slabs of 8 x indices, the third empty.
  const std::vector<std::uint64_t> keys = {VoxelGrid::key(0, 1, 2), VoxelGrid::key(7, 0, 0), VoxelGrid::key(8, 5, 5),
                                           VoxelGrid::key(30, 0, 1)};
  const std::string bytes = job_bytes(keys);
  const VolumeJobsBytes part(bytes);
  ASSERT_EQ(part.slabs(), 4u);
  EXPECT_EQ(part.entries(), 4u);
  const std::vector<std::vector<std::uint64_t>> expected = {{keys[0], keys[1]}, {keys[2]}, {}, {keys[3]}};
  for (std::size_t s = 0; s < 4; ++s) {
    VoxelList slab;
    part.decode(s, slab, s % 2 == 1);
    EXPECT_EQ(slab.keys, expected[s]) << s;
    EXPECT_EQ(slab.hits.size(), s % 2 ? 0u : expected[s].size()) << "keys only: no sums";
  }
  EXPECT_EQ(decode_volume_jobs(bytes).voxels.keys, keys);
  // A job's piece of the attractor: its table starts at its first slab.
  const VolumeJobsBytes piece(job_bytes({VoxelGrid::key(17, 0, 0), VoxelGrid::key(23, 4, 4)}));
  EXPECT_EQ(piece.first_slab(), 2u);
  EXPECT_EQ(piece.slabs(), 3u);
  VoxelList two;
  piece.decode(2, two);
  EXPECT_EQ(two.size(), 2u);
}

TEST(Jobs, MergingResultsSlabBySlabSumsEqualKeys) {
  // Two workers' results overlapping on two voxels: hits 2 there, 1 elsewhere, keys ascending.
  const Ifs system = test_systems::tetrahedron();
  const std::string a = job_bytes({VoxelGrid::key(1, 1, 1), VoxelGrid::key(9, 0, 0), VoxelGrid::key(20, 3, 3)});
  const std::string b = job_bytes({VoxelGrid::key(1, 1, 1), VoxelGrid::key(1, 1, 2), VoxelGrid::key(20, 3, 3)});
  for (int threads : {1, 2, 3}) {
    const Volume v = finish_volume_jobs({VolumeJobsBytes(a), VolumeJobsBytes(b)}, VoxelGrid{}, system,
                                        ChannelQuantizer(), VolumeDensity::Hits, 1.0, threads);
    EXPECT_EQ(v.keys, (std::vector<std::uint64_t>{VoxelGrid::key(1, 1, 1), VoxelGrid::key(1, 1, 2),
                                                  VoxelGrid::key(9, 0, 0), VoxelGrid::key(20, 3, 3)}));
    EXPECT_EQ(v.density, (std::vector<float>{2, 1, 1, 2})) << threads;
  }
}

TEST(Jobs, UnmergedListsEncodeAsTheirMerge) {
  // Three jobs' lists over 40 rows (5 slabs), overlapping, with two channels and extremes.
  std::vector<VoxelList> lists;
  for (std::uint64_t job = 0; job < 3; ++job) {
    VoxelList list(2);
    for (std::uint64_t i = job; i < 40; i += 2 + job) {
      const std::uint64_t sums[2] = {i, 7 * job};
      list.push(VoxelGrid::key(i, job, i % 3), 1 + job, 3 * i, sums);
      for (int e = 0; e < VoxelList::kExtremes; ++e) list.points.push_back(i * 10 + job + e);
    }
    lists.push_back(list);
  }
  std::vector<VoxelList> copy = lists;
  VolumeJobsResult merged;
  merged.voxels = merge_voxel_lists(copy, 1);
  merged.points = 123;
  merged.depth = 4;
  const std::string expected = encode_volume_jobs(merged, VolumeDensity::Measure);
  for (int threads : {1, 2, 3}) {
    std::vector<VoxelList> mine = lists;
    EXPECT_EQ(encode_volume_jobs(mine, 123, 4, VolumeDensity::Measure, threads), expected) << threads;
  }
  const VolumeJobsResult back = decode_volume_jobs(expected);
  EXPECT_EQ(back.voxels.keys, merged.voxels.keys);
  EXPECT_EQ(back.voxels.sums, merged.voxels.sums);
  EXPECT_EQ(back.voxels.points, merged.voxels.points);
  EXPECT_EQ(back.points, 123u);
}

TEST(Jobs, MalformedSlabsAreRefused) {
  std::string bytes = job_bytes({VoxelGrid::key(0, 0, 1), VoxelGrid::key(9, 0, 0)});
  const VolumeJobsBytes good(bytes);
  ASSERT_EQ(good.slabs(), 2u);
  EXPECT_THROW(VolumeJobsBytes(bytes + "x"), InputError) << "trailing bytes break the table's sum";
  // One slab ending (1 entry, 2 bytes: key 1, 1 hit); its key swapped for one of slab 1.
  const std::string one = job_bytes({VoxelGrid::key(0, 0, 1)});
  ASSERT_EQ(one.substr(one.size() - 3), std::string("\x02\x01\x01"));
  std::string body;
  put_varint(body, VoxelGrid::key(9, 0, 0));
  put_varint(body, 1);
  std::string outside = one.substr(0, one.size() - 3);
  put_varint(outside, body.size());
  outside += body;
  const VolumeJobsBytes crafted(outside);  // the table is consistent
  VoxelList list;
  EXPECT_THROW(crafted.decode(0, list), InputError) << "a voxel outside its slab";
  VoxelList other(2);
  other.keys = {1};
  EXPECT_THROW(good.decode(0, other), InputError) << "another number of channels";
  const Ifs colour = test_systems::tetrahedron(true);
  EXPECT_THROW(finish_volume_jobs({good}, VoxelGrid{}, colour, ChannelQuantizer(), VolumeDensity::Hits, 1.0, 1),
               InputError)
      << "a result of another system";
  // Every truncation is refused (never a read past the end).
  for (std::size_t n = 0; n < bytes.size(); ++n) EXPECT_THROW(decode_volume_jobs(bytes.substr(0, n)), InputError) << n;
}

}  // namespace
}  // namespace ifsforge
