#!/usr/bin/python3
"""Every hostile-input example (bombs, absurd sizes, signals, option values, names) run as a command, with its exit code, its
peak resident memory and how long it took to refuse or to stop after a signal: the catalogue
whose cases tests/python/test_hostile*.py assert, measured in one run.

    /usr/bin/python3 cpp/bench/hostile_report.py [--build build] [--results -]

Budget cases run under IFSFORGE_MEMORY_BUDGET_MB as the issue gave it; signal cases send
SIGINT or SIGTERM after a delay, or once the output's temporary file appears (the write phase).
"""
import argparse
import contextlib
import os
import shutil
import signal
import socket
import struct
import subprocess
import sys
import tempfile
import time
import zlib
from pathlib import Path

import results

ROOT = Path(__file__).resolve().parents[2]
SYSTEMS = ROOT / "samples" / "systems"
SIERPINSKI, FERN, SPONGE = SYSTEMS / "sierpinski_triangle.json", SYSTEMS / "barnsley_fern.json", SYSTEMS / "menger_sponge.json"
TERRAIN = ROOT / "samples" / "terrain" / "ember_hls.json"


def png(width, height, row=b"", rows=0, colour=False):
    """A gray (or RGB) 8-bit PNG declaring width x height whose data is `row` (filter byte
    included) `rows` times, compressed a row at a time: this process stays small, as its
    children's peak memory counts its own."""
    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))
    head = struct.pack(">IIBBBBB", width, height, 8, 2 if colour else 0, 0, 0, 0)
    packer = zlib.compressobj(9)
    data = b"".join(packer.compress(row) for _ in range(rows)) + packer.flush()
    return b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", head) + chunk(b"IDAT", data) + chunk(b"IEND", b"")


def inputs(folder):
    """The hand-made hostile files the cases read."""
    (folder / "huge.png").write_bytes(png(10**6, 10**6))
    side = 16000
    (folder / "bomb.png").write_bytes(png(side, side, b"\x00" + bytes(side), side))
    (folder / "bad.obj").write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 nan\nf 1 2 3\nf 1 2 4\n")
    (folder / "target.png").write_bytes(png(64, 64, b"\x00" + bytes(range(64)), 64))
    # A 2048² RGB photo-sized picture with detail everywhere (a byte ramp, shifted every row by
    # the "Paeth" filter), so the encoder has work in every block.
    side = 2048
    (folder / "photo.png").write_bytes(png(side, side, b"\x04" + bytes((i * 7) % 251 for i in range(3 * side)),
                                           side, colour=True))
    (folder / "victim.txt").write_text("the user's file\n")
    (folder / "povray").write_text("#!/bin/sh\necho 'Parse Error: No objects in scene.' >&2\nexit 1\n")
    (folder / "povray").chmod(0o755)


# Python callers: a progress callback that answers False cancels the render.
CANCEL = ("import sys, ifsforge\n"
          "s = ifsforge.load(sys.argv[1])\n"
          "try:\n"
          "    ifsforge.render(s, 'chaos', 64, iterations=10**11, progress=lambda f: False)\n"
          "except ifsforge.Cancelled:\n"
          "    sys.exit(130)\n")


