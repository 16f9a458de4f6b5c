#!/usr/bin/env bash
# Installs the ifsforge add-on into Blender's user scripts and enables it (one step):
#   bash blender_addon/install.sh [BUILD_DIR]
# - copies blender_addon/ifsforge_addon (with samples/systems and samples/terrain as presets) to
#   <user scripts>/addons/ifsforge_addon;
# - makes the `ifsforge` module importable: Blender 3.4 (Debian) already searches
#   /usr/local/lib/python3.11/dist-packages, where the README's set-up installs it. When
#   BUILD_DIR is given, or when Blender finds no module (or one older than the add-on),
#   BUILD_DIR/python/ifsforge (default: build/) is bundled in the add-on (vendor/), which the
#   add-on puts first on sys.path;
# - enables the add-on, saves the preferences and checks the result in a fresh Blender.
# Honours BLENDER (the executable), BLENDER_USER_SCRIPTS and BLENDER_USER_CONFIG.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
repo="$(cd "$here/.." && pwd)"
blender="${BLENDER:-blender}"
build="${1:-}"

command -v "$blender" >/dev/null || { echo "install: '$blender' not found (apt-get install blender)" >&2; exit 1; }

ask() {  # run a Python expression in Blender, print the lines it tags with ANSWER=
  "$blender" -b --factory-startup --python-expr "$1" 2>/dev/null | sed -n 's/^ANSWER=//p'
}

scripts="$(ask "import bpy; print('ANSWER=' + bpy.utils.user_resource('SCRIPTS'))")"
[ -n "$scripts" ] || { echo "install: could not ask Blender for its user scripts folder" >&2; exit 1; }
addons="$scripts/addons"
new="$addons/ifsforge_addon.new"
mkdir -p "$addons"
rm -rf "$new"
cp -r "$here/ifsforge_addon" "$new"
find "$new" -name __pycache__ -prune -exec rm -rf {} +
rm -rf "$new/vendor"
mkdir -p "$new/presets/systems" "$new/presets/terrain"
cp "$repo"/samples/systems/*.json "$repo"/samples/systems/*.ifs "$new/presets/systems/"
cp "$repo"/samples/terrain/*.json "$repo"/samples/terrain/*.png "$new/presets/terrain/"

# A module the add-on can use: importable, and with the add-on's newest function.
system_module="$(ask "
try:
    import ifsforge
    print('ANSWER=' + (ifsforge.__file__ if hasattr(ifsforge, 'preview_cloud') else ''))
except ImportError:
    print('ANSWER=')")"
if [ -n "$build" ] || [ -z "$system_module" ]; then
  package="${build:-$repo/build}/python/ifsforge"
  [ -f "$package/__init__.py" ] || { echo "install: Blender has no usable ifsforge module and '$package' does" \
    "not exist: build first (see README), or give the build folder: install.sh BUILD_DIR" >&2; exit 1; }
  mkdir -p "$new/vendor"
  cp -r "$package" "$new/vendor/ifsforge"
  find "$new/vendor" -name __pycache__ -prune -exec rm -rf {} +
  echo "install: ifsforge module bundled from $package"
else
  echo "install: ifsforge module: $system_module"
fi
rm -rf "$addons/ifsforge_addon"
mv "$new" "$addons/ifsforge_addon"
echo "install: add-on -> $addons/ifsforge_addon"

# Blender saves no preferences into a config folder that does not exist yet (a first run).
config="$(ask "import bpy; print('ANSWER=' + bpy.utils.user_resource('CONFIG'))")"
[ -n "$config" ] && mkdir -p "$config"

# Enable and save the preferences (not --factory-startup: the user's preferences are kept).
log="$("$blender" -b --python-expr "
import addon_utils, bpy
addon_utils.enable('ifsforge_addon', default_set=True, persistent=True, handle_error=None)
bpy.ops.wm.save_userpref()" 2>&1)" || true

state="$("$blender" -b --python-expr "
import addon_utils, bpy
default, loaded = addon_utils.check('ifsforge_addon')
ok = default and loaded and hasattr(bpy.types, 'IFSFORGE_OT_generate_volume')
import ifsforge
print('ANSWER=' + ('enabled, module ' + ifsforge.__file__ if ok else 'not enabled'))" 2>/dev/null |
  sed -n 's/^ANSWER=//p')"
case "$state" in
  enabled*) echo "install: ifsforge add-on ${state} (3D Viewport > Sidebar > IFS)" ;;
  *) echo "install: the add-on did not enable:" >&2
     echo "$log" | grep -v "^$" | tail -8 >&2
     exit 1 ;;
esac
