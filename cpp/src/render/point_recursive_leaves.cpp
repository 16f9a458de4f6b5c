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
  for (const LeafList& list : lists) {
    for (std::size_t k = 0; k < list.pixel.size(); ++k) {
      put_varint(out, list.pixel[k]);
      std::uint64_t bits;
      std::memcpy(&bits, &list.mass[k], 8);
      put_varint(out, bits);
      auto put_float = [&](float f) {
        std::uint32_t b;
        std::memcpy(&b, &f, 4);
        put_varint(out, b);
      };
      if (!list.depth.empty()) put_float(list.depth[k]);
      for (int c = 0; c < channels; ++c) put_float(list.channels[k * channels + c]);
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
  while (!in.done()) {
    const std::uint64_t px = in.next();
    if (px >= pixels) throw InputError("image job result: pixel out of range (another render or build)");
    list.pixel.push_back(static_cast<std::uint32_t>(px));
    const std::uint64_t bits = in.next();
    double mass;
    std::memcpy(&mass, &bits, 8);
    list.mass.push_back(mass);
    auto next_float = [&] {
      const auto b = static_cast<std::uint32_t>(in.next());
      float f;
      std::memcpy(&f, &b, 4);
      return f;
    };
    if (depth) list.depth.push_back(next_float());
    for (int c = 0; c < channels; ++c) list.channels.push_back(next_float());
  }
}

}  // namespace ifsforge::prr
