#pragma once
// The OpenVDB trees and grids src/io uses, declared instantiated elsewhere: libopenvdb exports
// them (their vtables and members), as it does the tools OPENVDB_USE_EXPLICIT_INSTANTIATION
// declares extern (openvdb/version.h). A tree or grid is polymorphic, so each file that made one
// otherwise compiled all its virtual members (print, readBuffers, writeBuffers, merge …), most of
// the compile time of vdb.cpp, vdb_mesh.cpp and vdb_voxels.cpp. Every src/io file includes
// OpenVDB through this header, so that these declarations come before any use; the few members
// libopenvdb does not export are instantiated where they are called (vdb_mesh.cpp).
#include <openvdb/openvdb.h>

namespace ifsforge::detail {
// The two trees of OpenVDB's iso-surface mesher (tools/VolumeToMesh.h) besides the scalar one.
using Int16Tree = openvdb::FloatTree::ValueConverter<openvdb::Int16>::Type;
using UInt32Tree = openvdb::FloatTree::ValueConverter<openvdb::Index32>::Type;
}  // namespace ifsforge::detail

// GCC only: it still compiles the inline members a file uses (C++17 [temp.explicit]/10), so only
// the out-of-line ones come from libopenvdb, whichever -O level. Clang assumes those inline members
// were compiled with the instantiation and calls them out of line wherever it does not inline
// them, and libopenvdb, which inlined many of them, does not export them all.
#if defined(__GNUC__) && !defined(__clang__)
extern template class openvdb::tree::Tree<openvdb::FloatTree::RootNodeType>;
extern template class openvdb::tree::Tree<openvdb::BoolTree::RootNodeType>;
extern template class openvdb::tree::Tree<openvdb::Vec3STree::RootNodeType>;
extern template class openvdb::tree::Tree<ifsforge::detail::Int16Tree::RootNodeType>;
extern template class openvdb::tree::Tree<ifsforge::detail::UInt32Tree::RootNodeType>;
extern template class openvdb::Grid<openvdb::FloatTree>;
extern template class openvdb::Grid<openvdb::BoolTree>;
extern template class openvdb::Grid<openvdb::Vec3STree>;
#endif
