"""Arguments and helpers shared by the CLI sub-commands."""
import argparse
import contextlib
import os

import ifsforge

SYSTEM_HELP = "a system: file.json, file.ifs (its first entry) or file.ifs:entry"


def add_system_argument(parser):
    parser.add_argument("system", help=SYSTEM_HELP)


def add_up_argument(parser):
    """--up for every command that writes meshes (default: what each format's reader expects)."""
    parser.add_argument("--up", choices=ifsforge.choices["up"], default=None,
                        help="the mesh files' up axis (default: the format's: .glb/.obj y, .ply z, so that "
                        "Blender's importers stand the mesh upright)")


def load_system(spec):
    return ifsforge.load(spec)


def parse_size(text, option="--size"):
    """'1024' or '1920x1080' -> (width, height); errors name `option`."""
    parts = text.lower().split("x")
    try:
        values = [int(p) for p in parts]
    except ValueError:
        raise ifsforge.InputError(f"{option} expects N or WxH, got '{text}'") from None
    if len(values) == 1:
        values *= 2
    if len(values) != 2 or min(values) < 1 or max(values) > 65535:
        raise ifsforge.InputError(f"{option} expects 1..65535 pixels per side, got '{text}'")
    return tuple(values)


def ensure_output_folder(path):
    folder = os.path.dirname(os.path.abspath(path))
    if not os.path.isdir(folder):
        raise ifsforge.FileError(f"cannot write '{path}': folder '{folder}' does not exist")
    # Outputs are renamed over their target: a device, FIFO or symbolic link is refused rather
    # than replaced by a regular file (the same rule as the C++ writers).
    if os.path.lexists(path) and (os.path.islink(path) or not os.path.isfile(path)):
        raise ifsforge.FileError(f"cannot write '{path}': it is not a regular file; "
                                 "ifsforge writes only regular files")


def int_option(low, high):
    """An argparse type: a whole number in [low, high], else argparse reports the option and the range."""
    def parse(text):
        try:
            value = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"expects a whole number, got '{text}'") from None
        if not low <= value <= high:
            raise argparse.ArgumentTypeError(f"expects {low}..{high}, got {value}")
        return value
    return parse


def float_option(low, high, low_open=False):
    """An argparse type: a number in [low, high] ((low, high] when low_open)."""
    def parse(text):
        try:
            value = float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"expects a number, got '{text}'") from None
        if not (low < value if low_open else low <= value) or not value <= high:
            raise argparse.ArgumentTypeError(f"expects a number in {'(' if low_open else '['}{low}, {high}], got {text}")
        return value
    return parse


def parse_parameters(items):
    """['norm=linear', 'threshold=1e-6'] -> {'norm': 'linear', 'threshold': '1e-6'}."""
    out = {}
    for item in items or []:
        key, sep, value = item.partition("=")
        if not sep or not key.strip():
            raise ifsforge.InputError(f"--param expects KEY=VALUE, got '{item}'")
        out[key.strip()] = value.strip()
    return out


@contextlib.contextmanager
def all_or_none(targets):
    """Yields {target: staging path beside it (same extension)}. When the block succeeds every
    staging file is renamed onto its target; when it fails (or is interrupted) all are removed
    and the error says no output was written: a multi-file command commits all or none."""
    staged = {t: os.path.join(os.path.dirname(os.path.abspath(t)),
                              f".ifsforge-stage-{os.getpid()}-{os.path.basename(t)}") for t in targets}
    try:
        yield staged
        for target, staging in staged.items():
            os.replace(staging, target)
    except (ifsforge.Error, OSError) as error:
        _remove(staged.values())
        message = str(error)
        for target, staging in staged.items():  # the user's names, not the staging files'
            message = message.replace(staging, target)
        raise type(error)(f"{message}; none of the {len(staged)} outputs was written") from None
    except BaseException:
        _remove(staged.values())
        raise


def _remove(paths):
    for path in paths:
        if os.path.exists(path):
            os.remove(path)
