"""ifsforge convert: Fractint .ifs (or any system) to ifsforge/1 JSON files."""
import os
import re

import ifsforge
from ifsforge import cli_common as common


def register(subparsers):
    p = subparsers.add_parser("convert", help="Fractint .ifs entries to one JSON file each")
    p.add_argument("source", help="file.ifs (every entry), file.ifs:entry, or file.json")
    p.add_argument("-o", "--output", required=True, help="folder to write the JSON files into")
    p.set_defaults(run=run)


def slug(name):
    text = re.sub(r"[^A-Za-z0-9]+", "_", name).strip("_").lower()
    return text or "system"


def run(args):
    source = args.source
    if source.lower().endswith(".ifs") and os.path.exists(source):
        systems = ifsforge.read_fractint(source)
    else:
        systems = [common.load_system(source)]
    used, paths = set(), []
    for system in systems:
        name = slug(system.name)
        while name in used:
            name += "_"
        used.add(name)
        paths.append(os.path.join(args.output, name + ".json"))
    for path in paths:
        if os.path.lexists(path) and (os.path.islink(path) or not os.path.isfile(path)):
            raise ifsforge.FileError(f"cannot write '{path}': it is not a regular file; ifsforge writes only regular files")
    with common.staged_folder(args.output) as staging:
        for system, path in zip(systems, paths):
            ifsforge.write_json(os.path.join(staging, os.path.basename(path)), system)
    for system, path in zip(systems, paths):
        print(f"{path}: {system.name} ({system.layout}, {len(system)} maps)")
    return 0
