#include "ifsforge/volume/volume_jobs.h"

#include <algorithm>
#include <optional>
#include <stdexcept>

#include "ifsforge/core/error.h"
#include "ifsforge/core/pages.h"
#include "ifsforge/core/parallel.h"
#include "ifsforge/core/varint.h"

namespace ifsforge {
namespace {
constexpr std::uint64_t kMagic = 0x4A56'4649;  // "IFVJ"
constexpr std::uint64_t kVersion = 3;
constexpr int kMaxChannels = 5;  // an 8-dimensional system's non-spatial channels
constexpr const char* kWhat = "volume job result";

std::uint64_t slab_of(std::uint64_t key) {
  return (key >> (2 * VoxelGrid::kKeyBits)) >> VolumeJobsBytes::kSlabShift;
}
}  // namespace

namespace {

/// What an encoding holds per voxel besides its key.
struct Fields {
  int channels = 0;
  bool hits = false, mass = false, extremes = false;
  Fields(int channel_count, bool with_extremes, VolumeDensity density)
      : channels(channel_count),
        hits(density == VolumeDensity::Hits || channel_count > 0),
        mass(density == VolumeDensity::Measure),
        extremes(with_extremes) {}
};

/// Slab chunk of entries [begin, end) of `v`: keys from 0, then the sums, so that a reader can
/// take any one slab.
std::string slab_bytes(const VoxelList& v, std::size_t begin, std::size_t end, const Fields& f) {
  const std::size_t n = end - begin;
  VarintBuffer out(n * (1 + f.hits + f.mass + f.channels + (f.extremes ? VoxelList::kExtremes : 0)));
  std::uint64_t previous = 0;
  for (std::size_t e = begin; e < end; ++e) {
    out.put(v.keys[e] - previous);
    previous = v.keys[e];
  }
  for (std::size_t e = begin; f.hits && e < end; ++e) out.put(v.hits[e]);
  for (std::size_t e = begin; f.mass && e < end; ++e) out.put(v.mass[e]);
  for (std::size_t e = begin * f.channels; e < end * f.channels; ++e) out.put(v.sums[e]);
  for (std::size_t e = begin * VoxelList::kExtremes; f.extremes && e < end * VoxelList::kExtremes; ++e)
    out.put(v.points[e]);
  return out.str();
}

/// The header, the slab table and the chunks of slabs first, first + 1, ... (`entries[k]`
/// voxels each).
std::string assemble(const Fields& f, std::uint64_t points, int depth, std::uint64_t first,
                     const std::vector<std::uint64_t>& entries, const std::vector<std::string>& chunks) {
  std::uint64_t total = 0, bytes = 0;
  for (std::size_t s = 0; s < chunks.size(); ++s) {
    total += entries[s];
    bytes += chunks[s].size();
  }
  std::string out;
  out.reserve(bytes + 20 * (chunks.size() + 10));
  for (std::uint64_t field : {kMagic, kVersion, std::uint64_t(f.channels), std::uint64_t(f.extremes),
                              std::uint64_t((f.hits ? 1 : 0) | (f.mass ? 2 : 0)), total, points, std::uint64_t(depth),
                              first, std::uint64_t(chunks.size())})
    put_varint(out, field);
  for (std::size_t s = 0; s < chunks.size(); ++s) {
    put_varint(out, entries[s]);
    put_varint(out, chunks[s].size());
  }
  for (const std::string& chunk : chunks) out += chunk;
  return out;
}

}  // namespace

std::string encode_volume_jobs(const VolumeJobsResult& r, VolumeDensity density) {
  const VoxelList& v = r.voxels;
  const Fields f(v.channels, !v.points.empty(), density);
  // The slabs from the first holding a voxel to the last (a job's piece spans a few).
  const std::uint64_t first = v.size() ? slab_of(v.keys.front()) : 0;
  const std::size_t slabs = v.size() ? static_cast<std::size_t>(slab_of(v.keys.back()) - first) + 1 : 0;
  std::vector<std::uint64_t> entries(slabs, 0);
  std::vector<std::string> chunks(slabs);
  for (std::size_t k = 0, i = 0; k < slabs; ++k) {
    const std::size_t begin = i;
    while (i < v.size() && slab_of(v.keys[i]) == first + k) ++i;
    entries[k] = i - begin;
    chunks[k] = slab_bytes(v, begin, i, f);
  }
  return assemble(f, r.points, r.depth, first, entries, chunks);
}

std::string encode_volume_jobs(std::vector<VoxelList>& lists, std::uint64_t points, int depth, VolumeDensity density,
                               int threads) {
  std::uint64_t first = ~std::uint64_t(0), last = 0;
  bool extremes = !lists.empty();
  for (const VoxelList& list : lists)
    if (list.size()) {
      first = std::min(first, slab_of(list.keys.front()));
      last = std::max(last, slab_of(list.keys.back()));
      extremes = extremes && !list.points.empty();
    }
  const std::size_t slabs = first <= last ? static_cast<std::size_t>(last - first) + 1 : 0;
  if (!slabs) first = 0;
  const Fields f(lists.empty() ? 0 : lists.front().channels, extremes && slabs > 0, density);
  std::vector<std::uint64_t> entries(slabs, 0);
  std::vector<std::string> chunks(slabs);
  merge_slabs(lists, std::uint64_t(1) << VolumeJobsBytes::kSlabShift, threads,
              [&](std::size_t s, const VoxelList& merged) {
                entries[s - first] = merged.size();
                chunks[s - first] = slab_bytes(merged, 0, merged.size(), f);
              });
  lists.clear();
  return assemble(f, points, depth, first, entries, chunks);
}

VolumeJobsBytes::VolumeJobsBytes(std::string_view bytes) : bytes_(bytes) {
  VarintReader in(bytes, kWhat);
  if (in.next() != kMagic || in.next() != kVersion) throw InputError("volume job result: not ifsforge job bytes of this version");
  const std::uint64_t channels = in.next(), extremes = in.next(), sums = in.next();
  entries_ = in.next();
  points_ = in.next();
  const std::uint64_t depth = in.next(), first = in.next(), slabs = in.next();
  // Each entry and each slab takes at least one byte: no count may exceed the bytes.
  if (channels > kMaxChannels || extremes > 1 || sums > 3 || entries_ > bytes.size() || depth > (1u << 30) ||
      slabs > bytes.size() || first > (std::uint64_t(1) << (VoxelGrid::kKeyBits - kSlabShift)))
    throw InputError("volume job result: malformed header");
  first_ = static_cast<std::size_t>(first);
  channels_ = static_cast<int>(channels);
  depth_ = static_cast<int>(depth);
  extremes_ = extremes == 1;
  hits_ = sums & 1;
  mass_ = sums & 2;
  slabs_.resize(slabs);
  std::uint64_t entries = 0, size = 0;
  for (Slab& slab : slabs_) {
    slab.entries = in.next();
    slab.size = in.next();
    if (slab.entries > slab.size || slab.size > bytes.size()) throw InputError("volume job result: malformed slab table");
    slab.begin = size;
    entries += slab.entries;
    size += slab.size;
  }
  if (entries != entries_ || size != bytes.size() - in.offset())
    throw InputError("volume job result: the slab table does not match the bytes");
  for (Slab& slab : slabs_) slab.begin += in.offset();
}

VarintReader VolumeJobsBytes::read_keys(std::size_t s, std::vector<std::uint64_t>& keys) const {
  if (s < first_ || s >= slabs()) throw std::out_of_range("volume job result: no such slab");
  const Slab& slab = slabs_[s - first_];
  VarintReader in(bytes_.substr(slab.begin, slab.size), kWhat);
  const std::size_t at = keys.size(), n = slab.entries;
  keys.resize(at + n);
  std::uint64_t key = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint64_t next = key + in.next();
    if (i > 0 && next <= key) throw InputError("volume job result: keys not ascending");
    keys[at + i] = key = next;
  }
  if (n && (slab_of(keys[at]) != s || slab_of(key) != s)) throw InputError("volume job result: a voxel outside its slab");
  return in;
}

