#!/usr/bin/python3
"""Scale-out on Dask: 1 against 2 worker processes (ifsforge.distributed.local_cluster, one thread
each) for a 1024^3 and a 2048^3 volume (to .vdb), a 4096^2 chaos image, a 4096^2 PRR image and a
240-frame 512^2 morph; on request (--cases prr1024) a 1024^2 PRR image.

    cpp/bench/bench_distributed.py [--quick] [--repeat N] [--cases volume1024,volume2048,image4096,prr4096,morph240,prr1024]

Printed per case and worker count: wall time, the workers' CPU time (user + sys of each worker
process, from getrusage) and its busiest worker, the driver's CPU time, the tasks, the per-task
overhead (wall time of empty tasks through the same scheduler) and the bytes moved per task.
The machine may be shared: the CPU-time figures (the busiest worker's CPU plus the driver's, which
merges) give the speed-up the work allows whatever the load; the wall figures are what this run saw.
Each case runs --repeat times (default 3) per worker count, in rounds of 1 then 2 workers (each a
fresh cluster), so that a shared machine's drift over minutes weighs on both; the run of median wall
time is shown.
--quick: 512^3 / 1024^3 volumes, 2048^2 images and 48 frames. Needs the built ifsforge (build/python).
"""
import argparse
import os
import resource
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "build" / "python"))
os.environ["PYTHONPATH"] = str(ROOT / "build" / "python")  # the worker processes import the same build

import distributed  # noqa: E402
import results  # noqa: E402

import ifsforge  # noqa: E402
from ifsforge import _core  # noqa: E402
from ifsforge import distributed as dist  # noqa: E402

SYSTEMS = ROOT / "samples" / "systems"


def worker_cpu(client):
    """CPU seconds (user + sys) each worker process has used so far."""
    def cpu():
        usage = resource.getrusage(resource.RUSAGE_SELF)
        return usage.ru_utime + usage.ru_stime
    return client.run(cpu)


def own_peak_mb():
    """This process's peak resident size, MB: VmHWM (getrusage's maxrss would include the
    high-water mark a spawned worker inherits from the large driver at exec)."""
    with open("/proc/self/status") as f:
        return next(int(line.split()[1]) for line in f if line.startswith("VmHWM")) / 1024


def peak_rss_mb(client):
    """The largest peak resident size of any worker process so far, MB."""
    return max(client.run(own_peak_mb).values())


def driver_cpu():
    return time.process_time()


def measure(client, run):
    """Runs run(client) -> (tasks, bytes); returns wall, per-worker CPU, driver CPU, tasks, bytes
    and the driver's merge (wall seconds after the last result arrived)."""
    before, driver = worker_cpu(client), driver_cpu()
    run.gathered = None
    start = time.perf_counter()
    tasks, moved = run(client)
    end = time.perf_counter()
    after = worker_cpu(client)
    cpu = {w: after[w] - before.get(w, 0.0) for w in after}
    return end - start, cpu, driver_cpu() - driver, tasks, moved, end - run.gathered if run.gathered else 0.0


def counting_runner(client, task, *head):
    """dist._runner that also counts the tasks and the bytes they return."""
    inner = dist._runner(client, task, *head)
    stats = {"tasks": 0, "bytes": 0}

    def distribute(first, last, depth=0):
        results = inner(first, last, depth)
        stats["gathered"] = time.perf_counter()  # the rest of the run is the driver's merge
        stats["tasks"] += len(results)
        stats["bytes"] += sum(len(r) for r in results)
        return results
    return distribute, stats


def volume_case(resolution, folder):
    """The volume to a .vdb, as `ifsforge volume ... -o p.vdb --cluster` makes it (merged and
    written a band at a time)."""
    system = ifsforge.load(str(SYSTEMS / "sierpinski_pyramid.json"))
    options = {"resolution": resolution}
    path = os.path.join(folder, f"pyramid_{resolution}.vdb")

    def run(client):
        distribute, stats = counting_runner(client, dist._volume_task, ifsforge.to_json(system), "prr",
                                            dist._worker_options(options))
        made = ifsforge.render_volume_to_vdb(path, system, "prr", distribute=distribute, **options)
        run.result, run.gathered = f"{made['voxels']:,} voxels to {os.path.getsize(path):,} bytes", stats["gathered"]
        return stats["tasks"], stats["bytes"]
    return run


def image_case(size, algorithm):
    system = ifsforge.load(str(SYSTEMS / "barnsley_fern.json"))
    options = {"width": size, "height": size}

    def run(client):
        distribute, stats = counting_runner(client, dist._render_task, ifsforge.to_json(system), algorithm,
                                            dist._worker_options(options), dist.IMAGE_TASKS_PER_THREAD)
        raster = _core.render_distributed(system, algorithm, options, distribute)
        run.result, run.gathered = f"{raster.covered():,} pixels covered", stats["gathered"]
        return stats["tasks"], stats["bytes"]
    return run


