#!/usr/bin/python3
"""POV-Ray parse benchmark of vector IFS scenes: an ifsforge scene of N spheres against a
hand-written union of the same spheres (same camera and lights), both parsed and bounded by the
real POV-Ray 3.7 at a tiny size; then what a manual bounded_by costs when tracing.

    PYTHONPATH=build/python /usr/bin/python3 cpp/bench/bench_vector_povray.py [--depth 8] [--bounded-depth 6]

Depth L of the Sierpinski tetrahedron sample gives 4^L spheres (8: 65,536; 9: 262,144; 10: 1,048,576)."""
import argparse
import re
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import ifsforge

SAMPLE = Path(__file__).resolve().parents[2] / "samples" / "systems" / "sierpinski_tetrahedron.json"


def povray(scene, width, height):
    """Parse, bounding and trace seconds as POV-Ray reports them, and the wall time."""
    start = time.perf_counter()
    result = subprocess.run(["povray", f"+I{scene.name}", f"+O{scene.stem}.png", f"+W{width}", f"+H{height}",
                             "-D", "-A", "-P", "+WT2"], cwd=scene.parent, capture_output=True, text=True)
    wall = time.perf_counter() - start
    if result.returncode != 0:
        sys.exit(f"POV-Ray failed on {scene}:\n{result.stderr[-2000:]}")
    times = {}
    for key in ("Parse", "Bounding", "Trace"):
        m = re.search(rf"{key} Time:.*\(([0-9.]+) seconds\)", result.stderr)
        times[key.lower()] = float(m.group(1)) if m else 0.0
    times["wall"] = wall
    return times


def hand_written(scene_text, instances):
    """The same preamble, then a plain union of sphere { centre, radius pigment { srgb } }."""
    head = scene_text[:scene_text.index("union {\n") + len("union {\n")]
    lines = [head]
    for p, s, c in zip(instances.positions, instances.scales, instances.colors):
        lines.append(f"sphere {{ <{p[0]:.7g}, {p[1]:.7g}, {p[2]:.7g}>, {s:.7g} "
                     f"pigment {{ srgb <{c[0]:.3f}, {c[1]:.3f}, {c[2]:.3f}> }} }}\n")
    lines.append("}\n")
    return "".join(lines)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--depth", type=int, default=8, help="4^depth spheres for the parse comparison")
    parser.add_argument("--bounded-depth", type=int, default=6, help="4^depth spheres for the bounded_by trace test")
    parser.add_argument("--repeat", type=int, default=3, help="runs per scene (the best is reported)")
    import results  # beside this script
    results.add_argument(parser)
    args = parser.parse_args()
    with results.Section("bench_vector_povray.py", args.results,
                         "POV-Ray parse and bounding (bench_vector_povray.py)",
                         preformatted=True) as out:
        report(args, out)


def report(args, out):
    system = ifsforge.read_json(str(SAMPLE))
    with tempfile.TemporaryDirectory() as folder:
        folder = Path(folder)
        instances = ifsforge.instances(system, depth=args.depth)
        start = time.perf_counter()
        ifsforge.write_pov_scene(str(folder / "ifsforge.pov"), instances, width=64, height=48, floor=False,
                                 sky=False, quality="draft")
        written = time.perf_counter() - start
        text = (folder / "ifsforge.pov").read_text()
        (folder / "hand.pov").write_text(hand_written(text, instances))
        out.print(f"{len(instances):,} spheres; ifsforge scene written in {written:.3f} s "
                  f"({(folder / 'ifsforge.pov').stat().st_size / len(instances):.0f} bytes/sphere, hand-written "
                  f"{(folder / 'hand.pov').stat().st_size / len(instances):.0f})")
        for name in ("ifsforge", "hand"):
            best = min((povray(folder / f"{name}.pov", 64, 48) for _ in range(args.repeat)), key=lambda t: t["wall"])
            out.print(f"  {name:9s} parse {best['parse']:6.3f} s  bounding {best['bounding']:6.3f} s  "
                      f"wall {best['wall']:6.3f} s")

        small = ifsforge.instances(system, depth=args.bounded_depth)
        for bounded in (False, True):
            scene = folder / f"bounded_{bounded}.pov"
            ifsforge.write_pov_scene(str(scene), small, width=160, height=120, floor=False, sky=False,
                                     quality="draft", bounded_by=bounded)
            t = povray(scene, 160, 120)
            out.print(f"  {len(small):,} spheres, bounded_by {'on ' if bounded else 'off'}: trace {t['trace']:7.3f} s "
                      f"at 160x120 (parse {t['parse']:.3f} s)")


if __name__ == "__main__":
    main()
