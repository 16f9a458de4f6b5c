"""Inside Blender: every generator runs on a sample and makes what it should (object types, grid
names, instance counts and transforms, vertex counts, palette pixels), Regenerate follows a
changed parameter, keyframes regenerate per frame (renders included), the parameters survive
save and reload, Cycles renders the results, long work cancels, and bad input is reported."""
import json
import shutil
import sys
import time
from pathlib import Path

import bpy
import numpy as np
from mathutils import Vector

sys.path.insert(0, str(Path(__file__).resolve().parent))
from addon_harness import Checks, arguments, close, enable_addon, expect_report, render_alpha  # noqa: E402

args = arguments()
OUT = Path(args.out) / "generate"
OUT.mkdir(parents=True, exist_ok=True)
SAMPLES = Path(__file__).resolve().parents[2] / "samples" / "systems"
enable_addon(args.python_path)

import ifsforge  # noqa: E402

from ifsforge_addon import generators, operators_generate, state  # noqa: E402
from ifsforge_addon.properties import snapshot  # noqa: E402

checks = Checks()
context = bpy.context
scene = context.scene
design = scene.ifsforge.system
settings = scene.ifsforge.settings
scene.ifsforge.cache_folder = str(OUT / "cache")
for obj in list(bpy.data.objects):
    if obj.type == 'MESH':
        bpy.data.objects.remove(obj)


def load(name):
    """Back to the scene's design (nothing selected), with a preset loaded."""
    for obj in context.selected_objects:
        obj.select_set(False)
    bpy.ops.ifsforge.load_preset(preset=name)
    return state.system_of(design)


def generate(kind):
    """Generate from the scene's design: deselect first (a selected generated object would be
    the one edited and generated from)."""
    for obj in context.selected_objects:
        obj.select_set(False)
    getattr(bpy.ops.ifsforge, f"generate_{kind}")()
    return context.active_object


