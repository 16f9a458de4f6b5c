"""The artist's journey, step 2 (tests/python/test_blender_journey.py runs it): Blender with a
window (xvfb-run), the add-on installed from the zip and enabled in the user's preferences, a
fresh scene. Every Shift+A > IFS entry, found in the drawn menu by its label, makes an object at
the 3D cursor on the first click; Generate Palette and a random terrain ask for no system;
File > Import > "IFS system" reaches the importer; the .blend is saved, undone and redone,
regenerated and undone, and saved again with every file it names on disk; F9's "+" saves a
preset holding every setting. The checks run from a timer once the window is up; operators run
as a click runs them (undo=True: an undo step, and registered as the last operation).
    xvfb-run blender --python tests/blender/journey_scene.py -- --out DIR"""
import argparse
import sys
from pathlib import Path

import bpy
import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from addon_harness import Checks, close, menu_entries, operator_by_label  # noqa: E402

argv = sys.argv[sys.argv.index("--") + 1:]
parser = argparse.ArgumentParser()
parser.add_argument("--out", required=True)
args = parser.parse_args(argv)
OUT = Path(args.out)
PROJECT = OUT / "project"
BLEND = PROJECT / "scene.blend"
bpy.context.preferences.view.show_splash = False
checks = Checks()
made = {}  # menu label -> object name


def override():
    window = bpy.context.window_manager.windows[0]
    area = next(a for a in window.screen.areas if a.type == 'VIEW_3D')
    region = next(r for r in area.regions if r.type == 'WINDOW')
    return bpy.context.temp_override(window=window, area=area, region=region)


def files_named():
    """Every file path the scene's datablocks name, absolute."""
    paths = [v.filepath for v in bpy.data.volumes] + [i.filepath for i in bpy.data.images if i.source == 'FILE']
    return [Path(bpy.path.abspath(p)) for p in paths if p]


def fresh_scene():
    import addon_utils
    import ifsforge
    assert addon_utils.check("ifsforge_addon") == (True, True), "the installed add-on is not enabled"
    addon = Path(bpy.utils.user_resource('SCRIPTS', path="addons")) / "ifsforge_addon"
    assert Path(ifsforge.__file__).resolve().is_relative_to(addon.resolve()), ifsforge.__file__
    design = bpy.context.scene.ifsforge.system
    assert len(design.maps) == 0 and not bpy.data.filepath  # nothing chosen yet
    assert not [o for o in bpy.data.objects if o.ifsforge.kind != 'NONE']


def draw_menus():
    """Blender draws Shift+A, its IFS sub-menu and File > Import (a draw function's exception
    would print a traceback, which fails the test), one per tick; Esc closes each."""
    window = bpy.context.window_manager.windows[0]
    for name in ("VIEW3D_MT_add", "IFSFORGE_MT_add", "TOPBAR_MT_file_import"):
        with override():
            bpy.ops.wm.call_menu(name=name)
        checks.values.setdefault("menus_drawn", []).append(name)
        yield
        window.event_simulate('ESC', 'PRESS')
        window.event_simulate('ESC', 'RELEASE')
        yield