void VolumeJobsBytes::decode_keys(std::size_t s, std::vector<std::uint64_t>& keys) const { read_keys(s, keys); }

void VolumeJobsBytes::decode(std::size_t s, VoxelList& out, bool keys_only) const {
  if (out.size() == 0) out.channels = channels_;
  if (out.channels != channels_) throw InputError("volume job result: another number of channels");
  const std::size_t at = out.size(), nc = channels_;
  VarintReader in = read_keys(s, out.keys);
  if (keys_only) return;
  const std::size_t n = out.size() - at;
  auto read = [&](std::vector<std::uint64_t>& values, std::size_t per_entry) {
    values.resize((at + n) * per_entry);
    for (std::size_t i = at * per_entry; i < values.size(); ++i) values[i] = in.next();
  };
  if (hits_) read(out.hits, 1);
  if (mass_) read(out.mass, 1);
  read(out.sums, nc);
  if (extremes_) read(out.points, VoxelList::kExtremes);
  if (!in.done()) throw InputError("volume job result: trailing bytes");
}

std::vector<VolumeJobsBytes> read_volume_jobs(const std::vector<std::string_view>& results, int threads) {
  std::vector<std::optional<VolumeJobsBytes>> read(results.size());
  parallel_jobs(results.size(), threads, [&](std::size_t k, int) { read[k].emplace(results[k]); });
  std::vector<VolumeJobsBytes> parts;
  parts.reserve(read.size());
  for (std::optional<VolumeJobsBytes>& part : read) parts.push_back(std::move(*part));
  return parts;
}

