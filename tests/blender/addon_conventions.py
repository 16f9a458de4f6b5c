"""Inside Blender: the add-on follows Blender's conventions. Generate operators carry their
settings (what F9 re-runs with), add at the 3D cursor, and take the shipped presets; the Add,
Import and Export menus hold the entries; the preferences set resolutions and threads; the
glTF importer reads an ifsforge .glb without any patch in the script."""
import sys
import types
from pathlib import Path

import bpy

sys.path.insert(0, str(Path(__file__).resolve().parent))
from addon_harness import Checks, arguments, close, enable_addon  # noqa: E402

args = arguments()
OUT = Path(args.out) / "conventions"
OUT.mkdir(parents=True, exist_ok=True)
module = enable_addon(args.python_path)

import ifsforge  # noqa: E402

from ifsforge_addon import menus, preferences  # noqa: E402

checks = Checks()
context = bpy.context


def deselect():
    for obj in context.selected_objects:
        obj.select_set(False)


def operator_settings_and_cursor():
    context.scene.ifsforge.cache_folder = str(OUT / "cache")
    bpy.ops.ifsforge.load_preset(preset="barnsley_fern.json")
    scene_settings = context.scene.ifsforge.settings
    scene_settings.terrain_resolution = 65
    context.scene.cursor.location = (1.0, -2.0, 3.0)
    deselect()
    # A first run copies the edited settings; a re-run (what F9 does) uses the operator's own.
    bpy.ops.ifsforge.generate_terrain()
    first = context.active_object
    assert len(first.data.vertices) == 65 * 65 and tuple(first.location) == (1.0, -2.0, 3.0)
    # (F9 re-runs with changed operator settings: tests/blender/addon_gui.py, it needs a window.)
    for kind in ("volume", "instances", "terrain", "mesh", "image"):
        cls = getattr(bpy.types, f"IFSFORGE_OT_generate_{kind}")
        assert {'REGISTER', 'UNDO', 'PRESET'} <= set(cls.bl_options), cls.bl_options
        properties = getattr(bpy.ops.ifsforge, f"generate_{kind}").get_rna_type().properties
        assert "settings" in properties and "sample" in properties
        # What F9's "+" writes into a user preset: the system and every setting (neither hidden
        # nor SKIP_SAVE); the first run of a new invocation takes the edited values instead.
        for name in ("settings", "system"):
            assert not properties[name].is_skip_save and not properties[name].is_hidden, (kind, name)


def negative_zero_does_not_rebuild():
    """-0.0 where 0.0 was (a keyframe, a script) is the same value: no rebuild, same file."""
    deselect()
    bpy.ops.ifsforge.load_preset(preset="sierpinski_tetrahedron.json")
    context.scene.ifsforge.settings.volume_resolution = 12
    bpy.ops.ifsforge.generate_volume()
    obj = context.active_object
    path, built = obj.data.filepath, obj.ifsforge.built_from
    rotation = obj.ifsforge.system.maps[0].rotation
    assert rotation[0] == 0.0
    rotation[:] = [-v if v == 0 else v for v in rotation]  # each zero's sign flipped
    obj.ifsforge.settings.view = [-v if v == 0 else v for v in obj.ifsforge.settings.view]
    context.scene.frame_set(context.scene.frame_current + 1)
    assert (obj.data.filepath, obj.ifsforge.built_from) == (path, built)


def shipped_presets():
    """Every shipped preset names a sample that exists and settings that exist; one runs."""
    folder = menus.SHIPPED_PRESETS
    files = sorted(folder.glob("*/*.py"))
    assert len(files) >= 10 and {p.parent.name for p in files} >= {
        f"ifsforge.generate_{k}" for k in ("volume", "instances", "terrain", "mesh", "image")}
    for path in files:
        op = types.SimpleNamespace(settings=types.SimpleNamespace())
        code = path.read_text().replace("import bpy\n", "")
        exec(code, {"bpy": types.SimpleNamespace(context=types.SimpleNamespace(active_operator=op))})
        assert (Path(module.__file__).parents[2] / "samples" / "systems" / op.sample).is_file(), path
        settings_rna = context.scene.ifsforge.settings.bl_rna.properties
        assert all(name in settings_rna for name in vars(op.settings)), (path, vars(op.settings))
    # A sample generates without touching the edited design's map list first.
    deselect()
    bpy.ops.ifsforge.generate_volume(sample="sierpinski_tetrahedron.json")
    assert context.active_object.ifsforge.system.name == "Sierpinski tetrahedron"
    # Copied where Blender's preset menu of the operator looks.
    user = Path(bpy.utils.user_resource('SCRIPTS', path="presets/operator/ifsforge.generate_volume"))
    assert (user / "Menger sponge 243.py").is_file()
    assert any(Path(p) == user for p in bpy.utils.preset_paths("operator/ifsforge.generate_volume"))


def menus_hold_the_entries():
    # Tooltips say what happens: Bake writes .vdb sequences and meshes in the .blend (Debian's
    # Blender has no Alembic), and the two POV-Ray exports are told apart.
    assert "Alembic" not in bpy.types.IFSFORGE_OT_bake_animation.bl_rna.description
    assert bpy.types.IFSFORGE_OT_export_povray.bl_rna.name != bpy.types.IFSFORGE_OT_export_povray_scene.bl_rna.name
    assert menus.draw_add in bpy.types.VIEW3D_MT_add._dyn_ui_initialize()
    assert menus.draw_import in bpy.types.TOPBAR_MT_file_import._dyn_ui_initialize()
    assert menus.draw_export in bpy.types.TOPBAR_MT_file_export._dyn_ui_initialize()
    for kind, _, _ in menus.ADD_ENTRIES:
        assert hasattr(bpy.ops.ifsforge, f"generate_{kind.lower()}")


def preferences_apply():
    prefs = preferences.get()
    prefs.volume_resolution, prefs.terrain_resolution, prefs.image_size = 77, 129, 333
    prefs.threads = 1
    assert ifsforge.default_threads() == 1
    prefs.threads = 0
    assert ifsforge.default_threads() >= 1
    bpy.ops.wm.read_homefile(use_empty=False)
    settings = bpy.context.scene.ifsforge.settings
    assert (settings.volume_resolution, settings.terrain_resolution, settings.image_size) == (77, 129, 333)


def gltf_import_without_a_patch():
    import numpy
    assert "bool" in numpy.__dict__  # the add-on gave it back
    path = OUT / "square.glb"
    ifsforge.write_mesh(str(path), numpy.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], numpy.float32),
                        numpy.array([[0, 1, 2], [0, 2, 3]], numpy.uint32))
    before = set(bpy.data.objects)
    bpy.ops.import_scene.gltf(filepath=str(path))
    new = [o for o in bpy.data.objects if o not in before]
    assert len(new) == 1 and len(new[0].data.vertices) == 4
    # write_mesh turns ifsforge's z-up points to glTF's y up and Blender's importer turns them
    # back: the square lies in Blender's xy plane as written.
    points = sorted(tuple(v.co) for v in new[0].data.vertices)
    close(points, [(0, 0, 0), (0, 1, 0), (1, 0, 0), (1, 1, 0)], 1e-6)


checks.run("operator_settings_and_cursor", operator_settings_and_cursor)
checks.run("negative_zero_does_not_rebuild", negative_zero_does_not_rebuild)
checks.run("shipped_presets", shipped_presets)
checks.run("menus_hold_the_entries", menus_hold_the_entries)
checks.run("preferences_apply", preferences_apply)
checks.run("gltf_import_without_a_patch", gltf_import_without_a_patch)
checks.finish()
