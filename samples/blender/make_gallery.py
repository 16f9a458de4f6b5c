"""Gallery items of the Blender add-on: scenes built by the add-on's operators in real Blender
(headless) and rendered by Cycles.

make(out) writes into out/blender/:
  volume_pyramid.png      the RGB Sierpinski pyramid as a Volume object (Principled Volume reading
                          the .vdb's density and color grids), 192 voxels across
  instances_coral.png     the 6D coral's vector IFS: 16k instanced spheres coloured per instance
  terrain_fern.png        a terrain whose control heights are the Barnsley fern's density, with the
                          'earth' fractal palette as its material
  iso_tetrahedron.png     the iso-surface mesh of the Sierpinski tetrahedron's volume
  design.blend            the scene, with every generator's parameters stored on its object
  preview.png             the viewport's live preview (collage colours) -- only when xvfb-run exists
Run alone: python3 samples/blender/make_gallery.py [OUT]   (Blender must be installed)
"""
import importlib.util
import os
import shutil
import subprocess
import sys
from pathlib import Path

HERE = Path(__file__).resolve()
ROOT = HERE.parents[2]
SIZE = (480, 360)


def make(out):
    import ifsforge
    folder = Path(out) / "blender"
    folder.mkdir(parents=True, exist_ok=True)
    python_path = str(Path(ifsforge.__file__).resolve().parents[1])
    result = subprocess.run(["blender", "-b", "--factory-startup", "--python-exit-code", "1",
                             "--python", str(HERE), "--", python_path,
                             str(folder)], capture_output=True, text=True)
    lines = [line[len("ITEM "):] for line in result.stdout.splitlines() if line.startswith("ITEM ")]
    if result.returncode != 0 or not lines:
        raise RuntimeError(f"Blender gallery failed:\n{result.stdout[-3000:]}\n{result.stderr[-3000:]}")
    for line in lines:
        print(f"  {line}")
    if shutil.which("xvfb-run"):
        gui = ROOT / "tests" / "blender" / "addon_gui.py"
        subprocess.run(["xvfb-run", "-a", "-s", "-screen 0 1024x800x24", "blender", "--factory-startup",
                        "--enable-event-simulate", "--python", str(gui), "--", "--python-path", python_path, "--out",
                        str(folder / "gui_run")], capture_output=True, text=True)
        shot = folder / "gui_run" / "gui" / "window.png"
        if shot.is_file():
            shutil.copy(shot, folder / "preview.png")
            print("  preview.png: the viewport preview and the IFS panel (Blender under xvfb)")
        shutil.rmtree(folder / "gui_run", ignore_errors=True)


