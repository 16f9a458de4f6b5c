"""Inside Blender: the add-on enables, designs systems (presets, Fractint and JSON import and
export, the map list, parameters, layouts), previews them (the data the viewport would draw),
renders an image, morphs and animates, keeps everything through save and reload, and turns
bad input into error reports."""
import sys
import time
from pathlib import Path

import bpy
import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from addon_harness import Checks, arguments, close, enable_addon, expect_report  # noqa: E402

args = arguments()
OUT = Path(args.out)
SAMPLES = Path(__file__).resolve().parents[2] / "samples" / "systems"
enable_addon(args.python_path)

import ifsforge  # noqa: E402

from ifsforge_addon import codec, preview, state  # noqa: E402

checks = Checks()
context = bpy.context
scene = context.scene
design = scene.ifsforge.system


def system():
    return state.system_of(design)


def registered():
    expected = ["load_preset", "import_system", "export_json", "export_povray", "new_system", "map_add",
                "map_remove", "map_duplicate", "map_move", "library_save", "library_load", "library_remove",
                "morph_set", "morph_apply", "copy_to_design", "view_preview", "regenerate", "generate_image",
                "generate_volume", "generate_instances", "generate_terrain", "generate_palette", "generate_mesh"]
    missing = [name for name in expected if not hasattr(bpy.types, "IFSFORGE_OT_" + name)]
    assert not missing, f"operators not registered: {missing}"
    assert hasattr(bpy.types, "IFSFORGE_PT_design") and bpy.types.IFSFORGE_PT_design.bl_category == "IFS"
    assert bpy.context.scene.ifsforge.preview.count == 200000


def presets_reproduce_the_samples():
    # Every JSON sample loads through the preset operator into the properties and comes back
    # as the same maps (properties are single precision: 1e-6).
    for path in sorted(SAMPLES.glob("*.json")):
        bpy.ops.ifsforge.load_preset(preset=path.name)
        original = ifsforge.read_json(str(path))
        built = system()
        assert built.layout == original.layout and len(built) == len(original), path.name
        for a, b in zip(built.maps, original.maps):
            close(a.matrix, b.matrix, 2e-6)
            close(a.offset, b.offset, 2e-6)
        close(built.probabilities, original.probabilities, 1e-6)
    # Fractint entries are presets too.
    bpy.ops.ifsforge.load_preset(preset="classic.ifs:fern")
    assert system().name == "fern" and len(system()) == 4


def analysis_follows_parameters():
    bpy.ops.ifsforge.load_preset(preset="sierpinski_triangle.json")
    analysis = state.analyse(design)
    assert analysis.classification == "hyperbolic"
    close(analysis.factors, [0.5, 0.5, 0.5], 1e-7)
    # Eq. 5: scale (0.5, 0.25) rotated by 30 degrees contracts by 0.5.
    m = design.maps[0]
    m.scale = (0.5, 0.25, 1.0)
    m.rotation = (30.0, 30.0, 0.0)
    close(state.analyse(design).factors[0], 0.5, 1e-7)
    c, s = np.cos(np.radians(30)), np.sin(np.radians(30))
    close(system().maps[0].matrix, [[0.5 * c, -0.25 * s], [0.5 * s, 0.25 * c]], 1e-7)
    # One expanding map, rarely used: average-contractive (Eq. 14), then divergent.
    design.probabilities = 'explicit'
    m.scale = (1.5, 1.5, 1.0)
    m.probability = 0.1
    assert state.analyse(design).classification == "average-contractive"
    close(state.analyse(design).factors[0], 1.5, 1e-6)
    for item in design.maps:
        item.scale = (1.6, 1.6, 1.0)
    analysis = state.analyse(design)
    assert analysis.classification == "divergent" and "no attractor" in analysis.error


