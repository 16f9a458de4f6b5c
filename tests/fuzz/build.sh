#!/usr/bin/env bash
# tests/fuzz/build.sh: configures and builds the libFuzzer targets (clang, ASan + UBSan) in
# build-fuzz; with CCACHE set, through ccache. tests/fuzz/run.sh calls it before fuzzing.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
build="$here/build-fuzz"
cmake -S "$here/tests/fuzz" -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_COMPILER=clang++ \
  ${CCACHE:+-DCMAKE_CXX_COMPILER_LAUNCHER=ccache} >/dev/null
cmake --build "$build" -j "$(nproc)" >/dev/null