def every_add_entry():
    """Shift+A > IFS: each entry of the menu, picked by its label, makes an object at the 3D cursor
    from the generator's own sample (the design is empty)."""
    add = [(kind, text, name) for kind, text, name, _ in menu_entries(bpy.types.VIEW3D_MT_add, bpy.context)]
    assert ("menu", "IFS", "IFSFORGE_MT_add") in add, add
    labels = [text for _, text, _, _ in menu_entries(bpy.types.IFSFORGE_MT_add, bpy.context)]
    assert labels == ["Volume", "Instances", "Terrain", "Iso-surface", "Image"], labels
    scene = bpy.context.scene
    for k, label in enumerate(labels):
        cursor = (3.0 * k - 6.0, 1.0, 0.5)
        scene.cursor.location = cursor
        for obj in bpy.context.selected_objects:  # (a selected generated object is what Generate edits)
            obj.select_set(False)
        operator, properties = operator_by_label(bpy.types.IFSFORGE_MT_add, bpy.context, label)
        with override():
            assert operator('EXEC_DEFAULT', True, **properties) == {'FINISHED'}, label
        obj = bpy.context.active_object
        assert obj is not None and obj.select_get(), label
        close(obj.location, cursor, 1e-6)
        made[label] = obj.name
        checks.values[f"add_{label}"] = (obj.type, obj.name)
    volume, instances, terrain, iso, image = (bpy.data.objects[made[label]] for label in labels)
    assert volume.type == 'VOLUME' and volume.data.grids.is_loaded and len(volume.data.grids) >= 1
    assert volume.ifsforge.system.name == "Sierpinski pyramid", volume.ifsforge.system.name
    assert instances.ifsforge.kind == 'INSTANCES' and len(instances.data.vertices) > 100
    assert terrain.ifsforge.kind == 'TERRAIN' and len(terrain.data.vertices) == 257 * 257
    assert iso.ifsforge.kind == 'MESH' and len(iso.data.polygons) > 1000
    assert image.type == 'EMPTY' and image.empty_display_type == 'IMAGE' and image.data.size[0] > 0
    assert image.data.ifsforge.kind == 'IMAGE' and image.data.ifsforge.system.name == "Barnsley fern"
    # Each object's pivot is the centre of what it shows (a terrain: of its base, on the cursor).
    for obj in (volume, instances, iso):
        depsgraph = bpy.context.evaluated_depsgraph_get()
        corners = np.array([tuple(c) for c in obj.evaluated_get(depsgraph).bound_box])
        if obj is not instances:  # (an instancer's own bounds are its points)
            close((corners.min(axis=0) + corners.max(axis=0)) / 2, (0, 0, 0), 0.05)
    assert bpy.context.scene.ifsforge.system.maps.__len__() == 0, "the design was filled behind the artist's back"
    # What each was made from is what it stores: a frame change does not rebuild it.
    from ifsforge_addon import generators, properties
    for obj in (volume, instances, terrain, iso, image.data):
        stored = generators.digest(properties.snapshot(obj.ifsforge.system, obj.ifsforge.settings))
        assert stored == obj.ifsforge.built_from, obj.name
    # Checked, the instances (15625 spheres of 325 vertices) are hidden in the viewport, as an
    # artist hides a heavy object: on xvfb-run's software OpenGL they cost 4 of every redraw's
    # 5 CPU seconds, and each save's thumbnail as much. They still render (hide_render).
    instances.hide_set(True)


def no_system_needed():
    """Generate Palette and a random terrain with the design still empty."""
    for obj in bpy.context.selected_objects:
        obj.select_set(False)
    settings = bpy.context.scene.ifsforge.settings
    with override():
        assert bpy.ops.ifsforge.generate_palette('EXEC_DEFAULT', True) == {'FINISHED'}
    palette = next(i for i in bpy.data.images if i.ifsforge.kind == 'PALETTE')
    assert palette.size[0] == settings.palette_entries
    settings.terrain_source = 'RANDOM'
    before = set(bpy.data.objects)
    with override():
        assert bpy.ops.ifsforge.generate_terrain('EXEC_DEFAULT', True) == {'FINISHED'}
    terrain = next(o for o in bpy.data.objects if o not in before)
    assert len(terrain.ifsforge.system.maps) == 0  # made from no system at all
    # "Height 1.0" spans 0 to 1.0 above the cursor.
    z = np.array([v.co.z for v in terrain.data.vertices])
    close([z.min(), z.max()], [0.0, settings.terrain_height], 1e-4)
    settings.terrain_source = 'ATTRACTOR'


def import_from_the_file_menu():
    for obj in bpy.context.selected_objects:  # (else the import edits the selected object's system)
        obj.select_set(False)
    operator, properties = operator_by_label(bpy.types.TOPBAR_MT_file_import, bpy.context, "IFS system (.json, .ifs)")
    sample = Path(bpy.utils.user_resource('SCRIPTS', path="addons")) / "ifsforge_addon/presets/systems/maple_leaf.json"
    with override():
        assert operator('EXEC_DEFAULT', True, filepath=str(sample), **properties) == {'FINISHED'}
    assert bpy.context.scene.ifsforge.system.name == "Maple leaf", bpy.context.scene.ifsforge.system.name


def distinct_labels():
    operators = [getattr(bpy.types, name) for name in dir(bpy.types) if name.startswith("IFSFORGE_OT_")]
    labels = {}
    for cls in operators:
        labels.setdefault(cls.bl_rna.name, []).append(cls.__name__)
    shared = {label: names for label, names in labels.items() if len(names) > 1}
    assert not shared, shared


