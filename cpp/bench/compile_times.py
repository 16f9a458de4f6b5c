#!/usr/bin/python3
"""The cold build's CPU time, group by group: the build CI makes from a clean clone (what
cpp/bootstrap.sh builds, then the fuzz targets as tests/fuzz/run.sh builds them), with no compiler
cache, each compile's user + system CPU seconds summed by group (the library, its OpenVDB files
apart, the Python bindings, the C++ tests, the fuzz build, in `--fuzz-build FOLDER` if given); a
precompiled header's compile counts in its target's group. CPU seconds, not wall time: the
2-core build machine is shared, and the load is reported beside them.

    nice -n 10 cpp/bench/compile_times.py [--source DIR] [--build FOLDER] [--jobs 2]
        [--groups library bindings tests fuzz] [--ccache] [--baseline LOG] [--log LOG] [--results FILE|-]

configures FOLDER (default build-times) from DIR (default this checkout; another tree, e.g.
`git archive main | tar -x -C base`, measures that one), with this script as the compiler
launcher, builds the targets of the groups asked for and writes FOLDER/compile_times.log (one
line per compile: CPU s, main or fuzz build, object). `--ccache` puts ccache behind the launcher
for the files of the groups not asked for (the library the bindings link comes from the cache),
while the groups asked for still compile cold (CCACHE_DISABLE): one group is measured without
rebuilding the rest. `--baseline LOG` adds an earlier run's log as the 'before' column; `--log LOG`
reports a log without building.
"""
import argparse
import os
import re
import resource
import subprocess
import sys
from pathlib import Path

import results

ROOT = Path(__file__).resolve().parents[2]
# Group of each compile, from its object's path (the first pattern that matches); the OpenVDB files
# are the library's heaviest, each parsing OpenVDB's headers and instantiating its trees (since
# they are built apart, as ifsforge_vdb, with a precompiled header of their own).
GROUPS = [("library: io/vdb_mesh.cpp", r"/src/io/vdb_mesh\.cpp\."),
          ("library: io/vdb.cpp", r"/src/io/vdb\.cpp\."),
          ("library: io/vdb_voxels.cpp", r"/src/io/vdb_voxels\.cpp\."),
          ("library: the other OpenVDB files", r"/src/io/vdb|/ifsforge_vdb\.dir/"),
          ("library: the other files", r"/ifsforge\.dir/"),
          ("Python bindings", r"/python/"),
          ("C++ tests", r"/ifsforge_tests\.dir/")]
FUZZ = "fuzz build (clang, ASan + UBSan)"
TARGETS = {"library": ["ifsforge"], "bindings": ["_core", "_vdb"], "tests": ["ifsforge_tests"]}
# The groups of --groups by the object paths of their compiles (those of the fuzz build are 'fuzz').
OBJECTS = {"library": ("/ifsforge.dir/", "/ifsforge_vdb.dir/"), "bindings": ("/python/",),
           "tests": ("/ifsforge_tests.dir/",)}
COLD = "IFSFORGE_COMPILE_TIMES_COLD"  # the environment variable naming the groups compiled cold


def launch(log, build, command):
    """Runs one compile and appends its CPU seconds (user + system, its whole process tree), its
    build ('main' or 'fuzz') and its object to `log`, unless the compiler cache served it;
    returns the compiler's exit code."""
    target = os.path.abspath(command[command.index("-o") + 1] if "-o" in command else command[-1])
    group = "fuzz" if build == "fuzz" else next(
        (g for g, keys in OBJECTS.items() if any(key in target for key in keys)), "other")
    cold = group in os.environ.get(COLD, "").split(",")
    env = dict(os.environ, CCACHE_DISABLE="1") if cold else os.environ
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    code = subprocess.call(command, env=env)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = after.ru_utime - before.ru_utime + after.ru_stime - before.ru_stime
    if cold or command[0] != "ccache":  # a file the cache served is no figure
        with open(log, "a") as f:  # one short line per write: appends from parallel compiles stay whole
            f.write(f"{cpu:.2f}\t{build}\t{target}\n")
    return code


