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


def test_same_volume_same_bytes(cli, tmp_path):
    for name, threads in (("a.vdb", 1), ("b.vdb", 2)):
        cli("volume", SYSTEM, "--res", "48", "--threads", threads, "-o", tmp_path / name, check=True)
    assert (tmp_path / "a.vdb").read_bytes() == (tmp_path / "b.vdb").read_bytes()


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
