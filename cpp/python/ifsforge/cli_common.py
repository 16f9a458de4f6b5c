"""Arguments and helpers shared by the CLI sub-commands."""
import argparse
import contextlib
import json
import math
import os
import secrets
import shutil
import tempfile

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
    """An argparse type: a whole number in [low, high], else argparse reports the option and the range.
    Every integer option goes through here (Parser refuses a bare int), so no value outside what
    the core's C++ type holds ever reaches pybind11."""
    def parse(text):
        try:
            value = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"expects a whole number, got '{text}'") from None
        if not low <= value <= high:
            raise argparse.ArgumentTypeError(f"expects {low}..{high}, got {value}")
        return value
    parse.domain = (low, high)
    return parse


def float_option(low=-math.inf, high=math.inf, low_open=False):
    """An argparse type: a finite number in [low, high] ((low, high] when low_open). NaN and
    infinities are refused whatever the range: no output of ifsforge is made of them."""
    def parse(text):
        try:
            value = float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"expects a number, got '{text}'") from None
        if not math.isfinite(value):
            raise argparse.ArgumentTypeError(f"expects a finite number, got {text}")
        if not (low < value if low_open else low <= value) or not value <= high:
            raise argparse.ArgumentTypeError(f"expects a number in {'(' if low_open else '['}{low:g}, {high:g}], got {text}")
        return value
    parse.domain = (low, high)
    return parse


# The domains every command shares: the core's seeds are 64-bit unsigned, thread counts 0 (all
# cores) to 1024, counts and sizes at least 1.
SEED = int_option(0, 2**64 - 1)
THREADS = int_option(0, 1024)
NUMBER = float_option()


def count_option(high):
    """A count: 1..high."""
    return int_option(1, high)


class DeprecatedAlias(argparse.Action):
    """An old spelling of an option, kept for one release: it stores into the new option's
    destination, with a note on stderr, and is hidden from the help."""

    def __init__(self, option_strings, dest, new=None, store=None, **kwargs):
        self.new, self.store = new, store
        super().__init__(option_strings, dest, help=argparse.SUPPRESS, **kwargs)

    def __call__(self, parser, namespace, values, option_string=None):
        import sys
        print(f"{parser.prog}: note: {option_string} is deprecated; use {self.new}", file=sys.stderr)
        setattr(namespace, self.dest, self.store if self.nargs == 0 else values)


def add_deprecated_alias(parser, old, action):
    """`old` (e.g. --colour-by) as a deprecated spelling of the option `action` added (the
    American spelling, as glTF, Blender and OpenVDB write it)."""
    flag = isinstance(action, (argparse._StoreTrueAction, argparse._StoreFalseAction))
    parser.add_argument(old, action=DeprecatedAlias, dest=action.dest, new=action.option_strings[0],
                        nargs=0 if flag else action.nargs, store=action.const if flag else None,
                        type=None if flag else action.type, choices=action.choices, metavar=action.metavar)


def finite(value):
    """`value` with every NaN or infinity (nested in lists and dicts) replaced by None: JSON has
    no such numbers (Python would write NaN or Infinity, which no JSON reader accepts), and a
    quantity that is not finite is unknown, not a number."""
    if isinstance(value, float):
        return value if math.isfinite(value) else None
    if isinstance(value, dict):
        return {k: finite(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [finite(v) for v in value]
    return value


def to_json(value, indent=2):
    """JSON text of a command's result: finite numbers only (see finite)."""
    return json.dumps(finite(value), indent=indent, allow_nan=False)


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
    # Names nobody can guess (a link planted at a predictable one would redirect a write).
    staged = {t: os.path.join(os.path.dirname(os.path.abspath(t)),
                              f".ifsforge-stage-{secrets.token_hex(8)}-{os.path.basename(t)}") for t in targets}
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



@contextlib.contextmanager
def scene_folder(scene):
    """Yields where to write the POV-Ray scene `scene`: its own name in a private folder beside
    it, where the files the scene reads by name (ifsforge.inc, height images, .df3) are written
    too and POV-Ray renders it. When the block succeeds every file of the folder moves beside
    `scene` (replacing its namesake; a command may first hand the scene itself to all_or_none
    with its other outputs); when it fails or is interrupted the folder goes with all of them, so
    a failed render leaves none. None yields None."""
    if scene is None:
        yield None
        return
    target = os.path.dirname(os.path.abspath(scene))
    folder = tempfile.mkdtemp(prefix=".ifsforge-scene-", dir=target)
    try:
        yield os.path.join(folder, os.path.basename(scene))
        for name in sorted(os.listdir(folder), key=lambda n: n == os.path.basename(scene)):  # the scene last
            os.replace(os.path.join(folder, name), os.path.join(target, name))
    except (ifsforge.Error, OSError) as error:
        raise type(error)(str(error).replace(folder, target)) from None  # the user's folder, not the private one
    finally:
        shutil.rmtree(folder, ignore_errors=True)

def _remove(paths):
    for path in paths:
        if os.path.lexists(path):
            os.remove(path)


@contextlib.contextmanager
def staged_folder(folder):
    """Yields a staging folder beside `folder` (which need not exist) that a command fills file
    by file, one frame at a time (nothing is held in memory for the end). When the block succeeds
    the files are moved into `folder` (created if missing); when it fails or is interrupted the
    staging folder goes, and `folder` is as it was: a multi-frame command commits all or none."""
    import shutil
    import tempfile
    parent = os.path.dirname(os.path.abspath(folder))
    if not os.path.isdir(parent):
        raise ifsforge.FileError(f"cannot write '{folder}': folder '{parent}' does not exist")
    if os.path.lexists(folder) and not os.path.isdir(folder):
        raise ifsforge.FileError(f"cannot write into '{folder}': it is not a folder")
    staging = tempfile.mkdtemp(prefix=".ifsforge-stage-", dir=parent)
    try:
        yield staging
        names = sorted(os.listdir(staging))
        if not os.path.isdir(folder):
            os.rename(staging, folder)
            os.chmod(folder, 0o777 & ~_umask())
            return
        for name in names:
            os.replace(os.path.join(staging, name), os.path.join(folder, name))
        os.rmdir(staging)
    except (ifsforge.Error, OSError) as error:
        shutil.rmtree(staging, ignore_errors=True)
        message = str(error).replace(staging, folder)
        raise type(error)(f"{message}; nothing was written to '{folder}'") from None
    except BaseException:
        shutil.rmtree(staging, ignore_errors=True)
        raise


def _umask():
    mask = os.umask(0)
    os.umask(mask)
    return mask