def morph_case(frames, folder):
    a = ifsforge.load(str(SYSTEMS / "sierpinski_triangle.json"))
    b = ifsforge.load(str(SYSTEMS / "barnsley_fern.json"))
    systems = [ifsforge.morph(a, b, k / (frames - 1)) for k in range(frames)]
    paths = [os.path.join(folder, f"morph_{k:04d}.png") for k in range(frames)]

    def run(client):
        sizes = dist.render_frames(client, zip(systems, paths), "chaos", "density", width=512, height=512)
        run.result = f"{len(sizes)} frames"
        tasks = min(len(sizes), dist.FRAME_TASKS_PER_THREAD * dist._threads(client))
        return tasks, 0  # each worker writes its frames: nothing but their sizes comes back
    return run


def task_overhead(client, count=200):
    """Wall seconds per task of `count` empty volume ranges (scheduling, pickling, the setup)."""
    system_json = ifsforge.to_json(ifsforge.load(str(SYSTEMS / "sierpinski_pyramid.json")))
    options = {"resolution": 16, "threads": 1}
    start = time.perf_counter()
    client.gather([client.submit(dist._volume_task, system_json, "prr", options, 0, 0, pure=False)
                   for _ in range(count)])
    return (time.perf_counter() - start) / count


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--quick", action="store_true")
    parser.add_argument("--cases", default="volume1024,volume2048,image4096,prr4096,morph240")
    parser.add_argument("--repeat", type=int, default=3, help="runs per case and worker count (the median is shown)")
    results.add_argument(parser)
    args = parser.parse_args()
    with results.Section("bench_distributed.py", args.results, "Scale-out on Dask (bench_distributed.py)",
                         preformatted=True) as out:
        report(args, out)


def report(args, out):
    small = args.quick
    folder = tempfile.mkdtemp(prefix="ifsforge-bench-")
    cases = {
        "volume1024": ("1024^3 pyramid volume (prr)" if not small else "512^3 pyramid volume (prr)",
                       volume_case(512 if small else 1024, folder)),
        "volume2048": ("2048^3 pyramid volume (prr)" if not small else "1024^3 pyramid volume (prr)",
                       volume_case(1024 if small else 2048, folder)),
        "image4096": ("4096^2 fern image (chaos)" if not small else "2048^2 fern image (chaos)",
                      image_case(2048 if small else 4096, "chaos")),
        "prr1024": ("1024^2 fern image (prr)", image_case(1024, "prr")),
        "prr4096": ("4096^2 fern image (prr)" if not small else "2048^2 fern image (prr)",
                    image_case(2048 if small else 4096, "prr")),
        "morph240": ("240-frame 512^2 morph (chaos)" if not small else "48-frame 512^2 morph (chaos)",
                     morph_case(48 if small else 240, folder)),
    }
    chosen = [c for c in args.cases.split(",") if c]
    # Rounds of (1 worker, then 2): a shared machine's speed drifts over minutes, and each round
    # measures both counts within a few of them (a fresh cluster each time).
    runs, overhead, peak = {}, {}, {}
    for _ in range(args.repeat):
        for workers in (1, 2):
            with dist.local_cluster(workers) as cluster, distributed.Client(cluster) as client:
                dist.check_workers(client)
                overhead.setdefault(workers, task_overhead(client))
                for name in chosen:
                    runs.setdefault((name, workers), []).append(measure(client, cases[name][1]))
                peak[workers] = max(peak.get(workers, 0.0), peak_rss_mb(client))
    figures = {}
    for workers in (1, 2):
        out.print(f"{workers} worker(s): {overhead[workers] * 1000:.1f} ms per empty task; worker peak RSS "
                  f"{peak[workers]:.0f} MB")
        for name in chosen:
            label, run = cases[name]
            # The run of median wall time among --repeat: a shared machine's runs scatter.
            ordered = sorted(runs[name, workers], key=lambda r: r[0])
            wall, cpu, driver, tasks, moved, merge = ordered[len(ordered) // 2]
            figures[name, workers] = (wall, cpu, driver)
            busiest = max(cpu.values())
            spread = f" (median of {len(ordered)}: {ordered[0][0]:.2f}-{ordered[-1][0]:.2f} s)" if len(ordered) > 1 else ""
            merged = f" (the driver's merge after the last result: {merge:.2f} s)" if merge else ""
            out.print(f"  {label}: {run.result}; wall {wall:.2f} s{spread}{merged}, workers' CPU {sum(cpu.values()):.2f} s "
                      f"(busiest {busiest:.2f} s), driver CPU {driver:.2f} s, {tasks} tasks, "
                      f"{moved / max(tasks, 1) / 1e6:.2f} MB per task")
    out.print(f"driver peak RSS {own_peak_mb():.0f} MB")
    out.print("speed-up of 2 workers over 1 (wall; CPU: the busiest worker's CPU plus the driver's, 1 against 2):")
    for name in chosen:
        (w1, c1, d1), (w2, c2, d2) = figures[name, 1], figures[name, 2]
        out.print(f"  {cases[name][0]}: wall {w1 / w2:.2f}x, CPU {(max(c1.values()) + d1) / (max(c2.values()) + d2):.2f}x")


if __name__ == "__main__":
    main()
