"""Hostile names through every SDL writer (palette .inc, instance scene, terrain scene) and the
SVG, each file consumed by the real POV-Ray 3.7 (or an XML parser): nothing the input holds
may declare, include or break anything."""
import json
import re
import shutil
import subprocess
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest

import ifsforge

ROOT = Path(__file__).resolve().parents[2]
TERRAIN = ROOT / "samples" / "terrain"

HOSTILE = [
    "ok\n#declare Evil=1;\n//",
    "end */ #declare Evil=2; /* more",
    '#include "evil.inc"',
    'quote " back\\slash \\" #declare Evil=3;',
    "Crème brûlée",
    "sphere",
    "union",
    "pi",
    "1st palette",
    "",
]
# Two names that reduce to the same identifier part (Creme_brulee).
TWINS = ["Crème brûlée", "Creme-brulee"]

IDENTIFIER = re.compile(r"[A-Za-z_][A-Za-z0-9_]*\Z")


def povray(folder, scene, no_gamma=False):
    """Renders `scene` tiny with the real POV-Ray; returns its messages after checking them.
    `no_gamma`: the scene sets no assumed_gamma, which POV-Ray reports about the scene itself."""
    r = subprocess.run(["povray", f"+I{scene}", "+Oout.png", "+W32", "+H24", "-D", "-A"], cwd=folder,
                       capture_output=True, text=True)
    messages = r.stdout + r.stderr
    assert r.returncode == 0, messages
    if no_gamma:
        assert "assumed_gamma not specified" in messages
        messages = messages.replace("Possible Parse Error: assumed_gamma not specified", "")
    assert (Path(folder) / "out.png").is_file()
    for bad in ("Parse Error", "not perpendicular", "Non-ASCII", "undeclared"):
        assert bad not in messages, messages
    assert "Warning:" not in messages, messages
    return messages


def directives(text):
    """The SDL lines that are not comments: what the file actually declares."""
    return [line.strip() for line in text.splitlines() if line.strip() and not line.lstrip().startswith("//")]


def assert_inert(text, declared):
    """No directive but the `declared` ones, nothing injected outside comments and strings."""
    assert all(ord(c) < 128 for c in text)
    for line in directives(text):
        if line.startswith("#"):
            assert re.match(r"#(version 3\.7;|include \"ifsforge\.inc\"$|default \{)", line) or \
                any(line.startswith(f"#declare {d} ") for d in declared), line
        unquoted = re.sub(r'"(\\.|[^"\\])*"', '""', line)
        words = set(re.findall(r"\w+", unquoted)) - set(declared)
        assert "Evil" not in words and "evil" not in words, line
    for line in text.splitlines():
        if line.lstrip().startswith("//"):
            assert "#" not in line and "*/" not in line and "/*" not in line, line


def palette_recipe(path, name):
    recipe = json.loads((TERRAIN / "ember_hls.json").read_text())
    recipe["name"] = name
    recipe["description"] = "desc\n#declare Evil=4; */"
    path.write_text(json.dumps(recipe))
    return recipe


def test_identifiers_follow_one_scheme():
    reserved = set(ifsforge.pov_reserved_words())
    assert {"sphere", "union", "pi", "declare", "srgb"} <= reserved
    assert all(w == w.lower() for w in reserved)  # "IFS_..." can never be one
    for name in HOSTILE + TWINS:
        identifier = ifsforge.pov_identifier("Palette", name)
        assert IDENTIFIER.match(identifier) and identifier.startswith("IFS_Palette") and identifier not in reserved
    assert ifsforge.pov_identifier("Palette", "Crème brûlée") == "IFS_Palette_Creme_brulee"
    assert ifsforge.pov_identifier("Palette", "") == "IFS_Palette"
    assert ifsforge.pov_identifier("Palette", "1st palette") == "IFS_Palette_1st_palette"


@pytest.mark.parametrize("name", HOSTILE)
def test_palette_include_parses_without_assumed_gamma(cli, tmp_path, name):
    palette_recipe(tmp_path / "recipe.json", name)
    cli("palette", "recipe.json", "--entries", "16", "-o", "pal.inc", check=True)
    text = (tmp_path / "pal.inc").read_text()
    identifier = ifsforge.pov_identifier("Palette", name)
    assert_inert(text, [identifier])
    assert [line for line in directives(text) if line.startswith("#")] == [f"#declare {identifier} = color_map {{"]
    # A scene that includes it first and never sets assumed_gamma: an unlit plane showing the
    # palette from x = 0 (left) to x = 1 (right).
    (tmp_path / "scene.pov").write_text(
        '#version 3.7;\n#include "pal.inc"\n'
        "camera { orthographic location <0.5, 0.5, -1> direction z right x up y }\n"
        f"plane {{ z, 0 pigment {{ gradient x color_map {{ {identifier} }} }} finish {{ ambient 1 diffuse 0 }} }}\n")
    povray(tmp_path, "scene.pov", no_gamma=True)
    # The colours are those of the palette (linear rgb, shown as sRGB in the PNG).
    palette = ifsforge.read_palette_recipe(str(tmp_path / "recipe.json")).make(16)
    image = ifsforge.read_png(str(tmp_path / "out.png"))
    for column in (1, 16, 30):
        expected = palette.lookup((column + 0.5) / 32)
        assert np.abs(image[12, column] - np.asarray(expected)).max() < 0.03, (column, image[12, column], expected)


