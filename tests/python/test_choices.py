"""The names of every enumerated setting come from one C++ table (ifsforge.choices): the CLI offers
exactly those, and the settings structs accept exactly those."""
import pytest

import ifsforge

# (settings struct, property, choices key)
SETTINGS = [
    (ifsforge.VolumeOptions, "density", "density"),
    (ifsforge.VolumeOptions, "escape_norm", "escape_norm"),
    (ifsforge.InstanceOptions, "normalization", "normalization"),
    (ifsforge.InstanceOptions, "color_source", "color_source"),
    (ifsforge.TerrainControlsOptions, "grid", "grid"),
    (ifsforge.TerrainControlsOptions, "signs", "signs"),
    (ifsforge.TerrainPovOptions, "shape", "pov_shape"),
    (ifsforge.TerrainPovOptions, "camera", "pov_camera"),
    (lambda: ifsforge.VdbWriteOptions(), "color_scale", "color_scale"),
    (ifsforge.PifsDecodeOptions, "zoom", "zoom"),
]


@pytest.mark.parametrize("make, prop, key", SETTINGS)
def test_every_choice_is_accepted_and_read_back(make, prop, key):
    options = make()
    assert getattr(options, prop) in ifsforge.choices[key]  # the default is one of them
    for name in ifsforge.choices[key]:
        setattr(options, prop, name)
        assert getattr(options, prop) == name
    with pytest.raises(ifsforge.InputError, match="choose one of: " + ", ".join(ifsforge.choices[key])):
        setattr(options, prop, "no-such-" + key)


@pytest.mark.parametrize("command, option, key", [
    ("volume", "--density", "density"), ("volume", "--escape-norm", "escape_norm"),
    ("volume", "--color-scale", "color_scale"), ("instances", "--color-by", "color_source"),
    ("terrain", "--signs", "signs"), ("terrain", "--pov-shape", "pov_shape"),
    ("terrain", "--pov-camera", "pov_camera"), ("decompress", "--decoder", "decoder"),
    ("decompress", "--zoom", "zoom")])
def test_cli_offers_the_core_names(cli, command, option, key):
    result = cli(command, "--help", check=True)
    assert "{" + ",".join(ifsforge.choices[key]) + "}" in result.stdout.replace("\n", "").replace(" ", "")
