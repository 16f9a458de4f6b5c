"""Inside Blender: a volume looks the same at any resolution and in any density mode with the
default material (its density is an average per world unit over the grid's box), Regenerate
applies a changed Material density, and a colour volume keeps the saturation of its colours
(against the iso-surface of the same system). Tiny Cycles renders: sizes where the truth still
shows."""
import colorsys
import sys
from pathlib import Path

import bpy
import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from addon_harness import Checks, arguments, enable_addon, render_alpha  # noqa: E402

args = arguments()
OUT = Path(args.out) / "volume_look"
OUT.mkdir(parents=True, exist_ok=True)
enable_addon(args.python_path)

from ifsforge_addon.properties import IFSFORGE_PG_settings  # noqa: E402

DEFAULT_STRENGTH = IFSFORGE_PG_settings.__annotations__["volume_strength"].keywords["default"]
checks = Checks()
context = bpy.context
scene = context.scene
scene.ifsforge.cache_folder = str(OUT / "cache")
settings = scene.ifsforge.settings
for obj in list(bpy.data.objects):
    if obj.type == 'MESH':
        bpy.data.objects.remove(obj)


def generate(kind, preset, **values):
    for obj in context.selected_objects:
        obj.select_set(False)
    bpy.ops.ifsforge.load_preset(preset=preset)
    for name, value in values.items():
        setattr(settings, name, value)
    getattr(bpy.ops.ifsforge, f"generate_{kind}")()
    return context.active_object


def look(obj, name, box=None):
    """(opacity, RGBA): the mean alpha of a small transparent-film render, and the render, seen from
    the diagonal of the object's evaluated box."""
    if box is None:
        corners = np.array(obj.evaluated_get(context.evaluated_depsgraph_get()).bound_box)
        box = (corners.min(axis=0) + obj.location, corners.max(axis=0) + obj.location)
    rgba = render_alpha(obj, OUT / f"{name}.png", size=40, samples=16, box=box)
    return float(rgba[..., 3].mean()), rgba


def at_every_resolution(preset, name):
    """(opacity, brightness) by resolution: the system's volume at 128, 256 and 512 with the
    default material, each seen in the first one's box around the object's origin."""
    opacity, brightness, box = {}, {}, None
    for resolution in (128, 256, 512):
        obj = generate("volume", preset, volume_resolution=resolution,
                       volume_density='binary', volume_strength=DEFAULT_STRENGTH)
        checks.values.setdefault(f"{name}_voxels_by_resolution", {})[resolution] = obj.ifsforge.summary.split(" ")[0]
        if box is None:
            corners = np.array(obj.evaluated_get(context.evaluated_depsgraph_get()).bound_box)
            box = (corners.min(axis=0), corners.max(axis=0))
        opacity[resolution], rgba = look(obj, f"{name}_{resolution}", box=box)
        brightness[resolution] = float(rgba[..., :3].mean())
        obj.hide_render = True
    checks.values[f"{name}_opacity_by_resolution"] = opacity
    checks.values[f"{name}_brightness_by_resolution"] = brightness
    return opacity, brightness


def spread(series):
    return (max(series.values()) - min(series.values())) / max(series.values())


def same_at_every_resolution():
    # The pyramid (the Volume entry's own sample) fills 1/5 of its box's voxels fewer at each
    # doubling: at a constant density it would fade with every finer resolution.
    opacity, brightness = at_every_resolution("sierpinski_pyramid.json", "pyramid")
    assert min(opacity.values()) > 0.05, opacity  # visible with the default material
    assert spread(opacity) <= 0.05 and spread(brightness) <= 0.05, (opacity, brightness)


def thin_fractal_at_every_resolution():
    """The tetrahedron (dimension 2: its mass lies on ever thinner sheets): the same mass at every
    resolution, yet finer sheets put it on fewer lines of sight, where the opacity saturates, so
    it fades somewhat per doubling (recorded; the bound is what the mass rule gives, wider than
    the pyramid's 5%)."""
    opacity, _ = at_every_resolution("sierpinski_tetrahedron.json", "tetrahedron")
    assert min(opacity.values()) > 0.05 and spread(opacity) <= 0.12, opacity


def every_density_mode_visible():
    opacity = {}
    for mode in ('binary', 'hits', 'measure'):
        obj = generate("volume", "sierpinski_tetrahedron.json", volume_resolution=48, volume_density=mode,
                       volume_strength=DEFAULT_STRENGTH)
        opacity[mode] = look(obj, f"mode_{mode}")[0]
        obj.hide_render = True
    checks.values["opacity_by_mode"] = opacity
    assert min(opacity.values()) > 0.05, opacity
    assert min(opacity.values()) > 0.5 * max(opacity.values()), opacity


def regenerate_applies_material_density():
    obj = generate("volume", "sierpinski_tetrahedron.json", volume_resolution=24, volume_density='binary')
    shader = next(n for n in obj.data.materials[0].node_tree.nodes if n.bl_idname == 'ShaderNodeVolumePrincipled')
    before = shader.inputs["Density"].default_value
    obj.ifsforge.settings.volume_strength *= 4
    bpy.ops.ifsforge.regenerate()
    after = shader.inputs["Density"].default_value
    checks.values["shader_density"] = [before, after]
    assert abs(after / before - 4) < 1e-4, (before, after)
    obj.hide_render = True


def saturation(rgba):
    """The mean HSV saturation of the pixels something covers."""
    covered = rgba[rgba[..., 3] > 0.3][:, :3]
    return float(np.mean([colorsys.rgb_to_hsv(*np.clip(c / max(c.max(), 1e-6), 0, 1))[1] for c in covered]))


def colour_keeps_saturation():
    volume = generate("volume", "volume_sierpinski_pyramid_rgb.json", volume_resolution=48, volume_density='binary')
    _, volume_rgba = look(volume, "colour_volume")
    volume.hide_render = True
    iso = generate("mesh", "volume_sierpinski_pyramid_rgb.json", volume_resolution=48)
    _, iso_rgba = look(iso, "colour_iso")
    iso.hide_render = True
    values = {"volume": saturation(volume_rgba), "iso_surface": saturation(iso_rgba)}
    checks.values["saturation"] = values
    assert values["volume"] >= 0.8 * values["iso_surface"], values


checks.run("same_at_every_resolution", same_at_every_resolution)
checks.run("thin_fractal_at_every_resolution", thin_fractal_at_every_resolution)
checks.run("every_density_mode_visible", every_density_mode_visible)
checks.run("regenerate_applies_material_density", regenerate_applies_material_density)
checks.run("colour_keeps_saturation", colour_keeps_saturation)
checks.finish()