# (what the issue found, arguments, budget in MB or None, signal or None, when: seconds after the
# start, or the prefix of a temporary file to wait for then seconds more, the test that holds it)
CASES = [
    ("68-byte PNG declaring 10^6 x 10^6, collage", ["collage", SIERPINSKI, "huge.png"], 500, None, None,
     "test_hostile_budget::test_every_png_reader_checks_the_declared_size_first"),
    ("the same PNG, fit", ["fit", "huge.png", "-o", "f.json"], 500, None, None, "same"),
    ("249 KB decompression bomb, compress", ["compress", "bomb.png", "-o", "c.pifs"], 300, None, None, "same"),
    ("the bomb, warp", ["warp", "bomb.png", "--from", SIERPINSKI, "--to", SIERPINSKI, "-o", "w.png"], 300, None,
     None, "same"),
    ("the bomb, palette --apply", ["palette", TERRAIN, "--apply", "bomb.png", "p.png"], 300, None, None, "same"),
    ("the bomb, terrain --heights-from", ["terrain", "-o", "t.png", "--heights-from", "bomb.png"], 300, None, None,
     "same"),
    ("the bomb, render --reference", ["render", SIERPINSKI, "-o", "r.png", "--reference", "bomb.png"], 300, None,
     None, "same"),
    ("decompress --size 8000 8000", ["decompress", "s.pifs", "-o", "d.png", "--size", 8000, 8000], 500, None, None,
     "test_hostile_budget::test_decompress_estimates_the_output_before_decoding"),
    ("morph --frames 3000000 --json (streams; SIGINT after 5 s)",
     ["morph", SIERPINSKI, SIERPINSKI, "-o", "frames", "--frames", 3000000, "--json"], 300, signal.SIGINT, 5.0,
     "test_hostile_budget::test_morph_streams_its_frames"),
    ("warp --frames 2000 (streams)", ["warp", "target.png", "--from", SIERPINSKI, "--to", SIERPINSKI, "-o", "wf",
                                      "--frames", 2000, "--size", 64], 300, None, None, "test_inverse (warp frames)"),
    ("interpolate --samples 200000000", ["interpolate", "--x", 0, 1, 2, "--values", 0, 1, 0, "--a22", 0.5, "-o",
                                         "f.csv", "--samples", 200000000], 300, None, None,
     "test_hostile_budget::test_generators_estimate_and_refuse_before_working"),
    ("palette at the add-on's maximums (65536 x 4096)",
     ["palette", TERRAIN, "-o", "p.png", "--entries", 65536, "--rows", 4096], 1536, None, None, "same"),
    ("breed --count 4096 --size 4096", ["breed", "--count", 4096, "--size", 4096, "-o", "sheet.png"], 500, None,
     None, "same"),
    ("instances --depth 60 --min-probability 1e-12",
     ["instances", FERN, "--depth", 60, "--min-probability", 1e-12, "--pov", "t.pov"], 300, None, None,
     "test_hostile_budget::test_a_pruned_instance_tree_is_estimated_before_it_is_walked"),
    ("volume --res 729, SIGINT in the render", ["volume", SPONGE, "--res", 729, "-o", "v.vdb"], None,
     signal.SIGINT, 1.0, "test_hostile::test_ctrl_c_stops_a_long_command_within_a_second"),
    ("volume --res 729, SIGINT in the .vdb write", ["volume", SPONGE, "--res", 729, "-o", "v.vdb"], None,
     signal.SIGINT, ("v.vdb.tmp-", 0.3), "test_hostile_interrupts"),
    ("volume --res 729, SIGTERM in the .vdb write", ["volume", SPONGE, "--res", 729, "-o", "v.vdb"], None,
     signal.SIGTERM, ("v.vdb.tmp-", 1.5), "test_hostile_interrupts"),
    ("volume --res 729 --compress, SIGINT late in the write",
     ["volume", SPONGE, "--res", 729, "-o", "v.vdb", "--compress"], None, signal.SIGINT, ("v.vdb.tmp-", 1.5),
     "test_hostile_interrupts"),
    ("volume --cluster local:2, SIGINT", ["volume", SPONGE, "--res", 729, "-o", "v.vdb", "--cluster", "local:2"],
     None, signal.SIGINT, 8.0, "test_installed_command (cluster Ctrl-C)"),
    ("fit --restarts 0", ["fit", "target.png", "-o", "f.json", "--restarts", 0], None, None, None,
     "test_cli_options (sweep)"),
    ("render --seed -1", ["render", SIERPINSKI, "-o", "r.png", "--seed", -1], None, None, None, "test_cli_options"),
    ("volume --res 2^63", ["volume", SPONGE, "--res", 2**63, "-o", "v.vdb"], None, None, None, "test_cli_options"),
    ("morph --frames 2^63", ["morph", SIERPINSKI, SIERPINSKI, "-o", "m", "--frames", 2**63], None, None, None,
     "test_cli_options"),
    ("compress --threads 100000", ["compress", "target.png", "-o", "c.pifs", "--threads", 100000], None, None, None,
     "test_cli_options"),
    ("POV-Ray scene named 'my scene +W1 #.pov'",
     ["instances", SIERPINSKI, "--depth", 3, "--pov", "my scene +W1 #.pov", "--render", "my out.png", "--size", "64x64"], None,
     None, None, "test_povray_names::test_a_scene_name_is_data"),
    ("mesh target with a NaN vertex, fit", ["fit", "bad.obj", "-o", "f.json"], None, None, None,
     "test_hostile_meshes::test_fit_names_the_bad_vertex_of_a_mesh_target"),
    ("compress of a 2048² RGB picture, SIGINT in the encode", ["compress", "photo.png", "-o", "c.pifs"], None,
     signal.SIGINT, 2.0, "test_hostile::test_ctrl_c_stops_a_long_command_within_a_second"),
    ("render, SIGTERM", ["render", FERN, "-o", "r.png", "--iterations", 10**11], None, signal.SIGTERM, 1.0,
     "test_hostile_interrupts"),
    ("Python render whose progress callback answers False", ["python", CANCEL, SIERPINSKI], None, None, None,
     "test_render::test_progress_is_reported_and_cancels"),
    ("terrain -o t.png -o full/t.obj -o t.pov, the mesh on a full disk",
     ["terrain", "-o", "t.png", "-o", "full/t.obj", "-o", "t.pov"], None, None, None,
     "test_hostile_writes::test_terrain_commits_none_of_its_outputs_on_a_full_disk", {"full": True}),
    ("growth onto a full disk", ["growth", SYSTEMS / "condensation_tree.json", "-o", "full/frames", "--size", 256],
     None, None, None, "test_hostile_writes::test_growth_on_a_full_disk_leaves_no_frame", {"full": True}),
    ("instances --pov --render --gltf with a failing POV-Ray",
     ["instances", SYSTEMS / "sierpinski_tetrahedron.json", "--depth", 2, "--pov", "s.pov", "--render", "s.png",
      "--gltf", "s.glb", "--size", "32x24"], None, None, None,
     "test_povray_names::test_a_failed_instances_render_leaves_nothing", {"fake_povray": True}),
    ("convert whose last entry cannot be written", ["convert", SYSTEMS / "classic.ifs", "-o", "out"], None, None,
     None, "test_hostile_writes::test_convert_writes_all_entries_or_none", {"blocked": "out/zigzag2.json"}),
    ("render -o r.png where r.png is a symlink to the user's file", ["render", SIERPINSKI, "-o", "r.png"], None,
     None, None, "test_hostile::test_symlink_is_refused_and_kept (and AtomicFile's planted-link test)",
     {"symlink": "r.png"}),
    ("volume --scheduler with no worker (IFSFORGE_CLUSTER_TIMEOUT=10)",
     ["volume", SPONGE, "--res", 64, "-o", "v.vdb", "--scheduler", "SCHEDULER"], None, None, None,
     "test_distributed::test_a_job_whose_every_worker_died_fails_in_bounded_time", {"scheduler": True}),
]

