#include "ifsforge/pifs/code_bytes.h"

#include <cstdio>
#include <cstring>

#include "ifsforge/core/error.h"
#include "ifsforge/pifs/plane_coding.h"
#include "ifsforge/pifs/residual.h"

namespace ifsforge {
namespace {

constexpr char kMagic[4] = {'P', 'I', 'F', 'S'};

std::uint32_t crc32(const std::uint8_t* data, std::size_t size) {
  static std::uint32_t table[256] = {0};
  static const bool ready = [] {
    for (std::uint32_t i = 0; i < 256; ++i) {
      std::uint32_t c = i;
      for (int k = 0; k < 8; ++k) c = (c & 1) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
      table[i] = c;
    }
    return true;
  }();
  (void)ready;
  std::uint32_t c = 0xFFFFFFFFu;
  for (std::size_t i = 0; i < size; ++i) c = table[(c ^ data[i]) & 0xFF] ^ (c >> 8);
  return c ^ 0xFFFFFFFFu;
}

void put_varint(std::vector<std::uint8_t>& out, std::uint64_t v) {
  while (v >= 0x80) {
    out.push_back(std::uint8_t(v | 0x80));
    v >>= 7;
  }
  out.push_back(std::uint8_t(v));
}

struct Reader {
  const std::uint8_t* data;
  std::size_t size, pos = 0;
  const std::string& where;
  std::uint8_t byte() {
    if (pos >= size) throw InputError(where + ": truncated (header ends early)");
    return data[pos++];
  }
  std::uint64_t varint() {
    std::uint64_t v = 0;
    for (int shift = 0; shift < 64; shift += 7) {
      const std::uint8_t b = byte();
      v |= std::uint64_t(b & 0x7F) << shift;
      if (!(b & 0x80)) return v;
    }
    throw InputError(where + ": corrupt (bad number in the header)");
  }
};

int plane_count(int channels, PifsColor) { return channels; }

std::vector<std::uint8_t> header(const PifsCode& code, const std::vector<PifsStreamSizes>& sizes) {
  std::vector<std::uint8_t> out(kMagic, kMagic + 4);
  out.push_back(std::uint8_t(kPifsVersion));
  out.push_back(std::uint8_t(code.channels));
  out.push_back(std::uint8_t(code.color));
  out.push_back(std::uint8_t(code.min_log));
  out.push_back(std::uint8_t(code.max_log));
  out.push_back(std::uint8_t(code.s_bits));
  out.push_back(std::uint8_t(code.dc_step));
  put_varint(out, std::uint64_t(code.width));
  put_varint(out, std::uint64_t(code.height));
  for (const PifsStreamSizes& s : sizes) {
    put_varint(out, s.transforms);
    put_varint(out, std::uint64_t(s.residual_step));
    if (s.residual_step) put_varint(out, s.residual);
  }
  return out;
}

struct Streams {
  std::vector<std::vector<std::uint8_t>> bytes;  ///< per plane: transforms, then residual
  std::vector<PifsStreamSizes> sizes;
};

Streams streams(const PifsCode& code) {
  Streams s;
  for (const PifsPlane& p : code.planes) {
    s.bytes.push_back(encode_plane(code, p));
    s.bytes.push_back(encode_residual(p.residual, p.width, p.height));
    s.sizes.push_back({s.bytes[s.bytes.size() - 2].size(), p.residual.step, s.bytes.back().size()});
  }
  return s;
}

}  // namespace

std::vector<std::uint8_t> pifs_to_bytes(const PifsCode& code) {
  const Streams s = streams(code);
  std::vector<std::uint8_t> out = header(code, s.sizes);
  for (const auto& b : s.bytes) out.insert(out.end(), b.begin(), b.end());
  const std::uint32_t c = crc32(out.data(), out.size());
  for (int i = 0; i < 4; ++i) out.push_back(std::uint8_t(c >> (8 * i)));
  return out;
}

std::size_t pifs_header_size(const PifsCode& code) {
  return header(code, streams(code).sizes).size();
}

std::size_t pifs_residual_bytes(const PifsCode& code) {
  std::size_t total = 0;
  for (const PifsStreamSizes& s : streams(code).sizes) total += s.residual;
  return total;
}

std::size_t pifs_file_size(const PifsCode& code, const std::vector<PifsStreamSizes>& sizes) {
  std::size_t total = header(code, sizes).size() + 4;  // the checksum
  for (const PifsStreamSizes& s : sizes) total += s.transforms + s.residual;
  return total;
}

PifsCode pifs_from_bytes(const std::uint8_t* data, std::size_t size, const std::string& where) {
  if (size < 4 || std::memcmp(data, kMagic, 4) != 0) throw InputError(where + ": not a PIFS file (no 'PIFS' magic)");
  Reader r{data, size, 4, where};
  const int version = r.byte();
  if (version < 1 || version > kPifsVersion)
    throw InputError(where + ": PIFS version " + std::to_string(version) + " is not supported (this reads " +
                     std::to_string(kPifsVersion) + ")");
  if (size < 4 + 1 + 4) throw InputError(where + ": truncated");
  const std::uint32_t stored = std::uint32_t(data[size - 4]) | std::uint32_t(data[size - 3]) << 8 |
                               std::uint32_t(data[size - 2]) << 16 | std::uint32_t(data[size - 1]) << 24;
  // The checksum first: a cut or altered file is named as such before any field is trusted.
  if (crc32(data, size - 4) != stored) throw InputError(where + ": corrupt or truncated (checksum mismatch)");
  r.size = size - 4;
  PifsCode code;
  code.channels = r.byte();
  const int color = r.byte();
  code.min_log = r.byte();
  code.max_log = r.byte();
  code.s_bits = r.byte();
  code.dc_step = r.byte();
  const std::uint64_t w = r.varint(), h = r.varint();
  if (code.channels < 1 || code.channels > 4 || color > 2 || code.min_log < 1 || code.max_log > 8 ||
      code.min_log > code.max_log || code.s_bits < 2 || code.s_bits > 8 || code.dc_step < 1 || code.dc_step > 64 ||
      w < 1 || h < 1 || w > 32768 || h > 32768)
    throw InputError(where + ": corrupt (header field out of range)");
  code.color = PifsColor(color);
  code.width = int(w);
  code.height = int(h);
  const int planes = plane_count(code.channels, code.color);
  // Version 1 has no residual layer: only each plane's transform bytes.
  std::vector<std::uint64_t> lengths(planes), steps(planes, 0), residuals(planes, 0);
  std::uint64_t total = 0;
  for (int k = 0; k < planes; ++k) {
    total += (lengths[k] = r.varint());
    if (version < 2) continue;
    steps[k] = r.varint();
    if (steps[k] > 65535) throw InputError(where + ": corrupt (residual step out of range)");
    if (steps[k]) total += (residuals[k] = r.varint());
  }
  if (total != r.size - r.pos) throw InputError(where + ": corrupt (plane sizes do not match the file)");
  for (int k = 0; k < planes; ++k) {
    const bool half = code.halved(std::size_t(k));
    const int pw = half ? (code.width + 1) / 2 : code.width, ph = half ? (code.height + 1) / 2 : code.height;
    const std::string plane = where + " (plane " + std::to_string(k + 1) + ")";
    code.planes.push_back(decode_plane(code, pw, ph, data + r.pos, std::size_t(lengths[k]), plane));
    r.pos += std::size_t(lengths[k]);
    code.planes.back().residual = decode_residual(int(steps[k]), pw, ph, data + r.pos, std::size_t(residuals[k]), plane);
    r.pos += std::size_t(residuals[k]);
  }
  return code;
}

}  // namespace ifsforge
