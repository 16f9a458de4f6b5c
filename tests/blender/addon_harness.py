"""Shared by the tests/blender/addon_*.py scripts, which run inside real Blender:
    blender -b --factory-startup --python tests/blender/addon_X.py -- --python-path BUILD/python --out DIR
Each script enables the add-on from the checkout, runs named checks, prints one
`CHECK name ok|FAIL message` line per check and a final `RESULT {json}` line, and exits 1
if any check failed (the pytest driver reads both)."""
import argparse
import json
import sys
import time
import traceback
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


def arguments():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    parser = argparse.ArgumentParser()
    parser.add_argument("--python-path", required=True, help="folder holding the built ifsforge package")
    parser.add_argument("--out", required=True, help="scratch folder")
    return parser.parse_args(argv)


def enable_addon(python_path):
    """The way install.sh's result is used, minus the copy: module and add-on on sys.path."""
    import addon_utils
    for folder in (str(python_path), str(ROOT / "blender_addon")):
        if folder not in sys.path:
            sys.path.insert(0, folder)
    module = addon_utils.enable("ifsforge_addon", default_set=True, handle_error=None)
    if module is None:
        raise RuntimeError("addon_utils.enable returned None")
    return module


class Checks:
    def __init__(self):
        self.results = {}
        self.values = {}

    def run(self, name, function, *args):
        start = time.perf_counter()
        try:
            function(*args)
            self.results[name] = "ok"
            print(f"CHECK {name} ok ({time.perf_counter() - start:.2f} s)", flush=True)
        except Exception as error:
            self.results[name] = f"{type(error).__name__}: {error}"
            print(f"CHECK {name} FAIL {self.results[name]}", flush=True)
            traceback.print_exc()

    def finish(self):
        print("RESULT " + json.dumps({"checks": self.results, "values": self.values}), flush=True)
        failed = [k for k, v in self.results.items() if v != "ok"]
        sys.stdout.flush()
        import os
        os._exit(1 if failed else 0)  # Blender would otherwise exit 0 whatever happened


def expect_report(operator_call, *fragments):
    """Runs an operator that must fail with an error report (a RuntimeError from bpy.ops in a
    script) whose text holds every fragment and no Python traceback."""
    try:
        operator_call()
    except RuntimeError as error:
        text = str(error)
        if "Traceback" in text:
            raise AssertionError(f"the report is a traceback: {text}") from None
        for fragment in fragments:
            if fragment.lower() not in text.lower():
                raise AssertionError(f"report {text!r} does not mention {fragment!r}") from None
        return text
    raise AssertionError("the operator did not report an error")


def close(a, b, tolerance):
    import numpy as np
    a, b = np.asarray(a, float), np.asarray(b, float)
    if a.shape != b.shape:
        raise AssertionError(f"shapes differ: {a.shape} != {b.shape}")
    if not np.allclose(a, b, atol=tolerance, rtol=0):
        k = np.unravel_index(np.argmax(np.abs(a - b)), a.shape)
        raise AssertionError(f"differ by {np.abs(a - b).max():.3g} > {tolerance} at {k}: {a[k]} != {b[k]}"
                             + (f" ({a.tolist()} != {b.tolist()})" if a.size <= 16 else ""))


def render_alpha(obj, path, size=32, samples=8, box=None):
    """A tiny Cycles render of `obj` alone, seen from a camera on the diagonal of its bounding
    box (or of `box`, (lo, hi)); returns RGBA (the film is transparent: alpha 0 where nothing
    was hit)."""
    import bpy
    import numpy as np
    from mathutils import Vector
    scene = bpy.context.scene
    for other in scene.objects:
        other.hide_render = other is not obj and other.type != 'CAMERA' and other.type != 'LIGHT'
    obj.hide_render = False
    if box is None:
        corners = [obj.matrix_world @ Vector(c) for c in obj.bound_box]
    else:
        corners = [Vector(box[0]), Vector(box[1])]
    centre = sum(corners, Vector()) / len(corners)
    radius = max((c - centre).length for c in corners)
    camera = scene.camera
    direction = Vector((1.0, -1.0, 0.8)).normalized()
    camera.location = centre + direction * radius * 3.5
    camera.rotation_euler = (-direction).to_track_quat('-Z', 'Y').to_euler()
    camera.data.type, camera.data.lens = 'PERSP', 50
    camera.data.clip_end = radius * 10
    scene.render.engine = 'CYCLES'
    scene.cycles.device = 'CPU'
    scene.cycles.samples = samples
    scene.cycles.use_denoising = False
    scene.render.resolution_x = scene.render.resolution_y = size
    scene.render.resolution_percentage = 100
    scene.render.film_transparent = True
    scene.render.image_settings.file_format = 'PNG'
    scene.render.image_settings.color_mode = 'RGBA'
    scene.render.filepath = str(path)
    bpy.ops.render.render(write_still=True)
    image = bpy.data.images.load(str(path), check_existing=False)
    pixels = np.array(image.pixels[:]).reshape(size, size, 4)
    bpy.data.images.remove(image)
    return pixels