INPUTS = ("huge.png", "bomb.png", "bad.obj", "target.png", "s.pifs", "photo.png")


def running(pid):
    """Whether the child `pid` has not exited (without reaping it: wait4 reads its usage)."""
    return os.waitid(os.P_PID, pid, os.WEXITED | os.WNOHANG | os.WNOWAIT) is None


def run(command, folder, budget, signum, when, env):
    """Runs one case; returns (exit code, peak RSS in MB, seconds to refuse or to stop, last line)."""
    env = dict(os.environ, **env)
    if budget:
        env["IFSFORGE_MEMORY_BUDGET_MB"] = str(budget)
    with open(folder / "stderr.txt", "w+b") as err:
        start = time.monotonic()
        process = subprocess.Popen(command, cwd=folder, env=env, stdout=subprocess.DEVNULL, stderr=err)
        sent = start
        if signum is not None:
            if isinstance(when, tuple):
                prefix, delay = when
                while not any(p.name.startswith(prefix) for p in folder.iterdir()) and running(process.pid):
                    time.sleep(0.01)
            else:
                delay = when
            time.sleep(delay)
            sent = time.monotonic()
            if running(process.pid):
                process.send_signal(signum)
            else:
                sent = None
        _, status, usage = os.wait4(process.pid, 0)
        process.returncode = os.waitstatus_to_exitcode(status)
        took = None if sent is None else time.monotonic() - sent
        err.seek(0)
        lines = [line for line in err.read().decode(errors="replace").splitlines() if line.strip()]
    return process.returncode, usage.ru_maxrss / 1024, took, lines[-1] if lines else ""


def free_port():
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return probe.getsockname()[1]


