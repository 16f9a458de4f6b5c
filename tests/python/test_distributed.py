"""Scale-out on Dask: a real dask-scheduler and dask-worker processes on 127.0.0.1 render the same
bytes as one process; a killed worker, an unreachable scheduler and a worker without ifsforge."""
import json
import os
import signal
import socket
import subprocess
import threading
import time

import numpy as np
import pytest

from conftest import BUILD_PYTHON, SAMPLES, patience

import ifsforge
from ifsforge import distributed

distributed_lib = pytest.importorskip("distributed")  # installed by the set-up (python3-distributed)


def start(command, tmp_path, name, env=None):
    log = open(tmp_path / f"{name}.log", "w")
    env = dict(os.environ, PYTHONPATH=str(BUILD_PYTHON), **(env or {}))
    return subprocess.Popen(command, stdout=log, stderr=subprocess.STDOUT, env=env, start_new_session=True)


def stop(process):
    if process.poll() is None:
        process.terminate()
        try:
            process.wait(10)
        except subprocess.TimeoutExpired:
            process.kill()
            process.wait()


class Cluster:
    """A dask-scheduler and worker processes (no nanny: killing a worker kills its process)."""

    def __init__(self, tmp_path, name):
        self.tmp_path, self.name = tmp_path, name
        self.file = tmp_path / f"{name}-scheduler.json"
        self.scheduler = start(["dask-scheduler", "--host", "127.0.0.1", "--port", "0", "--no-dashboard",
                                "--scheduler-file", str(self.file)], tmp_path, f"{name}-scheduler")
        self.workers = []
        deadline = time.time() + patience(30)
        while not self.file.exists() or not self.file.read_text().strip():
            assert time.time() < deadline and self.scheduler.poll() is None, "dask-scheduler did not start"
            time.sleep(0.1)
        self.address = json.loads(self.file.read_text())["address"]

    def add_worker(self, extra=()):
        worker = start(["dask-worker", self.address, "--nthreads", "1", "--no-nanny", "--no-dashboard",
                        "--host", "127.0.0.1", *extra], self.tmp_path, f"{self.name}-worker{len(self.workers)}")
        self.workers.append(worker)
        return worker

    def wait_for(self, client, count):
        client.wait_for_workers(count, timeout=patience(30))

    def close(self):
        for worker in self.workers:
            stop(worker)
        stop(self.scheduler)


@pytest.fixture(scope="module")
def cluster(tmp_path_factory):
    c = Cluster(tmp_path_factory.mktemp("dask"), "main")
    for _ in range(2):
        c.add_worker()
    with distributed_lib.Client(c.address, timeout=30) as client:
        c.wait_for(client, 2)
    yield c
    c.close()


def test_volume_through_two_workers_equals_the_local_vdb(cluster, cli, tmp_path):
    system = SAMPLES / "sierpinski_pyramid.json"
    cli("volume", system, "--res", "128", "-o", "local.vdb", check=True)
    cli("volume", system, "--res", "128", "-o", "cluster.vdb", "--scheduler", cluster.address, check=True)
    local, remote = (tmp_path / "local.vdb").read_bytes(), (tmp_path / "cluster.vdb").read_bytes()
    assert local == remote
    import pyopenvdb
    a, b = (pyopenvdb.read(str(tmp_path / f), "density") for f in ("local.vdb", "cluster.vdb"))
    assert a.activeVoxelCount() == b.activeVoxelCount() == 123280  # the pyramid's voxels at 128 (test_volume)


def test_image_through_two_workers_equals_the_local_png(cluster, cli, tmp_path):
    system = SAMPLES / "barnsley_fern.json"
    cli("render", system, "--size", "256", "--seed", "7", "-o", "local.png", check=True)
    cli("render", system, "--size", "256", "--seed", "7", "-o", "cluster.png", "--scheduler", cluster.address,
        check=True)
    assert (tmp_path / "local.png").read_bytes() == (tmp_path / "cluster.png").read_bytes()


def test_point_recursive_color_image_through_workers_equals_the_local_raster(cluster):
    system = ifsforge.load(str(SAMPLES / "colour5d_dragon_rgb.json"))  # floats summed in address order
    options = dict(width=160, height=120)
    local = ifsforge.render(system, "prr", **options)
    with distributed.connect(scheduler=cluster.address) as client:
        remote = distributed.render(system, "prr", client=client, **options)
    assert local.covered() > 1000
    assert np.array_equal(local.density, remote.density)
    assert np.array_equal(local.to_image("color"), remote.to_image("color"))
    assert local.points == remote.points


