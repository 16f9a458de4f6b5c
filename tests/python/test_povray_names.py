"""Names are data, and a POV-Ray render is all or nothing: the installed `ifsforge` renders scenes
whose names hold spaces, POV-Ray option words, comment and quote characters at the size asked
for; a failed render leaves none of the files the command wrote (scene, ifsforge.inc, height
image, glTF) and no staging file, and an older ifsforge.inc stays as it was."""
import os
import shutil
import struct

import pytest

pytestmark = pytest.mark.skipif(not shutil.which("povray"), reason="needs POV-Ray")

NAMES = ["my scene +W1 #.pov", "it's \"quoted\" ; -D +Ox.png.pov"]


def png_size(path):
    """(width, height) from a PNG's IHDR chunk."""
    data = path.read_bytes()[:24]
    assert data[:8] == b"\x89PNG\r\n\x1a\n" and data[12:16] == b"IHDR", data
    return struct.unpack(">II", data[16:24])


@pytest.mark.parametrize("name", NAMES)
def test_a_scene_name_is_data(cli, tmp_path, samples, name):
    result = cli("instances", samples / "sierpinski_tetrahedron.json", "--depth", 2, "--pov", name,
                 "--render", "out.png", "--size", "48x36", "--antialias", 0)
    assert result.returncode == 0, result.stderr
    assert png_size(tmp_path / "out.png") == (48, 36)
    assert sorted(os.listdir(tmp_path)) == sorted([name, "ifsforge.inc", "out.png"])


@pytest.fixture
def failing_povray(tmp_path, monkeypatch):
    """A `povray` first on PATH that fails as a parse error does."""
    folder = tmp_path / "bin"
    folder.mkdir()
    fake = folder / "povray"
    fake.write_text("#!/bin/sh\necho 'Parse Error: No objects in scene.' >&2\nexit 1\n")
    fake.chmod(0o755)
    monkeypatch.setenv("PATH", f"{folder}{os.pathsep}{os.environ['PATH']}")


def test_a_failed_instances_render_leaves_nothing(cli, tmp_path, samples, failing_povray):
    (tmp_path / "ifsforge.inc").write_text("// the user's own copy\n")
    result = cli("instances", samples / "sierpinski_tetrahedron.json", "--depth", 2,
                      "--pov", "s.pov", "--render", "s.png", "--gltf", "s.glb", "--size", "32x24")
    assert result.returncode != 0 and "Parse Error" in result.stderr, result.stderr
    assert "Traceback" not in result.stderr
    assert sorted(os.listdir(tmp_path)) == ["bin", "ifsforge.inc"]
    assert (tmp_path / "ifsforge.inc").read_text() == "// the user's own copy\n"


def test_a_failed_terrain_render_leaves_nothing(cli, tmp_path, failing_povray):
    result = cli("terrain", "--res", "17", "-o", "t.png", "-o", "t.glb", "-o", "t.pov",
                      "--povray-render", "r.png", "--povray-size", "32x24")
    assert result.returncode != 0 and "Parse Error" in result.stderr, result.stderr
    assert sorted(os.listdir(tmp_path)) == ["bin"]


def test_a_terrain_scene_renders_with_its_height_image(cli, tmp_path):
    name = "my terrain +W1 #.pov"
    result = cli("terrain", "--res", "17", "-o", name, "--povray-render", "r.png", "--povray-size", "40x30")
    assert result.returncode == 0, result.stderr
    assert png_size(tmp_path / "r.png") == (40, 30)
    files = sorted(os.listdir(tmp_path))
    assert len(files) == 3 and name in files and "r.png" in files, files
    height = next(f for f in files if f.endswith("_height.png"))
    assert f'png "{height}"' in (tmp_path / name).read_text()
