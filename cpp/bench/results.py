#!/usr/bin/python3
"""cpp/bench/RESULTS.md is written by the benchmarks themselves: each script owns one section,
keyed by its name, and replaces it after a run that finished, with the command that made it,
the date and the machine. Figures therefore never live in the README or in comments.

In a script:

    import results
    parser = argparse.ArgumentParser(...); results.add_argument(parser)
    args = parser.parse_args()
    with results.Section("bench_x.py", args.results) as out:
        out.print("| a | b |")        # printed now, written to RESULTS.md at the end

The Google Benchmark programs have no Python of their own; this file runs them:

    /usr/bin/python3 cpp/bench/results.py bench_render [--benchmark_filter=ChaosFern] [--build build]

runs build/cpp/bench/bench_render and writes its table as the section `bench_render`. The plain
programs (bench_scaling, bench_scatter) print Markdown themselves; `--plain` records it as it is:

    /usr/bin/python3 cpp/bench/results.py bench_scaling --plain [--threads 16]
`--results -` prints without writing (also for the scripts); `--results FILE` writes elsewhere.
"""
import argparse
import datetime
import json
import os
import platform
import re
import shlex
import subprocess
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parents[1]
RESULTS = HERE / "RESULTS.md"
HEADER = """# Benchmark results

Written by the benchmark scripts in `cpp/bench/` (see `cpp/bench/results.py`): each section
belongs to one script or program, which replaces it when it runs again. Each says the command
that made it, the date and the machine. How to run them: `docs/developer.md` (Benchmarking).
"""


def add_argument(parser):
    """The --results option every benchmark script takes."""
    parser.add_argument("--results", default=str(RESULTS), metavar="FILE",
                        help="the Markdown file whose section this script replaces (default "
                        "cpp/bench/RESULTS.md; '-': print only)")


def machine():
    """One line: cores, architecture, CPU model, system and the load when the run ended."""
    model = ""
    try:
        with open("/proc/cpuinfo") as f:
            model = next((line.split(":", 1)[1].strip() for line in f if line.startswith("model name")), "")
    except OSError:
        pass
    system = platform.system()
    try:
        with open("/etc/os-release") as f:
            system = dict(line.rstrip().split("=", 1) for line in f if "=" in line).get(
                "PRETTY_NAME", system).strip('"')
    except OSError:
        pass
    load = ""
    if hasattr(os, "getloadavg"):
        load = f", load {os.getloadavg()[0]:.1f}"
    # A run given the CPU before other sessions (Linux autogroups: `echo -20 > /proc/self/autogroup`
    # in a session of its own) says so: the load beside it then took little of its time.
    try:
        with open("/proc/self/autogroup") as f:
            nice = int(f.read().split("nice")[1])
        if nice < 0:
            load += f" (this run's session at CPU priority nice {nice})"
    except (OSError, IndexError, ValueError):
        pass
    return f"{os.cpu_count()}-core {platform.machine()}{f' ({model})' if model else ''}, {system}{load}"


def command_line(argv=None):
    """The command as typed from the repository's root."""
    argv = sys.argv if argv is None else argv
    script = Path(argv[0]).resolve()
    try:
        script = script.relative_to(ROOT)
    except ValueError:
        pass
    return " ".join(shlex.quote(str(a)) for a in ["/usr/bin/python3", str(script), *argv[1:]])


def begin(key):
    return f"<!-- results: {key} -->"


def end(key):
    return f"<!-- end: {key} -->"


def replace_section(path, key, body):
    """Writes `body` as the section `key` of the Markdown file `path` (made with HEADER if
    absent): in place of the old one, else at the end. The other sections stay as they are."""
    path = Path(path)
    text = path.read_text() if path.exists() else HEADER
    block = f"{begin(key)}\n{body.rstrip()}\n{end(key)}\n"
    pattern = re.compile(re.escape(begin(key)) + r".*?" + re.escape(end(key)) + r"\n?", re.S)
    if pattern.search(text):
        text = pattern.sub(lambda _: block, text, count=1)
    else:
        text = text.rstrip("\n") + "\n\n" + block
    tmp = path.with_name(path.name + ".tmp")
    tmp.write_text(text)
    os.replace(tmp, path)