def test_point_recursive_fall_back_to_a_fixed_depth_runs_on_the_workers_too(cluster):
    # The maple leaf's pieces run past PRR's node budget at this size: the render falls back to
    # a fixed depth, which the workers' jobs must run at as well.
    system = ifsforge.load(str(SAMPLES / "maple_leaf.json"))
    options = dict(width=256, height=256)
    local = ifsforge.render(system, "prr", **options)
    with distributed.connect(scheduler=cluster.address) as client:
        remote = distributed.render(system, "prr", client=client, **options)
    n = len(system.maps)
    assert local.points == n ** round(np.log(local.points) / np.log(n))  # N^L leaves: the fixed depth
    assert np.array_equal(local.density, remote.density)
    assert local.points == remote.points


def test_morph_frames_written_by_workers_equal_the_local_frames(cluster, cli, tmp_path):
    ends = (SAMPLES / "sierpinski_triangle.json", SAMPLES / "barnsley_fern.json")
    # More frames than tasks (FRAME_TASKS_PER_THREAD per worker thread): tasks of several frames.
    frames = str(3 * distributed.FRAME_TASKS_PER_THREAD)
    cli("morph", *ends, "--frames", frames, "--size", "64", "-o", "local", check=True)
    cli("morph", *ends, "--frames", frames, "--size", "64", "-o", tmp_path / "cluster", "--scheduler", cluster.address,
        check=True)
    names = sorted(p.name for p in (tmp_path / "local").iterdir())
    assert names == [f"morph_{k:04d}.png" for k in range(int(frames))]
    assert names == sorted(p.name for p in (tmp_path / "cluster").iterdir())  # no temporaries left behind
    for name in names:
        assert (tmp_path / "local" / name).read_bytes() == (tmp_path / "cluster" / name).read_bytes()


def test_random_iteration_volume_with_channels_merges_exactly(cluster):
    system = ifsforge.load(str(SAMPLES / "volume_hsi_tower.json"))
    options = dict(resolution=48, density="measure", iterations=5_000_000, seed=3)
    local = ifsforge.render_volume(system, "ria", **options)
    with distributed.connect(scheduler=cluster.address) as client:
        remote = distributed.render_volume(system, "ria", client=client, **options)
    assert len(local) == len(remote) > 1000
    assert np.array_equal(local.coords, remote.coords)
    assert np.array_equal(local.density, remote.density)
    assert np.array_equal(local.channels, remote.channels)
    assert local.points == remote.points == 5_000_000


def test_a_renderer_without_jobs_is_refused_by_name(cluster):
    system = ifsforge.load(str(SAMPLES / "sierpinski_pyramid.json"))
    with distributed.connect(scheduler=cluster.address) as client:
        with pytest.raises(ifsforge.InputError, match="dia volume renderer does not split"):
            distributed.render_volume(system, "dia", client=client, resolution=32)


def test_a_worker_killed_mid_render_changes_nothing(cluster):
    system = ifsforge.load(str(SAMPLES / "sierpinski_pyramid.json"))
    options = dict(resolution=64, density="hits", iterations=40 * 2**20, seed=11)
    local = ifsforge.render_volume(system, "ria", **options)
    victim = cluster.add_worker()
    with distributed.connect(scheduler=cluster.address) as client:
        cluster.wait_for(client, 3)
        address = next(w for w, pid in client.run(os.getpid).items() if pid == victim.pid)
        result, killed = {}, {}

        def start():
            result.clear()
            thread = threading.Thread(target=lambda: result.update(
                volume=distributed.render_volume(system, "ria", client=client, **options)))
            thread.start()
            return thread
        thread = start()
        deadline = time.time() + patience(30)
        while not client.processing().get(address):
            assert time.time() < deadline, "the victim never got a task"
            if not thread.is_alive():  # on a busy machine the others took every task first: again
                thread = start()
            time.sleep(0.01)
        killed["while_running"] = thread.is_alive()
        os.kill(victim.pid, signal.SIGKILL)
        thread.join(patience(60))
        assert not thread.is_alive(), "the render did not finish without the killed worker"
    assert killed["while_running"]
    assert victim.wait(patience(10)) == -signal.SIGKILL
    remote = result["volume"]
    assert np.array_equal(local.coords, remote.coords)
    assert np.array_equal(local.density, remote.density)
    assert remote.points == local.points == 40 * 2**20


