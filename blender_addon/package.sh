#!/usr/bin/env bash
# Writes the add-on as one zip that Blender installs by itself (Edit > Preferences > Add-ons >
# Install...), for artists who have neither root nor a compiler:
#   bash blender_addon/package.sh [BUILD_DIR [OUTPUT_DIR]]
# The zip, OUTPUT_DIR/ifsforge_addon-<version>.zip (default: BUILD_DIR, itself default build/),
# holds ifsforge_addon/ with
# - the add-on's Python files and its shipped operator presets;
# - presets/systems and presets/terrain: the sample systems and terrain recipes;
# - vendor/ifsforge: BUILD_DIR's compiled ifsforge module (_core and _vdb for this platform's
#   Python ABI), which the add-on puts first on sys.path, so no system-wide module is needed.
# Prints the zip's path.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
repo="$(cd "$here/.." && pwd)"
build="$(cd "${1:-$repo/build}" && pwd)"
out="${2:-$build}"
python="${PYTHON:-/usr/bin/python3}"
package="$build/python/ifsforge"

for module in _core _vdb; do
  compgen -G "$package/$module.*.so" >/dev/null || {
    echo "package: $package has no compiled $module module: build first (cmake --build $build)" >&2; exit 1; }
done
# The version the add-on declares (bl_info), read without importing it (it needs bpy).
version="$("$python" - "$here/ifsforge_addon/__init__.py" <<'EOF'
import ast, sys
tree = ast.parse(open(sys.argv[1]).read())
info = next(node.value for node in tree.body if isinstance(node, ast.Assign) and node.targets[0].id == "bl_info")
print(".".join(str(v) for v in ast.literal_eval(info)["version"]))
EOF
)"

stage="$(mktemp -d)"
trap 'rm -rf "$stage"' EXIT
addon="$stage/ifsforge_addon"
cp -r "$here/ifsforge_addon" "$addon"
rm -rf "$addon/vendor"
mkdir -p "$addon/presets/systems" "$addon/presets/terrain" "$addon/vendor"
cp "$repo"/samples/systems/*.json "$repo"/samples/systems/*.ifs "$addon/presets/systems/"
cp "$repo"/samples/terrain/*.json "$repo"/samples/terrain/*.png "$addon/presets/terrain/"
cp -r "$package" "$addon/vendor/ifsforge"
find "$addon" -name __pycache__ -prune -exec rm -rf {} +

mkdir -p "$out"
zip="$(cd "$out" && pwd)/ifsforge_addon-$version.zip"
rm -f "$zip"
(cd "$stage" && "$python" -m zipfile -c "$zip" ifsforge_addon)
echo "$zip"