VolumeJobsResult decode_volume_jobs(std::string_view bytes) {
  const VolumeJobsBytes part(bytes);
  VolumeJobsResult r;
  r.points = part.points();
  r.depth = part.depth();
  VoxelList& v = r.voxels;
  v.channels = part.channels();
  // Through the large-buffer helpers: a driver decodes every worker's voxels, hundreds of MB
  // whose first touch on small pages cost more than the decoding.
  reserve_large(v.keys, part.entries());
  if (part.hits_) reserve_large(v.hits, part.entries());
  if (part.mass_) reserve_large(v.mass, part.entries());
  reserve_large(v.sums, part.entries() * v.channels);
  if (part.extremes_) reserve_large(v.points, part.entries() * VoxelList::kExtremes);
  for (std::size_t s = part.first_slab(); s < part.slabs(); ++s) part.decode(s, v);
  return r;
}

namespace {

/// Which parts hold each slab (a render's jobs each span a few of them).
std::vector<std::vector<std::uint32_t>> slab_holders(const std::vector<VolumeJobsBytes>& parts, int channels) {
  std::vector<std::vector<std::uint32_t>> holders;
  for (std::size_t p = 0; p < parts.size(); ++p) {
    if (parts[p].channels() != channels) throw InputError("volume job result: not a result of this system");
    if (parts[p].slabs() > holders.size()) holders.resize(parts[p].slabs());
    for (std::size_t s = parts[p].first_slab(); s < parts[p].slabs(); ++s) holders[s].push_back(static_cast<std::uint32_t>(p));
  }
  return holders;
}

/// Loads slab s of every part holding it.
SlabLoader slab_loader(const std::vector<VolumeJobsBytes>& parts, const std::vector<std::vector<std::uint32_t>>& holders) {
  return [&](std::size_t s, std::vector<VoxelList>& lists, bool keys_only) {
    // The thread's lists are reused (their buffers kept); those past this slab's are emptied.
    const std::vector<std::uint32_t>& here = holders[s];
    if (lists.size() < here.size()) lists.resize(here.size());
    for (VoxelList& list : lists) list.clear();
    for (std::size_t k = 0; k < here.size(); ++k) parts[here[k]].decode(s, lists[k], keys_only);
  };
}

}  // namespace

Volume finish_volume_jobs(const std::vector<VolumeJobsBytes>& parts, const VoxelGrid& grid, const Ifs& ifs,
                          const ChannelQuantizer& quantizer, VolumeDensity mode, double total_mass, int threads) {
  const auto holders = slab_holders(parts, ifs.dim() - 3);
  return finish_volume(holders.size(), slab_loader(parts, holders), grid, ifs, quantizer, mode, total_mass, threads);
}

void give_volume_jobs(const std::vector<VolumeJobsBytes>& parts, const Volume& header, const ChannelQuantizer& quantizer,
                      double total_mass, const VolumeBandSink& sink) {
  const int channels = header.channel_count();
  const auto holders = slab_holders(parts, channels);
  const SlabLoader load = slab_loader(parts, holders);
  constexpr std::size_t kSlabsPerBand = kVolumeBandRows >> VolumeJobsBytes::kSlabShift;
  if (holders.size() > volume_bands(header.grid) * kSlabsPerBand)
    throw InputError("volume job result: voxels beyond the grid's " + std::to_string(header.grid.dims[0]) + " rows");
  sink(header, volume_bands(header.grid), [&](std::size_t band, bool keys_only, Volume& out) {
    const std::size_t first = std::min(band * kSlabsPerBand, holders.size());
    const std::size_t last = std::min(first + kSlabsPerBand, holders.size());
    if (!keys_only) return finish_slabs(first, last, load, quantizer, header.density_mode, total_mass, channels, out);
    // The keys of every part, slab after slab, unmerged (see VolumeBandLoader): decoded in place.
    // A band's keys take up to a second under load: Ctrl-C is heard between its slabs.
    out.keys.clear();
    for (std::size_t s = first; s < last; ++s) {
      if (stop_requested()) throw Cancelled();
      for (std::uint32_t p : holders[s]) parts[p].decode_keys(s, out.keys);
    }
    return VoxelSpan{out.keys.data(), nullptr, nullptr, out.keys.size()};
  });
}

}  // namespace ifsforge
