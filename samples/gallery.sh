#!/usr/bin/env bash
# The main job: set up (Debian packages, build, install), then make the sample gallery in out/.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
"$here/cpp/bootstrap.sh"
PYTHONPATH="$here/build/python${PYTHONPATH:+:$PYTHONPATH}" /usr/bin/python3 "$here/samples/gallery.py" "${1:-$here/out}"
