"""The `ifsforge` command line. Each sub-command lives in ifsforge/commands/<name>.py and
exposes register(subparsers); they are discovered, so adding one touches no shared file."""
import argparse
import importlib
import pkgutil
import sys

import ifsforge
import ifsforge.commands


def build_parser():
    parser = argparse.ArgumentParser(
        prog="ifsforge",
        description="Fractal content from iterated function systems: images, volumes, "
        "instance scenes, palettes and terrains.")
    parser.add_argument("--version", action="version", version=ifsforge.__version__)
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    sub.required = True
    for info in sorted(pkgutil.iter_modules(ifsforge.commands.__path__), key=lambda m: m.name):
        module = importlib.import_module(f"ifsforge.commands.{info.name}")
        module.register(sub)
    return parser


def main(argv=None):
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        return args.run(args) or 0
    except ifsforge.Error as error:
        print(f"ifsforge {args.command}: error: {error}", file=sys.stderr)
        return 2
    except OSError as error:
        print(f"ifsforge {args.command}: error: {error}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print(f"ifsforge {args.command}: interrupted", file=sys.stderr)
        return 130
