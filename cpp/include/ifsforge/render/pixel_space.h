#pragma once
/// @file What the image-plane algorithms of chapter 5 share (DIA, DIA-S, MPA, CMA, IBR, AFRA,
/// self-congruent growth, the recurrent photo-copy): the maps conjugated into pixel
/// coordinates, the channel quantiser, the condensation set on the pixel grid, a deterministic
/// parallel scatter and the Hutchinson operator on pixel sets.
#include <cstdint>
#include <string>
#include <vector>

#include "ifsforge/core/progress.h"
#include "ifsforge/model/ifs.h"
#include "ifsforge/render/frame.h"
#include "ifsforge/render/raster.h"
#include "ifsforge/render/renderer.h"

namespace ifsforge {

/// @brief Frame::fit, except that a system with a condensation set and no window is framed
/// on the box of its attractor with C (condensation_attractor_box) plus a 3% margin.
Frame fit_frame(const Ifs& ifs, const RenderOptions& options);

/// @brief One map in pixel coordinates (x right, y down, pixel (i, j) covers [i, i+1) x
/// [j, j+1)): x' = a x + b y + e, y' = c x + d y + f for the spatial rows, and the whole
/// conjugated nD map for the channels.
struct PixelMap {
  double a, b, c, d, e, f;
  AffineMap map;
  double determinant() const { return a * d - b * c; }
};

/// @brief A 2D system on the pixel grid of its frame.
struct PixelSpace {
  Frame frame;
  int width = 0, height = 0;
  int channels = 0;                  ///< extra (non-spatial) channels carried per pixel
  bool spatial_reads_channels = false;  ///< some spatial row reads a colour channel
  std::vector<PixelMap> maps;        ///< T o w_i o T^-1, T the world-to-pixel map
  std::vector<double> channel_lo, channel_hi;  ///< channel ranges (attractor and condensation)
  std::size_t pixels() const { return std::size_t(width) * height; }
  /// @brief The pixel holding continuous pixel coordinates (x, y), or -1 off the image.
  long long pixel_at(double x, double y) const {
    if (!(x >= 0.0 && x < width && y >= 0.0 && y < height)) return -1;
    return static_cast<long long>(y) * width + static_cast<long long>(x);
  }
  /// @brief Maps the centre of `pixel` (and its channel values) by map i: the target pixel
  /// (or -1 off the image), with the new channel values in `channels_out`.
  long long map_pixel(std::size_t i, std::uint32_t pixel, const float* values, double* channels_out) const;
};

/// @brief The pixel space of a render on a grid `supersample` times finer than the image in
/// each direction. InputError naming `algorithm` unless the system is 2D in space (these
/// algorithms work on the image plane).
PixelSpace make_pixel_space(const Ifs& ifs, const RenderOptions& options, const std::string& algorithm,
                            int supersample = 1);

/// @brief The parameter every pixel-grid algorithm takes.
RendererParameter supersample_parameter();
/// @brief The image's raster from one `k` times finer (k x k cells per pixel): density summed
/// (`sum`: a measure) or the largest (sets, ages); channels averaged over the covered cells,
/// weighted by density when summing. Returns `fine` itself when k is 1.
Raster reduce_supersampled(Raster fine, int k, bool sum);


/// @brief Quantises channel values to integers (2^20 steps of [lo, hi], clamped) so that
/// parallel sums are exact and order-independent.
class ChannelCodec {
 public:
  static constexpr double kSteps = 1048576.0;
  ChannelCodec() = default;
  ChannelCodec(const std::vector<double>& lo, const std::vector<double>& hi);
  std::uint64_t encode(int c, double value) const {
    double q = (value - lo_[c]) * scale_[c];
    q = q < 0.0 ? 0.0 : (q > kSteps ? kSteps : q);
    return static_cast<std::uint64_t>(q + 0.5);
  }
  /// @brief The value whose code is `mean_code` (a mean of codes).
  double decode(int c, double mean_code) const { return scale_[c] > 0 ? lo_[c] + mean_code / scale_[c] : lo_[c]; }

 private:
  std::vector<double> lo_, scale_;
};

/// @brief The pixels the condensation set covers: polylines sampled every quarter pixel,
/// polygons filled at pixel centres (even-odd) and outlined so thin ones still show. Sorted.
std::vector<std::uint32_t> condensation_pixels(const Ifs& ifs, const Frame& frame);

/// @brief Integer accumulation per pixel by several workers: each adds into its own buffer and
/// remembers the pixels it touched; merging adds the buffers over the touched pixels only.
/// Integer sums do not depend on the order, so the result does not depend on the threads.
class PixelScatter {
 public:
  /// `values` integers per pixel (0: only which pixels were touched).
  /// `poll` hears Ctrl-C while the buffers are faulted in.
  PixelScatter(std::size_t pixels, int values, int workers, const ProgressCallback& poll = {});
  static double bytes(std::size_t pixels, int values, int workers) {
    return static_cast<double>(pixels) * workers * (5.0 + 8.0 * values);
  }
  /// @brief One job's hold on its worker's buffer, for tight loops (the count is written back
  /// when it goes out of scope). Only one Writer per worker at a time.
  class Writer {
   public:
    /// Branch-free "first touch": always append, advance only when the pixel is new (a branch
    /// would mispredict on the irregular hit patterns of contracted images).
    void touch(std::uint32_t pixel) {
      const std::uint8_t seen = flag_[pixel];
      touched_[count_] = pixel;
      count_ += 1u - seen;
      flag_[pixel] = 1;
    }
    void add(std::uint32_t pixel, const std::uint64_t* v) {
      touch(pixel);
      std::uint64_t* s = sums_ + std::size_t(pixel) * values_;
      for (int k = 0; k < values_; ++k) s[k] += v[k];
    }
    /// Adds `v` to value `slot` of `pixel` only.
    void add_one(std::uint32_t pixel, int slot, std::uint64_t v) {
      touch(pixel);
      sums_[std::size_t(pixel) * values_ + slot] += v;
    }
    ~Writer() { *count_out_ = count_; }
    Writer(const Writer&) = delete;
    Writer& operator=(const Writer&) = delete;

