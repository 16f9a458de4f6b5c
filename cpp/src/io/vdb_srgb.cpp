#include "vdb_srgb.h"

#include <openvdb/Types.h>

#include <cmath>

#include "ifsforge/core/color.h"

namespace ifsforge::detail {
namespace {

float from_bits(std::uint32_t x) {
  float f;
  std::memcpy(&f, &x, sizeof f);
  return f;
}
std::uint32_t bits_of(float f) {
  std::uint32_t x;
  std::memcpy(&x, &f, sizeof x);
  return x;
}
float half_value(std::uint16_t h) {
  openvdb::math::half v;
  v.setBits(h);
  return static_cast<float>(v);
}

}  // namespace

std::uint16_t LinearHalves::exact(float c) { return openvdb::math::half(srgb_to_linear(c)).bits(); }

const LinearHalves& LinearHalves::get() {
  static const LinearHalves table;
  return table;
}

LinearHalves::LinearHalves() {
  // srgb_to_linear's power law: from the float after 0.04045 to 1.
  const std::uint32_t first = bits_of(0.04045f) + 1, last = bits_of(1.0f);
  auto half_at = [](std::uint32_t x) { return exact(from_bits(x)); };
  const std::uint32_t lowest = half_at(first), highest = half_at(last);
  std::vector<std::uint32_t> threshold{first};
  for (std::uint32_t h = lowest + 1; h <= highest; ++h) {
    // The inverse of the power law at the midpoint between the halves h - 1 and h, in double,
    // lands within a float or two of the first float whose half is h; powf decides from there.
    const double middle = 0.5 * (double(half_value(static_cast<std::uint16_t>(h - 1))) +
                                 double(half_value(static_cast<std::uint16_t>(h))));
    std::uint32_t x = bits_of(static_cast<float>(1.055 * std::pow(middle, 1.0 / 2.4) - 0.055));
    x = std::min(std::max(x, threshold.back()), last);
    if (half_at(x) >= h) {
      while (x > threshold.back() && half_at(x - 1) >= h) --x;
    } else {
      while (half_at(x) < h) ++x;  // half_at(last) == highest >= h: ends by `last`
    }
    // A half that decreases somewhere between two thresholds shows here as a threshold not
    // above the last one, or a float below it with this half: then powf decides every value.
    if (x <= threshold.back() || half_at(x - 1) >= h || half_at(x) != h) return;
    threshold.push_back(x);
  }
  threshold.push_back(last + 1);  // above every value of the table
  std::vector<std::uint16_t> bucket(((last - first) >> kShift) + 1), group((bucket.size() >> kGroupShift) + 1);
  std::uint32_t j = 0;
  for (std::size_t i = 0; i < bucket.size(); ++i) {
    const std::uint32_t start = first + (static_cast<std::uint32_t>(i) << kShift);
    while (threshold[j + 1] <= start) ++j;
    const std::uint32_t half = lowest + j;
    if (i % (std::size_t(1) << kGroupShift) == 0) group[i >> kGroupShift] = static_cast<std::uint16_t>(half);
    const std::uint32_t step = half - group[i >> kGroupShift], next = threshold[j + 1] - start;  // next > 0
    // Two thresholds in one bucket, or a group spanning 64 halves (never: see kShift), would
    // leave the table unused.
    const bool second = j + 2 < threshold.size() - 1 && threshold[j + 2] - start <= kInBucket;
    if (second || step >= (1u << (16 - kShift))) return;
    bucket[i] = static_cast<std::uint16_t>(step << kShift | (next <= kInBucket ? next - 1 : kInBucket));
  }
  bucket_ = std::move(bucket);
  group_ = std::move(group);
  first_ = first;
  span_ = last - first;
  in_use_ = true;
}

}  // namespace ifsforge::detail