# Refuses every import of the module and the add-on, even when the set-up installed the module
# system-wide: what a Blender without ifsforge sees. Runs before the .blend is loaded.
_HIDE_IFSFORGE = """
import sys
class HideIfsforge:
    attempts = []
    def find_spec(self, name, path=None, target=None):
        if name.split('.')[0] in ('ifsforge', 'ifsforge_addon'):
            HideIfsforge.attempts.append(name)
            raise ImportError(name + ' is hidden from this Blender')
sys.meta_path.insert(0, HideIfsforge())
sys.ifsforge_import_attempts = HideIfsforge.attempts
"""


def open_without_ifsforge(blend, probe, argv, folder):
    """Runs `probe` (Python text that fills a dict `out`) in a second Blender with factory
    settings that opens `blend` with ifsforge hidden; returns `out`, after checking that nothing
    tried to import ifsforge and that the add-on was not enabled."""
    import os
    import subprocess
    import bpy
    script = Path(folder) / "probe.py"
    script.write_text("out = {}\n" + probe + """
import bpy, json, sys
out["imports"] = sys.ifsforge_import_attempts
out["addon"] = "ifsforge_addon" in bpy.context.preferences.addons
print("PROBE " + json.dumps(out))
""")
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    result = subprocess.run([bpy.app.binary_path, "-b", "--factory-startup", "--python-expr", _HIDE_IFSFORGE,
                             str(blend), "--python", str(script), "--", *map(str, argv)],
                            capture_output=True, text=True, timeout=300, env=env)
    lines = [line for line in result.stdout.splitlines() if line.startswith("PROBE ")]
    if not lines:
        raise AssertionError(result.stdout[-3000:] + result.stderr[-3000:])
    seen = json.loads(lines[0][len("PROBE "):])
    if seen["imports"] or seen["addon"]:
        raise AssertionError(f"ifsforge was needed: imports {seen['imports']}, add-on enabled {seen['addon']}")
    return seen


class RecordingLayout:
    """Stands in for a menu's UILayout: records the entries a draw function adds, as
    (kind, label, id, properties): "operator" entries with the properties the menu sets on them,
    "menu" entries (sub-menus). Anything else a draw function calls (separators, columns,
    operator_context) is accepted and ignored."""

    def __init__(self):
        self.entries = []

    def operator(self, idname, text="", **options):
        import types
        properties = types.SimpleNamespace()
        self.entries.append(("operator", text or idname, idname, properties))
        return properties

    def menu(self, name, text="", **options):
        import bpy
        self.entries.append(("menu", text or getattr(bpy.types, name).bl_label, name, None))

    def __getattr__(self, name):
        return lambda *args, **kwargs: self

    def __setattr__(self, name, value):
        if name == "entries":
            object.__setattr__(self, name, value)


def menu_entries(menu, context):
    """What the menu class shows: its own draw and every function appended to it (what Blender
    draws), on a RecordingLayout."""
    import types
    layout = RecordingLayout()
    for draw in menu._dyn_ui_initialize():
        draw(types.SimpleNamespace(layout=layout, bl_idname=menu.__name__), context)
    return layout.entries


def operator_by_label(menu, context, label):
    """The operator entry of a menu shown as `label`: (bpy.ops function, the properties the menu
    sets). Fails when no entry has that label or the entry's operator does not exist (Blender
    would draw it greyed out)."""
    import bpy
    found = [(idname, props) for kind, text, idname, props in menu_entries(menu, context)
             if kind == "operator" and text == label]
    if not found:
        labels = [text for _, text, _, _ in menu_entries(menu, context)]
        raise AssertionError(f"{menu.__name__} has no entry '{label}' (it has {labels})")
    idname, props = found[0]
    group, name = idname.split(".")
    function = getattr(getattr(bpy.ops, group), name)
    try:
        function.get_rna_type()
    except KeyError:
        raise AssertionError(f"'{label}' in {menu.__name__} calls {idname}, which is no operator") from None
    return function, vars(props)