def map_list_editing():
    bpy.ops.ifsforge.load_preset(preset="sierpinski_triangle.json")
    before = ifsforge.render(system(), "prr", 96, window=(-0.1, -0.1, 1.1, 1.1), binary=True).mask
    design.active_map = 1
    bpy.ops.ifsforge.map_duplicate()
    assert len(design.maps) == 4 and design.active_map == 2
    close(system().maps[2].matrix, system().maps[1].matrix, 0)
    # A duplicated map adds no new piece: the attractor covers the same pixels (deterministic
    # point-recursive rendering in a fixed window).
    mask = ifsforge.render(system(), "prr", 96, window=(-0.1, -0.1, 1.1, 1.1), binary=True).mask
    assert np.array_equal(mask, before) and mask.sum() > 1000
    bpy.ops.ifsforge.map_move(direction='UP')
    assert design.active_map == 1
    bpy.ops.ifsforge.map_add()
    assert len(design.maps) == 5 and design.active_map == 4
    close(design.maps[4].color, ifsforge.piece_color(4), 1e-7)
    bpy.ops.ifsforge.map_remove()
    bpy.ops.ifsforge.map_remove()
    assert len(design.maps) == 3
    for _ in range(2):
        bpy.ops.ifsforge.map_remove()
    assert len(design.maps) == 1
    # The last map stays: a system needs one.
    assert not bpy.ops.ifsforge.map_remove.poll()


def layouts_and_channels():
    bpy.ops.ifsforge.new_system(layout="xy")
    design.layout = "xy+rgb"
    assert all(len(m.channels) == 3 for m in design.maps)
    built = system()
    assert built.layout == "xy+rgb" and built.dim == 5
    cloud = ifsforge.preview_cloud(built, 20000)
    assert cloud.coloring == "channels"
    # Default rows c' = c / 2 + v_i / 2 (v_i: the piece colour): piece i averages
    # (v_i + sum_j p_j v_j) / 2; colours in [0, 1] are drawn as they are.
    v = np.array([ifsforge.piece_color(i)[:3] for i in range(3)])
    mean = built.probabilities @ v
    for i in range(3):
        close(cloud.colors[cloud.pieces == i, :3].mean(axis=0), (v[i] + mean) / 2, 0.01)
    # A channel row edits one row of the matrix (Eq. 97-107).
    design.maps[0].channels[1].coefficients[0] = 0.25
    design.maps[0].channels[1].offset = 0.125
    matrix, offset = system().maps[0].matrix, system().maps[0].offset
    assert matrix[3, 0] == 0.25 and offset[3] == 0.125
    design.layout = "xyz+hsi"
    assert system().dim == 6 and all(len(m.channels) == 3 for m in design.maps)
    design.layout = "xyz+rainbow"
    assert "rainbow" in state.analyse(design).error
    design.layout = "xyz"


def import_export(tmp):
    library = tmp / "two.ifs"
    library.write_text("alpha { 0.5 0 0 0.5 0 0 1\n 0.5 0 0 0.5 0.5 0 1\n 0.5 0 0 0.5 0.25 0.5 1 }\n"
                       "beta { 0.6 0 0 0.6 0 0 1\n 0.4 0.2 -0.2 0.4 0.5 0.3 1 }\n")
    scene.ifsforge.library.clear()
    bpy.ops.ifsforge.import_system(filepath=str(library), entry="beta")
    assert system().name == "beta" and len(system()) == 2
    assert sorted(item.name for item in scene.ifsforge.library) == ["alpha", "beta"]
    close(system().maps[1].matrix, [[0.4, 0.2], [-0.2, 0.4]], 1e-7)
    out = tmp / "beta.json"
    bpy.ops.ifsforge.export_json(filepath=str(out))
    back = ifsforge.read_json(str(out))
    assert back.name == "beta"
    close(back.maps[1].matrix, [[0.4, 0.2], [-0.2, 0.4]], 1e-7)
    bpy.ops.ifsforge.import_system(filepath=str(SAMPLES / "menger_sponge.json"))
    assert system().layout == "xyz" and len(system()) == 20


def povray_export(tmp):
    bpy.ops.ifsforge.load_preset(preset="sierpinski_tetrahedron.json")
    scene.ifsforge.settings.instance_depth = 2
    scene.ifsforge.settings.instance_primitives = "sphere"
    out = tmp / "tetra.pov"
    bpy.ops.ifsforge.export_povray(filepath=str(out), width=64, height=48, render=True)
    text = out.read_text()
    assert (tmp / "ifsforge.inc").is_file() and "#include \"ifsforge.inc\"" in text
    assert text.count("sphere") >= 16, text.count("sphere")  # 4^2 leaves
    image = bpy.data.images["tetra.png"]
    assert tuple(image.size) == (64, 48)
    pixels = np.array(image.pixels[:]).reshape(48, 64, 4)[:, :, :3]
    assert pixels.std() > 0.02  # POV-Ray drew something, not a flat background
    expect_report(lambda: bpy.ops.ifsforge.export_povray(filepath=str(tmp / "missing" / "x.pov")), "missing")


