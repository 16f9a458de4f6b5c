#!/usr/bin/env bash
# Every test: set up (Debian packages, build, install), then the C++ suite (ctest) and the
# Python suite (pytest, which also drives real Blender and POV-Ray).
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
"$here/cpp/bootstrap.sh"
cd "$here/build"
ctest --output-on-failure -j "$(nproc)"
cd "$here"
PYTHONPATH="$here/build/python${PYTHONPATH:+:$PYTHONPATH}" /usr/bin/python3 -m pytest -q "$here/tests/python"
# Every fuzz target 30 s (ASan + UBSan); a crash fails the run.
"$here/tests/fuzz/run.sh" 30
