"""A volume as a participating medium: the density per world unit that makes it look the same at
any resolution and in any density mode (Blender's material and POV-Ray's media both use it), its
POV-Ray .df3 files (the density, and for a colour volume one file per linear colour channel,
named after the density's), and a POV-Ray scene of coloured media reading them (`ifsforge volume
--df3 V.df3 --pov S.pov`). The Blender add-on's scene export uses the same names."""
import os

import ifsforge

CHANNELS = ("red", "green", "blue")
MEDIA_SAMPLES = 16  # per interval of POV-Ray's adaptive media sampling (method 3); fewer render lit media too bright
GRAY = 0.8  # the colour of a volume without one (Principled Volume's default, linear)


def channel_path(path, channel):
    """The .df3 holding `channel` of the colour beside the density's `path`: V.df3 -> V_red.df3."""
    stem, extension = os.path.splitext(path)
    return f"{stem}_{channel}{extension}"


def df3_paths(path, volume):
    """Every .df3 `write_df3_files` writes for `volume` at `path`: the density's, then the colour's."""
    return [path] + ([channel_path(path, c) for c in CHANNELS] if volume.color is not None else [])


def write_df3_files(path, volume, bits=8, border=False, targets=None):
    """The density at `path` and, for a colour volume, its linear red, green and blue beside it
    (ifsforge.write_df3's content). `targets` maps each name of df3_paths to where to write it
    (a staging file), by default itself."""
    for name, content in zip(df3_paths(path, volume), ("density",) + CHANNELS):
        ifsforge.write_df3((targets or {}).get(name, name), volume, bits=bits, content=content, border=border)


DENSITY = 2.0  # the default density per world unit (Blender's Material density, --pov-density)


def per_world_unit(volume):
    """The factor that turns the grid's values into a density per world unit whose integral over
    the grid's box -- the mass of the seed's invariant measure, density x voxel volume summed -- is
    the box's volume, at any resolution and in any density mode: (voxels of the box) / (sum of
    the values). A fractal fills a smaller share of its box at every finer resolution (binary),
    and each voxel gets a smaller share of the points (hits, measure): without it, the same
    density would render fainter at every resolution, and hits or measure near invisible."""
    import numpy as np  # late: the command's parser imports this module, numpy only its work
    total = float(np.sum(np.asarray(volume.density, np.float64)))
    return float(np.prod(np.asarray(volume.dims, np.float64))) / total if total > 0 else 1.0


def _density(name):
    return f"density_file df3 {ifsforge.pov_string(name)} interpolate 0"


def media_box(volume, names, density):
    """A box over the volume's grid (in the system's coordinates) holding media: absorption of
    `density` (per world unit, per_world_unit already applied) times the grid's density, and
    emission of the same times the voxel's linear colour (its three channel files averaged into
    an RGB density, each x 3) or GRAY: where the volume is opaque POV-Ray shows its colour."""
    import numpy as np
    top = float(np.max(volume.density)) if len(volume) else 0.0  # the .df3 holds density / top
    sigma = density * top
    grid = f"density {{ {_density(names[0])} }}"
    if len(names) > 1:
        entries = "".join(f"        [1 {_density(name)} color_map {{ [0 rgb 0] [1 rgb {axis}] }}]\n"
                          for name, axis in zip(names[1:], ("<3, 0, 0>", "<0, 3, 0>", "<0, 0, 3>")))
        tint, glow = f"      density {{ average density_map {{\n{entries}      }} }}\n", sigma
    else:
        tint, glow = "", sigma * GRAY
    size = np.asarray(volume.dims, np.float64) * volume.voxel_size
    lo = np.asarray(volume.origin, np.float64)
    sampling = f"method 3 intervals 1 samples {MEDIA_SAMPLES}"
    return (f"box {{ 0, 1 pigment {{ rgbt 1 }} hollow\n  interior {{\n"
            f"    media {{ {sampling}\n      absorption {sigma:.9g}\n      {grid}\n    }}\n"
            f"    media {{ {sampling}\n      emission {glow:.9g}\n      {grid}\n{tint}    }}\n  }}\n"
            f"  scale <{size[0]:.9g}, {size[1]:.9g}, {size[2]:.9g}> translate <{lo[0]:.9g}, {lo[1]:.9g}, {lo[2]:.9g}>\n}}\n")


def scene(volume, names, density, width, height, title=""):
    """A POV-Ray 3.7 scene of the volume as media_box, seen from the diagonal of its box with z up
    (the system's coordinates unchanged, as ifsforge's instance scenes), on a black background."""
    import numpy as np
    size = np.asarray(volume.dims, np.float64) * volume.voxel_size
    centre = np.asarray(volume.origin, np.float64) + size / 2
    eye = centre + np.array([1.0, -1.0, 0.8]) / np.linalg.norm([1.0, -1.0, 0.8]) * np.linalg.norm(size) * 1.8
    vec = lambda v: "<" + ", ".join(f"{x:.9g}" for x in v) + ">"  # noqa: E731
    return (f"// {ifsforge.pov_comment(title)}: an ifsforge volume as media\n#version 3.7;\n"
            "global_settings { assumed_gamma 1.0 }\nbackground { rgb 0 }\n"
            # right -x: the system's right-handed axes in POV-Ray's left-handed camera.
            f"camera {{ perspective location {vec(eye)} sky z up y right -x * {width / height:.9g} angle 40 "
            f"look_at {vec(centre)} }}\n" + media_box(volume, names, density))
