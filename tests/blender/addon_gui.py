"""Blender with a window (under xvfb-run): the viewport draw handler really draws the preview
with the gpu module, a value change reaches the screen through it, and the sidebar panels draw.
    xvfb-run -a -s "-screen 0 960x600x24" blender --factory-startup --enable-event-simulate \
        --python tests/blender/addon_gui.py -- --python-path BUILD/python --out DIR
The checks run from a timer once the window is up; the script quits Blender at the end."""
import statistics
import sys
import threading
import time
from pathlib import Path

import bpy
import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from addon_harness import Checks, arguments, enable_addon  # noqa: E402

args = arguments()
OUT = Path(args.out) / "gui"
OUT.mkdir(parents=True, exist_ok=True)
enable_addon(args.python_path)
bpy.context.preferences.view.show_splash = False

import ifsforge  # noqa: E402

from ifsforge_addon import outputs, panels, preview  # noqa: E402

checks = Checks()
drawn = set()


def record(cls):
    """Wraps a panel's draw to note that Blender called it."""
    original = cls.draw

    def draw(self, context):
        drawn.add(cls.__name__)
        original(self, context)
    cls.draw = draw


for panel in (panels.IFSFORGE_PT_design, panels.IFSFORGE_PT_map, panels.IFSFORGE_PT_preview,
              panels.IFSFORGE_PT_generate):
    record(panel)


def view3d():
    window = bpy.context.window_manager.windows[0]
    area = next(a for a in window.screen.areas if a.type == 'VIEW_3D')
    region = next(r for r in area.regions if r.type == 'WINDOW')
    sidebar = next(r for r in area.regions if r.type == 'UI')
    return window, area, region, sidebar


def redraw(window, area, region):
    with bpy.context.temp_override(window=window, area=area, region=region):
        bpy.ops.wm.redraw_timer(type='DRAW', iterations=1)


def setup():
    window, area, region, _ = view3d()
    for obj in list(bpy.data.objects):
        if obj.type != 'CAMERA':
            bpy.data.objects.remove(obj)
    bpy.ops.ifsforge.load_preset(preset="barnsley_fern.json")
    area.spaces[0].show_region_ui = True
    with bpy.context.temp_override(window=window, area=area, region=region):
        bpy.ops.view3d.view_axis(type='TOP')
        bpy.ops.ifsforge.view_preview()


def draws_the_preview():
    window, area, region, _ = view3d()
    preview.current.__init__()
    redraw(window, area, region)
    assert preview.current.cloud is not None and preview.current.batches is not None, preview.current.error
    # Live: a value changes, the next draw of the viewport computes the new cloud and uploads it
    # (software OpenGL here: the whole redraw takes far longer than the preview's part).
    system = bpy.context.scene.ifsforge.system
    compute, upload = [], []
    for k in range(5):
        system.maps[1].rotation[0] = -2.5 + 0.2 * k
        redraw(window, area, region)
        assert preview.current.batches is not None
        compute.append(preview.current.seconds)
        upload.append(preview.current.upload_seconds)
    checks.values["cloud_ms_median"] = 1e3 * statistics.median(compute)
    checks.values["upload_ms_median"] = 1e3 * statistics.median(upload)
    checks.values["gpu"] = __import__("gpu").platform.renderer_get()


def screenshot(window, area, name):
    """The viewport as an RGB array (rows bottom to top), also kept as OUT/name."""
    path = OUT / name
    with bpy.context.temp_override(window=window, area=area):
        bpy.ops.screen.screenshot_area(filepath=str(path))
    image = bpy.data.images.load(str(path), check_existing=False)
    rgb = np.array(image.pixels[:]).reshape(image.size[1], image.size[0], 4)[:, :, :3]
    bpy.data.images.remove(image)
    return rgb


