#include "ifsforge/pifs/code_bytes.h"

#include <cstdio>
#include <cstring>

#include "ifsforge/core/error.h"
#include "ifsforge/pifs/plane_coding.h"

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

std::vector<std::uint8_t> header(const PifsCode& code, const std::vector<std::size_t>& stream_sizes) {
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
  for (std::size_t s : stream_sizes) put_varint(out, s);
  return out;
}

std::vector<std::size_t> sizes(const std::vector<std::vector<std::uint8_t>>& streams) {
  std::vector<std::size_t> out;
  for (const auto& s : streams) out.push_back(s.size());
  return out;
}

}  // namespace

std::vector<std::uint8_t> pifs_to_bytes(const PifsCode& code) {
  std::vector<std::vector<std::uint8_t>> streams;
  for (const PifsPlane& p : code.planes) streams.push_back(encode_plane(code, p));
  std::vector<std::uint8_t> out = header(code, sizes(streams));
  for (const auto& s : streams) out.insert(out.end(), s.begin(), s.end());
  const std::uint32_t c = crc32(out.data(), out.size());
  for (int i = 0; i < 4; ++i) out.push_back(std::uint8_t(c >> (8 * i)));
  return out;
}

std::size_t pifs_header_size(const PifsCode& code) {
  std::vector<std::vector<std::uint8_t>> streams;
  for (const PifsPlane& p : code.planes) streams.push_back(encode_plane(code, p));
  return header(code, sizes(streams)).size();
}

std::size_t pifs_file_size(const PifsCode& code, const std::vector<std::size_t>& stream_sizes) {
  std::size_t total = header(code, stream_sizes).size() + 4;  // the checksum
  for (std::size_t s : stream_sizes) total += s;
  return total;
}

PifsCode pifs_from_bytes(const std::uint8_t* data, std::size_t size, const std::string& where) {
  if (size < 4 || std::memcmp(data, kMagic, 4) != 0) throw InputError(where + ": not a PIFS file (no 'PIFS' magic)");
  Reader r{data, size, 4, where};
  const int version = r.byte();
  if (version != kPifsVersion)
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
  if (code.channels < 1 || code.channels > 4 || color > 1 || code.min_log < 1 || code.max_log > 8 ||
      code.min_log > code.max_log || code.s_bits < 2 || code.s_bits > 8 || code.dc_step < 1 || code.dc_step > 64 ||
      w < 1 || h < 1 || w > 32768 || h > 32768)
    throw InputError(where + ": corrupt (header field out of range)");
  code.color = PifsColor(color);
  code.width = int(w);
  code.height = int(h);
  const int planes = plane_count(code.channels, code.color);
  std::vector<std::uint64_t> lengths(planes);
  std::uint64_t total = 0;
  for (auto& l : lengths) total += (l = r.varint());
  if (total != r.size - r.pos) throw InputError(where + ": corrupt (plane sizes do not match the file)");
  const bool ycc = code.color == PifsColor::YCbCr420 && code.channels >= 3;
  for (int k = 0; k < planes; ++k) {
    const bool half = ycc && (k == 1 || k == 2);
    const int pw = half ? (code.width + 1) / 2 : code.width, ph = half ? (code.height + 1) / 2 : code.height;
    code.planes.push_back(decode_plane(code, pw, ph, data + r.pos, std::size_t(lengths[k]),
                                       where + " (plane " + std::to_string(k + 1) + ")"));
    r.pos += std::size_t(lengths[k]);
  }
  return code;
}

}  // namespace ifsforge
