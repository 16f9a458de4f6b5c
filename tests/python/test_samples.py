"""Every sample in samples/systems loads, has an attractor and renders a non-empty image."""
import pytest

import ifsforge
from conftest import SAMPLES

JSON = sorted(SAMPLES.glob("*.json"))


def test_the_library_has_the_classics():
    names = {p.stem for p in JSON}
    for required in ("sierpinski_triangle", "barnsley_fern", "cantor_dust", "koch_curve", "heighway_dragon",
                     "levy_c_curve", "tree", "maple_leaf", "spiral", "crystal", "sierpinski_pyramid",
                     "menger_sponge"):
        assert required in names


@pytest.mark.parametrize("path", JSON, ids=[p.stem for p in JSON])
def test_sample_renders(path):
    system = ifsforge.read_json(str(path))
    assert system.classify() != "divergent"
    defaults = system.render_defaults
    raster = ifsforge.render(system, defaults.get("algorithm", "chaos"), 128, iterations=200_000,
                             window=defaults.get("window"), view=defaults.get("view"))
    assert raster.covered() > 200, f"{path.name} covers only {raster.covered()} pixels"
    # The canonical JSON reloads to the same maps.
    again = ifsforge.parse_json(ifsforge.to_json(system))
    for a, b in zip(system.maps, again.maps):
        assert (a.matrix == b.matrix).all() and (a.offset == b.offset).all()


def test_fractint_library():
    entries = ifsforge.read_fractint(str(SAMPLES / "classic.ifs"))
    assert len(entries) >= 5
    assert any(e.dim == 3 for e in entries)
    for e in entries:
        assert ifsforge.render(e, "prr", 64).covered() > 20, e.name