@contextlib.contextmanager
def prepared(folder, base, extra):
    """Sets up what a case needs beside its inputs (a full disk, a planted link, a blocked entry,
    a failing POV-Ray, a scheduler without workers); yields (environment, command words to
    replace), and takes it all down again."""
    env, words, teardown = {}, {}, []
    if extra.get("full"):
        (folder / "full").mkdir()
        if os.geteuid() != 0 or subprocess.run(["mount", "-t", "tmpfs", "-o", "size=64k", "tmpfs",
                                                str(folder / "full")], capture_output=True).returncode:
            raise RuntimeError("needs root to mount a small tmpfs")
        teardown.append(lambda: subprocess.run(["umount", str(folder / "full")], check=True))
    if extra.get("symlink"):
        os.symlink(folder / "victim.txt", folder / extra["symlink"])
    if extra.get("blocked"):
        (folder / extra["blocked"]).mkdir(parents=True)
    if extra.get("fake_povray"):
        env["PATH"] = f"{folder / 'bin'}{os.pathsep}{os.environ['PATH']}"
        (folder / "bin").mkdir()
        os.link(base / "povray", folder / "bin" / "povray")
    if extra.get("scheduler"):
        port = free_port()
        scheduler = subprocess.Popen(["dask-scheduler", "--host", "127.0.0.1", "--port", str(port),
                                      "--no-dashboard"], cwd=folder, stdout=subprocess.DEVNULL,
                                     stderr=subprocess.DEVNULL)
        teardown.append(lambda: (scheduler.terminate(), scheduler.wait()))
        deadline = time.monotonic() + 60
        while socket.socket().connect_ex(("127.0.0.1", port)) and time.monotonic() < deadline:
            time.sleep(0.1)
        env["IFSFORGE_CLUSTER_TIMEOUT"] = "10"
        words["SCHEDULER"] = f"tcp://127.0.0.1:{port}"
    try:
        yield env, words
    finally:
        for step in reversed(teardown):
            step()


def left_behind(folder, before, code, extra):
    """What a refused or stopped command left that it did not find: must be nothing. A planted
    link's target must keep its bytes."""
    if extra.get("symlink"):
        kept = (folder / "victim.txt").read_text() == "the user's file\n" and (folder / extra["symlink"]).is_symlink()
        return "link and its target kept" if kept else "TARGET CHANGED"
    if code == 0:
        return "—"
    new = sorted(str(p.relative_to(folder)) for p in folder.rglob("*")
                 if p.relative_to(folder).parts[0] not in before and p.name != "stderr.txt")
    new += sorted(str(p.relative_to(folder)) for sub in ("full", "out") if (folder / sub).is_dir()
                  for p in (folder / sub).rglob("*") if str(p.relative_to(folder)) != extra.get("blocked"))
    return ", ".join(new) if new else "nothing"


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--build", default=str(ROOT / "build"), help="the build folder whose python/ to run")
    results.add_argument(parser)
    args = parser.parse_args()
    os.environ["PYTHONPATH"] = str(Path(args.build).resolve() / "python")
    cli = ["/usr/bin/python3", "-P", str(ROOT / "cpp" / "python" / "ifsforge-launcher")]
    with results.Section("hostile_report.py", args.results, "Hostile input: refusals and stops (hostile_report.py)") as out:
        out.print("Peak: the command's peak resident memory; time: from the start to the refusal, or from the "
                  "signal to the exit; left behind: what a refused or stopped command left of its outputs "
                  "(temporary files included).")
        out.print()
        out.print("| example | budget | exit | peak | time | left behind | held by |")
        out.print("| --- | ---: | ---: | ---: | ---: | --- | --- |")
        with tempfile.TemporaryDirectory() as tmp:
            base = Path(tmp)
            inputs(base)
            subprocess.run([*cli, "render", str(SIERPINSKI), "-o", "s.png", "--size", "64"], cwd=base, check=True)
            subprocess.run([*cli, "compress", "s.png", "-o", "s.pifs"], cwd=base, check=True,
                           stdout=subprocess.DEVNULL)
            for number, (what, command, budget, signum, when, test, *extra) in enumerate(CASES):
                extra = extra[0] if extra else {}
                if ("--render" in command or extra.get("fake_povray")) and not shutil.which("povray"):
                    continue
                folder = base / f"case{number}"
                folder.mkdir()
                for name in (*INPUTS, "victim.txt"):
                    os.link(base / name, folder / name)
                with prepared(folder, base, extra) as (env, words):
                    before = {p.name for p in folder.iterdir()}
                    head = ["/usr/bin/python3", "-c"] if command[0] == "python" else cli
                    command_line = [*head, *(words.get(str(word), str(word)) for word in command[command[0] == "python":])]
                    code, peak, took, last = run(command_line, folder, budget, signum, when, env)
                    left = left_behind(folder, before, code, extra)
                print(f"  {what}: {last}", file=sys.stderr)
                took = "ended first" if took is None else f"{took:.2f} s"
                out.print(f"| {what} | {f'{budget} MB' if budget else '—'} | {code} | {peak:.0f} MB | {took} | "
                          f"{left} | {test} |")
                shutil.rmtree(folder)


if __name__ == "__main__":
    main()
