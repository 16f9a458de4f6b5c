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
  png_read_png(png, info, PNG_TRANSFORM_EXPAND | PNG_TRANSFORM_PACKING, nullptr);
  const int width = static_cast<int>(png_get_image_width(png, info));
  const int height = static_cast<int>(png_get_image_height(png, info));
  const int channels = png_get_channels(png, info);
  const int depth = png_get_bit_depth(png, info);
  png_bytepp rows = png_get_rows(png, info);
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
