#include "point_recursive_leaves.h"

#include <cstring>
#include <utility>

#include "ifsforge/core/error.h"
#include "ifsforge/core/varint.h"

namespace ifsforge::prr {

std::string encode_leaves(const std::vector<LeafList>& lists, bool over_budget, const NodeCounts& counts,
                          int channels) {
  std::string out;
  put_varint(out, over_budget ? 1 : 0);
  std::vector<std::pair<std::uint64_t, std::uint64_t>> counted;
  for (std::size_t g = 0; g < counts.groups(); ++g)
    if (counts.count(g)) counted.emplace_back(g, counts.count(g));
  put_varint(out, counted.size());
  for (const auto& [group, nodes] : counted) {
    put_varint(out, group);
    put_varint(out, nodes);
  }
  auto put_float = [&](float f) {
    std::uint32_t b;
    std::memcpy(&b, &f, 4);
    put_varint(out, b);
  };
  auto put_double = [&](double d) {
    std::uint64_t b;
    std::memcpy(&b, &d, 8);
    put_varint(out, b);
  };
  // A pixel as the zigzag of its step from the last one (a job's pixels lie near each other:
  // one or two bytes instead of three or four). The mass goes as the float the raster adds.
  std::int64_t last = 0;
  for (const LeafList& list : lists) {
    for (std::size_t k = 0; k < list.pixel.size(); ++k) {
      const std::int64_t step = std::int64_t(list.pixel[k]) - last;
      last = list.pixel[k];
      put_varint(out, (std::uint64_t(step) << 1) ^ std::uint64_t(step >> 63));
      put_varint(out, list.leaves[k]);
      put_float(list.mass[k]);
      if (!list.depth.empty()) put_float(list.depth[k]);
      for (int c = 0; c < channels; ++c) put_double(list.channels[k * channels + c]);
    }
  }
  return out;
}

void decode_leaves(std::string_view bytes, bool depth, int channels, std::size_t pixels, LeafList& list,
                   NodeCounts& counts) {
  VarintReader in(bytes, "image job result");
  if (in.next() != 0) throw OverBudget{};
  const std::uint64_t counted = in.next();
  for (std::uint64_t k = 0; k < counted; ++k) {
    const std::uint64_t group = in.next();
    if (group >= counts.groups()) throw InputError("image job result: group out of range (another render or build)");
    counts.add(group, in.next());
  }
  auto next_float = [&] {
    const std::uint64_t b = in.next();
    if (b > 0xFFFFFFFFu) throw InputError("image job result: malformed float");
    const auto bits = static_cast<std::uint32_t>(b);
    float f;
    std::memcpy(&f, &bits, 4);
    return f;
  };
  std::uint64_t last = 0;  // unsigned: hostile steps wrap (defined) and fail the range check
  while (!in.done()) {
    const std::uint64_t zigzag = in.next();
    const std::uint64_t px = last + ((zigzag >> 1) ^ (~(zigzag & 1) + 1));
    if (px >= pixels) throw InputError("image job result: pixel out of range (another render or build)");
    last = px;
    const std::uint64_t leaves = in.next();
    if (leaves == 0 || leaves > 0xFFFFFFFFu) throw InputError("image job result: malformed leaf count");
    list.pixel.push_back(static_cast<std::uint32_t>(px));
    list.leaves.push_back(static_cast<std::uint32_t>(leaves));
    list.mass.push_back(next_float());
    if (depth) list.depth.push_back(next_float());
    for (int c = 0; c < channels; ++c) {
      const std::uint64_t b = in.next();
      double sum;
      std::memcpy(&sum, &b, 8);
      list.channels.push_back(sum);
    }
  }
}

}  // namespace ifsforge::prr
