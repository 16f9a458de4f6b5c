"""Reading .vdb files in a process of their own.

OpenVDB 10's reader (Debian's libopenvdb10) copies a chunk a file calls uncompressed before it
checks the chunk's length (io::bloscFromStream, unzipFromStream): a crafted .vdb overflows a heap
buffer and takes the process down (found by fuzzing). ifsforge.read_vdb_info and
ifsforge.read_voxel_target therefore read a .vdb in a child Python process: a damaged file costs
the child, and the caller gets an ifsforge error. Meshes are read in process (their readers are
ifsforge's own checks in front of OpenMesh, fuzzed). The child costs 0.13-0.15 s per file (its Python and OpenVDB start-up).
"""
import os
import pickle
import subprocess
import sys

import ifsforge

# The child: calls the extension's reader and writes a pickle of ("ok", result) or
# ("error", class name, message) on its stdout, whose descriptor is first moved aside: OpenVDB
# prints its warnings on stdout, which then go to stderr.
_CHILD = """
import os, pickle, sys
result = os.fdopen(os.dup(1), "wb")
os.dup2(2, 1)
import ifsforge
from ifsforge import _vdb
name, path, options = pickle.loads(sys.stdin.buffer.read())
try:
    out = ("ok", getattr(_vdb, name)(path, **options))
except ifsforge.Error as error:
    out = ("error", type(error).__name__, str(error))
result.write(pickle.dumps(out))
result.flush()
"""


def _in_child(name, path, options):
    package_root = os.path.dirname(os.path.dirname(os.path.abspath(ifsforge.__file__)))
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([package_root, os.environ.get("PYTHONPATH", "")]))
    child = subprocess.run([sys.executable, "-c", _CHILD], input=pickle.dumps((name, path, options)),
                           capture_output=True, env=env)
    if child.returncode != 0 or not child.stdout:
        raise ifsforge.InputError(f"cannot read '{path}' as OpenVDB: the reader failed on it "
                                  f"(exit {child.returncode}; a damaged or hostile file)")
    out = pickle.loads(child.stdout)
    if out[0] == "error":
        raise getattr(ifsforge, out[1], ifsforge.InputError)(out[2])
    return out[1]


def read_vdb_info(path):
    """The grids (name, type, active_voxels, voxel_size, index_bounds) and metadata of a .vdb,
    read in a child process."""
    return _in_child("read_vdb_info", os.fspath(path), {})


def read_voxel_target(path, **options):
    """A 3D shape to fit (see ifsforge._vdb.read_voxel_target); a .vdb is read in a child process."""
    path = os.fspath(path)
    if path.lower().endswith(".vdb"):
        return _in_child("read_voxel_target", path, options)
    from ifsforge import _vdb
    return _vdb.read_voxel_target(path, **options)
