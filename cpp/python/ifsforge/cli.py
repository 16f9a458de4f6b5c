"""The `ifsforge` command line. Each sub-command lives in ifsforge/commands/<name>.py and
exposes register(subparsers); they are discovered, so adding one touches no shared file."""
import argparse
import importlib
import os
import signal
import sys

import ifsforge
import ifsforge.commands


def command_names():
    """The sub-command modules, listed without importing them (from the folder: pkgutil would
    import inspect, a noticeable part of every command's start)."""
    folder = ifsforge.commands.__path__[0]
    return sorted(name[:-3] for name in os.listdir(folder) if name.endswith(".py") and not name.startswith("_"))


def terminal_width():
    """What argparse's help fills: $COLUMNS, else the terminal's width, else 80 (less 2, as
    argparse does), read once (see Formatter)."""
    if not hasattr(terminal_width, "columns"):
        try:
            columns = int(os.environ.get("COLUMNS", "0"))
        except ValueError:
            columns = 0
        if columns <= 0:
            try:
                columns = os.get_terminal_size(sys.__stdout__.fileno()).columns
            except (AttributeError, ValueError, OSError):
                columns = 80
        terminal_width.columns = columns - 2
    return terminal_width.columns


class Formatter(argparse.HelpFormatter):
    """argparse's formatter with the width read once: argparse builds one for every option it
    adds, each importing shutil (and bz2, lzma) and asking the terminal again."""

    def __init__(self, prog, indent_increment=2, max_help_position=24, width=None):
        super().__init__(prog, indent_increment, max_help_position, terminal_width() if width is None else width)


class Parser(argparse.ArgumentParser):
    """An ArgumentParser whose help uses Formatter (the sub-commands' parsers too), and whose
    numeric options all come from cli_common's checked types: a bare int or float would let -1,
    2^63, NaN or infinity through to the core (a pybind11 traceback, or a wrong answer)."""

    def __init__(self, *args, **kwargs):
        kwargs.setdefault("formatter_class", Formatter)
        super().__init__(*args, **kwargs)

    def _add_action(self, action):
        if action.type in (int, float) and not action.choices:
            raise TypeError(f"{self.prog} {'/'.join(action.option_strings) or action.dest}: numeric options "
                            "take cli_common.int_option / float_option (a checked domain), not a bare "
                            f"{action.type.__name__}")
        return super()._add_action(action)


def build_parser(only=None):
    """The parser with every sub-command, or with `only` that one (a run imports just the
    command it runs: some import numpy or large helpers that the others never need)."""
    parser = Parser(
        prog="ifsforge",
        description="Fractal content from iterated function systems: images, volumes, "
        "instance scenes, palettes and terrains.")
    parser.add_argument("--version", action="version", version=ifsforge.__version__)
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=Parser)
    sub.required = True
    for name in command_names():
        if only is None or name == only:
            importlib.import_module(f"ifsforge.commands.{name}").register(sub)
    parser.commands = sub.choices
    return parser


def parse_arguments(parser, argv):
    """parse_args, except that words no option takes are reported with the sub-command's usage
    (argparse reports them with the top-level one, which lists no option of the command)."""
    args, extras = parser.parse_known_args(argv)
    if extras:
        command = parser.commands.get(getattr(args, "command", None), parser)
        command.error(f"unrecognized arguments: {' '.join(extras)}")
    return args


def requested_command(argv):
    """The sub-command named by argv (its first word), or None (help, version, a typo)."""
    words = sys.argv[1:] if argv is None else list(argv)
    if words and words[0] in command_names():
        return words[0]
    return None


def as_option(message, args):
    """The core names a setting as Python does ("depth: ..."); on the command line it is the
    option the user typed ("--depth: ...")."""
    name, colon, rest = message.partition(": ")
    if colon and name.isidentifier() and hasattr(args, name) and name != "command":
        return f"--{name.replace('_', '-')}: {rest}"
    return message


# Exit statuses of a command stopped by a signal, as a shell reports them (128 + the signal).
STOPPED = {signal.SIGINT: (130, "interrupted"), signal.SIGTERM: (143, "terminated")}


def on_interrupt(signum, frame):
    """Ctrl-C and SIGTERM alike: Python's KeyboardInterrupt, which the core hears at its next
    progress poll and unwinds through (staging files removed, nothing committed). The signal is
    remembered: a KeyboardInterrupt raised inside an import that C code makes (numpy's, when the
    first array is returned) comes out as an ImportError, yet the user asked to stop."""
    on_interrupt.received = signum
    raise KeyboardInterrupt


def main(argv=None):
    parser = build_parser(only=requested_command(argv))
    args = parse_arguments(parser, argv)
    on_interrupt.received = None
    for signum in STOPPED:
        try:
            signal.signal(signum, on_interrupt)
        except ValueError:
            pass  # not the main thread: the caller's handlers stay
    try:
        return args.run(args) or 0
    except (KeyboardInterrupt, Exception) as error:
        if on_interrupt.received is not None or isinstance(error, KeyboardInterrupt):
            status, word = STOPPED[on_interrupt.received or signal.SIGINT]
            print(f"ifsforge {args.command}: {word}", file=sys.stderr)
            return status
        if isinstance(error, ifsforge.Error):
            print(f"ifsforge {args.command}: error: {as_option(str(error), args)}", file=sys.stderr)
            return 2
        if isinstance(error, OSError):
            print(f"ifsforge {args.command}: error: {error}", file=sys.stderr)
            return 2
        raise


def run():
    """The command's entry point: main(), then leave without the interpreter's teardown. Every
    output is written and closed by then (files are committed by rename); the teardown frees
    every object of every module one by one, which takes longer than some commands' work."""
    status = main()
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(status)
