"""Shared by the tests/blender/addon_*.py scripts, which run inside real Blender:
    blender -b --factory-startup --python tests/blender/addon_X.py -- --python-path BUILD/python --out DIR
Each script enables the add-on from the checkout, runs named checks, prints one
`CHECK name ok|FAIL message` line per check and a final `RESULT {json}` line, and exits 1
if any check failed (the pytest driver reads both)."""
import argparse
import json
import sys
import time
import traceback
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


def arguments():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    parser = argparse.ArgumentParser()
    parser.add_argument("--python-path", required=True, help="folder holding the built ifsforge package")
    parser.add_argument("--out", required=True, help="scratch folder")
    return parser.parse_args(argv)


def enable_addon(python_path):
    """The way install.sh's result is used, minus the copy: module and add-on on sys.path."""
    import addon_utils
    for folder in (str(python_path), str(ROOT / "blender_addon")):
        if folder not in sys.path:
            sys.path.insert(0, folder)
    module = addon_utils.enable("ifsforge_addon", default_set=True, handle_error=None)
    if module is None:
        raise RuntimeError("addon_utils.enable returned None")
    return module


class Checks:
    def __init__(self):
        self.results = {}
        self.values = {}

    def run(self, name, function, *args):
        start = time.perf_counter()
        try:
            function(*args)
            self.results[name] = "ok"
            print(f"CHECK {name} ok ({time.perf_counter() - start:.2f} s)", flush=True)
        except Exception as error:
            self.results[name] = f"{type(error).__name__}: {error}"
            print(f"CHECK {name} FAIL {self.results[name]}", flush=True)
            traceback.print_exc()

    def finish(self):
        print("RESULT " + json.dumps({"checks": self.results, "values": self.values}), flush=True)
        failed = [k for k, v in self.results.items() if v != "ok"]
        sys.stdout.flush()
        import os
        os._exit(1 if failed else 0)  # Blender would otherwise exit 0 whatever happened


def expect_report(operator_call, *fragments):
    """Runs an operator that must fail with an error report (a RuntimeError from bpy.ops in a
    script) whose text holds every fragment and no Python traceback."""
    try:
        operator_call()
    except RuntimeError as error:
        text = str(error)
        if "Traceback" in text:
            raise AssertionError(f"the report is a traceback: {text}") from None
        for fragment in fragments:
            if fragment.lower() not in text.lower():
                raise AssertionError(f"report {text!r} does not mention {fragment!r}") from None
        return text
    raise AssertionError("the operator did not report an error")


def close(a, b, tolerance):
    import numpy as np
    a, b = np.asarray(a, float), np.asarray(b, float)
    if a.shape != b.shape:
        raise AssertionError(f"shapes differ: {a.shape} != {b.shape}")
    if not np.allclose(a, b, atol=tolerance, rtol=0):
        k = np.unravel_index(np.argmax(np.abs(a - b)), a.shape)
        raise AssertionError(f"differ by {np.abs(a - b).max():.3g} > {tolerance} at {k}: {a[k]} != {b[k]}"
                             + (f" ({a.tolist()} != {b.tolist()})" if a.size <= 16 else ""))
