#include "vdb_archive.h"

#include <openvdb/io/Archive.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <vector>

#include "ifsforge/core/error.h"

namespace ifsforge::detail {
namespace {

/// The header: magic (8 bytes), file version, library major and minor (4 each), the
/// has-grid-offsets flag (1), then the UUID as 36 characters.
constexpr std::streamoff kUuidOffset = 21;
constexpr std::size_t kUuidLength = 36;

/// io::File::write without its unchecked stream: Archive::write is protected.
class CheckedArchive : public openvdb::io::Archive {
 public:
  void write_to(std::ostream& os, const openvdb::GridCPtrVec& grids, const openvdb::MetaMap& meta) const {
    Archive::write(os, grids, /*seekable=*/true, meta);
  }
};

std::uint64_t fnv1a(std::uint64_t h, const char* data, std::size_t n) {
  for (std::size_t i = 0; i < n; ++i) h = (h ^ static_cast<unsigned char>(data[i])) * 0x100000001b3ull;
  return h;
}

/// A UUID (8-4-4-4-12 hex) from two FNV-1a hashes of every byte after the UUID.
std::string content_uuid(std::ifstream& in) {
  std::uint64_t a = 0xcbf29ce484222325ull, b = 0x84222325cbf29ce4ull;
  in.seekg(kUuidOffset + static_cast<std::streamoff>(kUuidLength));
  std::vector<char> chunk(1 << 20);
  while (in) {
    in.read(chunk.data(), static_cast<std::streamsize>(chunk.size()));
    const auto n = static_cast<std::size_t>(in.gcount());
    a = fnv1a(a, chunk.data(), n);
    b = fnv1a(b ^ 0x9e3779b97f4a7c15ull, chunk.data(), n);
  }
  char text[kUuidLength + 1];
  std::snprintf(text, sizeof text, "%08x-%04x-%04x-%04x-%012llx", unsigned(a >> 32), unsigned((a >> 16) & 0xFFFF),
                unsigned(a & 0xFFFF), unsigned(b >> 48), static_cast<unsigned long long>(b & 0xFFFFFFFFFFFFull));
  return text;
}

/// The numbers of `text` (separated by spaces or commas), or none when any token is not one.
std::vector<double> numbers_of(const std::string& text) {
  std::vector<double> out;
  const char* p = text.c_str();
  while (*p) {
    while (*p == ' ' || *p == ',') ++p;
    if (!*p) break;
    char* end = nullptr;
    const double v = std::strtod(p, &end);
    if (end == p || !std::isfinite(v) || (*end && *end != ' ' && *end != ',')) return {};
    out.push_back(v);
    p = end;
  }
  return out;
}

bool whole(double v) { return v == std::floor(v) && std::fabs(v) < 9e15; }

}  // namespace

openvdb::Metadata::Ptr typed_metadata(const std::string& text) {
  const std::vector<double> v = numbers_of(text);
  const bool all_whole = !v.empty() && whole(v[0]) && (v.size() < 3 || (whole(v[1]) && whole(v[2])));
  if (v.size() == 1) {
    if (all_whole && text.find_first_of(".eE") == std::string::npos)
      return openvdb::Int64Metadata(static_cast<std::int64_t>(v[0])).copy();
    return openvdb::DoubleMetadata(v[0]).copy();
  }
  if (v.size() == 3) {
    if (all_whole && text.find_first_of(".eE") == std::string::npos && std::fabs(v[0]) < 2e9 &&
        std::fabs(v[1]) < 2e9 && std::fabs(v[2]) < 2e9)
      return openvdb::Vec3IMetadata(openvdb::Vec3i(int(v[0]), int(v[1]), int(v[2]))).copy();
    return openvdb::Vec3DMetadata(openvdb::Vec3d(v[0], v[1], v[2])).copy();
  }
  return openvdb::StringMetadata(text).copy();
}

void write_vdb_archive(const std::string& file_path, const std::string& shown_path,
                       const openvdb::GridCPtrVec& grids, const openvdb::MetaMap& meta, std::uint32_t compression) {
  auto fail = [&](const std::string& why) { throw FileError("cannot write '" + shown_path + "': " + why); };
  std::streamoff size = 0;
  {
    std::ofstream os(file_path, std::ios::binary | std::ios::trunc);
    if (!os) fail(std::strerror(errno));
    CheckedArchive archive;
    archive.setCompression(compression);
    try {
      archive.write_to(os, grids, meta);
    } catch (const openvdb::Exception& e) {
      fail(e.what());
    }
    os.flush();
    if (!os) fail("the disk refused the data (full?)");
    size = os.tellp();
    os.close();
    if (os.fail()) fail("the disk refused the data (full?)");
  }
  std::ifstream in(file_path, std::ios::binary);
  in.seekg(0, std::ios::end);
  if (!in || in.tellg() != size) fail("only part of the file reached the disk");
  char header[kUuidOffset + kUuidLength];
  in.seekg(0);
  if (!in.read(header, sizeof header) || header[kUuidOffset + 8] != '-') fail("unexpected OpenVDB header layout");
  const std::string uuid = content_uuid(in);
  in.close();
  std::fstream patch(file_path, std::ios::binary | std::ios::in | std::ios::out);
  patch.seekp(kUuidOffset);
  patch.write(uuid.data(), static_cast<std::streamsize>(uuid.size()));
  patch.flush();
  if (!patch) fail("cannot stamp the file UUID");
}

}  // namespace ifsforge::detail
