"""Inside Blender: datablocks and files behave. A duplicate (Shift+D, Alt+D) regenerates into its
own datablock and leaves the original alone; a prototype the user replaced survives Regenerate;
files made before the first save move beside the .blend (relative paths); a project copied
elsewhere opens and renders; a .blend copied without its files regenerates them on load."""
import shutil
import sys
from pathlib import Path

import bpy
import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from addon_harness import Checks, arguments, enable_addon, render_alpha  # noqa: E402

args = arguments()
OUT = Path(args.out) / "files"
OUT.mkdir(parents=True, exist_ok=True)
enable_addon(args.python_path)

from ifsforge_addon import outputs  # noqa: E402

checks = Checks()


def scene():
    return bpy.context.scene


def generate(kind, preset, **values):
    """Generates from the scene's design with the preset loaded and settings changed."""
    context = bpy.context
    for obj in context.selected_objects:
        obj.select_set(False)
    bpy.ops.ifsforge.load_preset(preset=preset)
    for name, value in values.items():
        setattr(scene().ifsforge.settings, name, value)
    getattr(bpy.ops.ifsforge, f"generate_{kind}")()
    return context.active_object


def select_only(obj):
    for other in bpy.context.selected_objects:
        other.select_set(False)
    obj.select_set(True)
    bpy.context.view_layer.objects.active = obj


def duplicate_regenerates_into_its_own_datablock():
    scene().ifsforge.cache_folder = str(OUT / "cache")
    for linked in (False, True):  # Shift+D (a volume's data is shared by default), Alt+D
        original = generate("volume", "sierpinski_tetrahedron.json", volume_resolution=16)
        file, data = original.data.filepath, original.data
        select_only(original)
        bpy.ops.object.duplicate(linked=linked)
        copy = bpy.context.active_object
        assert copy is not original and copy.data == data, "the duplicate should start sharing the volume"
        copy.ifsforge.settings.volume_resolution = 24
        bpy.ops.ifsforge.regenerate()
        assert copy.data != data and original.data == data, "Regenerate repointed the original's volume"
        assert original.data.filepath == file and Path(bpy.path.abspath(file)).is_file()
        assert copy.data.filepath != file and Path(bpy.path.abspath(copy.data.filepath)).is_file()
        assert original.ifsforge.settings.volume_resolution == 16
    terrain = generate("terrain", "barnsley_fern.json", terrain_source='RANDOM', terrain_resolution=17)
    select_only(terrain)
    bpy.ops.object.duplicate(linked=True)
    copy = bpy.context.active_object
    copy.ifsforge.settings.terrain_resolution = 33
    bpy.ops.ifsforge.regenerate()
    assert (len(terrain.data.vertices), len(copy.data.vertices)) == (17 * 17, 33 * 33)


def replaced_prototype_survives_regenerate():
    obj = generate("instances", "sierpinski_tetrahedron.json", instance_depth=2, instance_primitives="sphere")
    collection = bpy.data.collections[f"{obj.name} primitives"]
    sphere = collection.objects["000 sphere"]
    bpy.ops.mesh.primitive_monkey_add()
    monkey = bpy.context.active_object
    suzanne = monkey.data
    bpy.data.objects.remove(monkey)
    sphere.data = suzanne  # the user's replacement
    select_only(obj)
    obj.ifsforge.settings.instance_depth = 3
    bpy.ops.ifsforge.regenerate()
    assert len(obj.data.vertices) == 64
    kept = [o for o in collection.objects]
    assert len(kept) == 1 and kept[0].data == suzanne and len(suzanne.vertices) == 507, \
        [(o.name, o.data.name) for o in kept]
    # The evaluated instances are Suzannes: 64 of them.
    meshes = [i.object.data.original.name for i in bpy.context.evaluated_depsgraph_get().object_instances
              if i.is_instance and i.parent and i.parent.original == obj]
    assert meshes == [suzanne.name] * 64, meshes[:3]


def instance_inputs():
    """The instances' node group inputs: Scale multiplies every instance's scale; an Object, or a
    Collection's children, replace the prototypes."""
    obj = generate("instances", "sierpinski_tetrahedron.json", instance_depth=2, instance_primitives="sphere")
    modifier = obj.modifiers["ifsforge instances"]
    sockets = modifier.node_group.inputs

    def seen():
        depsgraph = bpy.context.evaluated_depsgraph_get()
        return sorted((i.object.data.original.name, round(i.matrix_world.to_scale()[0], 5))
                      for i in depsgraph.object_instances if i.is_instance and i.parent and i.parent.original == obj)

    before = seen()
    assert len(before) == 16 and before[0][0] == f"{obj.name} sphere"
    modifier[sockets["Scale"].identifier] = 2.0
    obj.update_tag()
    doubled = seen()
    assert [round(2 * s, 4) for _, s in before] == [round(s, 4) for _, s in doubled], (before[:2], doubled[:2])
    bpy.ops.mesh.primitive_cone_add()
    cone = bpy.context.active_object
    modifier[sockets["Object"].identifier] = cone
    obj.update_tag()
    assert {name for name, _ in seen()} == {cone.data.name} and len(seen()) == 16
    modifier[sockets["Object"].identifier] = None
    mine = bpy.data.collections.new("mine")
    bpy.ops.mesh.primitive_cube_add()
    mine.objects.link(bpy.context.active_object)
    modifier[sockets["Collection"].identifier] = mine
    obj.update_tag()
    assert {name for name, _ in seen()} == {bpy.context.active_object.data.name}


