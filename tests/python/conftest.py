"""Shared fixtures. The suite tests the Python binding and the CLI, not the C++ core again."""
import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
BUILD_PYTHON = next((Path(p).resolve() for p in os.environ.get("PYTHONPATH", "").split(os.pathsep)
                     if p and (Path(p) / "ifsforge").is_dir()), ROOT / "build" / "python")
if str(BUILD_PYTHON) not in sys.path:
    sys.path.insert(0, str(BUILD_PYTHON))

SAMPLES = ROOT / "samples" / "systems"


@pytest.fixture
def samples():
    return SAMPLES


@pytest.fixture
def cli(tmp_path):
    """Run `python3 -m ifsforge ARGS` with Debian's Python; returns the CompletedProcess."""
    def run(*args, check=False):
        env = dict(os.environ, PYTHONPATH=str(BUILD_PYTHON))
        result = subprocess.run(["/usr/bin/python3", "-m", "ifsforge", *map(str, args)],
                                capture_output=True, text=True, env=env, cwd=tmp_path)
        if check and result.returncode != 0:
            raise AssertionError(f"ifsforge {args} failed:\n{result.stderr}")
        return result
    return run