def volume():
    system = load("sierpinski_tetrahedron.json")
    settings.volume_resolution, settings.volume_algorithm, settings.volume_density = 32, 'prr', 'binary'
    generate("volume")
    obj = context.active_object
    assert obj.type == 'VOLUME' and obj.ifsforge.kind == 'VOLUME' and obj.name == "Sierpinski tetrahedron volume"
    assert sorted(g.name for g in obj.data.grids) == ["density"]
    expected = len(ifsforge.render_volume(system, "prr", 32))
    assert obj.ifsforge.summary.startswith(f"{expected:,} voxels"), obj.ifsforge.summary
    path = Path(bpy.path.abspath(obj.data.filepath))
    assert path.parent == OUT / "cache" and path.suffix == ".vdb"
    shader = obj.data.materials[0].node_tree.nodes["Principled Volume"]
    assert shader.inputs["Density Attribute"].default_value == "density"
    # Blender's idea of the volume: its evaluated bounding box is the grid's, the unit cube, centred
    # on the object's origin (the pivot artists expect), which is the system's point (1/2, 1/2, 1/2).
    box = np.array(obj.evaluated_get(context.evaluated_depsgraph_get()).bound_box)
    close(box.min(axis=0), [-0.5] * 3, 0.05)
    close(box.max(axis=0), [0.5] * 3, 0.05)
    close(box.min(axis=0) + box.max(axis=0), [0.0] * 3, 1e-6)  # the box's centre is the origin
    close(obj.ifsforge.origin, [0.5, 0.5, 0.5], 0.05)
    # The file's transform centres the grid (no modifier moves Blender's shared grid): the box
    # stays put however often the scene is evaluated, across frame changes, and in world space
    # it sits around the object's location.
    assert not obj.modifiers, [m.name for m in obj.modifiers]
    obj.location = (2.0, -1.0, 0.5)
    boxes = []
    for frame in (1, 2, 3, 1, 5):
        scene.frame_set(frame)
        obj.update_tag()  # evaluated again, its modifiers included (a grid moved by one drifts)
        obj.data.update_tag()
        depsgraph = context.evaluated_depsgraph_get()
        depsgraph.update()
        evaluated = obj.evaluated_get(depsgraph)
        boxes.append([tuple(evaluated.matrix_world @ Vector(c)) for c in evaluated.bound_box])
    checks.values["volume_world_boxes"] = [np.array(b).min(axis=0).tolist() for b in boxes]
    for b in boxes:
        close(b, boxes[0], 0.0)
    close(np.array(boxes[0]).mean(axis=0), obj.location, 1e-6)
    obj.location = (0.0, 0.0, 0.0)
    # Regenerate after a change of the stored system: without the copy at (0, 0, 1/2) the
    # tetrahedron is the Sierpinski triangle in the plane z = 0: fewer voxels, a new file, and
    # Blender shows it (its box is then a few voxels thick, whatever margin the grid keeps).
    obj.ifsforge.system.maps.remove(3)
    bpy.ops.ifsforge.regenerate()
    box = np.array(obj.evaluated_get(context.evaluated_depsgraph_get()).bound_box)
    assert box[:, 2].max() - box[:, 2].min() < 0.3, box
    fewer = len(ifsforge.render_volume(state.system_of(obj.ifsforge.system), "prr", 32))
    assert fewer < expected and obj.ifsforge.summary.startswith(f"{fewer:,} voxels")
    after = Path(bpy.path.abspath(obj.data.filepath))
    assert after != path and after.is_file() and path.is_file()  # a new file; the old one stays for undo
    checks.values["tetrahedron_vdb_after"] = [str(after), fewer]
    # Colour layouts get a colour grid that the material reads.
    load("volume_sierpinski_pyramid_rgb.json")
    generate("volume")
    coloured = context.active_object
    assert sorted(g.name for g in coloured.data.grids) == ["color", "density"]
    shader = coloured.data.materials[0].node_tree.nodes["Principled Volume"]
    assert shader.inputs["Color Attribute"].default_value == "color"
    checks.values["pyramid_vdb"] = str(bpy.path.abspath(coloured.data.filepath))
    alpha = render_alpha(coloured, OUT / "volume.png")[:, :, 3]
    checks.values["volume_render_covered"] = float((alpha > 0.05).mean())
    assert (alpha > 0.05).mean() > 0.02, "the volume rendered empty"
    assert alpha[0, 0] < 0.01 and alpha[-1, -1] < 0.01, "the volume fills the frame"