def save_undo_redo():
    """Save, undo and redo across the save, Regenerate and undo it, save again: every file the
    saved states name is on disk, beside the .blend."""
    PROJECT.mkdir(parents=True, exist_ok=True)
    with override():
        assert bpy.ops.wm.save_as_mainfile(filepath=str(BLEND)) == {'FINISHED'}
    named = files_named()
    assert named and all(p.is_file() and p.parent == PROJECT / "scene_ifsforge" for p in named), named
    volume = bpy.data.objects[made["Volume"]]
    assert volume.data.filepath.startswith("//scene_ifsforge/"), volume.data.filepath
    first = Path(bpy.path.abspath(volume.data.filepath))
    with override():  # Regenerate at another resolution: a new file, the old one kept for undo
        bpy.context.view_layer.objects.active = volume
        volume.select_set(True)
        volume.ifsforge.settings.volume_resolution = 40
        bpy.ops.ed.undo_push(message="resolution")
        assert bpy.ops.ifsforge.regenerate('EXEC_DEFAULT', True) == {'FINISHED'}
    second = Path(bpy.path.abspath(bpy.data.objects[made["Volume"]].data.filepath))
    assert second != first and second.is_file() and first.is_file()
    with override():
        for _ in range(4):
            bpy.ops.ed.undo()
        undone = [bpy.data.objects.get(name) for name in made.values()]
        checks.values["objects_after_undo"] = sum(o is not None for o in undone)
        assert all(p.is_file() for p in files_named()), [p for p in files_named() if not p.is_file()]
        bpy.ops.wm.save_mainfile()
        assert all(p.is_file() for p in files_named())
        for _ in range(4):
            bpy.ops.ed.redo()
        bpy.ops.ed.undo()  # back before Regenerate: the first file again
    volume = bpy.data.objects[made["Volume"]]
    assert Path(bpy.path.abspath(volume.data.filepath)) == first and first.is_file()
    assert volume.data.grids.load(), volume.data.grids.error_message
    with override():
        assert bpy.ops.wm.save_mainfile() == {'FINISHED'}
    named = files_named()
    assert all(p.is_file() and p.parent == PROJECT / "scene_ifsforge" for p in named), named
    checks.values["saved_files"] = sorted(p.name for p in named)


def user_preset():
    """F9's "+" on a finished Generate Volume: the preset file holds the system and every setting."""
    for obj in bpy.context.selected_objects:
        obj.select_set(False)
    bpy.ops.ifsforge.load_preset(preset="sierpinski_tetrahedron.json")
    design = bpy.context.scene.ifsforge
    design.system.maps[0].rotation[2] = 12.5  # the artist's own system
    design.settings.volume_resolution, design.settings.volume_density, design.settings.seed = 20, 'hits', 3
    design.settings.volume_strength = 3.5
    with override():
        assert bpy.ops.ifsforge.generate_volume('EXEC_DEFAULT', True) == {'FINISHED'}
        assert bpy.context.active_operator.bl_idname == "IFSFORGE_OT_generate_volume"
        assert bpy.ops.wm.operator_preset_add(name="My tetrahedron", operator="IFSFORGE_OT_generate_volume") \
            == {'FINISHED'}
    obj = bpy.context.active_object
    preset = Path(bpy.utils.user_resource('SCRIPTS', path="presets/operator/ifsforge.generate_volume")) / \
        "My_tetrahedron.py"
    text = preset.read_text()
    for line in ("op.settings.volume_resolution = 20", "op.settings.volume_density = 'hits'",
                 "op.settings.seed = 3", "op.settings.volume_strength = 3.5", "op.system = "):
        assert line in text, (line, text)
    checks.values["preset"] = str(preset)
    checks.values["preset_object"] = {"file": Path(obj.data.filepath).name, "summary": obj.ifsforge.summary,
                                      "rotation": obj.ifsforge.system.maps[0].rotation[2]}
    with override():
        assert bpy.ops.wm.save_mainfile() == {'FINISHED'}


def render_what_was_made():
    """A picture of the fresh-scene objects (looked at by a person; the disabled-add-on render
    of step 3 is the one the test measures)."""
    scene = bpy.context.scene
    scene.render.engine = 'CYCLES'
    scene.cycles.samples, scene.cycles.use_denoising = 16, False
    scene.render.resolution_x, scene.render.resolution_y, scene.render.resolution_percentage = 320, 180, 100
    camera = scene.camera
    camera.location, camera.rotation_euler = (0.0, -20.0, 10.0), (1.1, 0.0, 0.0)
    for obj in bpy.data.objects:  # the startup scene's cube would hide the terrain
        obj.hide_render = obj.name == "Cube"
    scene.render.filepath = str(OUT / "fresh_scene.png")
    bpy.ops.render.render(write_still=True)
    with override():
        assert bpy.ops.wm.save_mainfile() == {'FINISHED'}


steps = [fresh_scene, draw_menus, every_add_entry, no_system_needed, import_from_the_file_menu, distinct_labels,
         save_undo_redo, user_preset, render_what_was_made]
running = None


def tick():
    global running
    if steps[0] is draw_menus:  # a generator: one tick per yield
        running = running or draw_menus()
        try:
            if next(running, "done") != "done":
                return 0.3
            checks.results["draw_menus"] = "ok"
        except Exception as error:
            checks.results["draw_menus"] = f"{type(error).__name__}: {error}"
        steps.pop(0)
        return 0.3
    step = steps.pop(0)
    checks.run(step.__name__, step)
    if steps:
        return 0.2
    checks.finish()


bpy.app.timers.register(tick, first_interval=1.0)
