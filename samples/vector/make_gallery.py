#!/usr/bin/python3
"""Vector IFS gallery: instance lists of the vector_* samples rendered by the real POV-Ray
(spheres tree, cones spiral, a 7D system mixing three primitives), a 2D triangles-and-squares
system as SVG and PNG, and a glTF for Blender. make(out) writes into out/vector/."""
import sys
import time
from pathlib import Path

import ifsforge

HERE = Path(__file__).resolve().parent
SYSTEMS = HERE.parent / "systems"

# name, system, instance options, scene options
SCENES = [
    ("sphere_tree", "vector_sphere_tree.json",
     dict(depth=6, primitives="sphere", normalization="constant", length=0.011, normalize_colors=False),
     dict(view=(30, 10), fov=35)),
    ("cone_spiral", "vector_cone_spiral.json",
     dict(depth=60, min_probability=3e-4, primitives="cone"),
     dict(view=(20, 45), fov=35)),
    ("csg_pyramid", "vector_csg_pyramid.json",
     dict(depth=4, primitives="sphere,box,cone", base_vector=[0, 0, 0.87]),
     dict(view=(35, 25), fov=35)),
]
SIZE = (640, 480)


def make(out: Path):
    folder = out / "vector"
    folder.mkdir(parents=True, exist_ok=True)
    for name, system_file, options, scene in SCENES:
        start = time.perf_counter()
        system = ifsforge.read_json(str(SYSTEMS / system_file))
        instances = ifsforge.instances(system, **options)
        pov = folder / f"{name}.pov"
        ifsforge.write_pov_scene(str(pov), instances, width=SIZE[0], height=SIZE[1], **scene)
        ifsforge.render_povray(str(pov), str(folder / f"{name}.png"), *SIZE)
        print(f"  vector/{name}.png  {len(instances):>6} {', '.join(p.name for p in instances.primitives)}"
              f"  POV-Ray  {time.perf_counter() - start:5.2f} s")

    start = time.perf_counter()
    system = ifsforge.read_json(str(SYSTEMS / "vector_triangles_squares.json"))
    for suffix, primitives in (("", "triangle,square"), ("_outline", "triangle-outline,square-outline")):
        instances = ifsforge.instances(system, depth=5, primitives=primitives, base_point=[0, 0, 0],
                                       base_vector=[1, 0])
        ifsforge.write_svg(str(folder / f"triangles_squares{suffix}.svg"), instances, width=SIZE[1],
                           background=(1, 1, 1))
        ifsforge.write_png(str(folder / f"triangles_squares{suffix}.png"),
                           ifsforge.draw_instances(instances, SIZE[1], SIZE[1]))
        print(f"  vector/triangles_squares{suffix}.svg/.png  {len(instances):>6} {primitives}"
              f"  {time.perf_counter() - start:5.2f} s")

    start = time.perf_counter()
    system = ifsforge.read_json(str(SYSTEMS / "vector_csg_pyramid.json"))
    instances = ifsforge.instances(system, depth=3, primitives="sphere,box,cone", base_vector=[0, 0, 0.87])
    ifsforge.write_gltf_instances(str(folder / "csg_pyramid.glb"), instances)
    print(f"  vector/csg_pyramid.glb  {len(instances):>6} nodes for Blender  {time.perf_counter() - start:5.2f} s")


if __name__ == "__main__":
    target = Path(sys.argv[1] if len(sys.argv) > 1 else "out").resolve()
    make(target)