def test_palette_include_after_assumed_gamma(cli, tmp_path):
    palette_recipe(tmp_path / "recipe.json", "Crème brûlée")
    cli("palette", "recipe.json", "--entries", "16", "-o", "pal.inc", check=True)
    (tmp_path / "scene.pov").write_text(
        '#version 3.7;\nglobal_settings { assumed_gamma 1.0 }\n#include "pal.inc"\n'
        "camera { orthographic location <0.5, 0.5, -1> direction z right x up y }\n"
        "plane { z, 0 pigment { gradient x color_map { IFS_Palette_Creme_brulee } } finish { ambient 1 } }\n")
    povray(tmp_path, "scene.pov")


def mesh_file(path):
    path.write_text("v 0 0 0\nv 1 0 0\nv 0.5 0.3 0\nv 0.5 0.1 0.2\nf 1 2 3\nf 1 4 2\nf 2 4 3\nf 3 4 1\n")
    return f"mesh:{path}"


@pytest.mark.parametrize("name", HOSTILE)
def test_instance_scene_with_hostile_names_renders(samples, tmp_path, name):
    system = ifsforge.read_json(str(samples / "sierpinski_tetrahedron.json"))
    system.name = name
    # Mesh files named like the system, and two whose names reduce to the same identifier.
    meshes = [mesh_file(tmp_path / f"{name or 'x'}.obj".replace("/", "_"))] + \
        [mesh_file(tmp_path / f"{twin}.obj") for twin in TWINS]
    inst = ifsforge.instances(system, depth=2, primitives=["sphere", "cone"] + meshes)
    ifsforge.write_pov_scene(str(tmp_path / "scene.pov"), inst, width=32, height=24)
    text = (tmp_path / "scene.pov").read_text()
    declared = re.findall(r"^#declare (\w+) ", text, re.M)
    meshes = [d for d in declared if d.startswith("IFS_Mesh")]
    assert len(meshes) == 3 and len(set(meshes)) == 3, meshes
    assert "IFS_Mesh_Creme_brulee" in meshes and "IFS_Mesh_Creme_brulee_2" in meshes
    assert all(IDENTIFIER.match(d) and d.startswith("IFS_") for d in declared)
    assert_inert(text, declared)
    povray(tmp_path, "scene.pov")
    # The title string holds the name, made ASCII and one line.
    assert f"#declare IFS_Title = {ifsforge.pov_string('IFS instances: ' + name)};" in text


@pytest.mark.parametrize("view,orthographic", [((30, 25), False), ((-70, -30), False), ((10, 80), True)])
def test_cameras_are_exactly_perpendicular(samples, tmp_path, view, orthographic):
    system = ifsforge.read_json(str(samples / "sierpinski_tetrahedron.json"))
    inst = ifsforge.instances(system, depth=2)
    ifsforge.write_pov_scene(str(tmp_path / "scene.pov"), inst, width=32, height=24, view=view,
                             orthographic=orthographic)
    povray(tmp_path, "scene.pov")  # no "Camera vectors are not perpendicular"


@pytest.mark.parametrize("name", HOSTILE)
def test_terrain_scene_with_hostile_names_renders(cli, tmp_path, name):
    palette = palette_recipe(tmp_path / "palette.json", name)
    recipe = json.loads((TERRAIN / "ridge_range.json").read_text())
    recipe["name"] = name
    recipe["palette"] = palette
    (tmp_path / "terrain.json").write_text(json.dumps(recipe))
    scene = "Crème brûlée \"1\".pov"
    cli("terrain", "terrain.json", "--res", "17x13", "-o", scene, check=True)
    assert (tmp_path / "Creme_brulee__1__height.png").is_file()
    text = (tmp_path / scene).read_text()
    identifier = ifsforge.pov_identifier("Palette", name)
    assert_inert(text, ["IFS_Title", identifier])
    assert f"#declare IFS_Title = {ifsforge.pov_string('ifsforge terrain: ' + name)};" in text
    shutil.copy(tmp_path / scene, tmp_path / "t.pov")  # POV-Ray's +I cannot take every file name
    povray(tmp_path, "t.pov")


@pytest.mark.parametrize("shape,camera", [("mesh2", "top"), ("height_field", "top"), ("mesh2", "perspective")])
def test_terrain_cameras_and_shapes_parse_cleanly(cli, tmp_path, shape, camera):
    recipe = json.loads((TERRAIN / "ridge_range.json").read_text())
    recipe["palette"] = palette_recipe(tmp_path / "palette.json", "Crème brûlée")
    (tmp_path / "terrain.json").write_text(json.dumps(recipe))
    cli("terrain", "terrain.json", "--res", "17x13", "-o", "t.pov", "--pov-shape", shape, "--pov-camera", camera,
        check=True)
    assert "#declare IFS_Palette_Creme_brulee = color_map {" in (tmp_path / "t.pov").read_text()
    povray(tmp_path, "t.pov")


@pytest.mark.parametrize("name", HOSTILE + ["a ]]> <b>&amp; \x01 </title>"])
def test_svg_title_is_well_formed_xml(samples, tmp_path, name):
    system = ifsforge.read_json(str(samples / "sierpinski_triangle.json"))
    system.name = name
    inst = ifsforge.instances(system, depth=2, primitives="triangle")
    ifsforge.write_svg(str(tmp_path / "t.svg"), inst, width=64)
    root = ET.parse(tmp_path / "t.svg").getroot()
    title = root.find("{http://www.w3.org/2000/svg}title")
    assert (title.text or "") == name.replace("\x01", " ")
    assert len(root.findall("{http://www.w3.org/2000/svg}title")) == 1
