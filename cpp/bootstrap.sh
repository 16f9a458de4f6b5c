#!/usr/bin/env bash
# Set-up shared by the README's two commands: install the Debian packages ifsforge needs
# (only those missing; as root or through sudo), then configure, build and install.
#   IFSFORGE_BUILD_DIR   build folder (default: build)
#   IFSFORGE_NO_INSTALL  set to 1 to skip `cmake --install` (tests use the build tree)
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${IFSFORGE_BUILD_DIR:-$here/build}"

packages=(build-essential cmake pkg-config libgtest-dev libbenchmark-dev
  blender povray libopenvdb-dev libboost-iostreams-dev python3-openvdb libopenvdb-tools
  libopenmesh-dev libtinygltf-dev pybind11-dev nlohmann-json3-dev libpng-dev
  python3-numpy python3-pytest python3-pytest-xdist python3-tqdm python3-imath xvfb xauth
  python3-skimage python3-pil python3-matplotlib python3-distributed clang libclang-rt-14-dev
  python3-pip python3-venv python3-setuptools python3-wheel)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  sudo=""
  if [ "$(id -u)" -ne 0 ]; then
    command -v sudo >/dev/null || { echo "bootstrap: need root or sudo to install: ${missing[*]}" >&2; exit 1; }
    sudo="sudo"
  fi
  echo "bootstrap: installing ${missing[*]}"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

# Debian's interpreter: the python3 first on PATH may be another one, without the python3-* packages.
cmake -S "$here" -B "$build" -DCMAKE_BUILD_TYPE=Release -DCMAKE_INTERPROCEDURAL_OPTIMIZATION=OFF \
  -DPython_EXECUTABLE=/usr/bin/python3 >/dev/null
cmake --build "$build" -j "$(nproc)"
if [ "${IFSFORGE_NO_INSTALL:-0}" != 1 ]; then
  sudo=""; [ "$(id -u)" -ne 0 ] && sudo="sudo"
  $sudo cmake --install "$build" >/dev/null
  # The Blender add-on, enabled in the user's Blender preferences (it imports the module just installed).
  bash "$here/blender_addon/install.sh" >/dev/null || echo "bootstrap: warning: the Blender add-on did not install (see bash blender_addon/install.sh)" >&2
fi
