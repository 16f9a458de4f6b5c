"""Systems as plain records (what the add-on's properties hold) and back. No bpy here.

A record is a dict:
    {"name", "description", "layout", "probabilities": "explicit" | "jacobian" | "uniform",
     "maps": [map record, ...], "morph": None | {"from": json text, "to": json text, "t": float}}
and a map record is
    {"translation", "rotation", "scale", "shear": 3 floats each, "reflect": 3 bools,
     "probability": float,
     "channels": one row per extra channel: n coefficients then the offset,
     "coupling": one row per spatial axis: the coefficients of the extra channels}.
The spatial block follows ifsforge.MapParams (Eq. 5 in 2D: rotation = (theta_x, theta_y),
shear = (h, 0, 0); 3D: rotation = (rx, ry, rz) degrees, shear = (hxy, hxz, hyz)); the rest of
the n x n matrix is kept as it is so that any system survives the round trip.
"""
import json

import numpy as np

import ifsforge

PROBABILITY_MODES = ("explicit", "jacobian", "uniform")


def default_map(index=0, count=1, layout="xy"):
    """A half-size copy placed on a circle. Colour channels follow c' = c / 2 + v / 2 with v
    the map's piece color, so a point's colour mixes the colours of its address with weights
    1/2, 1/4, ... and piece i averages (v_i + sum_j p_j v_j) / 2; a primitive index
    k' = index picks a primitive per map; alpha settles on 1."""
    channel_layout = ifsforge.ChannelLayout(layout)
    n, s = channel_layout.dim, channel_layout.spatial_dims
    angle = 2 * np.pi * index / max(count, 1)
    color = ifsforge.piece_color(index)
    channels = []
    for k, name in enumerate(channel_layout.names[s:]):
        row = [0.0] * (n + 1)
        if name == "k":
            row[n] = float(index)
        else:
            row[s + k] = 0.5
            row[n] = 0.5 if name == "alpha" else 0.5 * color[k % 3]
        channels.append(row)
    return {
        "translation": (float(0.5 + 0.5 * np.cos(angle)), float(0.5 + 0.5 * np.sin(angle)), 0.0 if s == 2 else 0.5),
        "rotation": (0.0, 0.0, 0.0), "scale": (0.5, 0.5, 0.5), "shear": (0.0, 0.0, 0.0),
        "reflect": (False, False, False), "probability": 1.0,
        "channels": channels, "coupling": [[0.0] * (n - s) for _ in range(s)],
    }


def build_system(record):
    """The ifsforge.Ifs a record describes (a morph record: ifsforge.morph of its two systems).
    Raises ifsforge.InputError for anything malformed."""
    morph = record.get("morph")
    if morph:
        start = ifsforge.parse_json(morph["from"], "morph start")
        end = ifsforge.parse_json(morph["to"], "morph end")
        return ifsforge.morph(start, end, float(morph["t"]))
    layout = ifsforge.ChannelLayout(record["layout"])
    maps = [build_map(m, layout, i) for i, m in enumerate(record["maps"])]
    if not maps:
        raise ifsforge.InputError("the system has no maps")
    mode = record["probabilities"]
    if mode not in PROBABILITY_MODES:
        raise ifsforge.InputError(f"unknown probability mode '{mode}'")
    probabilities = {"explicit": [m["probability"] for m in record["maps"]], "jacobian": None,
                     "uniform": [1.0] * len(maps)}[mode]
    system = ifsforge.Ifs(maps, probabilities, layout.text, record.get("name") or "untitled")
    system.description = record.get("description", "")
    return system


def build_map(m, layout, index=0):
    n, s = layout.dim, layout.spatial_dims
    params = ifsforge.MapParams(dim=s, scale=list(m["scale"]), rotation=list(m["rotation"]),
                                shear=list(m["shear"]), reflect=[bool(v) for v in m["reflect"]],
                                translation=list(m["translation"]))
    spatial = ifsforge.AffineMap.from_params(params)
    if n == s:
        return spatial
    if len(m["channels"]) != n - s:
        raise ifsforge.InputError(f"map {index + 1}: layout '{layout.text}' needs {n - s} channel rows, "
                                  f"the map has {len(m['channels'])}")
    matrix = np.zeros((n, n))
    offset = np.zeros(n)
    matrix[:s, :s] = spatial.matrix
    offset[:s] = spatial.offset
    coupling = np.asarray(m.get("coupling") or np.zeros((s, n - s)), float).reshape(s, -1)[:, :n - s]
    matrix[:s, s:] = coupling
    for k, row in enumerate(m["channels"]):
        if len(row) < n + 1:
            raise ifsforge.InputError(f"map {index + 1}: channel row {k + 1} needs {n + 1} numbers")
        matrix[s + k] = row[:n]
        offset[s + k] = row[n]
    return ifsforge.AffineMap(matrix, offset)


def map_record(affine, probability, spatial_dims):
    """The record of one map: parameters of its spatial block (QR), the rest as numbers."""
    n, s = affine.dim, spatial_dims
    p = affine.params(s)
    matrix, offset = affine.matrix, affine.offset
    return {
        "translation": tuple(p.translation), "rotation": tuple(p.rotation), "scale": tuple(p.scale),
        "shear": tuple(p.shear), "reflect": tuple(bool(v) for v in p.reflect),
        "probability": float(probability),
        "channels": [[float(v) for v in matrix[r]] + [float(offset[r])] for r in range(s, n)],
        "coupling": [[float(v) for v in matrix[r, s:]] for r in range(s)],
    }


def system_record(system):
    """The record of an ifsforge.Ifs (explicit probabilities: they reproduce it exactly)."""
    return {
        "name": system.name, "description": system.description, "layout": system.layout,
        "probabilities": "explicit",
        "maps": [map_record(m, p, system.spatial_dims) for m, p in zip(system.maps, system.probabilities)],
        "morph": None,
    }


def extensions(json_text):
    """Parts of an ifsforge/1 document the map list cannot edit (recurrent transitions, super
    IFS members, condensation sets, polar maps: their affine shadows come in instead), so that an
    import can say what it leaves out."""
    document = json.loads(json_text)
    known = {"format", "name", "description", "layout", "maps", "probabilities", "render"}
    polar = any(isinstance(m, dict) and "polar" in m for m in document.get("maps", []))
    return sorted(k for k in document if k not in known) + (["polar maps"] if polar else [])


def load_entries(path):
    """Every system in a file: a JSON system, or each entry of a Fractint .ifs file."""
    if str(path).lower().endswith(".ifs"):
        return list(ifsforge.read_fractint(str(path)))
    return [ifsforge.read_json(str(path))]
