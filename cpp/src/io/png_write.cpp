// PNG writing in parallel strips: the rows are quantised and filtered on every core, then
// deflated strip by strip, each strip primed with the 32 KB of filtered bytes before it (as
// pigz does) and ended on a byte boundary, so the strips join into one zlib stream. The
// strips are cut by size, never by thread count: the file is the same for any --threads.
#include <zlib.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <optional>
#include <stdexcept>
#include <vector>

#include "ifsforge/core/error.h"
#include "ifsforge/core/pages.h"
#include "ifsforge/core/parallel.h"
#include "ifsforge/io/atomic_file.h"
#include "ifsforge/io/png.h"

namespace ifsforge {
namespace {

constexpr std::size_t kStripBytes = 256 * 1024;  ///< filtered bytes per deflate job
constexpr std::size_t kWindow = 32 * 1024;       ///< deflate's window: the dictionary of a strip
constexpr int kLevel = 6;                        ///< zlib's default, as libpng's

void put32(std::vector<unsigned char>& out, std::uint32_t v) {
  for (int shift = 24; shift >= 0; shift -= 8) out.push_back(static_cast<unsigned char>(v >> shift));
}

std::uint32_t chunk_crc(const char* type, const unsigned char* data, std::size_t size) {
  uLong crc = crc32(crc32(0L, Z_NULL, 0), reinterpret_cast<const unsigned char*>(type), 4);
  if (size > 0) crc = crc32_z(crc, data, size);
  return static_cast<std::uint32_t>(crc);
}

/// One chunk: length, type, data, CRC of type and data (`crc` when already computed).
void write_chunk(std::FILE* file, const char* type, const unsigned char* data, std::size_t size,
                 std::optional<std::uint32_t> crc = std::nullopt) {
  std::vector<unsigned char> head;
  put32(head, static_cast<std::uint32_t>(size));
  head.insert(head.end(), type, type + 4);
  std::vector<unsigned char> tail;
  put32(tail, crc ? *crc : chunk_crc(type, data, size));
  std::fwrite(head.data(), 1, head.size(), file);
  if (size > 0) std::fwrite(data, 1, size, file);
  std::fwrite(tail.data(), 1, tail.size(), file);
}

/// A sample in [0, 1] (NaN as 0) as an integer in [0, top].
inline int quantise(float sample, double top) {
  const double v = std::min(std::max(0.0, double(sample)), 1.0);  // max(0, NaN) is 0
  return static_cast<int>(v * top + 0.5);
}

/// Row y's samples as bytes (16-bit big-endian, as PNG stores them); branch-free loops, which
/// the compiler vectorises.
void quantise_row(const Image& image, int y, int bit_depth, unsigned char* row) {
  const std::size_t samples = std::size_t(image.width) * image.channels;
  const float* src = &image.pixels[std::size_t(y) * samples];
  if (bit_depth == 8) {
    for (std::size_t i = 0; i < samples; ++i) row[i] = static_cast<unsigned char>(quantise(src[i], 255.0));
    return;
  }
  for (std::size_t i = 0; i < samples; ++i) {
    const unsigned q = quantise(src[i], 65535.0);
    row[2 * i] = static_cast<unsigned char>(q >> 8);
    row[2 * i + 1] = static_cast<unsigned char>(q & 0xFF);
  }
}

int paeth(int a, int b, int c) {
  const int p = a + b - c, pa = std::abs(p - a), pb = std::abs(p - b), pc = std::abs(p - c);
  return pa <= pb && pa <= pc ? a : pb <= pc ? b : c;
}

/// Row filtered by PNG filter `f` (0 none, 1 sub, 2 up, 3 average, 4 Paeth) into `t`; returns
/// the sum of its absolute signed bytes. `above` is the row above (zeros for the first row).
/// One loop per filter, without branches inside: the compiler vectorises all but Paeth.
template <int f>
std::uint64_t filter_with(const unsigned char* row, const unsigned char* above, std::size_t size, int bpp,
                          unsigned char* t) {
  const auto predict = [](int a, int b, int c) {
    if constexpr (f == 1) return a;
    if constexpr (f == 2) return b;
    if constexpr (f == 3) return (a + b) / 2;
    if constexpr (f == 4) return paeth(a, b, c);
    return 0;
  };
  std::uint64_t sum = 0;
  const std::size_t lead = std::min(size, std::size_t(bpp));
  for (std::size_t i = 0; i < lead; ++i) {  // no left neighbour
    t[i] = static_cast<unsigned char>(row[i] - predict(0, above[i], 0));
    sum += static_cast<std::uint32_t>(std::abs(static_cast<int>(static_cast<signed char>(t[i]))));
  }
  for (std::size_t i = lead; i < size; ++i) {
    t[i] = static_cast<unsigned char>(row[i] - predict(row[i - bpp], above[i], above[i - bpp]));
    sum += static_cast<std::uint32_t>(std::abs(static_cast<int>(static_cast<signed char>(t[i]))));
  }
  return sum;
}

/// The filtered row (type byte first) with the smallest sum of absolute signed bytes over the
/// five PNG filters: libpng's default heuristic for non-palette images.
void filter_row(const unsigned char* row, const unsigned char* above, std::size_t size, int bpp,
                unsigned char* out, std::array<std::vector<unsigned char>, 5>& trial) {
  for (auto& t : trial) t.resize(size);
  const std::uint64_t sums[5] = {filter_with<0>(row, above, size, bpp, trial[0].data()),
                                 filter_with<1>(row, above, size, bpp, trial[1].data()),
                                 filter_with<2>(row, above, size, bpp, trial[2].data()),
                                 filter_with<3>(row, above, size, bpp, trial[3].data()),
                                 filter_with<4>(row, above, size, bpp, trial[4].data())};
  const int best = static_cast<int>(std::min_element(sums, sums + 5) - sums);  // the first of equals
  out[0] = static_cast<unsigned char>(best);
  std::copy(trial[best].begin(), trial[best].end(), out + 1);
}

/// The raw deflate of filtered[begin, end), primed with the window before it; the last strip
/// finishes the stream, the others end with a sync flush (a byte boundary).
std::vector<unsigned char> deflate_strip(const LargeVector<unsigned char>& filtered, std::size_t begin,
                                         std::size_t end) {
  z_stream z{};
  if (deflateInit2(&z, kLevel, Z_DEFLATED, -15, 8, Z_DEFAULT_STRATEGY) != Z_OK)
    throw std::bad_alloc();
  struct End {
    z_stream* z;
    ~End() { deflateEnd(z); }
  } end_guard{&z};
  if (begin > 0) {
    const std::size_t from = begin > kWindow ? begin - kWindow : 0;
    deflateSetDictionary(&z, filtered.data() + from, static_cast<uInt>(begin - from));
  }
  // Room for the worst case, left uninitialised: deflate writes only the first fifth or so of
  // it, and only those pages are ever touched (zeroing it all would fault in every page).
  const std::size_t room = deflateBound(&z, end - begin) + 16;
  const std::unique_ptr<unsigned char[]> out(new unsigned char[room]);
  z.next_in = const_cast<unsigned char*>(filtered.data() + begin);
  z.avail_in = static_cast<uInt>(end - begin);
  z.next_out = out.get();
  z.avail_out = static_cast<uInt>(room);
  const bool last = end == filtered.size();
  const int status = deflate(&z, last ? Z_FINISH : Z_SYNC_FLUSH);
  if (status != (last ? Z_STREAM_END : Z_OK) || z.avail_in != 0) throw std::runtime_error("deflate failed");
  return std::vector<unsigned char>(out.get(), out.get() + (room - z.avail_out));
}

}  // namespace

void write_png(const std::string& path, const Image& image, int bit_depth) {
  if (bit_depth != 8 && bit_depth != 16) throw InputError("PNG bit depth must be 8 or 16");
  if (image.channels < 1 || image.channels > 4) throw InputError("PNG images have 1 to 4 channels");
  if (image.width < 1 || image.height < 1) throw InputError("cannot write an empty image");
  std::string extension = path.size() >= 4 ? path.substr(path.size() - 4) : std::string();
  for (char& c : extension) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (extension != ".png")
    throw FileError("cannot write '" + path + "': images are written as PNG only; give a name ending in .png");
  AtomicFile out(path);

  // Filtering: each job quantises its rows and the row above them (filters read it).
  const int bpp = image.channels * bit_depth / 8;
  const std::size_t row_bytes = std::size_t(image.width) * bpp, line = row_bytes + 1;
  const int rows_per_job = static_cast<int>(std::max<std::size_t>(1, kStripBytes / line));
  const std::size_t jobs = (std::size_t(image.height) + rows_per_job - 1) / rows_per_job;
  LargeVector<unsigned char> filtered(line * image.height);
  parallel_jobs(jobs, 0, [&](std::size_t job, int) {
    std::vector<unsigned char> above(row_bytes, 0), row(row_bytes);
    std::array<std::vector<unsigned char>, 5> trial;
    const int first = static_cast<int>(job) * rows_per_job;
    const int last = std::min(image.height, first + rows_per_job);
    if (first > 0) quantise_row(image, first - 1, bit_depth, above.data());
    for (int y = first; y < last; ++y) {
      quantise_row(image, y, bit_depth, row.data());
      filter_row(row.data(), above.data(), row_bytes, bpp, &filtered[line * y], trial);  // above: zeros at y = 0
      std::swap(row, above);
    }
  });

  // Deflate strip by strip (cut by size, so the bytes never depend on the thread count); each
  // strip is one IDAT chunk, the zlib header leading the first and the Adler-32 in a last one.
  std::vector<std::vector<unsigned char>> strips(jobs);
  std::vector<uLong> adlers(jobs);
  std::vector<std::uint32_t> crcs(jobs);
  const auto strip_end = [&](std::size_t job) { return std::min(filtered.size(), (job + 1) * rows_per_job * line); };
  parallel_jobs(jobs, 0, [&](std::size_t job, int) {
    const std::size_t begin = job * rows_per_job * line, end = strip_end(job);
    strips[job] = deflate_strip(filtered, begin, end);
    if (job == 0) strips[job].insert(strips[job].begin(), {0x78, 0x9C});  // deflate, 32 KB window, level 6
    adlers[job] = adler32_z(adler32(0L, Z_NULL, 0), filtered.data() + begin, end - begin);
    crcs[job] = chunk_crc("IDAT", strips[job].data(), strips[job].size());
  });
  uLong adler = adler32(0L, Z_NULL, 0);
  for (std::size_t job = 0; job < jobs; ++job)
    adler = adler32_combine(adler, adlers[job], static_cast<z_off_t>(strip_end(job) - job * rows_per_job * line));
  std::vector<unsigned char> trailer;
  put32(trailer, static_cast<std::uint32_t>(adler));

  static const unsigned char kSignature[] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
  static const unsigned char kColorTypes[] = {0, 4, 2, 6};  // gray, gray+alpha, RGB, RGBA
  std::vector<unsigned char> ihdr;
  put32(ihdr, static_cast<std::uint32_t>(image.width));
  put32(ihdr, static_cast<std::uint32_t>(image.height));
  ihdr.insert(ihdr.end(), {static_cast<unsigned char>(bit_depth), kColorTypes[image.channels - 1], 0, 0, 0});
  std::FILE* file = out.file();
  std::fwrite(kSignature, 1, sizeof kSignature, file);
  write_chunk(file, "IHDR", ihdr.data(), ihdr.size());
  for (std::size_t job = 0; job < jobs; ++job) write_chunk(file, "IDAT", strips[job].data(), strips[job].size(), crcs[job]);
  write_chunk(file, "IDAT", trailer.data(), trailer.size());
  write_chunk(file, "IEND", nullptr, 0);
  out.commit();
}

}  // namespace ifsforge
