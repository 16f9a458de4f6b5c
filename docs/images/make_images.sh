#!/usr/bin/env bash
# The README's pictures, made with the project's own commands (after the set-up), then reduced
# to small palette PNGs with Pillow so the repository stays light:
#   bash docs/images/make_images.sh
# gallery.png is the gallery's contact sheet (samples/gallery.py's images(), at 512 pixels).
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
repo="$(cd "$here/../.." && pwd)"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
export PYTHONPATH="${PYTHONPATH:-$repo/build/python}"   # another build: set PYTHONPATH
ifsforge="${IFSFORGE:-ifsforge}"

/usr/bin/python3 - "$repo/samples" "$work" <<'PY'
import sys
from pathlib import Path
sys.path.insert(0, sys.argv[1])
import gallery
gallery.SIZE = 512
gallery.images(Path(sys.argv[2]))
PY
cd "$work"
"$ifsforge" render "$repo/samples/systems/colour5d_fern_hsi.json" -o colour_fern.png --size 360
"$ifsforge" instances "$repo/samples/systems/vector_csg_pyramid.json" --depth 4 --primitive sphere,box,cone \
  --base-vector 0 0 0.87 --pov csg_pyramid.pov --render csg_pyramid.png --size 360x270
"$ifsforge" terrain "$repo/samples/terrain/crater.json" --res 257 -o crater.pov \
  --povray-render crater.png --povray-size 360x270

/usr/bin/python3 - "$work" "$here" <<'PY'
import sys
from pathlib import Path
from PIL import Image
work, out = Path(sys.argv[1]), Path(sys.argv[2])
for name, width, colours in (("gallery.png", 800, 128), ("colour_fern.png", 360, 96),
                             ("csg_pyramid.png", 360, 96), ("crater.png", 360, 96)):
    image = Image.open(work / name).convert("RGB")
    if image.width > width:
        image = image.resize((width, round(image.height * width / image.width)), Image.LANCZOS)
    image.quantize(colors=colours, method=Image.Quantize.MEDIANCUT, dither=Image.Dither.NONE).save(
        out / name, optimize=True)
    print(f"{name}: {image.width}x{image.height}, {(out / name).stat().st_size:,} bytes")
PY