def instances():
    system = load("sierpinski_tetrahedron.json")
    settings.instance_depth, settings.instance_primitives, settings.instance_color_by = 3, "sphere,box", 'first-map'
    generate("instances")
    obj = context.active_object
    expected = ifsforge.instances(system, depth=3, primitives="sphere,box", color_source="first-map")
    assert (len(expected), len(obj.data.vertices)) == (64, 64), (obj.name, len(expected), len(obj.data.vertices))
    depsgraph = context.evaluated_depsgraph_get()
    placed = [(i.matrix_world.copy(), i.object.original.name) for i in depsgraph.object_instances
              if i.is_instance and i.parent.original == obj]
    assert len(placed) == 64, len(placed)
    assert all(name == "000 sphere" for _, name in placed)  # no k channel: primitive 0
    # Each instance's matrix is the leaf's frame scaled by d, at the leaf's position.
    matrices = sorted(placed, key=lambda m: tuple(np.round(m[0].translation, 5)))
    order = np.lexsort(np.round(expected.positions, 5).T[::-1])
    for (matrix, _), k in zip(matrices, order):
        m = np.array(matrix)
        close(m[:3, 3], expected.positions[k] - np.array(obj.ifsforge.origin) + np.array(obj.location), 1e-5)
        close(m[:3, :3], expected.frames[k].T * expected.scales[k], 1e-5)
    collection = bpy.data.collections["Sierpinski tetrahedron instances"]
    assert obj.name in collection.objects
    node = obj.modifiers["ifsforge instances"].node_group
    assert node is not None and any(n.bl_idname == 'GeometryNodeInstanceOnPoints' for n in node.nodes)
    colours = np.zeros(64 * 4, np.float32)
    obj.data.attributes["ifs_color"].data.foreach_get("color_srgb", colours)
    close(colours.reshape(-1, 4), expected.colors, 5e-4)  # stored linear: the sRGB round trip rounds
    material = bpy.data.materials["Sierpinski tetrahedron instances"]  # not "... instances instances"
    attribute = material.node_tree.nodes["Attribute"]
    assert (attribute.attribute_type, attribute.attribute_name) == ('INSTANCER', "ifs_color")
    # (An instancer's own bounding box is empty: frame the leaves' balls.)
    radius = expected.scales.max()
    box = (expected.positions.min(axis=0) - radius, expected.positions.max(axis=0) + radius)
    pixels = render_alpha(obj, OUT / "instances.png", size=48, samples=4, box=box)
    checks.values["instances_render_covered"] = float((pixels[:, :, 3] > 0.5).mean())
    assert (pixels[:, :, 3] > 0.5).mean() > 0.03, "the instances rendered empty"
    # Four first maps, four colours: the render shows more than one hue.
    lit = pixels[pixels[:, :, 3] > 0.9][:, :3]
    hues = {tuple(np.round(c / max(c.max(), 1e-6), 1)) for c in lit}
    assert len(hues) > 2, hues
    # Regenerate at depth 2: 16 instances.
    obj.ifsforge.settings.instance_depth = 2
    bpy.ops.ifsforge.regenerate()
    assert len(obj.data.vertices) == 16


