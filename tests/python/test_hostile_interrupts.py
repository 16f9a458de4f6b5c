"""Ctrl-C and SIGTERM in the `.vdb` write phase: the writer polls in its band, leaf, hashing and
syncing loops, so a signal sent once the temporary file exists stops the command within a second
(scaled with the machine's load) with 130 or 143, and leaves no file behind."""
import signal

import pytest

from conftest import SAMPLES, patience, signal_after


@pytest.mark.parametrize("signum, code, delay, extra", [
    (signal.SIGINT, 130, 0.3, []),                 # the bands' topology and values
    (signal.SIGTERM, 143, 1.5, []),                # later: the values, the hash or the sync to disk
    (signal.SIGINT, 130, 1.5, ["--compress"]),     # Blosc's leaves, then the kept bytes' writes
])
def test_a_signal_in_the_vdb_write_stops_within_a_second(tmp_path, signum, code, delay, extra):
    # The write phase begins when the temporary file appears.
    writing = lambda: any(p.name.startswith("v.vdb.tmp-") for p in tmp_path.iterdir())  # noqa: E731
    returned, err, stop = signal_after(tmp_path, signum, delay, "volume", SAMPLES / "menger_sponge.json",
                                       "--res", "729", "-o", "v.vdb", *extra, ready=writing)
    assert returned == code and "Traceback" not in err, err
    assert stop < patience(1.0), f"{stop:.2f} s to stop"
    assert not any(tmp_path.iterdir()), "a file was left"
