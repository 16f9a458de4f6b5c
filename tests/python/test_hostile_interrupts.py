"""Ctrl-C and SIGTERM in the `.vdb` write phase: the writer polls in its band, leaf, hashing and
syncing loops, so a signal sent once the temporary file exists stops the command within a second
(scaled with the machine's load) with 130 or 143, and leaves no file behind."""
import signal

import pytest

from conftest import SAMPLES, patience, signal_after


def temporary_holds(tmp_path, size):
    """The write phase has begun (the temporary file exists) and holds at least `size` bytes."""
    def holds(path):
        try:
            return path.name.startswith("v.vdb.tmp-") and path.stat().st_size >= size
        except FileNotFoundError:  # renamed or removed between the listing and the look
            return False
    return lambda: any(holds(p) for p in tmp_path.iterdir())


# Each phase is recognised by the temporary file itself, not by a delay: how long the write
# takes depends on the machine, and a signal after the rename would find the file complete.
@pytest.mark.parametrize("signum, code, size, extra", [
    (signal.SIGINT, 130, 0, []),                    # the bands' topology and values, before a byte
    (signal.SIGTERM, 143, 16 << 20, []),            # later: the values, the hash or the sync to disk
    (signal.SIGINT, 130, 1, ["--compress"]),        # Blosc's leaves, then the kept bytes' writes
])
def test_a_signal_in_the_vdb_write_stops_within_a_second(tmp_path, signum, code, size, extra):
    returned, err, stop = signal_after(tmp_path, signum, 0.0, "volume", SAMPLES / "menger_sponge.json",
                                       "--res", "729", "-o", "v.vdb", *extra,
                                       ready=temporary_holds(tmp_path, size))
    assert returned == code and "Traceback" not in err, err
    assert stop < patience(1.0), f"{stop:.2f} s to stop"
    assert not any(tmp_path.iterdir()), "a file was left"
