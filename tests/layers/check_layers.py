#!/usr/bin/env python3
"""Checks the layering of the C++ core: every folder of cpp/include/ifsforge and cpp/src may
include only its own folder and folders of lower layers, so no two folders include each other.

Usage: check_layers.py [REPOSITORY]   (exit status 1 and one line per offending #include)
"""
import os
import re
import sys

# Bottom to top; a folder may include folders of strictly lower layers (and its own).
LAYERS = [
    ["core"],                                    # errors, threads, memory, random, Image, colours
    ["geometry", "model"],                       # TriangleMesh, normals, axes; the IFS models
    ["interpolation", "pifs", "render"],         # fractal interpolation; image coding; 2D renderers
    ["design", "texture", "vector", "volume"],   # targets built on the renderers / interpolation
    ["inverse", "terrain"],                      # fitting (uses vector addresses); terrain (palettes)
    ["io"],                                      # every reader and writer, above what it serialises
]
RANK = {folder: rank for rank, folders in enumerate(LAYERS) for folder in folders}
INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"')


def folder_includes(root):
    """(folder, file, line number, included folder) for every include of a core header."""
    for base in ("cpp/include/ifsforge", "cpp/src"):
        top = os.path.join(root, base)
        for directory, _, files in os.walk(top):
            for name in sorted(files):
                path = os.path.join(directory, name)
                folder = os.path.relpath(path, top).split(os.sep)[0]
                with open(path, encoding="utf-8") as f:
                    for number, line in enumerate(f, 1):
                        m = INCLUDE.match(line)
                        if not m:
                            continue
                        target = m.group(1)
                        if target.startswith("ifsforge/"):
                            yield folder, path, number, target.split("/")[1]
                        elif "/" in target:  # a relative path into another src folder
                            resolved = os.path.normpath(os.path.join(directory, target))
                            yield folder, path, number, os.path.relpath(resolved, top).split(os.sep)[0]


def check(root):
    problems, edges = [], {}
    for folder, path, number, target in folder_includes(root):
        where = f"{os.path.relpath(path, root)}:{number}"
        for name in (folder, target):
            if name not in RANK:
                problems.append(f"{where}: folder '{name}' has no layer in {__file__}")
        if folder == target or folder not in RANK or target not in RANK:
            continue
        edges.setdefault((folder, target), where)
        if RANK[target] >= RANK[folder]:
            problems.append(f"{where}: {folder} (layer {RANK[folder]}) includes {target} (layer {RANK[target]})")
    for (a, b), where in sorted(edges.items()):
        if a < b and (b, a) in edges:
            problems.append(f"two-way dependency {a} <-> {b}: {where} and {edges[(b, a)]}")
    return sorted(set(problems))


def main():
    root = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "..", ".."))
    problems = check(root)
    for p in problems:
        print(p)
    if problems:
        return 1
    print("layers ok: " + " < ".join("{" + ", ".join(layer) + "}" for layer in LAYERS))
    return 0


if __name__ == "__main__":
    sys.exit(main())
