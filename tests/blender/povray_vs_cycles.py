"""Inside Blender: one scene (coloured instances, a terrain, a coloured iso-surface and a colour
volume, a sun and a coloured world) rendered by Cycles and, through File > Export > POV-Ray scene,
by the real POV-Ray, whole and each object alone, at a low resolution. The images are compared
outside Blender (tests/python/test_povray_vs_cycles.py); this script renders them and names them
in its RESULT values. Cycles uses the Standard view transform: POV-Ray writes plain sRGB."""
import sys
from pathlib import Path

import bpy
from mathutils import Vector

sys.path.insert(0, str(Path(__file__).resolve().parent))
from addon_harness import Checks, arguments, enable_addon  # noqa: E402

args = arguments()
OUT = Path(args.out) / "povray_vs_cycles"
OUT.mkdir(parents=True, exist_ok=True)
enable_addon(args.python_path)

checks = Checks()
context = bpy.context
scene = context.scene
WIDTH, HEIGHT = 128, 96
WORLD = (0.30, 0.34, 0.42)  # linear
# Where each object's box centre goes, and its longest side there.
PLACES = {"instances": ((-1.1, 0.9, 0.8), 1.1), "terrain": ((1.1, 0.9, 0.3), 2.0),
          "isosurface": ((-1.1, -1.1, 0.8), 1.6), "volume": ((1.1, -1.1, 0.8), 1.6)}


def generate(kind, preset, **values):
    for obj in context.selected_objects:
        obj.select_set(False)
    bpy.ops.ifsforge.load_preset(preset=preset)
    for name, value in values.items():
        setattr(scene.ifsforge.settings, name, value)
    getattr(bpy.ops.ifsforge, f"generate_{kind}")()
    return context.active_object


def place(obj, centre, size):
    """Scales and moves `obj` so that its world box has its longest side `size` around `centre`."""
    context.view_layer.update()
    if obj.type == 'MESH':  # an instances object's box is that of its points (the instances have none)
        corners = [obj.matrix_world @ v.co for v in obj.data.vertices]
    else:
        corners = [obj.matrix_world @ Vector(c) for c in obj.bound_box]
    lo = Vector([min(c[i] for c in corners) for i in range(3)])
    hi = Vector([max(c[i] for c in corners) for i in range(3)])
    factor = size / max(hi - lo)
    obj.scale = obj.scale * factor
    obj.location = Vector(centre) - ((lo + hi) / 2 - obj.location) * factor
    context.view_layer.update()


def build():
    for obj in list(scene.objects):
        if obj.type != 'CAMERA':
            bpy.data.objects.remove(obj)
    objects = {
        "instances": generate("instances", "menger_sponge.json", instance_depth=1, instance_color_by='first-map'),
        "terrain": generate("terrain", "barnsley_fern.json", terrain_source='RANDOM', terrain_grid='regular',
                            terrain_resolution=33, terrain_size=3.0, terrain_height=1.0),
        "isosurface": generate("mesh", "volume_sierpinski_pyramid_rgb.json", volume_resolution=32),
        "volume": generate("volume", "volume_sierpinski_pyramid_rgb.json", volume_resolution=32),
    }
    for name, obj in objects.items():
        place(obj, *PLACES[name])
    sun = bpy.data.objects.new("Sun", bpy.data.lights.new("Sun", 'SUN'))
    scene.collection.objects.link(sun)
    sun.data.energy = 3.0
    sun.rotation_euler = (0.6, 0.3, 0.8)
    world = scene.world or bpy.data.worlds.new("World")
    scene.world = world
    world.use_nodes = True
    background = next(n for n in world.node_tree.nodes if n.type == 'BACKGROUND')
    background.inputs["Color"].default_value = (*WORLD, 1.0)
    background.inputs["Strength"].default_value = 1.0
    camera = scene.camera
    camera.location = (0.0, -5.8, 4.2)
    camera.rotation_euler = (Vector((0.0, -0.1, 0.6)) - camera.location).to_track_quat('-Z', 'Y').to_euler()
    camera.data.type, camera.data.lens = 'PERSP', 45
    r = scene.render
    r.engine = 'CYCLES'
    scene.cycles.device, scene.cycles.samples, scene.cycles.use_denoising = 'CPU', 24, False
    scene.view_settings.view_transform, scene.view_settings.look = 'Standard', 'None'
    scene.view_settings.exposure, scene.view_settings.gamma = 0.0, 1.0
    r.resolution_x, r.resolution_y, r.resolution_percentage = WIDTH, HEIGHT, 100
    r.film_transparent = False
    r.image_settings.file_format, r.image_settings.color_mode = 'PNG', 'RGB'
    checks.values["objects"] = {name: obj.name for name, obj in objects.items()}
    return objects


def render_both(objects, shown, name):
    """Cycles and POV-Ray images of the scene with only `shown` of `objects` rendered."""
    for key, obj in objects.items():
        obj.hide_render = key not in shown
    context.view_layer.update()
    scene.render.filepath = str(OUT / f"cycles_{name}.png")
    bpy.ops.render.render(write_still=True)
    result = bpy.ops.ifsforge.export_povray_scene(filepath=str(OUT / f"povray_{name}.pov"), render=True)
    assert result == {'FINISHED'}, result
    checks.values.setdefault("images", {})[name] = [str(OUT / f"cycles_{name}.png"), str(OUT / f"povray_{name}.png")]


def renders():
    objects = build()
    render_both(objects, list(objects), "all")
    text = (OUT / "povray_all.pov").read_text()
    assert "background { rgb <0.3, 0.34, 0.42> }" in text, text[:600]
    assert text.count("srgb <") >= 20 and "density_file df3" in text, "per-instance colours and coloured media"
    for name in objects:
        render_both(objects, [name], name)
    checks.values["world"] = list(WORLD)


checks.run("renders", renders)
checks.finish()
