#!/usr/bin/env bash
# Every test: set up (Debian packages, build, install), then the C++ suite (ctest) and the
# Python suite (pytest, which also drives real Blender and POV-Ray).
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
"$here/cpp/bootstrap.sh"
cd "$here/build"
ctest --output-on-failure -j "$(nproc)"
cd "$here"
# Two workers (pytest-xdist), one per core of the smallest machine we test on; tests sharing a
# module-scoped fixture stay on one worker (tests/python/conftest.py groups them). The 25
# slowest tests are listed at the end, so a run's log shows where the suite's time goes.
PYTHONPATH="$here/build/python${PYTHONPATH:+:$PYTHONPATH}" /usr/bin/python3 -m pytest -q -n 2 --dist loadgroup --durations=25 \
  "$here/tests/python"
# Every fuzz target 30 s (ASan + UBSan), two at a time; a crash fails the run.
"$here/tests/fuzz/run.sh" 30 2
