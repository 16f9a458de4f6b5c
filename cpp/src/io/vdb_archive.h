#pragma once
// Writing a .vdb through a stream ifsforge checks: OpenVDB's io::File ignores a failed write
// (a full disk leaves a truncated file it reports as written) and stamps a random UUID.
#include <openvdb/openvdb.h>

#include <string>

namespace ifsforge::detail {

/// Writes `grids` and `meta` to `file_path` (seekable, like io::File), checks every byte
/// reached the file, then replaces the random UUID by one hashed from the content, so the same
/// volume always gives the same bytes. FileError naming `shown_path` on any failure.
void write_vdb_archive(const std::string& file_path, const std::string& shown_path,
                       const openvdb::GridCPtrVec& grids, const openvdb::MetaMap& meta, std::uint32_t compression);

/// A metadata value of the type its text holds: a whole number -> Int64, another number ->
/// Double, three numbers separated by spaces or commas -> Vec3d (Vec3i when all whole), else
/// String; readers (Blender, OpenVDB tools) then see numbers as numbers.
openvdb::Metadata::Ptr typed_metadata(const std::string& text);

}  // namespace ifsforge::detail
