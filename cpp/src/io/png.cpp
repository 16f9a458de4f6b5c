#include "ifsforge/io/png.h"

#include <cctype>
#include <png.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <memory>
#include <vector>

#include "ifsforge/core/error.h"
#include "ifsforge/core/memory.h"
#include "ifsforge/io/atomic_file.h"

namespace ifsforge {
namespace {

// libpng reports errors through a callback; throwing from it unwinds through libpng's
// frames, which is safe on x86-64 Linux where C code carries unwind tables.
[[noreturn]] void on_error(png_structp png, png_const_charp message) {
  const auto* where = static_cast<const std::string*>(png_get_error_ptr(png));
  throw InputError("'" + *where + "': " + message);
}
void on_warning(png_structp, png_const_charp) {}

}  // namespace

Image read_png(const std::string& path) {
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> file(std::fopen(path.c_str(), "rb"), std::fclose);
  if (!file) throw FileError("cannot read '" + path + "': " + std::strerror(errno));
  unsigned char signature[8] = {};
  if (std::fread(signature, 1, 8, file.get()) != 8 || png_sig_cmp(signature, 0, 8) != 0)
    throw InputError("'" + path + "' is not a PNG file");
  png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, const_cast<std::string*>(&path),
                                           on_error, on_warning);
  png_infop info = png_create_info_struct(png);
  struct Cleanup {
    png_structp* png;
    png_infop* info;
    ~Cleanup() { png_destroy_read_struct(png, info, nullptr); }
  } cleanup{&png, &info};
  png_init_io(png, file.get());
  png_set_sig_bytes(png, 8);
  // The header's size is checked against the budget before a row is inflated: a few hundred
  // bytes of PNG may declare 10^12 pixels, and a small file may inflate to gigabytes.
  png_set_user_limits(png, 1u << 20, 1u << 20);
  png_read_info(png, info);
  png_set_expand(png);
  png_set_packing(png);
  png_set_interlace_handling(png);
  png_read_update_info(png, info);
  const int width = static_cast<int>(png_get_image_width(png, info));
  const int height = static_cast<int>(png_get_image_height(png, info));
  const int channels = png_get_channels(png, info);
  const int depth = png_get_bit_depth(png, info);
  const double row_bytes = static_cast<double>(png_get_rowbytes(png, info));
  check_memory(row_bytes * height + 4.0 * width * height * channels,
               "reading '" + path + "' (" + std::to_string(width) + "x" + std::to_string(height) + " pixels)");
  std::vector<png_byte> data(static_cast<std::size_t>(row_bytes) * height);
  std::vector<png_bytep> rows(height);
  for (int y = 0; y < height; ++y) rows[y] = data.data() + std::size_t(y) * std::size_t(row_bytes);
  png_read_image(png, rows.data());
  Image image(width, height, channels);
  const double top = depth == 16 ? 65535.0 : 255.0;
  for (int y = 0; y < height; ++y)
    for (std::size_t i = 0; i < std::size_t(width) * channels; ++i) {
      const unsigned v = depth == 16 ? (rows[y][2 * i] << 8) | rows[y][2 * i + 1] : rows[y][i];
      image.pixels[std::size_t(y) * width * channels + i] = static_cast<float>(v / top);
    }
  return image;
}

}  // namespace ifsforge
