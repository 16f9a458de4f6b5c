"""Ctrl-C and SIGTERM in the `.vdb` write phase: the writer polls in its band, leaf, hashing and
syncing loops, so a signal sent once the temporary file exists stops the command within a second
(scaled with the machine's load) with 130 or 143, and leaves no file behind."""
import os
import signal
import subprocess
import time

import pytest

from conftest import BUILD_PYTHON, SAMPLES, ifsforge_command, patience


def interrupt_while_writing(tmp_path, signum, delay, *args):
    """Starts the CLI, waits for its temporary `.vdb` to appear, then `delay` seconds more, and
    sends `signum`; returns (exit code, stderr, seconds to stop)."""
    env = dict(os.environ, PYTHONPATH=str(BUILD_PYTHON))
    process = subprocess.Popen([*ifsforge_command(), *map(str, args)], cwd=tmp_path, env=env,
                               stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    deadline = time.monotonic() + 120
    while not any(p.name.startswith("v.vdb.tmp-") for p in tmp_path.iterdir()):
        assert process.poll() is None, "finished before writing: " + process.stderr.read().decode()
        assert time.monotonic() < deadline, "no temporary file appeared"
        time.sleep(0.01)
    time.sleep(delay)
    assert process.poll() is None, "finished before the signal: make the case larger"
    sent = time.monotonic()
    process.send_signal(signum)
    err = process.communicate(timeout=120)[1].decode(errors="replace")
    return process.returncode, err, time.monotonic() - sent


@pytest.mark.parametrize("signum, code, delay, extra", [
    (signal.SIGINT, 130, 0.3, []),                 # the bands' topology and values
    (signal.SIGTERM, 143, 1.5, []),                # later: the values, the hash or the sync to disk
    (signal.SIGINT, 130, 1.5, ["--compress"]),     # Blosc's leaves, then the kept bytes' writes
])
def test_a_signal_in_the_vdb_write_stops_within_a_second(tmp_path, signum, code, delay, extra):
    returned, err, stop = interrupt_while_writing(tmp_path, signum, delay, "volume", SAMPLES / "menger_sponge.json",
                                                  "--res", "729", "-o", "v.vdb", *extra)
    assert returned == code and "Traceback" not in err, err
    assert stop < patience(1.0), f"{stop:.2f} s to stop"
    assert not any(tmp_path.iterdir()), "a file was left"