   private:
    friend class PixelScatter;
    Writer(std::uint8_t* flag, std::uint32_t* touched, std::uint64_t* sums, int values, std::size_t* count)
        : flag_(flag), touched_(touched), sums_(sums), values_(values), count_(*count), count_out_(count) {}
    std::uint8_t* flag_;
    std::uint32_t* touched_;
    std::uint64_t* sums_;
    int values_;
    std::size_t count_;
    std::size_t* count_out_;
  };
  Writer writer(int worker) {
    Worker& w = workers_[worker];
    return Writer(w.flag.data(), w.touched.data(), w.sums.data(), values_, &w.count);
  }
  void add(int worker, std::uint32_t pixel, const std::uint64_t* v) { writer(worker).add(pixel, v); }
  /// @brief Adds every worker's sums into `sums` (pixels x values, may be empty when values
  /// is 0) and lists the pixels any worker touched, increasing, in `touched`; leaves the
  /// workers cleared for the next round.
  /// `poll` hears Ctrl-C.
  void merge(std::vector<std::uint64_t>& sums, std::vector<std::uint32_t>& touched, const ProgressCallback& poll = {});
  int values() const { return values_; }

 private:
  struct Worker {
    std::vector<std::uint8_t> flag;
    std::vector<std::uint32_t> touched;  ///< the first `count` entries are the touched pixels
    std::size_t count = 0;
    std::vector<std::uint64_t> sums;
  };
  /// Moves worker `w`'s sums of `pixel` into `sums` and clears its flag there.
  void take(Worker& w, std::size_t pixel, std::vector<std::uint64_t>& sums);
  int values_;
  std::vector<Worker> workers_;
  std::vector<std::uint64_t> merged_;  ///< one bit per pixel touched by any worker
};

/// @brief A scatter shaped for hutchinson(): a count and the channel codes per pixel.
inline PixelScatter set_scatter(const PixelSpace& space, int workers, const ProgressCallback& poll = {}) {
  return PixelScatter(space.pixels(), space.channels ? 1 + space.channels : 0, workers, poll);
}

/// @brief Reports `fraction` to the caller's progress callback; throws Cancelled when it
/// asks to stop. Call only from the thread that started the render.
void report_progress(const RenderOptions& options, double fraction);

/// @brief A set of pixels with the channel values of each (a binary image with colour).
struct PixelSet {
  std::vector<std::uint32_t> pixels;  ///< increasing
  std::vector<float> values;          ///< pixels.size() x channels, in the same order
  bool operator==(const PixelSet& o) const { return pixels == o.pixels; }
};

/// @brief The whole image with every pixel carrying `values` (the seed's initial grey image),
/// filled on `threads` threads; `progress` hears the fill (Cancelled when it says stop).
PixelSet full_pixel_set(const PixelSpace& space, const std::vector<float>& values, int threads,
                        const ProgressCallback& progress);
/// @brief The condensation set as a pixel set (its channel values on every pixel).
PixelSet condensation_set(const Ifs& ifs, const PixelSpace& space);

/// @brief One term w_map(source) of a Hutchinson operator on pixel sets.
struct SetImage {
  std::size_t map;
  const PixelSet* source;
};

/// @brief The Hutchinson operator on pixel sets: the union of the images of the terms (each
/// source pixel's centre mapped and rounded to the pixel holding it), united with `extra` (may
/// be null). A pixel's channel values are the mean of the values mapped into it. Work is split
/// into fixed chunks; the result does not depend on `threads`. Adds the map applications to
/// `operations`. `progress` (optional) hears the fraction of this pass done, and cancels it.
PixelSet hutchinson(const PixelSpace& space, const std::vector<SetImage>& terms, const PixelSet* extra,
                    PixelScatter& scatter, int threads, std::uint64_t& operations,
                    const ProgressCallback& progress = nullptr);

/// @brief A raster for `space` with the system's channel metadata, density 0 everywhere.
Raster empty_raster(const Ifs& ifs, const PixelSpace& space);
/// @brief Writes `set` into the raster: density `value` on its pixels, their channel values.
void paint_set(const PixelSet& set, float value, Raster& raster);

}  // namespace ifsforge
