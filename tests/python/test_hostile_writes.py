"""Writes that cannot lie: a full disk fails with exit 2 and leaves no file,
multi-file commands commit all or none, the same volume gives the same .vdb bytes."""
import os
import subprocess

import pytest

from conftest import SAMPLES

SYSTEM = SAMPLES / "sierpinski_pyramid.json"


@pytest.fixture
def full_disk(tmp_path):
    """A 64 KiB tmpfs (root only): big enough for the folder, too small for a volume."""
    folder = tmp_path / "full"
    folder.mkdir()
    if os.geteuid() != 0 or subprocess.run(["mount", "-t", "tmpfs", "-o", "size=64k", "tmpfs", str(folder)],
                                           capture_output=True).returncode != 0:
        pytest.skip("cannot mount a small tmpfs")
    yield folder
    subprocess.run(["umount", str(folder)], check=True)


def test_full_disk_vdb_fails_and_leaves_nothing(cli, full_disk):
    result = cli("volume", SYSTEM, "--res", "128", "-o", full_disk / "v.vdb")
    assert result.returncode == 2, result.stderr
    assert "Traceback" not in result.stderr and "v.vdb" in result.stderr
    assert os.listdir(full_disk) == []


def test_full_disk_png_fails_and_leaves_nothing(cli, full_disk):
    result = cli("render", SYSTEM, "--size", "1024", "--mode", "shaded", "-o", full_disk / "p.png")
    assert result.returncode == 2, result.stderr
    assert "p.png" in result.stderr
    assert os.listdir(full_disk) == []


def test_volume_with_mesh_commits_none_when_the_mesh_fails(cli, tmp_path, full_disk):
    # The .vdb fits on the normal disk; the mesh goes to the full one: neither is kept.
    result = cli("volume", SYSTEM, "--res", "64", "-o", tmp_path / "v.vdb", "--mesh", full_disk / "m.ply")
    assert result.returncode == 2, result.stderr
    assert "none of the 2 outputs was written" in result.stderr
    assert not (tmp_path / "v.vdb").exists() and os.listdir(full_disk) == []
    assert not [p for p in os.listdir(tmp_path) if p.startswith(".ifsforge")]


def test_instances_commit_none_when_one_output_fails(cli, tmp_path, full_disk):
    # The scene, SVG and CSV fit; the 2.6 MB glTF does not: none of the four is kept.
    result = cli("instances", SAMPLES / "tree.json", "--pov", tmp_path / "t.pov", "--svg", tmp_path / "t.svg",
                 "--csv", tmp_path / "t.csv", "--gltf", full_disk / "t.glb")
    assert result.returncode == 2, result.stderr
    assert "none of the 4 outputs was written" in result.stderr and "Traceback" not in result.stderr
    assert not list(tmp_path.glob("t.*")) and os.listdir(full_disk) == []
    assert not [p for p in os.listdir(tmp_path) if p.startswith(".ifsforge")]


def test_terrain_commits_none_of_its_outputs_on_a_full_disk(cli, tmp_path, full_disk):
    # All or none: the PNG fits on the disk, the mesh does not; neither may stay.
    result = cli("terrain", "-o", tmp_path / "t.png", "-o", full_disk / "t.obj", "-o", tmp_path / "t.pov")
    assert result.returncode == 2 and "Traceback" not in result.stderr, result.stderr
    assert not list(tmp_path.glob("t.*")) and os.listdir(full_disk) == []


def test_growth_on_a_full_disk_leaves_no_frame(cli, full_disk):
    # The frames are staged and committed together: none stays when one cannot be written.
    result = cli("growth", SAMPLES / "condensation_tree.json", "-o", full_disk / "frames", "--size", "256")
    assert result.returncode == 2 and "Traceback" not in result.stderr, result.stderr
    assert os.listdir(full_disk) == []


def test_same_volume_same_bytes(cli, tmp_path):
    for name, threads in (("a.vdb", 1), ("b.vdb", 2)):
        cli("volume", SYSTEM, "--res", "48", "--threads", threads, "-o", tmp_path / name, check=True)
    assert (tmp_path / "a.vdb").read_bytes() == (tmp_path / "b.vdb").read_bytes()


# The .vdb bytes of three sample volumes, each way it can be written (half or full floats, with
# or without Blosc), as the writer made them before its copies between stages were removed.
VDB_DIGESTS = {
    ("volume_sierpinski_pyramid_rgb", 96, False, True): "5f090cf92287dad34779158adf0cea6ce6aff293443ec9bff0c7c472ce972cfc",
    ("volume_sierpinski_pyramid_rgb", 96, False, False): "e993cee70f53e6558bc2954e79fd491220f25820d3e40693c206581ebad1c834",
    ("volume_sierpinski_pyramid_rgb", 96, True, True): "1f1d6484924d6abaf9294b0a4cd6c25235d33575a1778eb0151c17c426969975",
    ("volume_sierpinski_pyramid_rgb", 96, True, False): "e6cbe35c4d5483e38beddb86a7e6045ce281da3ffa6450025bc65a8938b6759f",
    ("menger_sponge", 81, False, True): "93f5326f6381554e6638f74d516c3765eff30e9e172c156663b6a32ef657e637",
    ("menger_sponge", 81, True, False): "619c2f030c28fb15b71deedb924dfba463bf436b4453019ad05a33e7463b5b8c",
    ("volume_hsi_tower", 64, False, True): "949155609f8a3a51c9ea52d2dc04e752dee751adefd3d195aba3e07c78dfb8f4",
    ("volume_hsi_tower", 64, True, True): "57762b0336831485e645469d5f10783d6ea97788cbeb2c64530be55376e32c04",
}


@pytest.mark.parametrize("name, res, compress, half", sorted(VDB_DIGESTS))
def test_the_vdb_writer_keeps_its_bytes(tmp_path, name, res, compress, half):
    import hashlib
    import ifsforge
    system = ifsforge.load(str(SAMPLES / f"{name}.json"))
    path = tmp_path / "v.vdb"
    ifsforge.write_vdb(str(path), ifsforge.render_volume(system, "prr", res), system, compress=compress, half=half)
    assert hashlib.sha256(path.read_bytes()).hexdigest() == VDB_DIGESTS[(name, res, compress, half)]


def test_vdb_metadata_is_typed_and_holds_no_threads_or_path(cli, tmp_path):
    import pyopenvdb
    cli("volume", SYSTEM, "--res", "48", "--threads", "2", "-o", tmp_path / "v.vdb", check=True)
    file_meta = pyopenvdb.readMetadata(str(tmp_path / "v.vdb"))
    assert file_meta["ifsforge_resolution"] == 48 and isinstance(file_meta["ifsforge_resolution"], int)
    command = file_meta["ifsforge_command"]
    assert "threads" not in command and str(tmp_path) not in command and "res=48" in command


def test_convert_writes_all_entries_or_none(cli, tmp_path):
    out = tmp_path / "out"
    (out / "zigzag2.json").mkdir(parents=True)  # the last entry cannot be written
    result = cli("convert", SAMPLES / "classic.ifs", "-o", out)
    assert result.returncode == 2 and "zigzag2.json" in result.stderr, result.stderr
    assert sorted(p.name for p in out.iterdir()) == ["zigzag2.json"]
    (out / "zigzag2.json").rmdir()
    assert cli("convert", SAMPLES / "classic.ifs", "-o", out).returncode == 0
    assert len(list(out.glob("*.json"))) == 13
