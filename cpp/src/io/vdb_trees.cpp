// The members of the trees vdb_trees.h declares that libopenvdb does not export (it inlined them
// everywhere) but src/io calls out of line: the mesher's two index trees, only their destructor's
// helper. A link error naming another member of a declared tree or grid belongs here too.
#include "vdb_trees.h"

template void openvdb::tree::Tree<ifsforge::detail::Int16Tree::RootNodeType>::releaseAllAccessors();
template void openvdb::tree::Tree<ifsforge::detail::UInt32Tree::RootNodeType>::releaseAllAccessors();