def bad_input(tmp):
    broken = tmp / "broken.json"
    broken.write_text('{"format": "ifsforge/1", "maps": [')
    expect_report(lambda: bpy.ops.ifsforge.import_system(filepath=str(broken)), "broken.json")
    expect_report(lambda: bpy.ops.ifsforge.import_system(filepath=str(tmp / "missing.json")), "missing.json")
    garbage = tmp / "garbage.ifs"
    garbage.write_text("fern { 0.5 0 zero }\n")
    expect_report(lambda: bpy.ops.ifsforge.import_system(filepath=str(garbage)), "garbage.ifs")
    expect_report(lambda: bpy.ops.ifsforge.import_system(filepath=str(SAMPLES / "classic.ifs"), entry="nothing"),
                  "no entry 'nothing'")
    bpy.ops.ifsforge.load_preset(preset="barnsley_fern.json")
    for m in design.maps:
        m.scale = (1.4, 1.4, 1.0)
    expect_report(lambda: bpy.ops.ifsforge.generate_image(), "no attractor")
    expect_report(lambda: bpy.ops.ifsforge.export_json(filepath=str(tmp / "div.json")), "no attractor")
    assert not (tmp / "div.json").exists()
    design.layout = "xyzw"
    expect_report(lambda: bpy.ops.ifsforge.generate_image(), "xyzw")
    expect_report(lambda: bpy.ops.ifsforge.regenerate(), "nothing to regenerate")
    bpy.ops.ifsforge.load_preset(preset="barnsley_fern.json")


def preview_data_path():
    bpy.ops.ifsforge.load_preset(preset="barnsley_fern.json")
    settings = scene.ifsforge.preview
    settings.count = 200000
    cloud = preview.current.update(context)
    assert cloud is not None and cloud.count == 200000 and cloud.coloring == "pieces"
    first = np.array(cloud.positions)
    # The highlighted piece is the active map's; the fern's map 2 (index 1) is the big leaf.
    design.active_map = 1
    cloud = preview.current.update(context)
    assert np.array_equal(cloud.colors[cloud.pieces == 1][0], ifsforge.piece_color(1))
    # A drag: the rotation changes, the next draw sees new points.
    timings = []
    for k in range(20):
        start = time.perf_counter()
        design.maps[1].rotation[0] = -2.5 + 0.1 * k
        cloud = preview.current.update(context)
        timings.append(time.perf_counter() - start)
    assert not np.array_equal(cloud.positions, first)
    checks.values["preview_update_ms_median"] = 1e3 * float(np.median(timings))
    # No change, no work: the same cloud object comes back.
    assert preview.current.update(context) is cloud
    # A divergent system draws nothing and says why.
    for m in design.maps:
        m.scale = (1.5, 1.5, 1.0)
    assert preview.current.update(context) is None and "no attractor" in preview.current.error


def image_and_regenerate():
    bpy.ops.ifsforge.load_preset(preset="sierpinski_triangle.json")
    settings = scene.ifsforge.settings
    settings.image_size, settings.image_algorithm, settings.image_mode = 64, 'prr', 'binary'
    bpy.ops.ifsforge.generate_image()
    image = bpy.data.images["Sierpinski triangle image"]
    assert image.ifsforge.kind == 'IMAGE' and tuple(image.size) == (64, 64)
    assert Path(bpy.path.abspath(image.filepath)).is_file()
    pixels = np.array(image.pixels[:]).reshape(64, 64, 4)
    covered = int((pixels[:, :, 0] > 0.5).sum())
    expected = int((ifsforge.render(ifsforge.read_json(str(SAMPLES / "sierpinski_triangle.json")), "prr", 64,
                                    binary=True).density > 0).sum())
    assert covered == expected, (covered, expected)
    # Editing the stored system after the fact, then Regenerate: a new picture.
    image.ifsforge.system.maps[0].scale = (0.3, 0.3, 1.0)
    bpy.ops.ifsforge.regenerate(image=image.name)
    after = np.array(image.pixels[:]).reshape(64, 64, 4)
    assert int((after[:, :, 0] > 0.5).sum()) != covered
    # A second generation from the same design is a new datablock with its own file.
    bpy.ops.ifsforge.generate_image()
    second = bpy.data.images["Sierpinski triangle image.001"]
    assert bpy.path.abspath(second.filepath) != bpy.path.abspath(image.filepath)