def terrain_and_palette():
    system = load("barnsley_fern.json")
    settings.terrain_source, settings.terrain_grid, settings.terrain_controls = 'ATTRACTOR', 'regular', 9
    settings.terrain_resolution, settings.terrain_size, settings.terrain_height = 33, 4.0, 1.5
    settings.palette_recipe, settings.palette_entries, settings.palette_rows = "", 128, 8
    generate("terrain")
    obj = context.active_object
    assert obj.type == 'MESH' and obj.ifsforge.kind == 'TERRAIN'
    # The same terrain from the module: identical vertices.
    from ifsforge_addon.generate_terrain import TerrainGenerator
    values = generators.get('TERRAIN').resolve(dict(settings_values()))
    terrain = ifsforge.make_terrain(TerrainGenerator.controls(system, values), 33, 33)
    mesh = terrain.mesh(up="z")
    assert len(obj.data.vertices) == len(mesh["positions"]) == 33 * 33, (len(obj.data.vertices), len(mesh["positions"]))
    co = np.zeros(33 * 33 * 3, np.float32)
    obj.data.vertices.foreach_get("co", co)
    close(co.reshape(-1, 3), fitted(mesh["positions"], 1.5), 1e-5)
    close([co[2::3].min(), co[2::3].max()], [0.0, 1.5], 1e-6)  # "Height 1.5" spans 1.5
    # One quad per cell, split by Blender into exactly the core's triangles; every lattice edge once.
    me = obj.data
    assert len(me.polygons) == 32 * 32 and len(me.edges) == 2 * 32 * 33, (len(me.polygons), len(me.edges))
    me.calc_loop_triangles()
    tris = np.zeros(len(me.loop_triangles) * 3, np.int64)
    me.loop_triangles.foreach_get("vertices", tris)
    def as_set(triangles):  # each triangle's corners sorted, then the triangles sorted
        triangles = np.sort(np.asarray(triangles, np.int64).reshape(-1, 3), axis=1)
        return triangles[np.lexsort(triangles.T[::-1])]
    # Blender splits a quad along its other diagonal where that one would fold it over (its
    # tessellator's flip test), so a few cells of a rough terrain differ from the core's split.
    blender_tris = {tuple(t) for t in as_set(tris).tolist()}
    core_tris = {tuple(t) for t in as_set(mesh["triangles"]).tolist()}
    assert len(blender_tris) == len(core_tris) == 2 * 32 * 32
    differing = len(core_tris - blender_tris)
    assert differing <= 0.02 * len(core_tris), differing
    ends = np.zeros(len(me.edges) * 2, np.int64)
    me.edges.foreach_get("vertices", ends)
    assert len({tuple(sorted(e)) for e in ends.reshape(-1, 2).tolist()}) == len(me.edges)
    # The palette coordinate the material reads: the core's u (normalised height) per vertex.
    level = np.zeros(33 * 33, np.float32)
    me.attributes["ifs_level"].data.foreach_get("value", level)
    close(level, mesh["uvs"][:, 0], 1e-7)
    assert obj.data.materials[0].node_tree.nodes["Attribute"].attribute_name == "ifs_level"
    texture = obj.data.materials[0].node_tree.nodes["Image Texture"]
    assert tuple(texture.image.size) == (128, 1)
    pixels = render_alpha(obj, OUT / "terrain.png", samples=4)
    assert (pixels[:, :, 3] > 0.5).mean() > 0.1
    # The palette texture on its own: an image datablock, entries x rows, the palette's colours.
    generate("palette")
    image = bpy.data.images["Barnsley fern palette"]
    assert image.ifsforge.kind == 'PALETTE' and tuple(image.size) == (128, 8)
    recipe = ifsforge.read_palette_recipe(str(SAMPLES.parent / "terrain" / "earth.json"))
    expected = recipe.make(128).colors
    loaded = np.array(image.pixels[:]).reshape(8, 128, 4)[0, :, :3]
    if image.is_float:  # 16-bit PNGs load as linear floats
        loaded = np.where(loaded <= 0.0031308, loaded * 12.92, 1.055 * np.power(np.maximum(loaded, 0), 1 / 2.4) - 0.055)
    close(loaded, expected, 2e-3)
    # A random circular terrain and one from a recipe.
    settings.terrain_source, settings.terrain_grid = 'RANDOM', 'circular'
    generate("terrain")
    assert context.active_object.ifsforge.summary.startswith("circular terrain")
    recipe = OUT / "small.json"
    recipe.write_text(json.dumps({"format": "ifsforge-terrain/1", "name": "small", "grid": "regular",
                                  "heights": [[0, 0.1, 0.2, 0.1, 0], [0.1, 0.4, 0.5, 0.3, 0.1], [0.2, 0.5, 1, 0.5, 0.2],
                                              [0.1, 0.3, 0.5, 0.4, 0.1], [0, 0.1, 0.2, 0.1, 0]],
                                  "roughness": {"u": 0.3, "v": 0.3, "signs": "random", "seed": 1},
                                  "size": [2, 2], "resolution": [17, 17], "palette": "earth.json"}))
    shutil.copy(SAMPLES.parent / "terrain" / "earth.json", OUT / "earth.json")
    settings.terrain_source, settings.terrain_recipe = 'RECIPE', str(recipe)
    obj = generate("terrain")
    assert len(obj.data.vertices) == 17 * 17 and obj.ifsforge.summary.startswith("regular terrain, 17x17")


def terrain_same_seed():
    """A random terrain from the panel: the height field the CLI and Python make from the same
    settings and seed (test_blender_addon compares the bytes)."""
    load("barnsley_fern.json")
    settings.terrain_source, settings.terrain_grid, settings.terrain_controls = 'RANDOM', 'irregular', 9
    settings.terrain_resolution, settings.terrain_size, settings.terrain_height = 65, 4.0, 1.0
    # Values a float32 Blender property holds exactly, so the add-on passes what the CLI parses.
    settings.terrain_roughness, settings.seed = (0.375, 0.25), 7
    obj = generate("terrain")
    from ifsforge_addon.generate_terrain import TerrainGenerator
    values = generators.get('TERRAIN').resolve(dict(settings_values()))
    terrain = ifsforge.make_terrain(TerrainGenerator.controls(None, values), 65, 65)
    co = np.zeros(65 * 65 * 3, np.float32)
    obj.data.vertices.foreach_get("co", co)
    close(co.reshape(-1, 3), fitted(terrain.mesh(up="z")["positions"], 1.0), 1e-5)  # the object is that terrain
    path = OUT / "terrain_same_seed.png"
    ifsforge.write_png(str(path), terrain.height_image(65, 65), 16)
    checks.values["terrain_same_seed_png"] = str(path)


