#include "ifsforge/render/accumulator.h"

#include <algorithm>
#include <cstring>
#include <limits>

#include "ifsforge/core/error.h"
#include "ifsforge/core/pages.h"
#include "ifsforge/core/parallel.h"
#include "ifsforge/core/varint.h"

namespace ifsforge {

Accumulator::Accumulator(int width, int height, bool measure, std::vector<double> lo,
                         std::vector<double> hi)
    : width_(width), height_(height), channels_(static_cast<int>(lo.size())),
      lo_(std::move(lo)),
      scale_(channels_) {
  // Huge pages before the first touch (at 1024^2 the 4 KB page faults of a fresh accumulator
  // cost more than plotting 15 M points), and the kernel's zeros kept: no second pass writes them.
  const std::size_t slots = std::size_t(width) * height + 1;  // +1: a slot that off-image points may hit
  zeroed_large(hits_, slots);
  zeroed_large(mass_, measure ? slots : 0);
  zeroed_large(sums_, slots * channels_);
  for (int c = 0; c < channels_; ++c) {
    const double range = hi[c] - lo_[c];
    scale_[c] = range > 0 ? kChannelSteps / range : 0.0;
  }
}

double Accumulator::bytes(int width, int height, bool measure, int channels) {
  return static_cast<double>(width) * height * 8.0 * (1 + (measure ? 1 : 0) + channels);
}

void Accumulator::merge(const Accumulator& other) {
  for (std::size_t i = 0; i < hits_.size(); ++i) hits_[i] += other.hits_[i];
  for (std::size_t i = 0; i < mass_.size(); ++i) mass_[i] += other.mass_[i];
  for (std::size_t i = 0; i < sums_.size(); ++i) sums_[i] += other.sums_[i];
  for (std::size_t i = 0; i < nearest_.size(); ++i) nearest_[i] = std::max(nearest_[i], other.nearest_[i]);
}

namespace {
constexpr std::uint64_t kMagic = 0x4149'4649;  // "IFIA"
}

std::string Accumulator::encode() const {
  std::string out;
  put_varint(out, kMagic);
  for (std::uint64_t v : {std::uint64_t(width_), std::uint64_t(height_), std::uint64_t(channels_),
                          std::uint64_t(mass_.empty() ? 0 : 1), std::uint64_t(nearest_.empty() ? 0 : 1)})
    put_varint(out, v);
  // Pixels without hits hold nothing else (no mass, sums or depth): only the others travel.
  std::size_t previous = 0;
  for (std::size_t i = 0; i < hits_.size(); ++i) {
    if (!hits_[i]) continue;
    put_varint(out, i - previous);
    previous = i;
    put_varint(out, hits_[i]);
    if (!mass_.empty()) put_varint(out, mass_[i]);
    for (int c = 0; c < channels_; ++c) put_varint(out, sums_[i * channels_ + c]);
    if (!nearest_.empty()) {
      std::uint32_t bits;
      std::memcpy(&bits, &nearest_[i], 4);
      put_varint(out, bits);
    }
  }
  return out;
}

void Accumulator::merge_encoded(std::string_view bytes) {
  VarintReader in(bytes, "image job result");
  if (in.next() != kMagic || in.next() != std::uint64_t(width_) || in.next() != std::uint64_t(height_) ||
      in.next() != std::uint64_t(channels_) || in.next() != (mass_.empty() ? 0u : 1u) ||
      in.next() != (nearest_.empty() ? 0u : 1u))
    throw InputError("image job result: not the histogram of this render (another size, system or build)");
  std::size_t i = 0;
  bool first = true;
  while (!in.done()) {
    i += in.next();
    if (i >= hits_.size() || (!first && i == 0)) throw InputError("image job result: pixel out of range");
    first = false;
    hits_[i] += in.next();
    if (!mass_.empty()) mass_[i] += in.next();
    for (int c = 0; c < channels_; ++c) sums_[i * channels_ + c] += in.next();
    if (!nearest_.empty()) {
      const auto bits = static_cast<std::uint32_t>(in.next());
      float d;
      std::memcpy(&d, &bits, 4);
      nearest_[i] = std::max(nearest_[i], d);
    }
  }
}

void Accumulator::finish(Raster& raster, int threads) const {
  const std::size_t pixels = std::size_t(width_) * height_;
  raster.width = width_;
  raster.height = height_;
  assign_large(raster.density, pixels, 0.0f);
  assign_large(raster.channels, pixels * channels_, 0.0f);
  if (!nearest_.empty()) raster.depth.assign(nearest_.begin(), nearest_.begin() + pixels);
  constexpr std::size_t kBand = 1 << 16;
  parallel_jobs((pixels + kBand - 1) / kBand, threads, [&](std::size_t band, int) {
    for (std::size_t i = band * kBand, end = std::min(pixels, i + kBand); i < end; ++i) {
      if (hits_[i] == 0) continue;
      const double d = mass_.empty() ? static_cast<double>(hits_[i]) : mass_[i] / kMassUnit;
      raster.density[i] = std::max(static_cast<float>(d), std::numeric_limits<float>::denorm_min());
      for (int c = 0; c < channels_; ++c) {
        const double mean = static_cast<double>(sums_[i * channels_ + c]) / hits_[i];
        raster.channels[i * channels_ + c] =
            static_cast<float>(scale_[c] > 0 ? lo_[c] + mean / scale_[c] : lo_[c]);
      }
    }
  });
}

void channel_ranges(const Ifs& ifs, std::vector<double>& lo, std::vector<double>& hi) {
  lo.clear();
  hi.clear();
  if (ifs.dim() == ifs.spatial_dims()) return;
  const Bounds b = ifs.attractor_bounds(1u << 16);
  lo.assign(b.lo.begin() + ifs.spatial_dims(), b.lo.end());
  hi.assign(b.hi.begin() + ifs.spatial_dims(), b.hi.end());
}

void describe_channels(const Ifs& ifs, Raster& raster) {
  const auto& names = ifs.layout().names();
  raster.channel_names.assign(names.begin() + ifs.spatial_dims(), names.end());
  raster.color_model = ifs.layout().color_model();
  raster.channels_in_unit_range = false;
}

std::size_t Raster::covered() const {
  std::size_t n = 0;
  for (double d : density) n += d > 0.0;
  return n;
}

}  // namespace ifsforge