def inside_blender(python_path, folder):
    """Runs in Blender: builds each item with the add-on's operators and renders it."""
    import time

    import addon_utils
    import bpy
    import numpy as np
    from mathutils import Vector
    sys.path[:0] = [python_path, str(ROOT / "blender_addon")]
    addon_utils.enable("ifsforge_addon", default_set=True, handle_error=None)
    context, scene = bpy.context, bpy.context.scene
    scene.ifsforge.cache_folder = str(folder / "cache")
    for obj in list(bpy.data.objects):
        if obj.type == 'MESH':
            bpy.data.objects.remove(obj)
    world = scene.world
    world.use_nodes = True
    world.node_tree.nodes["Background"].inputs["Color"].default_value = (0.55, 0.6, 0.7, 1.0)
    world.node_tree.nodes["Background"].inputs["Strength"].default_value = 0.8
    sun = bpy.data.objects["Light"]
    sun.data.type, sun.data.energy = 'SUN', 3.0
    sun.rotation_euler = (0.6, 0.2, 0.8)
    scene.render.engine = 'CYCLES'
    scene.cycles.device, scene.cycles.samples, scene.cycles.use_denoising = 'CPU', 16, False
    scene.render.resolution_x, scene.render.resolution_y = SIZE
    scene.render.image_settings.file_format = 'PNG'

    def generate(preset, kind, **settings):
        for obj in context.selected_objects:
            obj.select_set(False)
        bpy.ops.ifsforge.load_preset(preset=preset)
        for key, value in settings.items():
            setattr(scene.ifsforge.settings, key, value)
        getattr(bpy.ops.ifsforge, f"generate_{kind}")()
        return context.active_object

    def world_box(obj):
        """The object's bounds in world space: generated objects sit at the 3D cursor with their
        origin at their bounds' centre, so frame them where they are. A mesh by its vertices (an
        instancer's vertices are its instances' places), anything else by its evaluated box."""
        if obj.type == 'MESH' and len(obj.data.vertices):
            local = np.empty(3 * len(obj.data.vertices), np.float64)
            obj.data.vertices.foreach_get("co", local)
            points = local.reshape(-1, 3)
            corners = [obj.matrix_world @ Vector(p) for p in (points.min(axis=0), points.max(axis=0))]
        else:
            evaluated = obj.evaluated_get(context.evaluated_depsgraph_get())
            corners = [evaluated.matrix_world @ Vector(corner) for corner in evaluated.bound_box]
        return ([min(c[k] for c in corners) for k in range(3)], [max(c[k] for c in corners) for k in range(3)])

    def shoot(obj, name, direction=(1.0, -1.2, 0.9), text=""):
        start = time.perf_counter()
        for other in scene.objects:
            other.hide_render = other is not obj and other.type not in ('CAMERA', 'LIGHT')
        lo, hi = (Vector(corner) for corner in world_box(obj))
        centre, radius = (lo + hi) / 2, (hi - lo).length / 2
        direction = Vector(direction).normalized()
        camera = scene.camera
        camera.location = centre + direction * radius * 3.2
        camera.rotation_euler = (-direction).to_track_quat('-Z', 'Y').to_euler()
        camera.data.clip_end = radius * 20
        scene.render.filepath = str(folder / name)
        bpy.ops.render.render(write_still=True)
        # A picture of the background alone is a framing bug, not a sample: stop the gallery.
        image = bpy.data.images.load(str(folder / name))
        pixels = np.asarray(image.pixels[:], np.float32).reshape(-1, 4)[:, :3]
        covered = float(np.mean(np.abs(pixels - pixels[0]).max(axis=1) > 0.02))
        bpy.data.images.remove(image)
        if covered < 0.05:
            raise RuntimeError(f"{name}: the object covers {covered:.1%} of the picture")
        print(f"ITEM {name}: {text} ({time.perf_counter() - start:.1f} s render, {covered:.0%} of the frame)",
              flush=True)

    volume = generate("volume_sierpinski_pyramid_rgb.json", "volume", volume_resolution=192, volume_strength=60.0)
    shoot(volume, "volume_pyramid.png", direction=(1.0, -1.2, 0.55), text=volume.ifsforge.summary)
    instances = generate("volume_coral_6d.json", "instances", instance_primitives="sphere", instance_depth=7)
    shoot(instances, "instances_coral.png", text=instances.ifsforge.summary)
    terrain = generate("barnsley_fern.json", "terrain", terrain_source='ATTRACTOR', terrain_controls=33,
                       terrain_resolution=257, terrain_size=4.0, terrain_height=0.8, terrain_roughness=(0.15, 0.15))
    shoot(terrain, "terrain_fern.png", direction=(0.3, -1.0, 0.8), text=terrain.ifsforge.summary)
    surface = generate("sierpinski_tetrahedron.json", "mesh", volume_resolution=96)
    shoot(surface, "iso_tetrahedron.png", direction=(-0.5, -1.0, 0.45), text=surface.ifsforge.summary)
    bpy.ops.wm.save_as_mainfile(filepath=str(folder / "design.blend"))
    print("ITEM design.blend: the scene; each object keeps its system and settings (select it, edit, Regenerate)")


if __name__ == "__main__":
    if importlib.util.find_spec("bpy") is None:  # plain Python: start Blender on this file
        make(Path(sys.argv[1] if len(sys.argv) > 1 else "out").resolve())
    else:
        argv = sys.argv[sys.argv.index("--") + 1:]
        inside_blender(argv[0], Path(argv[1]))
        sys.stdout.flush()
        os._exit(0)
