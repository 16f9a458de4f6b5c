#include "ifsforge/pifs/planes.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <vector>

#include "ifsforge/core/error.h"
#include "ifsforge/core/pages.h"
#include "ifsforge/core/parallel.h"

namespace ifsforge {
namespace {

float level(float v) { return std::round(std::clamp(v, 0.f, 1.f) * 255.f); }

/// Full-range YCbCr of 8-bit levels (JPEG's matrix, the seed's YUV of Step 1) and back.
void to_ycc(float v[3]) {
  const float r = v[0], g = v[1], b = v[2];
  v[0] = 0.299f * r + 0.587f * g + 0.114f * b;
  v[1] = 128.f - 0.168736f * r - 0.331264f * g + 0.5f * b;
  v[2] = 128.f + 0.5f * r - 0.418688f * g - 0.081312f * b;
}

void to_rgb(float v[3]) {
  const float Y = v[0], cb = v[1] - 128.f, cr = v[2] - 128.f;
  v[0] = Y + 1.402f * cr;
  v[1] = Y - 0.344136f * cb - 0.714136f * cr;
  v[2] = Y + 1.772f * cb;
}

/// The mean over rows of per-row sums, summed in row order: the same on any number of threads.
double mean_of_rows(std::size_t rows, double count, int threads, const std::function<double(std::size_t)>& row_sum,
                    const ProgressCallback& progress = nullptr) {
  std::vector<double> sums(rows);
  parallel_jobs(rows, threads, [&](std::size_t row, int) { sums[row] = row_sum(row); }, progress);
  double total = 0;
  for (double s : sums) total += s;
  return total / count;
}

}  // namespace

PifsRaster plane_raster(int width, int height, float value) {
  PifsRaster p;
  p.width = width;
  p.height = height;
  assign_large(p.values, std::size_t(width) * height, value);  // huge pages, faulted in on every core
  return p;
}

std::vector<std::array<int, 2>> plane_sizes(const Image& image, PifsColor color) {
  const int w = image.width, h = image.height, c = image.channels;
  const bool half = color == PifsColor::YCbCr420 && c >= 3;
  std::vector<std::array<int, 2>> sizes;
  for (int k = 0; k < c; ++k)
    sizes.push_back(half && (k == 1 || k == 2) ? std::array<int, 2>{(w + 1) / 2, (h + 1) / 2} : std::array<int, 2>{w, h});
  return sizes;
}

int conversion_rows(const Image& image, PifsColor color) {
  return color == PifsColor::YCbCr420 && image.channels >= 3 ? (image.height + 1) / 2 : image.height;
}

void convert_rows(const Image& image, PifsColor color, std::vector<PifsRaster>& planes, int begin, int end) {
  const int w = image.width, h = image.height, c = image.channels;
  const bool ycc = color != PifsColor::Direct && c >= 3, half = ycc && color == PifsColor::YCbCr420;
  // The levels of pixel (x, y), converted to JPEG's full-range YCbCr (the seed's YUV, Step 1).
  const auto pixel = [&](int x, int y, float v[4]) {
    for (int k = 0; k < c; ++k) v[k] = level(image.at(x, y, k));
    if (ycc) to_ycc(v);
  };
  // Each pixel on its own: any split of the rows gives the same planes. Half-size chroma is
  // averaged over 2×2 as it is converted (the seed's Step 2; odd edges average what exists),
  // never held at full size.
  float v[4];
  for (int y = begin; y < end; ++y) {
    if (!half) {
      for (int x = 0; x < w; ++x) {
        pixel(x, y, v);
        for (int k = 0; k < c; ++k) planes[k].row(y)[x] = v[k];
      }
      continue;
    }
    const int y1 = std::min(2 * y + 2, h);
    for (int x = 0; x < (w + 1) / 2; ++x) {
      const int x1 = std::min(2 * x + 2, w);
      float cb = 0, cr = 0;
      for (int j = 2 * y; j < y1; ++j)
        for (int i = 2 * x; i < x1; ++i) {
          pixel(i, j, v);
          cb += v[1];
          cr += v[2];
          planes[0].row(j)[i] = v[0];
          if (c == 4) planes[3].row(j)[i] = v[3];
        }
      const float count = float((y1 - 2 * y) * (x1 - 2 * x));
      planes[1].row(y)[x] = cb / count;
      planes[2].row(y)[x] = cr / count;
    }
  }
}

void pad_rows(PifsRaster& padded, int width, int height, int begin, int end) {
  // Row y < height keeps its first `width` samples, and a row below copies row height − 1's;
  // only those are read, so the rows can be padded in any order, side by side.
  for (int y = begin; y < end; ++y) {
    const float* src = padded.row(std::min(y, height - 1));
    float* dst = padded.row(y);
    for (int x = y < height ? width : 0; x < padded.width; ++x) dst[x] = src[std::min(x, width - 1)];
  }
}

int pass_threads(int threads, double pixels) {
  constexpr double kPixelsPerThread = 1 << 20;
  return std::max(1, std::min(resolve_threads(threads), int(pixels / kPixelsPerThread)));
}

Image planes_to_image(const std::vector<PifsRaster>& planes, int channels, PifsColor color, int width,
                      int height, int threads) {
  const bool ycc = color != PifsColor::Direct && channels >= 3;
  Image image(width, height, channels);
  // Each pixel on its own: row bands on any number of threads give the same image.
  parallel_jobs(std::size_t(height), pass_threads(threads, double(width) * height * channels), [&](std::size_t row, int) {
    const int y = int(row);
    for (int x = 0; x < width; ++x) {
      float v[4];
      for (int k = 0; k < channels; ++k) v[k] = planes[k].row(y)[x];
      if (ycc) to_rgb(v);
      for (int k = 0; k < channels; ++k) image.at(x, y, k) = std::clamp(v[k] / 255.f, 0.f, 1.f);
    }
  });
  return image;
}

double chroma_halving_error(const Image& image, int threads, const ProgressCallback& progress) {
  const int w = image.width, h = image.height;
  if (image.channels < 3) return 0;
  // Each pair of rows on its own: the 2×2 cell's chroma averaged as convert_rows does, every
  // pixel rebuilt from its own Y and the cell's chroma.
  return mean_of_rows(std::size_t((h + 1) / 2), 3.0 * w * h, threads, [&](std::size_t row) {
    const int y0 = 2 * int(row), y1 = std::min(y0 + 2, h);
    double sum = 0;
    for (int x0 = 0; x0 < w; x0 += 2) {
      const int x1 = std::min(x0 + 2, w), count = (y1 - y0) * (x1 - x0);
      float ycc[4][3], cb = 0, cr = 0;
      int n = 0;
      for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x, ++n) {
          for (int k = 0; k < 3; ++k) ycc[n][k] = level(image.at(x, y, k));
          to_ycc(ycc[n]);
          cb += ycc[n][1];
          cr += ycc[n][2];
        }
      n = 0;
      for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x, ++n) {
          float v[3] = {ycc[n][0], cb / count, cr / count};
          to_rgb(v);
          for (int k = 0; k < 3; ++k) {
            const double d = double(v[k]) - level(image.at(x, y, k));
            sum += d * d;
          }
        }
    }
    return sum;
  }, progress);
}

