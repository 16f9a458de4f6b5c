#include "ifsforge/volume/volume_jobs.h"

#include "ifsforge/core/error.h"
#include "ifsforge/core/pages.h"
#include "ifsforge/core/varint.h"

namespace ifsforge {
namespace {
constexpr std::uint64_t kMagic = 0x4A56'4649;  // "IFVJ"
constexpr std::uint64_t kVersion = 2;
constexpr int kMaxChannels = 5;  // an 8-dimensional system's non-spatial channels
}  // namespace

std::string encode_volume_jobs(const VolumeJobsResult& r, VolumeDensity density) {
  const VoxelList& v = r.voxels;
  const bool hits = density == VolumeDensity::Hits || v.channels > 0, mass = density == VolumeDensity::Measure;
  std::string out;
  out.reserve(v.size() * (4 + v.channels * 3));
  put_varint(out, kMagic);
  put_varint(out, kVersion);
  put_varint(out, static_cast<std::uint64_t>(v.channels));
  put_varint(out, v.points.empty() ? 0 : 1);
  put_varint(out, (hits ? 1 : 0) | (mass ? 2 : 0));
  put_varint(out, v.size());
  put_varint(out, r.points);
  put_varint(out, static_cast<std::uint64_t>(r.depth));
  std::uint64_t previous = 0;
  for (std::uint64_t key : v.keys) {
    put_varint(out, key - previous);
    previous = key;
  }
  if (hits)
    for (std::uint64_t h : v.hits) put_varint(out, h);
  if (mass)
    for (std::uint64_t m : v.mass) put_varint(out, m);
  for (std::uint64_t s : v.sums) put_varint(out, s);
  for (std::uint64_t p : v.points) put_varint(out, p);
  return out;
}

VolumeJobsResult decode_volume_jobs(const std::string& bytes) {
  VarintReader in(bytes, "volume job result");
  if (in.next() != kMagic || in.next() != kVersion)
    throw InputError("volume job result: not ifsforge job bytes of this version");
  const std::uint64_t channels = in.next();
  const std::uint64_t extremes = in.next();
  const std::uint64_t sums = in.next();
  const std::uint64_t n = in.next();
  if (channels > kMaxChannels || extremes > 1 || sums > 3 || n > bytes.size())
    throw InputError("volume job result: malformed header");
  VolumeJobsResult r;
  r.points = in.next();
  r.depth = static_cast<int>(in.next());
  VoxelList& v = r.voxels;
  v.channels = static_cast<int>(channels);
  // Through the large-buffer helpers: a driver decodes every worker's voxels, hundreds of MB
  // whose first touch on small pages cost more than the decoding. Hits and mass the job did
  // not send stay empty (1 and 0 per voxel): 8 bytes per voxel that no one reads.
  resize_large(v.keys, n);
  if (sums & 1) resize_large(v.hits, n);
  if (sums & 2) resize_large(v.mass, n);
  resize_large(v.sums, n * channels);
  std::uint64_t key = 0;
  for (std::uint64_t i = 0; i < n; ++i) {
    const std::uint64_t delta = in.next();
    if (i > 0 && delta == 0) throw InputError("volume job result: keys not ascending");
    v.keys[i] = key += delta;
  }
  if (sums & 1)
    for (auto& h : v.hits) h = in.next();
  if (sums & 2)
    for (auto& m : v.mass) m = in.next();
  for (auto& s : v.sums) s = in.next();
  if (extremes) {
    resize_large(v.points, n * VoxelList::kExtremes);
    for (auto& p : v.points) p = in.next();
  }
  if (!in.done()) throw InputError("volume job result: trailing bytes");
  return r;
}

}  // namespace ifsforge