def pixels_show_the_pieces():
    window, area, region, _ = view3d()
    system = bpy.context.scene.ifsforge.system
    system.active_map = 1  # the big leaf, highlighted
    redraw(window, area, region)
    rgb = screenshot(window, area, "viewport.png")
    bright = np.array(ifsforge.piece_color(1)[:3])
    near = np.abs(rgb - bright).max(axis=2) < 0.06
    checks.values["highlighted_pixels"] = int(near.sum())
    # The highlighted leaf's points cover ~29500 pixels of the 960x600 window; the maps' frame
    # outlines, drawn in the same colour, ~1700 without a single point.
    assert near.sum() > 10000, near.sum()


def draws_the_target():
    """A target picture (magenta) lies behind the 2D preview with each map's copy outlined."""
    window, area, region, _ = view3d()
    settings = bpy.context.scene.ifsforge.collage
    image = bpy.data.images.new("gui target", 64, 64)
    rgba = np.zeros((64, 64, 4), np.float32)
    rgba[..., 3] = 1
    rgba[8:56, 8:56] = (1, 0, 1, 1)
    image.pixels.foreach_set(rgba.ravel())
    settings.window = (-3.0, 0.0, 3.0, 10.0)
    settings.threshold = 0.2  # magenta on black: luminance 0.28
    settings.image = image
    assert settings.error == "" and settings.distance_pixels >= 0, settings.error
    redraw(window, area, region)
    rgb = screenshot(window, area, "viewport_target.png")
    magenta = (rgb[..., 0] > 0.6) & (rgb[..., 1] < 0.35) & (rgb[..., 2] > 0.6)
    checks.values["target_pixels"] = int(magenta.sum())
    settings.image = None  # the later checks look at the preview alone
    assert magenta.sum() > 500, magenta.sum()


def tab_clicks():
    """Clicks down the sidebar's tab strip, one per timer tick (the event loop handles each
    and redraws), until the IFS tab's panels have been drawn."""
    window, area, region, sidebar = view3d()
    x = sidebar.x + sidebar.width - 8
    for y in range(sidebar.y + sidebar.height - 20, sidebar.y + 40, -12):
        if "IFSFORGE_PT_design" in drawn:
            return
        window.event_simulate('MOUSEMOVE', 'NOTHING', x=x, y=y)
        window.event_simulate('LEFTMOUSE', 'PRESS', x=x, y=y)
        window.event_simulate('LEFTMOUSE', 'RELEASE', x=x, y=y)
        yield


def panels_draw():
    missing = {"IFSFORGE_PT_design", "IFSFORGE_PT_map", "IFSFORGE_PT_preview", "IFSFORGE_PT_generate"} - drawn
    assert not missing, f"panels not drawn: {missing}"
    window = view3d()[0]
    with bpy.context.temp_override(window=window):
        bpy.ops.screen.screenshot(filepath=str(OUT / "window.png"))


def modal_generate():
    """Invoked from the UI the generator runs modally (a thread, the progress, Esc): one tick
    per yield until it has finished and made the object."""
    window, area, region, _ = view3d()
    for obj in bpy.context.selected_objects:
        obj.select_set(False)
    bpy.ops.ifsforge.load_preset(preset="sierpinski_tetrahedron.json")
    bpy.context.scene.ifsforge.settings.volume_resolution = 32
    with bpy.context.temp_override(window=window, area=area, region=region):
        assert bpy.ops.ifsforge.generate_volume('INVOKE_DEFAULT') == {'RUNNING_MODAL'}
    for _ in range(100):
        if "Sierpinski tetrahedron volume" in bpy.data.objects:
            break
        yield
    obj = bpy.data.objects.get("Sierpinski tetrahedron volume")
    checks.values["modal_volume"] = obj.ifsforge.summary if obj else ""


