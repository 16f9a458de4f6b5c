#!/usr/bin/env bash
# Installs the ifsforge add-on into Blender's user scripts and enables it (one step):
#   bash blender_addon/install.sh [BUILD_DIR]
# - packs the add-on with BUILD_DIR's compiled ifsforge module (default: build/) into a zip
#   (package.sh) and installs that zip the way Edit > Preferences > Add-ons > Install does
#   (bpy.ops.preferences.addon_install): the add-on puts its own copy of the module first on
#   sys.path, so whatever else Blender's Python finds does not matter;
# - enables the add-on, saves the preferences and checks the result in a fresh Blender.
# Honours BLENDER (the executable), BLENDER_USER_SCRIPTS and BLENDER_USER_CONFIG.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
repo="$(cd "$here/.." && pwd)"
blender="${BLENDER:-blender}"
build="${1:-$repo/build}"

command -v "$blender" >/dev/null || { echo "install: '$blender' not found (apt-get install blender)" >&2; exit 1; }

ask() {  # run a Python expression in Blender, print the lines it tags with ANSWER=
  "$blender" -b --factory-startup --python-expr "$1" 2>/dev/null | sed -n 's/^ANSWER=//p'
}

work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
zip="$(bash "$here/package.sh" "$build" "$work")"

# Blender saves no preferences into a config folder that does not exist yet (a first run).
config="$(ask "import bpy; print('ANSWER=' + bpy.utils.user_resource('CONFIG'))")"
[ -n "$config" ] && mkdir -p "$config"

# Install, enable and save the preferences (not --factory-startup: the user's preferences are kept).
log="$("$blender" -b --python-expr "
import addon_utils, bpy
bpy.ops.preferences.addon_install(filepath=r'$zip', overwrite=True)
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