def fitted(positions, height):
    """A terrain's vertices as the object holds them: heights mapped onto [0, height] (the core's
    fractal interpolation overshoots its controls), x and y as the core has them (centred)."""
    positions = np.array(positions, np.float64)
    z = positions[:, 2]
    positions[:, 2] = (z - z.min()) * height / (z.max() - z.min())
    return positions


def settings_values():
    return {p.identifier: (getattr(settings, p.identifier) if isinstance(getattr(settings, p.identifier),
                                                                         (str, int, float, bool))
                           else tuple(getattr(settings, p.identifier)))
            for p in settings.bl_rna.properties if p.identifier != "rna_type"}


def iso_surface():
    system = load("sierpinski_tetrahedron.json")
    settings.volume_resolution, settings.mesh_iso, settings.mesh_adaptivity = 16, 0.5, 0.0
    generate("mesh")
    obj = context.active_object
    assert obj.type == 'MESH' and obj.ifsforge.kind == 'MESH'
    expected = ifsforge.volume_to_mesh(ifsforge.render_volume(system, "prr", 16))
    vertices = (len(obj.data.vertices), len(expected["positions"]))
    assert vertices[0] == vertices[1] > 0, vertices
    # The mesher's quads come as triangle pairs (a, b, c), (a, c, d): Blender gets the quads back.
    assert len(obj.data.polygons) * 2 == len(expected["triangles"])
    obj.data.calc_loop_triangles()
    assert len(obj.data.loop_triangles) == len(expected["triangles"])
    lo, hi = np.array(obj.bound_box[0]), np.array(obj.bound_box[6])
    # The attractor's box [0, 1]^3, to within a voxel or so, around the object's origin.
    close(lo, [-0.5, -0.5, -0.5], 0.1)
    close(hi, [0.5, 0.5, 0.5], 0.1)
    close(np.array(obj.ifsforge.origin) + lo, [0, 0, 0], 0.1)


def keyframes_regenerate_per_frame():
    load("sierpinski_tetrahedron.json")
    settings.volume_resolution = 24
    generate("volume")
    obj = context.active_object
    item = obj.ifsforge.system.maps[0]
    scene.frame_set(1)
    item.scale = (0.5, 0.5, 0.5)
    item.keyframe_insert("scale", frame=1)
    item.scale = (0.25, 0.25, 0.25)
    item.keyframe_insert("scale", frame=2)
    assert generators.animated(obj)
    scene.frame_set(2)
    second = Path(bpy.path.abspath(obj.data.filepath))
    assert second.is_file(), second
    summary_2 = obj.ifsforge.summary
    scene.frame_set(1)
    first = Path(bpy.path.abspath(obj.data.filepath))
    assert first != second and first.is_file() and second.is_file()  # one file per state
    assert obj.ifsforge.summary != summary_2
    # Rendering the animation regenerates every frame: two frames, two different pictures.
    render_alpha(obj, OUT / "unused.png", size=24, samples=4)  # sets up camera, engine and film
    scene.frame_start, scene.frame_end = 1, 2
    scene.render.filepath = str(OUT / "anim_")
    bpy.ops.render.render(animation=True)
    frames = []
    for k in (1, 2):
        image = bpy.data.images.load(str(OUT / f"anim_{k:04d}.png"), check_existing=False)
        frames.append(np.array(image.pixels[:]))
        bpy.data.images.remove(image)
    alpha = [f[3::4] for f in frames]
    assert alpha[0].max() > 0.05 and alpha[1].max() > 0.05, (alpha[0].max(), alpha[1].max())
    assert np.abs(alpha[0] - alpha[1]).max() > 0.05, np.abs(alpha[0] - alpha[1]).max()
    obj.animation_data_clear()


