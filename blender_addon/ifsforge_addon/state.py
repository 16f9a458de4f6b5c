"""Which system the panel edits, and what the core derives from it (cached per datablock
until a value changes, so panels can redraw at any rate)."""
import itertools

import bpy

import ifsforge

from . import codec
from .properties import read_record


def generated(owner):
    """True for an object or image the add-on generated."""
    return isinstance(owner, (bpy.types.Object, bpy.types.Image)) and owner.ifsforge.kind != 'NONE'


def target(context):
    """(owner, system, settings): the stored system of the active generated object when it is
    selected (editing after the fact), else the scene's design system (deselect to get back)."""
    obj = getattr(context, "active_object", None)
    if generated(obj) and obj.select_get():
        return obj, obj.ifsforge.system, obj.ifsforge.settings
    scene = context.scene
    return scene, scene.ifsforge.system, scene.ifsforge.settings


class Analysis:
    """The ifsforge.Ifs of a record with its contraction factors and classification, or the
    error that stops it from being built."""

    _serials = itertools.count()

    def __init__(self, record):
        self.serial = next(self._serials)  # identifies this state of the values
        self.record = record
        self.system = None
        self.error = ""
        self.classification = ""
        self.factors = []
        self.probabilities = []
        try:
            system = codec.build_system(record)
            self.factors = [float(v) for v in system.contraction_factors()]
            self.probabilities = [float(v) for v in system.probabilities]
            self.classification = system.classify()
            self.system = system
            if self.classification == "divergent":
                self.error = f"'{system.name}' is divergent: it has no attractor"
        except ifsforge.Error as error:
            self.error = str(error)

    @property
    def usable(self):
        """True when the system has an attractor."""
        return self.system is not None and not self.error


_cache = {}


def analyse(pg):
    """The Analysis of a system PropertyGroup, rebuilt only when one of its values changed
    (values are compared, so keyframes, undo and scripts are noticed as well as the UI)."""
    record = read_record(pg)
    key = pg.as_pointer()
    cached = _cache.get(key)
    if cached is None or cached.record != record:
        if len(_cache) > 64:
            _cache.clear()
        cached = _cache[key] = Analysis(record)
    return cached


def system_of(pg):
    """The ifsforge.Ifs of a system PropertyGroup; raises ifsforge errors (divergent included)."""
    analysis = analyse(pg)
    if analysis.system is None:
        raise ifsforge.InputError(analysis.error)
    if analysis.error:
        raise ifsforge.DivergentSystemError(analysis.error)
    return analysis.system


def record_of(values):
    """The codec record (its morph included) of properties.snapshot_system() values."""
    morph = values["morph"]
    return values["record"] | {
        "morph": {"from": morph["source"], "to": morph["target"], "t": morph["factor"]} if morph["enabled"] else None}


def analyse_values(values):
    """The Analysis of snapshot_system() values (an operator's stored system)."""
    return Analysis(record_of(values))


def system_of_values(values):
    """The ifsforge.Ifs of snapshot_system() values; raises as system_of() does."""
    analysis = analyse_values(values)
    if analysis.system is None:
        raise ifsforge.InputError(analysis.error)
    if analysis.error:
        raise ifsforge.DivergentSystemError(analysis.error)
    return analysis.system


def empty(pg):
    """True for a design nobody has filled yet (a fresh scene's): no maps and no morph."""
    return len(pg.maps) == 0 and not pg.morph.enabled


def clear():
    _cache.clear()