class Section:
    """Collects what a script prints and, when the `with` block ends without an error, replaces
    the script's section of RESULTS.md with it under a heading, the command, date and machine."""

    def __init__(self, key, path=str(RESULTS), title=None, argv=None, preformatted=False):
        self.key, self.path, self.title = key, path, title or key
        self.preformatted = preformatted  # plain text (aligned columns): kept as a code block
        self.command = command_line(argv)
        self.lines = []

    def print(self, *values, sep=" "):
        text = sep.join(str(v) for v in values)
        print(text, flush=True)
        self.lines.append(text)

    def body(self):
        when = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
        lines = ["```text", *self.lines, "```"] if self.preformatted else self.lines
        return "\n".join([f"## {self.title}", "", f"Command: `{self.command}`  ", f"Date: {when}  ",
                          f"Machine: {machine()}", "", *lines])

    def __enter__(self):
        return self

    def __exit__(self, kind, value, traceback):
        if kind is None and self.path != "-":
            replace_section(self.path, self.key, self.body())
            print(f"(section '{self.key}' of {self.path} replaced)", file=sys.stderr)
        return False


def record_blender_tables(key, path, title, result):
    """The section `key` from what a benchmark run inside Blender printed (`result`: its
    CompletedProcess): its markdown tables ('|' lines) go to the section, its BENCH lines (the
    figures as JSON, for other programs) to stdout; exits when Blender printed neither."""
    lines = [line for line in result.stdout.splitlines() if line.startswith(("BENCH", "|"))]
    if not lines:
        sys.exit(f"the benchmark did not run:\n{result.stdout[-3000:]}\n{result.stderr[-3000:]}")
    with Section(key, path, title) as section:
        for k, line in enumerate(lines):
            if line.startswith("BENCH"):
                print(line[len("BENCH "):])
                continue
            if section.lines and k + 1 < len(lines) and lines[k + 1].startswith("|---"):
                section.print()  # a blank line between two tables
            section.print(line)


def program_path(program, build):
    """build/cpp/bench/PROGRAM, built (or brought up to date) first: the benchmark programs are
    not part of the default build (`cmake --build build --target benchmarks` builds them all)."""
    path = Path(build) / "cpp" / "bench" / program
    built = subprocess.run(["cmake", "--build", str(build), "--target", program, "-j", str(os.cpu_count() or 1)],
                           capture_output=True, text=True)
    if built.returncode != 0 or not path.exists():
        sys.exit(f"results.py: could not build {program} in {build}:\n{built.stdout[-2000:]}{built.stderr[-2000:]}")
    return path


def google_benchmark_table(program, arguments, build):
    """Runs a Google Benchmark program with `arguments` and returns its rows as Markdown: a column
    per counter that any row has (read from the JSON report, where rows may have different
    counters: the CSV reporter aborts unless every row has every counter)."""
    path = program_path(program, build)
    out = subprocess.run([str(path), *arguments, "--benchmark_format=json"], capture_output=True, text=True,
                         cwd=path.parent, check=True).stdout
    rows = [r for r in json.loads(out).get("benchmarks", []) if r.get("run_type", "iteration") == "iteration"]
    if not rows:
        return ["(no benchmark matched)"]
    fixed = {"name", "family_index", "per_family_instance_index", "run_name", "run_type", "repetitions",
             "repetition_index", "threads", "iterations", "real_time", "cpu_time", "time_unit", "bytes_per_second",
             "items_per_second", "label", "error_occurred", "error_message", "aggregate_name", "aggregate_unit"}
    counters = []
    for r in rows:
        counters += [k for k, v in r.items() if k not in fixed and isinstance(v, (int, float)) and k not in counters]
    table = ["| benchmark | real time | CPU time | " + " | ".join(counters) + " |",
             "| --- | ---: | ---: | " + " | ".join("---:" for _ in counters) + " |"]
    for r in rows:
        unit = r["time_unit"]
        cells = [f"{float(r[c]):.4g}" if c in r else "" for c in counters]
        table.append(f"| {r['name']} | {float(r['real_time']):.4g} {unit} | "
                     f"{float(r['cpu_time']):.4g} {unit} | " + " | ".join(cells) + " |")
    return table


def plain_program_lines(program, arguments, build):
    """Runs a plain benchmark program (one that prints Markdown) and returns its lines."""
    path = program_path(program, build)
    return subprocess.run([str(path), *arguments], capture_output=True, text=True, check=True).stdout.splitlines()


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("program", help="a Google Benchmark program of build/cpp/bench (bench_render, ...)")
    parser.add_argument("--build", default=str(ROOT / "build"))
    parser.add_argument("--plain", action="store_true",
                        help="a plain program printing Markdown (bench_scaling, bench_scatter), not Google Benchmark")
    add_argument(parser)
    args, arguments = parser.parse_known_args()
    table = plain_program_lines if args.plain else google_benchmark_table
    with Section(args.program, args.results) as out:
        for line in table(args.program, arguments, args.build):
            out.print(line)


if __name__ == "__main__":
    main()