def test_a_job_whose_every_worker_died_fails_in_bounded_time(tmp_path, monkeypatch):
    # Dask waits for a worker to join forever: the watchdog gives up after
    # IFSFORGE_CLUSTER_TIMEOUT seconds and names the scheduler.
    monkeypatch.setenv("IFSFORGE_CLUSTER_TIMEOUT", "3")
    lonely = Cluster(tmp_path, "lonely")
    system = ifsforge.load(str(SAMPLES / "sierpinski_pyramid.json"))
    try:
        victim = lonely.add_worker()
        with distributed_lib.Client(lonely.address, timeout=patience(30)) as client:
            lonely.wait_for(client, 1)
        with distributed.connect(scheduler=lonely.address) as client:
            address = next(iter(client.scheduler_info()["workers"]))
            outcome = {}

            def job():
                try:
                    distributed.render_volume(system, "ria", client=client, resolution=64, density="hits",
                                              iterations=2**34, seed=1)
                except distributed.ClusterError as error:
                    outcome["error"] = str(error)
            thread = threading.Thread(target=job)
            thread.start()
            deadline = time.time() + patience(30)
            while not client.processing().get(address):
                assert time.time() < deadline and thread.is_alive(), "the worker never got a task"
                time.sleep(0.01)
            os.kill(victim.pid, signal.SIGKILL)
            killed = time.time()
            thread.join(patience(3 + 10))
            assert not thread.is_alive(), "the job still waits for a worker"
            assert time.time() - killed < patience(3 + 5)
        assert "has had no worker" in outcome["error"] and lonely.address in outcome["error"], outcome
    finally:
        lonely.close()


def test_an_unreachable_scheduler_fails_fast_and_cleanly(cli, tmp_path):
    with socket.socket() as s:  # a port nobody listens on
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    begin = time.time()
    result = cli("volume", SAMPLES / "sierpinski_pyramid.json", "--res", "32", "-o", "out.vdb",
                 "--scheduler", f"tcp://127.0.0.1:{port}")
    assert time.time() - begin < patience(10)
    assert result.returncode == 2
    assert f"cannot reach the Dask scheduler at tcp://127.0.0.1:{port}" in result.stderr
    assert "Traceback" not in result.stderr
    assert not (tmp_path / "out.vdb").exists()


BLOCKER = '''
import sys
class HideIfsforge:
    def find_spec(self, name, path=None, target=None):
        if name == "ifsforge" or name.startswith("ifsforge."):
            raise ModuleNotFoundError("No module named 'ifsforge'")
sys.meta_path.insert(0, HideIfsforge())
'''


def test_a_worker_without_ifsforge_is_named(tmp_path):
    blocker = tmp_path / "hide_ifsforge.py"
    blocker.write_text(BLOCKER)  # the set-up installs ifsforge system-wide: hide it from this worker
    bare = Cluster(tmp_path, "bare")
    try:
        worker = bare.add_worker(["--preload", str(blocker)])
        with distributed_lib.Client(bare.address, timeout=30) as client:
            bare.wait_for(client, 1)
            address = next(iter(client.scheduler_info()["workers"]))
        with pytest.raises(distributed.ClusterError, match=f"worker {address} cannot import ifsforge"):
            with distributed.connect(scheduler=bare.address):
                pass
        assert worker.poll() is None
    finally:
        bare.close()


def test_cluster_option_is_checked():
    assert distributed.parse_cluster("local") == 2
    assert distributed.parse_cluster("local:3") == 3
    for bad in ("remote:2", "local:0", "local:x"):
        with pytest.raises(ifsforge.InputError, match="--cluster"):
            distributed.parse_cluster(bad)


def test_a_local_cluster_starts_quiet_workers():
    # Their stack profiler and monitors take CPU the render needs, for a dashboard nobody opens.
    with distributed.connect(cluster="local:1") as client:
        settings = client.run(lambda: {key: __import__("dask").config.get(key) for key in distributed.QUIET_WORKERS})
    assert list(settings.values()) == [distributed.QUIET_WORKERS]
    assert distributed.QUIET_WORKERS["distributed.worker.profile.enabled"] is False