def escape_cancels():
    """A slow job (a 512^3 Menger sponge) gets Esc: the modal operator stops it, nothing is made."""
    window, area, region, _ = view3d()
    for obj in bpy.context.selected_objects:
        obj.select_set(False)
    bpy.ops.ifsforge.load_preset(preset="menger_sponge.json")
    bpy.context.scene.ifsforge.settings.volume_resolution = 512
    with bpy.context.temp_override(window=window, area=area, region=region):
        assert bpy.ops.ifsforge.generate_volume('INVOKE_DEFAULT') == {'RUNNING_MODAL'}
    yield
    x, y = region.x + region.width // 2, region.y + region.height // 2
    window.event_simulate('MOUSEMOVE', 'NOTHING', x=x, y=y)
    window.event_simulate('ESC', 'PRESS', x=x, y=y)
    window.event_simulate('ESC', 'RELEASE', x=x, y=y)
    pressed = time.perf_counter()
    for _ in range(100):
        yield
        if not any(t.name == "ifsforge job" and t.is_alive() for t in threading.enumerate()):
            break
    checks.values["escape_seconds"] = time.perf_counter() - pressed
    yield  # the modal operator's next timer tick ends it


def modal_results():
    assert checks.values["modal_volume"].endswith("grids density"), checks.values["modal_volume"]
    assert "Menger sponge volume" not in bpy.data.objects, "a cancelled job made an object"
    # A 512^3 sponge takes minutes: stopping within seconds means the core saw the cancel.
    assert checks.values["escape_seconds"] < 20
    cache = Path(bpy.context.scene.ifsforge.cache_folder or outputs.folder(bpy.context.scene))
    assert not list(cache.glob("Menger_sponge_volume*")), "a cancelled job left a file"


def adjust_last_operation():
    """F9: the finished Generate Terrain is the last operation; changing its settings (as the
    Adjust Last Operation panel does, or a preset) and redoing makes the terrain anew from them."""
    window, area, region, _ = view3d()
    for obj in bpy.context.selected_objects:
        obj.select_set(False)
    bpy.ops.ifsforge.load_preset(preset="barnsley_fern.json")
    bpy.context.scene.ifsforge.settings.terrain_resolution = 65
    with bpy.context.temp_override(window=window, area=area, region=region):
        bpy.ops.ed.undo_push(message="design")  # what the UI does after each edit: redo starts here
        bpy.ops.wm.call_menu(name="IFSFORGE_MT_add")  # Shift+A > IFS draws (a traceback would fail the test)
        assert bpy.ops.ifsforge.generate_terrain('INVOKE_DEFAULT') == {'RUNNING_MODAL'}
    for _ in range(100):
        if "Barnsley fern terrain" in bpy.data.objects:
            break
        yield
    yield
    operator = bpy.context.window_manager.operators[-1]
    assert operator.bl_idname == "IFSFORGE_OT_generate_terrain", operator.bl_idname
    assert operator.properties.settings.terrain_resolution == 65
    operator.properties.settings.terrain_resolution = 33
    operator.properties.settings.terrain_source = 'RANDOM'
    with bpy.context.temp_override(window=window, area=area, region=region):
        assert bpy.ops.ed.undo_redo() == {'FINISHED'}
    yield
    terrains = [o for o in bpy.data.objects if o.name.startswith("Barnsley fern terrain")]
    checks.values["adjusted_terrains"] = [(o.name, len(o.data.vertices), o.ifsforge.settings.terrain_source)
                                          for o in terrains]


def adjusted_results():
    assert checks.values["adjusted_terrains"] == [("Barnsley fern terrain", 33 * 33, 'RANDOM')], \
        checks.values["adjusted_terrains"]
    assert bpy.context.scene.ifsforge.settings.terrain_resolution == 65  # the edited settings stay


steps = [setup, draws_the_preview, pixels_show_the_pieces, draws_the_target, tab_clicks, panels_draw, modal_generate, escape_cancels,
         modal_results, adjust_last_operation, adjusted_results]
GENERATORS = (tab_clicks, modal_generate, escape_cancels, adjust_last_operation)
running = None


def tick():
    global running
    if steps[0] in GENERATORS:
        running = running or steps[0]()
        if next(running, "done") != "done":
            return 0.2
        running = None
        steps.pop(0)
        if not steps[0:1] or steps[0] in GENERATORS:
            return 0.2
    step = steps.pop(0)
    if step is setup:
        step()
    else:
        checks.run(step.__name__, step)
    if steps:
        return 0.3
    checks.finish()


bpy.app.timers.register(tick, first_interval=1.0)