def morph_and_animation():
    scene.ifsforge.library.clear()
    bpy.ops.ifsforge.load_preset(preset="sierpinski_triangle.json")
    bpy.ops.ifsforge.library_save()
    bpy.ops.ifsforge.load_preset(preset="barnsley_fern.json")
    bpy.ops.ifsforge.library_save()
    data = scene.ifsforge
    data.morph_source, data.morph_target = "Sierpinski triangle", "Barnsley fern"
    bpy.ops.ifsforge.morph_set()
    assert design.morph.enabled
    start, end = (ifsforge.parse_json(data.library[name].json) for name in (data.morph_source, data.morph_target))
    # Keyframed factor: 0 at frame 1, 1 at frame 11 (linear): frame 6 is t = 0.5.
    design.morph.factor = 0.0
    design.morph.keyframe_insert("factor", frame=1)
    design.morph.factor = 1.0
    design.morph.keyframe_insert("factor", frame=11)
    for fcurve in scene.animation_data.action.fcurves:
        for point in fcurve.keyframe_points:
            point.interpolation = 'LINEAR'
    scene.frame_set(6)
    assert abs(design.morph.factor - 0.5) < 1e-6
    expected = ifsforge.morph(start, end, 0.5)
    for a, b in zip(system().maps, expected.maps):
        close(a.matrix, b.matrix, 1e-9)
    scene.frame_set(1)
    for a, b in zip(system().maps, ifsforge.pad_maps(start, 4).maps):
        close(a.matrix, b.matrix, 0)
    # Apply bakes the morph into the map list.
    scene.frame_set(6)
    bpy.ops.ifsforge.morph_apply()
    assert not design.morph.enabled and len(design.maps) == 4
    for a, b in zip(system().maps, expected.maps):
        close(a.matrix, b.matrix, 2e-6)
    scene.animation_data_clear()
    # Any map value can be keyframed too.
    design.maps[0].keyframe_insert("rotation", index=0, frame=1)
    design.maps[0].rotation[0] = 40.0
    design.maps[0].keyframe_insert("rotation", index=0, frame=11)
    scene.frame_set(1)
    first = system().maps[0].matrix.copy()
    scene.frame_set(11)
    assert not np.allclose(system().maps[0].matrix, first)
    scene.animation_data_clear()
    scene.frame_set(1)


def save_and_reload(tmp):
    bpy.ops.ifsforge.load_preset(preset="maple_leaf.json")
    design.maps[2].shear[0] = 0.125
    design.maps[1].reflect[1] = True
    scene.ifsforge.settings.image_size = 32
    bpy.ops.ifsforge.generate_image()
    before = codec.build_system(state.analyse(design).record)
    library = [item.name for item in scene.ifsforge.library]
    path = tmp / "design.blend"
    bpy.ops.wm.save_as_mainfile(filepath=str(path))
    bpy.ops.wm.read_homefile(use_empty=True)
    assert len(bpy.context.scene.ifsforge.system.maps) == 0
    bpy.ops.wm.open_mainfile(filepath=str(path))
    reloaded = bpy.context.scene.ifsforge
    assert reloaded.system.maps[2].shear[0] == 0.125 and reloaded.system.maps[1].reflect[1]
    after = state.system_of(reloaded.system)
    for a, b in zip(after.maps, before.maps):
        close(a.matrix, b.matrix, 0)
    assert [item.name for item in reloaded.library] == library
    image = bpy.data.images["Maple leaf image"]
    assert image.ifsforge.kind == 'IMAGE' and image.ifsforge.settings.image_size == 32
    assert len(image.ifsforge.system.maps) == len(before.maps)
    assert tuple(image.size) == (32, 32)


tmp = OUT / "design"
tmp.mkdir(parents=True, exist_ok=True)
checks.run("registered", registered)
checks.run("presets_reproduce_the_samples", presets_reproduce_the_samples)
checks.run("analysis_follows_parameters", analysis_follows_parameters)
checks.run("map_list_editing", map_list_editing)
checks.run("layouts_and_channels", layouts_and_channels)
checks.run("import_export", import_export, tmp)
checks.run("povray_export", povray_export, tmp)
checks.run("bad_input", bad_input, tmp)
checks.run("preview_data_path", preview_data_path)
checks.run("image_and_regenerate", image_and_regenerate)
checks.run("morph_and_animation", morph_and_animation)
checks.run("save_and_reload", save_and_reload, tmp)
checks.finish()