def save_and_reload():
    load("volume_coral_6d.json")
    settings.volume_resolution, settings.volume_algorithm, settings.volume_density = 20, 'prr', 'hits'
    generate("volume")
    name = context.active_object.name
    context.active_object.ifsforge.system.maps[1].rotation = (10.0, 20.0, 30.0)
    path = OUT / "generated.blend"
    bpy.ops.wm.save_as_mainfile(filepath=str(path))
    bpy.ops.wm.open_mainfile(filepath=str(path))
    obj = bpy.data.objects[name]
    data = obj.ifsforge
    assert (data.kind, data.settings.volume_resolution, data.settings.volume_density) == ('VOLUME', 20, 'hits'), (
        data.kind, data.settings.volume_resolution, data.settings.volume_density)
    assert tuple(data.system.maps[1].rotation) == (10.0, 20.0, 30.0) and data.system.layout == "xyz+rgb"
    # Saved next to the .blend, the cache folder still given: regenerate works after the reload.
    bpy.context.view_layer.objects.active = obj
    bpy.ops.ifsforge.regenerate()
    assert Path(bpy.path.abspath(obj.data.filepath)).is_file()
    assert sorted(g.name for g in obj.data.grids) == ["color", "density"]


def cancelling():
    load("menger_sponge.json")
    settings.volume_resolution = 512
    owner, system_pg, settings_pg = state.target(context)
    plan = operators_generate.Plan(context, generators.get('VOLUME'), owner, snapshot(system_pg, settings_pg),
                                   new=True)
    plan.job.start()
    deadline = time.perf_counter() + 30
    while plan.job.fraction <= 0 and time.perf_counter() < deadline:
        time.sleep(0.01)
    plan.job.cancel()
    started = time.perf_counter()
    plan.job.wait(30)
    assert plan.job.done and isinstance(plan.job.error, ifsforge.Cancelled), plan.job.error
    checks.values["cancel_seconds"] = time.perf_counter() - started
    assert not list((OUT / "cache").glob("Menger_sponge_volume*")), "a cancelled job left a file"


def bad_input():
    load("barnsley_fern.json")
    expect_report(lambda: bpy.ops.ifsforge.generate_volume(), "planar", "xyz")
    expect_report(lambda: bpy.ops.ifsforge.generate_mesh(), "planar")
    load("sierpinski_tetrahedron.json")
    settings.instance_primitives = "blob"
    expect_report(lambda: bpy.ops.ifsforge.generate_instances(), "blob")
    settings.instance_primitives = "sphere"
    settings.terrain_source, settings.terrain_recipe = 'RECIPE', str(OUT / "no_such_recipe.json")
    expect_report(lambda: bpy.ops.ifsforge.generate_terrain(), "no_such_recipe.json")
    settings.terrain_source = 'ATTRACTOR'
    settings.palette_recipe = str(OUT / "missing_palette.json")
    expect_report(lambda: bpy.ops.ifsforge.generate_palette(), "missing_palette.json")
    settings.palette_recipe = ""
    for m in design.maps:
        m.scale = (1.3, 1.3, 1.3)
    for op in (bpy.ops.ifsforge.generate_volume, bpy.ops.ifsforge.generate_instances,
               bpy.ops.ifsforge.generate_mesh):
        expect_report(op, "no attractor")


checks.run("volume", volume)
checks.run("instances", instances)
checks.run("terrain_and_palette", terrain_and_palette)
checks.run("terrain_same_seed", terrain_same_seed)
checks.run("iso_surface", iso_surface)
checks.run("keyframes_regenerate_per_frame", keyframes_regenerate_per_frame)
checks.run("cancelling", cancelling)
checks.run("bad_input", bad_input)
checks.run("save_and_reload", save_and_reload)
checks.finish()
