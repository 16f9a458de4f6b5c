"""Arguments and helpers shared by the CLI sub-commands."""
import os
import tempfile

import ifsforge

SYSTEM_HELP = "a system: file.json, file.ifs (its first entry) or file.ifs:entry"


def add_system_argument(parser):
    parser.add_argument("system", help=SYSTEM_HELP)


def add_up_argument(parser):
    """--up for every command that writes meshes (default: what each format's reader expects)."""
    parser.add_argument("--up", choices=["y", "z"], default=None,
                        help="the mesh files' up axis (default: the format's: .glb/.obj y, .ply z, so that "
                        "Blender's importers stand the mesh upright)")


def load_system(spec):
    return ifsforge.load(spec)


def parse_size(text):
    """'1024' or '1920x1080' -> (width, height)."""
    parts = text.lower().split("x")
    try:
        values = [int(p) for p in parts]
    except ValueError:
        raise ifsforge.InputError(f"--size expects N or WxH, got '{text}'") from None
    if len(values) == 1:
        values *= 2
    if len(values) != 2 or min(values) < 1 or max(values) > 65535:
        raise ifsforge.InputError(f"--size expects 1..65535 pixels per side, got '{text}'")
    return tuple(values)


def ensure_output_folder(path):
    folder = os.path.dirname(os.path.abspath(path))
    if not os.path.isdir(folder):
        raise ifsforge.FileError(f"cannot write '{path}': folder '{folder}' does not exist")


def parse_parameters(items):
    """['norm=linear', 'threshold=1e-6'] -> {'norm': 'linear', 'threshold': '1e-6'}."""
    out = {}
    for item in items or []:
        key, sep, value = item.partition("=")
        if not sep or not key.strip():
            raise ifsforge.InputError(f"--param expects KEY=VALUE, got '{item}'")
        out[key.strip()] = value.strip()
    return out


def write_atomic(path, write, binary=False):
    """Calls write(file) on a temporary beside `path`, then renames it over `path`: a failure
    leaves neither a partial file nor the temporary."""
    folder = os.path.dirname(os.path.abspath(path))
    fd, temporary = tempfile.mkstemp(prefix=".ifsforge-", dir=folder)
    try:
        with os.fdopen(fd, "wb" if binary else "w") as f:
            write(f)
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(temporary, 0o666 & ~umask)  # mkstemp's 0600 is not what a plain write gives
        os.replace(temporary, path)
    except BaseException:
        if os.path.exists(temporary):
            os.remove(temporary)
        raise
