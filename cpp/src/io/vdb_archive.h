#pragma once
// Typed file metadata for .vdb files, and reading one through a stream that stops at the first
// short read.
#include "vdb_trees.h"
#include <openvdb/io/Stream.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <new>
#include <string>

#include "ifsforge/core/error.h"

namespace ifsforge::detail {

/// A metadata value of the type its text holds: a whole number -> Int64, another number ->
/// Double, three numbers separated by spaces or commas -> Vec3d (Vec3i when all whole), else
/// String; readers (Blender, OpenVDB tools) then see numbers as numbers.
openvdb::Metadata::Ptr typed_metadata(const std::string& text);

/// Reads the .vdb file at `path` whole and calls use(stream) while its metadata and grids are
/// alive. OpenVDB does not check its reads: past the end of a truncated file it goes on with
/// uninitialised sizes and counts (or returns no grids), so the stream throws on the first short
/// read (which also means reading the grids whole, not delay-loaded). OpenVDB's errors, a short
/// read and a size no memory holds (OpenVDB allocates what a file declares before reading it: a
/// compressed leaf buffer of 64 GB, found by fuzzing) become `Error` naming the file.
template <class Error, class Use>
void read_vdb_archive(const std::string& path, Use&& use) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw FileError("cannot read '" + path + "': " + std::strerror(errno));
  const std::string cannot = "cannot read '" + path + "' as OpenVDB: ";
  try {
    in.exceptions(std::ios::failbit | std::ios::badbit);
    openvdb::io::Stream file(in, /*delayLoad=*/false);
    use(file);
  } catch (const openvdb::Exception& e) {
    throw Error(cannot + e.what());
  } catch (const std::ios_base::failure&) {
    throw Error(cannot + "the file is truncated or damaged");
  } catch (const std::bad_alloc&) {
    throw Error(cannot + "it declares more data than memory holds (a damaged file)");
  }
}

}  // namespace ifsforge::detail
