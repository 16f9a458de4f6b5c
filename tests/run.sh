#!/usr/bin/env bash
# Every test: set up (Debian packages, build, install), then the C++ suite (ctest) and the
# Python suite (pytest, which also drives real Blender and POV-Ray).
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
"$here/cpp/bootstrap.sh"
# The fuzz targets are built beside the suites at idle priority (SCHED_IDLE): the build takes only
# the cycles ctest and pytest leave (Blender's start-ups, POV-Ray's parses, a worker's last test),
# so the suites run as fast as alone. It gets a process group of its own (set -m), stopped if this
# script stops, but not a session of its own: the kernel shares the CPU between sessions
# (autogroups) before it looks at priorities, and setsid let the idle build take one core of two.
fuzz_log="$here/build/fuzz-build.log"
set -m
chrt --idle 0 "$here/tests/fuzz/build.sh" >"$fuzz_log" 2>&1 &
fuzz_build=$!
set +m
trap 'kill -- "-$fuzz_build" 2>/dev/null || true' EXIT
cd "$here/build"
ctest --output-on-failure -j "$(nproc)"
cd "$here"
# Two workers (pytest-xdist), one per core of the smallest machine we test on; tests sharing a
# module-scoped fixture stay on one worker (tests/python/conftest.py groups them). The 25
# slowest tests are listed at the end, so a run's log shows where the suite's time goes.
PYTHONPATH="$here/build/python${PYTHONPATH:+:$PYTHONPATH}" /usr/bin/python3 -m pytest -q -n 2 --dist loadgroup --durations=25 \
  "$here/tests/python"
if ! wait "$fuzz_build"; then
  echo "the fuzz targets' build failed:" >&2
  tail -40 "$fuzz_log" >&2
  exit 1
fi
trap - EXIT
# Every fuzz target 30 s (ASan + UBSan), two at a time; a crash fails the run.
"$here/tests/fuzz/run.sh" 30 2
