#include "vdb_archive.h"

#include <cmath>
#include <cstdlib>
#include <vector>

namespace ifsforge::detail {
namespace {

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

}  // namespace ifsforge::detail
