#include "ifsforge/render/pixel_space.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "ifsforge/core/error.h"
#include "ifsforge/core/pages.h"
#include "ifsforge/core/parallel.h"
#include "ifsforge/core/random.h"
#include "ifsforge/render/accumulator.h"

namespace ifsforge {

Frame fit_frame(const Ifs& ifs, const RenderOptions& options) {
  if (options.window || ifs.condensation().empty())
    return Frame::fit(ifs, options.width, options.height, options.window, options.view);
  const auto box = condensation_attractor_box(ifs);
  const double mx = 0.03 * (box[2] - box[0]) + 1e-12, my = 0.03 * (box[3] - box[1]) + 1e-12;
  return Frame::fit(ifs, options.width, options.height, Window{box[0] - mx, box[1] - my, box[2] + mx, box[3] + my},
                    options.view);
}

namespace {

/// Channel ranges: the attractor's, widened by the values the condensation set and its images
/// take (the attractor of an IFS with condensation holds w_s(C) for every address s).
void channel_ranges_of(const Ifs& ifs, std::vector<double>& lo, std::vector<double>& hi) {
  channel_ranges(ifs, lo, hi);
  const Condensation& c = ifs.condensation();
  if (lo.empty() || c.empty()) return;
  const int k = ifs.spatial_dims(), n = ifs.dim();
  std::vector<std::array<double, 2>> vertices;
  for (const auto* shapes : {&c.polylines, &c.polygons})
    for (const auto& path : *shapes) vertices.insert(vertices.end(), path.begin(), path.end());
  Rng rng(0xC0DE, 0);
  for (int sample = 0; sample < 4096; ++sample) {
    Point p{};
    const auto& v = vertices[rng.next() % vertices.size()];
    p[0] = v[0];
    p[1] = v[1];
    for (int ch = k; ch < n; ++ch) p[ch] = c.channels[ch - k];
    const int length = static_cast<int>(rng.next() % 24);
    for (int step = 0; step <= length; ++step) {
      for (int ch = k; ch < n; ++ch) {
        lo[ch - k] = std::min(lo[ch - k], p[ch]);
        hi[ch - k] = std::max(hi[ch - k], p[ch]);
      }
      p = ifs.map(rng.next() % ifs.size())(p);
    }
  }
}

}  // namespace

RendererParameter supersample_parameter() {
  return {"supersample", "2",
          "a pixel grid k times finer than the image (k x k cells per pixel): rounding errors (Eq. 53's delta) "
          "shrink k-fold for k^2 the work"};
}

Raster reduce_supersampled(Raster fine, int k, bool sum) {
  if (k == 1) return fine;
  Raster out;
  out.width = fine.width / k;
  out.height = fine.height / k;
  out.channel_names = fine.channel_names;
  out.color_model = fine.color_model;
  out.channels_in_unit_range = fine.channels_in_unit_range;
  out.pixel_size = fine.pixel_size * k;
  out.points = fine.points;
  const int ch = fine.channel_count();
  out.density.assign(std::size_t(out.width) * out.height, 0.0f);
  out.channels.assign(out.density.size() * ch, 0.0f);
  std::vector<double> moments(ch);
  for (int y = 0; y < out.height; ++y)
    for (int x = 0; x < out.width; ++x) {
      double d = 0.0, weight = 0.0;
      std::fill(moments.begin(), moments.end(), 0.0);
      for (int dy = 0; dy < k; ++dy)
        for (int dx = 0; dx < k; ++dx) {
          const std::size_t cell = std::size_t(y * k + dy) * fine.width + (x * k + dx);
          const double v = fine.density[cell];
          if (!(v > 0.0)) continue;
          d = sum ? d + v : std::max(d, v);
          const double w = sum ? v : 1.0;
          weight += w;
          for (int c = 0; c < ch; ++c) moments[c] += w * fine.channels[cell * ch + c];
        }
      const std::size_t pixel = std::size_t(y) * out.width + x;
      if (!(weight > 0.0)) continue;
      out.density[pixel] = std::max(static_cast<float>(d), std::numeric_limits<float>::denorm_min());
      for (int c = 0; c < ch; ++c) out.channels[pixel * ch + c] = static_cast<float>(moments[c] / weight);
    }
  return out;
}

PixelSpace make_pixel_space(const Ifs& ifs, const RenderOptions& options, const std::string& algorithm,
                            int supersample) {
  if (ifs.spatial_dims() != 2)
    throw InputError("algorithm '" + algorithm + "' works on the image plane, but system '" + ifs.name() +
                     "' is " + std::to_string(ifs.spatial_dims()) + "D in space (layout '" + ifs.layout().text() +
                     "'); use chaos, prr, string-rewriting, tsa or probabilistic-domain");
  ifs.require_attractor();
  PixelSpace s;
  if (supersample < 1 || static_cast<double>(options.width) * supersample > 65535.0 ||
      static_cast<double>(options.height) * supersample > 65535.0)
    throw InputError("algorithm '" + algorithm + "': supersample must be >= 1 and keep the grid within 65535 cells per side");
  RenderOptions fine = options;
  fine.width *= supersample;
  fine.height *= supersample;
  s.frame = fit_frame(ifs, fine);
  s.width = s.frame.width();
  s.height = s.frame.height();
  const int n = ifs.dim();
  s.channels = n - 2;
  const double scale = 1.0 / s.frame.pixel_size();
  AffineMap to_pixel(n);
  to_pixel.a(0, 0) = scale;
  to_pixel.a(1, 1) = -scale;
  to_pixel.b(0) = -s.frame.window().xmin * scale;
  to_pixel.b(1) = s.frame.window().ymax * scale;
  const AffineMap from_pixel = *to_pixel.inverse();
  for (const AffineMap& w : ifs.maps()) {
    const AffineMap m = to_pixel.compose(w).compose(from_pixel);
    s.maps.push_back({m.a(0, 0), m.a(0, 1), m.a(1, 0), m.a(1, 1), m.b(0), m.b(1), m});
    for (int r = 0; r < 2; ++r)
      for (int c = 2; c < n; ++c) s.spatial_reads_channels |= w.a(r, c) != 0.0;
  }
  channel_ranges_of(ifs, s.channel_lo, s.channel_hi);
  return s;
}

long long PixelSpace::map_pixel(std::size_t i, std::uint32_t pixel, const float* values, double* channels_out) const {
  const PixelMap& m = maps[i];
  const double x = static_cast<double>(pixel % static_cast<std::uint32_t>(width)) + 0.5;
  const double y = static_cast<double>(pixel / static_cast<std::uint32_t>(width)) + 0.5;
  if (channels == 0) return pixel_at(m.a * x + m.b * y + m.e, m.c * x + m.d * y + m.f);
  Point p{}, q;
  p[0] = x;
  p[1] = y;
  for (int c = 0; c < channels; ++c) p[2 + c] = values[c];
  m.map.apply(p.data(), q.data());
  for (int c = 0; c < channels; ++c) channels_out[c] = q[2 + c];
  return pixel_at(q[0], q[1]);
}

void report_progress(const RenderOptions& options, double fraction) {
  if (options.progress && !options.progress(std::clamp(fraction, 0.0, 1.0))) throw Cancelled();
}

ChannelCodec::ChannelCodec(const std::vector<double>& lo, const std::vector<double>& hi) : lo_(lo) {
  for (std::size_t c = 0; c < lo.size(); ++c) {
    const double range = hi[c] - lo[c];
    scale_.push_back(range > 0 ? kSteps / range : 0.0);
  }
}

std::vector<std::uint32_t> condensation_pixels(const Ifs& ifs, const Frame& frame) {
  const Condensation& c = ifs.condensation();
  std::vector<std::uint32_t> out;
  if (c.empty()) return out;
  const int w = frame.width(), h = frame.height();
  std::vector<std::uint8_t> mask(std::size_t(w) * h, 0);
  auto to_pixel = [&](const std::array<double, 2>& p) {
    Point q{};
    q[0] = p[0];
    q[1] = p[1];
    return frame.to_pixel(q);
  };
  auto mark = [&](double x, double y) {
    if (x >= 0.0 && x < w && y >= 0.0 && y < h) mask[std::size_t(y) * w + std::size_t(x)] = 1;
  };
  auto line = [&](std::array<double, 2> a, std::array<double, 2> b) {
    const auto pa = to_pixel(a), pb = to_pixel(b);
    const double length = std::hypot(pb[0] - pa[0], pb[1] - pa[1]);
    const int steps = static_cast<int>(std::ceil(length * 4.0)) + 1;
    for (int k = 0; k <= steps; ++k) {
      const double t = static_cast<double>(k) / steps;
      mark(pa[0] + t * (pb[0] - pa[0]), pa[1] + t * (pb[1] - pa[1]));
    }
  };
  for (const auto& path : c.polylines)
    for (std::size_t k = 0; k + 1 < path.size(); ++k) line(path[k], path[k + 1]);
  for (const auto& path : c.polygons) {
    std::vector<std::array<double, 2>> px;
    for (const auto& p : path) px.push_back(to_pixel(p));
    for (std::size_t k = 0; k < path.size(); ++k) line(path[k], path[(k + 1) % path.size()]);
    // Even-odd scanline fill at pixel centres.
    for (int y = 0; y < h; ++y) {
      const double yc = y + 0.5;
      std::vector<double> xs;
      for (std::size_t k = 0; k < px.size(); ++k) {
        const auto& a = px[k];
        const auto& b = px[(k + 1) % px.size()];
        if ((a[1] <= yc) != (b[1] <= yc)) xs.push_back(a[0] + (yc - a[1]) / (b[1] - a[1]) * (b[0] - a[0]));
      }
      std::sort(xs.begin(), xs.end());
      for (std::size_t k = 0; k + 1 < xs.size(); k += 2) {
        const int x0 = std::max(0, static_cast<int>(std::ceil(xs[k] - 0.5)));
        const int x1 = std::min(w - 1, static_cast<int>(std::floor(xs[k + 1] - 0.5)));
        for (int x = x0; x <= x1; ++x) mask[std::size_t(y) * w + x] = 1;
      }
    }
  }
  for (std::size_t i = 0; i < mask.size(); ++i)
    if (mask[i]) out.push_back(static_cast<std::uint32_t>(i));
  return out;
}

PixelScatter::PixelScatter(std::size_t pixels, int values, int workers, const ProgressCallback& poll)
    : values_(values), workers_(workers), merged_((pixels + 63) / 64, 0) {
  // A huge image's worker buffers run to gigabytes: they are faulted in on every core, within
  // reach of Ctrl-C (a fill without a check would keep it waiting), then zeroed.
  for (Worker& w : workers_) {
    resize_large(w.flag, pixels, poll);
    resize_large(w.touched, pixels + 1, poll);
    resize_large(w.sums, pixels * values, poll);
  }
}

void PixelScatter::take(Worker& w, std::size_t pixel, std::vector<std::uint64_t>& sums) {
  w.flag[pixel] = 0;
  std::uint64_t* s = w.sums.data() + pixel * values_;
  std::uint64_t* t = sums.data() + pixel * values_;
  for (int c = 0; c < values_; ++c) {
    t[c] += s[c];
    s[c] = 0;
  }
}

void PixelScatter::merge(std::vector<std::uint64_t>& sums, std::vector<std::uint32_t>& touched,
                         const ProgressCallback& poll) {
  std::size_t count = 0;
  for (const Worker& w : workers_) count += w.count;
  const std::size_t pixels = workers_.empty() ? 0 : workers_[0].flag.size();
  if (workers_.size() > 1 && count > pixels / 16) {
    // Most pixels touched (the first passes of DIA map every pixel): the workers' flags read
    // in runs of pixels on every core beat a walk of their lists in random order (one core,
    // cache misses). Runs in order give the list increasing, as below.
    constexpr std::size_t kRun = std::size_t(1) << 16;
    std::vector<std::vector<std::uint32_t>> runs((pixels + kRun - 1) / kRun);
    parallel_jobs(runs.size(), static_cast<int>(workers_.size()), [&](std::size_t run, int) {
      for (std::size_t p = run * kRun, end = std::min(pixels, p + kRun); p < end; ++p) {
        bool any = false;
        for (Worker& w : workers_) {
          if (!w.flag[p]) continue;
          any = true;
          take(w, p, sums);
        }
        if (any) runs[run].push_back(static_cast<std::uint32_t>(p));
      }
    }, poll);
    touched.clear();
    reserve_large(touched, count, poll);  // 1 GB at 16000^2: faulted in on every core
    for (const auto& run : runs) touched.insert(touched.end(), run.begin(), run.end());
    for (Worker& w : workers_) w.count = 0;
    return;
  }
  for (Worker& w : workers_) {
    for (std::size_t k = 0; k < w.count; ++k) {
      const std::uint32_t p = w.touched[k];
      merged_[p >> 6] |= std::uint64_t(1) << (p & 63);
      take(w, p, sums);
    }
    w.count = 0;
  }
  // The bitmap in order, a word at a time: the list comes out increasing.
  touched.clear();
  for (std::size_t word = 0; word < merged_.size(); ++word) {
    std::uint64_t bits = merged_[word];
    if (!bits) continue;
    merged_[word] = 0;
    while (bits) {
      touched.push_back(static_cast<std::uint32_t>(word * 64 + __builtin_ctzll(bits)));
      bits &= bits - 1;
    }
  }
}

PixelSet full_pixel_set(const PixelSpace& space, const std::vector<float>& values, int threads,
                        const ProgressCallback& progress) {
  // Faulted in on every core (resize_large: a 16000^2 grid is a 1 GB list), filled in jobs
  // that Ctrl-C reaches.
  PixelSet set;
  const std::size_t n = space.pixels(), channels = space.channels;
  resize_large(set.pixels, n, progress);
  if (channels) resize_large(set.values, n * channels, progress);
  constexpr std::size_t kChunk = std::size_t(1) << 22;
  parallel_jobs((n + kChunk - 1) / kChunk, threads, [&](std::size_t job, int) {
    const std::size_t begin = job * kChunk, end = std::min(n, begin + kChunk);
    for (std::size_t i = begin; i < end; ++i) set.pixels[i] = static_cast<std::uint32_t>(i);
    for (std::size_t i = begin * channels; i < end * channels; ++i) set.values[i] = values[i % channels];
  }, progress);
  return set;
}

PixelSet condensation_set(const Ifs& ifs, const PixelSpace& space) {
  PixelSet set;
  set.pixels = condensation_pixels(ifs, space.frame);
  const auto& c = ifs.condensation().channels;
  for (std::size_t i = 0; i < set.pixels.size(); ++i)
    for (double v : c) set.values.push_back(static_cast<float>(v));
  return set;
}

PixelSet hutchinson(const PixelSpace& space, const std::vector<SetImage>& terms, const PixelSet* extra,
                    PixelScatter& scatter, int threads, std::uint64_t& operations,
                    const ProgressCallback& progress) {
  if (scatter.values() != (space.channels ? 1 + space.channels : 0))
    throw std::logic_error("hutchinson: the scatter must come from set_scatter()");
  // Terms reading the same source are done together: each source pixel is visited once.
  std::vector<const PixelSet*> sources;
  std::vector<std::vector<std::size_t>> maps_of;
  for (const SetImage& t : terms) {
    const auto it = std::find(sources.begin(), sources.end(), t.source);
    if (it == sources.end()) {
      sources.push_back(t.source);
      maps_of.push_back({t.map});
    } else {
      maps_of[it - sources.begin()].push_back(t.map);
    }
    operations += t.source->pixels.size();
  }
  constexpr std::size_t kChunk = 1u << 15;
  struct Job {
    std::size_t source, begin, end;
  };
  std::vector<Job> jobs;
  for (std::size_t k = 0; k < sources.size(); ++k)
    for (std::size_t b = 0; b < sources[k]->pixels.size(); b += kChunk)
      jobs.push_back({k, b, std::min(sources[k]->pixels.size(), b + kChunk)});
  const int channels = space.channels;
  const ChannelCodec codec(space.channel_lo, space.channel_hi);
  parallel_jobs(jobs.size(), threads, [&](std::size_t index, int worker) {
    const Job& job = jobs[index];
    PixelScatter::Writer out = scatter.writer(worker);
    const PixelSet& source = *sources[job.source];
    const std::vector<std::size_t>& maps = maps_of[job.source];
    std::uint64_t codes[kMaxDim + 1];
    codes[0] = 1;
    const double w = space.width, h = space.height;
    const auto width = static_cast<std::uint32_t>(space.width);
    // The spatial rows of the maps in locals: the byte stores of the scatter may alias
    // anything the compiler cannot see is private, and would force a reload per pixel.
    struct Coefficients {
      double a, b, c, d, e, f;
    };
    Coefficients local[64];
    const int count = static_cast<int>(std::min<std::size_t>(maps.size(), 64));
    for (int i = 0; i < count; ++i) {
      const PixelMap& m = space.maps[maps[i]];
      local[i] = {m.a, m.b, m.c, m.d, m.e, m.f};
    }
    // Pixels are increasing: follow the row instead of dividing.
    std::uint32_t row = source.pixels[job.begin] / width, row_start = row * width;
    for (std::size_t k = job.begin; k < job.end; ++k) {
      const std::uint32_t pixel = source.pixels[k];
      while (pixel >= row_start + width) {
        ++row;
        row_start += width;
      }
      const double x = pixel - row_start + 0.5, y = row + 0.5;
      if (!channels && maps.size() <= 64) {
        for (int i = 0; i < count; ++i) {
          const Coefficients& m = local[i];
          const double tx = m.a * x + m.b * y + m.e, ty = m.c * x + m.d * y + m.f;
          if (tx >= 0.0 && tx < w && ty >= 0.0 && ty < h)
            out.touch(static_cast<std::uint32_t>(ty) * width + static_cast<std::uint32_t>(tx));
        }
        continue;
      }
      Point p{}, q;
      p[0] = x;
      p[1] = y;
      for (int c = 0; c < channels; ++c) p[2 + c] = source.values[k * channels + c];
      for (std::size_t i : maps) {
        space.maps[i].map.apply(p.data(), q.data());
        const long long target = space.pixel_at(q[0], q[1]);
        if (target < 0) continue;
        for (int c = 0; c < channels; ++c) codes[1 + c] = codec.encode(c, q[2 + c]);
        out.add(static_cast<std::uint32_t>(target), codes);
      }
    }
  }, progress);
  if (extra) {
    std::uint64_t codes[kMaxDim + 1];
    codes[0] = 1;
    for (std::size_t k = 0; k < extra->pixels.size(); ++k) {
      for (int c = 0; c < channels; ++c) codes[1 + c] = codec.encode(c, extra->values[k * channels + c]);
      scatter.add(0, extra->pixels[k], codes);
    }
  }
  // The merge of a 16000^2 grid's first passes takes seconds: Ctrl-C hears it too.
  const ProgressCallback poll = progress_range(progress, 1.0, 1.0);
  std::vector<std::uint64_t> sums;
  assign_large(sums, channels ? space.pixels() * (1 + channels) : 0, std::uint64_t(0), poll);
  PixelSet out;
  scatter.merge(sums, out.pixels, poll);
  for (std::size_t k = 0; k < out.pixels.size() && channels; ++k) {
    poll_now_and_then(k, poll);
    const std::uint32_t p = out.pixels[k];
    for (int c = 0; c < channels; ++c) {
      const double mean = static_cast<double>(sums[std::size_t(p) * (1 + channels) + 1 + c]) /
                          static_cast<double>(sums[std::size_t(p) * (1 + channels)]);
      out.values.push_back(static_cast<float>(codec.decode(c, mean)));
    }
  }
  return out;
}

Raster empty_raster(const Ifs& ifs, const PixelSpace& space) {
  Raster r;
  describe_channels(ifs, r);
  r.width = space.width;
  r.height = space.height;
  r.pixel_size = space.frame.pixel_size();
  r.density.assign(space.pixels(), 0.0f);
  r.channels.assign(space.pixels() * space.channels, 0.0f);
  return r;
}

void paint_set(const PixelSet& set, float value, Raster& raster) {
  const int channels = raster.channel_count();
  for (std::size_t k = 0; k < set.pixels.size(); ++k) {
    const std::uint32_t p = set.pixels[k];
    raster.density[p] = value;
    for (int c = 0; c < channels; ++c) raster.channels[std::size_t(p) * channels + c] = set.values[k * channels + c];
  }
}

}  // namespace ifsforge
