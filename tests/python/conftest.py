"""Shared fixtures. The suite tests the Python binding and the CLI, not the C++ core again."""
import os
import shutil
import signal
import subprocess
import sys
from pathlib import Path

import pytest

pytest_plugins = ["cpu_durations"]  # --cpu-durations=N

ROOT = Path(__file__).resolve().parents[2]
BUILD_PYTHON = next((Path(p).resolve() for p in os.environ.get("PYTHONPATH", "").split(os.pathsep)
                     if p and (Path(p) / "ifsforge").is_dir()), ROOT / "build" / "python")
if str(BUILD_PYTHON) not in sys.path:
    sys.path.insert(0, str(BUILD_PYTHON))

SAMPLES = ROOT / "samples" / "systems"


@pytest.fixture
def samples():
    return SAMPLES


def patience(seconds):
    """A responsiveness limit stretched by the machine's load: a command that must stop within a
    second on a quiet machine gets its share of the cores on a busy one (load / cores times more).
    The load is the larger of the last minute's average and the threads runnable now, less this
    one: a neighbour (the other test worker) that started seconds ago is not yet in the average."""
    load = os.getloadavg()[0]
    try:
        with open("/proc/loadavg") as f:
            load = max(load, int(f.read().split()[3].split("/")[0]) - 1)
    except (OSError, ValueError, IndexError):
        pass
    return seconds * max(1.0, load / (os.cpu_count() or 1))


def run_group(command, timeout, **kwargs):
    """subprocess.run (text, output captured) in a process group of its own, all of which goes on
    a timeout: killing xvfb-run alone leaves its Blender holding the pipes, and the wait for them
    hangs. The timeout is the quiet machine's, stretched by the load (patience)."""
    process = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                               start_new_session=True, **kwargs)
    try:
        stdout, stderr = process.communicate(timeout=patience(timeout))
    except subprocess.TimeoutExpired:
        os.killpg(process.pid, signal.SIGKILL)
        process.communicate()
        raise
    return subprocess.CompletedProcess(process.args, process.returncode, stdout, stderr)


def xvfb_run(screen):
    """xvfb-run with a display number of this process's own: `-a` alone takes the first free number,
    and two runs starting together (the suite's two workers, another checkout's suite) take the
    same one and one of them fails."""
    return ["xvfb-run", "-a", "-n", str(100 + 10 * (os.getpid() % 4000)), "-s", f"-screen 0 {screen}x24"]


def pytest_configure(config):
    config.addinivalue_line("markers", "long: a test of a minute or more (or a case of one split up), started first (see below)")


@pytest.hookimpl(tryfirst=True)
def pytest_collection_modifyitems(items):
    """The order and groups pytest-xdist's workers take tests in (tests/run.sh: -n 2 --dist
    loadgroup). Long tests go first, so that none starts last and leaves the other worker idle;
    tests sharing a module-scoped fixture (one render, one Dask cluster) go to one worker, which
    makes it once."""
    items.sort(key=lambda item: item.get_closest_marker("long") is None)  # stable: file order otherwise
    for item in items:
        fixtures = getattr(item, "_fixtureinfo", None)
        shared = fixtures and any(d.scope == "module" for defs in fixtures.name2fixturedefs.values() for d in defs)
        if shared and not item.get_closest_marker("xdist_group"):
            item.add_marker(pytest.mark.xdist_group(item.nodeid.split("::")[0]))


def ifsforge_command():
    """The `ifsforge` command as the README's set-up installs it (its launcher on PATH), else the
    same launcher from the source tree: tests run what users run, not `python3 -m ifsforge`."""
    installed = shutil.which("ifsforge", path="/usr/local/bin" + os.pathsep + os.environ.get("PATH", ""))
    # -P: the source folder of the launcher holds the package without its compiled modules.
    return [installed] if installed else ["/usr/bin/python3", "-P", str(ROOT / "cpp" / "python" / "ifsforge-launcher")]


def catches(pid, signum):
    """Whether process `pid` has a handler for `signum` (the SigCgt mask of /proc/PID/status)."""
    with open(f"/proc/{pid}/status") as status:
        mask = next(int(line.split()[1], 16) for line in status if line.startswith("SigCgt:"))
    return bool(mask >> (signum - 1) & 1)


def signal_after(tmp_path, signum, seconds, *args, ready=None):
    """Starts the installed CLI in tmp_path, waits until it handles `signum` and ready() is true
    (when given), then `seconds`, and sends `signum`; returns (exit code, stderr, seconds from
    the signal to the exit). On a busy machine the interpreter's start-up alone can take seconds:
    a signal before the command has installed its handler tests the start-up, not the command."""
    import time
    env = dict(os.environ, PYTHONPATH=str(BUILD_PYTHON))
    process = subprocess.Popen([*ifsforge_command(), *map(str, args)], cwd=tmp_path, env=env,
                               stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    deadline = time.monotonic() + 120
    while not catches(process.pid, signum) or (ready is not None and not ready()):
        assert process.poll() is None, "finished before it was ready: " + process.stderr.read().decode()
        assert time.monotonic() < deadline, "never ready"
        time.sleep(0.01)
    time.sleep(seconds)
    assert process.poll() is None, "finished before the signal: make the case larger"
    sent = time.monotonic()
    process.send_signal(signum)
    err = process.communicate(timeout=120)[1].decode(errors="replace")
    return process.returncode, err, time.monotonic() - sent


@pytest.fixture
def cli(tmp_path):
    """Run the installed `ifsforge ARGS` on the build tree's module; returns the CompletedProcess."""
    def run(*args, check=False, timeout=None):
        env = dict(os.environ, PYTHONPATH=str(BUILD_PYTHON))
        result = subprocess.run([*ifsforge_command(), *map(str, args)],
                                capture_output=True, text=True, env=env, cwd=tmp_path, timeout=timeout)
        if check and result.returncode != 0:
            raise AssertionError(f"ifsforge {args} failed:\n{result.stderr}")
        return result
    return run