def build(args, folder, log):
    def launcher(build):
        command = [sys.executable, str(Path(__file__).resolve()), "--launch", str(log), build]
        return "-DCMAKE_CXX_COMPILER_LAUNCHER=" + ";".join(command + (["ccache"] if args.ccache else []))
    source = Path(args.source).resolve()
    os.environ[COLD] = ",".join(args.groups)
    main_groups = [g for g in args.groups if g != "fuzz"]
    if main_groups:  # as cpp/bootstrap.sh configures
        subprocess.run(["cmake", "-S", str(source), "-B", str(folder), "-DCMAKE_BUILD_TYPE=Release",
                        "-DCMAKE_INTERPROCEDURAL_OPTIMIZATION=OFF", "-DPython_EXECUTABLE=/usr/bin/python3",
                        launcher("main")], check=True, stdout=subprocess.DEVNULL)
        targets = [t for g in main_groups for t in TARGETS[g]]
        subprocess.run(["cmake", "--build", str(folder), "-j", str(args.jobs), "--target", *targets],
                       check=True, stdout=subprocess.DEVNULL)
    if "fuzz" in args.groups:  # as tests/fuzz/run.sh configures
        fuzz = Path(args.fuzz_build).resolve() if args.fuzz_build else folder / "fuzz"
        subprocess.run(["cmake", "-S", str(source / "tests" / "fuzz"), "-B", str(fuzz),
                        "-DCMAKE_BUILD_TYPE=RelWithDebInfo", "-DCMAKE_CXX_COMPILER=clang++", launcher("fuzz")],
                       check=True, stdout=subprocess.DEVNULL)
        subprocess.run(["cmake", "--build", str(fuzz), "-j", str(args.jobs)], check=True,
                       stdout=subprocess.DEVNULL)


def sums(log):
    """{group: (compiles, CPU s)} of a log."""
    out = {}
    for line in Path(log).read_text().splitlines():
        cpu, build, target = line.split("\t")
        group = FUZZ if build == "fuzz" else next((name for name, key in GROUPS if re.search(key, target)), "other")
        n, s = out.get(group, (0, 0.0))
        out[group] = (n + 1, s + float(cpu))
    return out


def main():
    if len(sys.argv) > 3 and sys.argv[1] == "--launch":
        sys.exit(launch(sys.argv[2], sys.argv[3], sys.argv[4:]))
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--source", default=str(ROOT))
    parser.add_argument("--build", default=str(ROOT / "build-times"))
    parser.add_argument("--jobs", type=int, default=2)
    parser.add_argument("--groups", nargs="+", choices=["library", "bindings", "tests", "fuzz"],
                        default=["library", "bindings", "tests", "fuzz"])
    parser.add_argument("--fuzz-build", metavar="FOLDER", help="the fuzz build's folder (default FOLDER/fuzz)")
    parser.add_argument("--ccache", action="store_true")
    parser.add_argument("--baseline", metavar="LOG")
    parser.add_argument("--log", metavar="LOG", help="report this earlier run's log instead of building")
    results.add_argument(parser)
    args = parser.parse_args()
    folder = Path(args.build).resolve()
    folder.mkdir(parents=True, exist_ok=True)
    log = Path(args.log) if args.log else folder / "compile_times.log"
    load_before = os.getloadavg()[0]
    if not args.log:
        log.unlink(missing_ok=True)
        build(args, folder, log)
    load_after = os.getloadavg()[0]
    after = sums(log)
    before = sums(args.baseline) if args.baseline else {}
    with results.Section("compile_times.py", args.results, "Cold build CPU time by group (compile_times.py)") as out:
        if args.log:
            out.print(f"From the log of an earlier run ({Path(args.log).name}); load now {load_after:.1f}.")
        else:
            out.print(f"Groups built: {' '.join(args.groups)}; {'ccache behind the launcher' if args.ccache else 'no cache'}; "
                      f"-j{args.jobs}; load {load_before:.1f} before, {load_after:.1f} after.")
        out.print()
        out.print("| group | compiles | CPU s before | CPU s |")
        out.print("|---|---:|---:|---:|")
        for name in [name for name, _ in GROUPS] + [FUZZ, "other"]:
            if name in after or name in before:
                n, s = after.get(name, (0, 0.0))
                b = f"{before[name][1]:.0f}" if name in before else ""
                out.print(f"| {name} | {n} | {b} | {s:.0f} |")
        total = sum(s for _, s in after.values())
        total_before = f"{sum(s for _, s in before.values()):.0f}" if before else ""
        out.print(f"| all | {sum(n for n, _ in after.values())} | {total_before} | {total:.0f} |")


if __name__ == "__main__":
    main()
