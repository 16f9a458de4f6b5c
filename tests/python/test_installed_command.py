"""The `ifsforge` command as the README's set-up installs it (the launcher on PATH), not only
`python3 -m ifsforge`: a local Dask cluster (whose spawned workers import the main module
again), signals, and the interpreter entry point."""
import os
import signal
import subprocess

import pytest

from conftest import BUILD_PYTHON, SAMPLES, ifsforge_command, patience, signal_after

ENV = dict(os.environ, PYTHONPATH=str(BUILD_PYTHON))


def test_the_launcher_guards_its_entry_point(tmp_path):
    # Importing the launcher as a module (what multiprocessing's spawn does to __main__) runs nothing.
    launcher = ifsforge_command()[-1]
    code = ("import importlib.util, sys; spec = importlib.util.spec_from_loader('launcher', "
            f"importlib.machinery.SourceFileLoader('launcher', {str(launcher)!r})); "
            "module = importlib.util.module_from_spec(spec); spec.loader.exec_module(module); print('imported')")
    result = subprocess.run(["/usr/bin/python3", "-c", code], capture_output=True, text=True, env=ENV, timeout=60)
    assert result.returncode == 0 and result.stdout.strip() == "imported", result.stderr


def test_a_local_cluster_run_by_the_installed_command_gives_the_local_bytes(tmp_path):
    system = SAMPLES / "sierpinski_pyramid.json"
    local = subprocess.run([*ifsforge_command(), "volume", system, "--res", "64", "-o", "local.vdb"],
                           capture_output=True, text=True, env=ENV, cwd=tmp_path, timeout=120)
    assert local.returncode == 0, local.stderr
    cluster = subprocess.run([*ifsforge_command(), "volume", system, "--res", "64", "-o", "cluster.vdb",
                              "--cluster", "local:2"], capture_output=True, text=True, env=ENV, cwd=tmp_path,
                             timeout=300)
    assert cluster.returncode == 0, cluster.stderr
    assert "bootstrapping" not in cluster.stderr and "Traceback" not in cluster.stderr, cluster.stderr
    assert (tmp_path / "local.vdb").read_bytes() == (tmp_path / "cluster.vdb").read_bytes()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["cluster.vdb", "local.vdb"]


def test_python_dash_m_is_the_same_command():
    result = subprocess.run(["/usr/bin/python3", "-m", "ifsforge", "--version"], capture_output=True, text=True,
                            env=ENV, timeout=60)
    installed = subprocess.run([*ifsforge_command(), "--version"], capture_output=True, text=True, env=ENV,
                               timeout=60)
    assert result.returncode == installed.returncode == 0
    assert result.stdout == installed.stdout


@pytest.mark.parametrize("args", [
    ["render", SAMPLES / "barnsley_fern.json", "--iterations", "100000000000", "-o", "f.png"],
    ["volume", SAMPLES / "menger_sponge.json", "--res", "729", "-o", "v.vdb"],
])
def test_sigterm_stops_like_ctrl_c_and_leaves_nothing(tmp_path, args):
    code, err, stop = signal_after(tmp_path, signal.SIGTERM, 2.0, *args)
    assert code == 143 and "terminated" in err and "Traceback" not in err, err
    assert stop < patience(1.0), f"{stop:.1f} s to stop"
    assert not any(tmp_path.iterdir()), list(tmp_path.iterdir())


def test_ctrl_c_stops_a_local_cluster_without_a_traceback(tmp_path):
    code, err, stop = signal_after(tmp_path, signal.SIGINT, 10.0, "volume", SAMPLES / "menger_sponge.json",
                                 "--res", "729", "-o", "v.vdb", "--cluster", "local:2")
    assert code == 130 and "interrupted" in err and "Traceback" not in err, err
    # The interrupt lands while the cluster starts, works or shuts down (on a busy machine the
    # file may already be committed): never a temporary or a partial file.
    assert [p.name for p in tmp_path.iterdir() if p.name != "v.vdb"] == []
    if (tmp_path / "v.vdb").exists():
        import ifsforge
        assert ifsforge.read_vdb_info(str(tmp_path / "v.vdb"))["grids"], "a partial .vdb"