def files_move_beside_the_blend_and_travel():
    bpy.ops.wm.read_homefile(use_empty=False)
    assert not bpy.data.filepath and not scene().ifsforge.cache_folder
    obj = generate("volume", "sierpinski_tetrahedron.json", volume_resolution=24)
    before = Path(obj.data.filepath)
    assert before.is_absolute() and before.parent == outputs.session_folder() and before.is_file(), before
    # A fractal texture made before the save: its picture and its code go beside the .blend too.
    source = bpy.data.images.new("swatch", 32, 32)
    source.pixels.foreach_set(np.random.default_rng(1).random(32 * 32 * 4).astype(np.float32))
    scene().ifsforge_fractal_texture.source = source
    assert bpy.ops.ifsforge.fractal_texture() == {'FINISHED'}
    texture = scene().ifsforge_fractal_texture.result
    code = Path(texture[outputs.CODE_KEY])
    assert code.parent == outputs.session_folder() and code.is_file()
    project = OUT / "project"
    project.mkdir(exist_ok=True)
    bpy.ops.wm.save_as_mainfile(filepath=str(project / "scene.blend"))
    assert obj.data.filepath == f"//scene_ifsforge/{before.name}", obj.data.filepath
    assert obj.ifsforge.output == obj.data.filepath
    assert texture[outputs.CODE_KEY] == f"//scene_ifsforge/{code.name}", texture[outputs.CODE_KEY]
    assert texture.filepath.startswith("//scene_ifsforge/") and Path(bpy.path.abspath(texture.filepath)).is_file()
    # Copied: the originals stay while an undo step may name them (until this session ends).
    assert before.exists() and (project / "scene_ifsforge" / before.name).is_file()
    assert (project / "scene_ifsforge" / code.name).is_file()
    # A later save deletes what nothing can name: a generated file of an earlier session that the
    # saved state does not use; what this session made stays (an undo step may name it).
    stale = project / "scene_ifsforge" / "Old_volume-0123456789ab.vdb"
    stale.write_bytes(b"stale")
    mine = project / "scene_ifsforge" / "notes.txt"  # not the add-on's: never touched
    mine.write_text("the artist's")
    bpy.ops.wm.save_mainfile()
    assert not stale.exists() and mine.exists() and (project / "scene_ifsforge" / before.name).is_file()
    # The file on disk says so too (the handler saved again): copy the project and open the copy.
    elsewhere = OUT / "elsewhere" / "copied"
    shutil.rmtree(elsewhere.parent, ignore_errors=True)
    shutil.copytree(project, elsewhere)
    shutil.rmtree(project)
    name = obj.name
    bpy.ops.wm.open_mainfile(filepath=str(elsewhere / "scene.blend"))
    assert not before.exists() and not code.exists(), "the ended session left its cache files"
    obj = bpy.data.objects[name]
    path = Path(bpy.path.abspath(obj.data.filepath))
    assert path.parent == elsewhere / "scene_ifsforge" and path.is_file(), path
    alpha = render_alpha(obj, OUT / "copied.png", size=24, samples=4)[:, :, 3]
    assert alpha.max() > 0.2 and (alpha < 0.01).any(), (alpha.min(), alpha.max())


def missing_files_regenerate_on_load():
    source = OUT / "elsewhere" / "copied" / "scene.blend"
    bare = OUT / "bare"
    shutil.rmtree(bare, ignore_errors=True)
    bare.mkdir()
    shutil.copy(source, bare / "renamed.blend")  # without its folder, under another name
    bpy.ops.wm.open_mainfile(filepath=str(bare / "renamed.blend"))
    obj = next(o for o in bpy.data.objects if o.type == 'VOLUME')
    path = Path(bpy.path.abspath(obj.data.filepath))
    assert path.parent == bare / "renamed_ifsforge" and path.is_file(), path
    assert obj.data.filepath.startswith("//renamed_ifsforge/")
    obj.data.grids.load()
    assert sorted(g.name for g in obj.data.grids) == ["density"]
    density = obj.data.grids["density"]
    assert density.load()
    # The regenerated grid is the one the copied project had (deterministic output).
    original = next((source.parent / "scene_ifsforge").glob("*.vdb"))
    import ifsforge
    voxels = [[g["active_voxels"] for g in ifsforge.read_vdb_info(str(p))["grids"]] for p in (path, original)]
    assert path.name == original.name and voxels[0] == voxels[1] and voxels[0][0] > 0, voxels


checks.run("duplicate_regenerates_into_its_own_datablock", duplicate_regenerates_into_its_own_datablock)
checks.run("replaced_prototype_survives_regenerate", replaced_prototype_survives_regenerate)
checks.run("instance_inputs", instance_inputs)
checks.run("files_move_beside_the_blend_and_travel", files_move_beside_the_blend_and_travel)
checks.run("missing_files_regenerate_on_load", missing_files_regenerate_on_load)
checks.finish()