double squared_error(const Image& a, const Image& b, int threads) {
  if (a.width != b.width || a.height != b.height || a.channels != b.channels)
    throw InputError("squared_error: the images differ in size");
  return mean_of_rows(std::size_t(a.height), double(a.width) * a.height * a.channels, threads, [&](std::size_t row) {
    double sum = 0;
    for (int x = 0; x < a.width; ++x)
      for (int k = 0; k < a.channels; ++k) {
        const double d = 255.0 * (double(a.at(x, int(row), k)) - b.at(x, int(row), k));
        sum += d * d;
      }
    return sum;
  });
}

PifsRaster resample_area(const PifsRaster& p, int width, int height) {
  if (width == p.width && height == p.height) return p;
  // Separable box filter: output pixel i covers [i·f, (i+1)·f) of the source.
  auto weights = [](int from, int to) {
    std::vector<std::vector<std::pair<int, float>>> w(to);
    const double f = double(from) / to;
    for (int i = 0; i < to; ++i) {
      const double a = i * f, b = (i + 1) * f;
      if (f <= 1) {  // upsampling: linear between sample centres
        const double c = std::clamp((i + 0.5) * f - 0.5, 0.0, double(from - 1));
        const int k = std::min(int(c), from - 1);
        const double t = c - k;
        w[i].push_back({k, float(1 - t)});
        if (k + 1 < from) w[i].push_back({k + 1, float(t)});
        continue;
      }
      for (int k = int(a); k < std::min(from, int(std::ceil(b))); ++k) {
        const double o = std::min(b, double(k + 1)) - std::max(a, double(k));
        if (o > 0) w[i].push_back({k, float(o / f)});
      }
    }
    return w;
  };
  const auto wx = weights(p.width, width), wy = weights(p.height, height);
  PifsRaster mid = plane_raster(width, p.height);
  for (int y = 0; y < p.height; ++y)
    for (int x = 0; x < width; ++x) {
      float s = 0;
      for (auto [k, w] : wx[x]) s += w * p.row(y)[k];
      mid.row(y)[x] = s;
    }
  PifsRaster out = plane_raster(width, height);
  for (int y = 0; y < height; ++y)
    for (auto [k, w] : wy[y]) {
      const float* src = mid.row(k);
      float* dst = out.row(y);
      for (int x = 0; x < width; ++x) dst[x] += w * src[x];
    }
  return out;
}

}  // namespace ifsforge
