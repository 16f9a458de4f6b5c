"""The sample files the add-on offers: its own copy (made by install.sh), or the repository's
samples/ when the add-on runs from a checkout."""
from pathlib import Path

HERE = Path(__file__).resolve().parent


def folder(kind):
    """The folder of sample `kind` ('systems' or 'terrain'), or None."""
    for candidate in (HERE / "presets" / kind, HERE.parents[1] / "samples" / kind):
        if candidate.is_dir():
            return candidate
    return None


def sample(kind, name):
    """The path of a sample file; FileNotFoundError names what is missing."""
    base = folder(kind)
    if base is None or not (base / name).is_file():
        raise FileNotFoundError(f"the sample '{kind}/{name}' is not installed (run blender_addon/install.sh)")
    return base / name
