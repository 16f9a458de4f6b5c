"""Every numeric option of every command, fed hostile values (0, -1, NaN, infinity, 1e308, 2^63,
a word): each is refused by the parser with exit 2 and the option's name, or accepted inside the
domain its checked type declares and then run by the command's entry point to a result or a
clear refusal: never a traceback, never a signal."""
import argparse
import contextlib
import io
import json
import math
import shutil

import pytest

from conftest import BUILD_PYTHON, ROOT, SAMPLES, run_group

import ifsforge
from ifsforge import cli

HOSTILE = ["0", "-1", "nan", "inf", "1e308", str(2**63), "word"]
SIERPINSKI = SAMPLES / "sierpinski_triangle.json"

# A small, valid command line for each command ({tmp} is the test's folder, made by `inputs`).
MINIMAL = {
    "address": ["address", SIERPINSKI, "0.5", "0.25"],
    "breed": ["breed", "-o", "{tmp}/sheet.png", "--count", "1", "--size", "16", "--maps", "2"],
    "collage": ["collage", SIERPINSKI, "{tmp}/target.png"],
    "compare": ["compare", SIERPINSKI, "-o", "{tmp}/cmp", "--size", "32", "--algorithms", "chaos"],
    "compress": ["compress", "{tmp}/target.png", "-o", "{tmp}/t.pifs"],
    "decompress": ["decompress", "{tmp}/code.pifs", "-o", "{tmp}/d.png"],
    "fit": ["fit", "{tmp}/target.png", "-o", "{tmp}/f.json", "--maps", "2", "--restarts", "1", "--raster", "16",
            "--time-limit", "3"],
    "growth": ["growth", SAMPLES / "condensation_tree.json", "-o", "{tmp}/g", "--size", "32"],
    "info": ["info", SIERPINSKI, "--dimension-size", "64"],
    "instances": ["instances", SIERPINSKI, "--depth", "2", "--npy", "{tmp}/i.npy"],
    "interpolate": ["interpolate", "--x", "0", "1", "2", "--values", "0", "1", "0", "--a22", "0.5",
                    "-o", "{tmp}/f.csv", "--samples", "16"],
    "morph": ["morph", SIERPINSKI, SIERPINSKI, "-o", "{tmp}/m", "--frames", "2", "--size", "16"],
    "palette": ["palette", ROOT / "samples" / "terrain" / "ember_hls.json", "-o", "{tmp}/p.png", "--entries", "16"],
    "render": ["render", SIERPINSKI, "-o", "{tmp}/r.png", "--size", "32"],
    "terrain": ["terrain", "-o", "{tmp}/t.png", "--res", "33", "--controls", "3", "3"],
    "volume": ["volume", SAMPLES / "sierpinski_tetrahedron.json", "-o", "{tmp}/v.vdb", "--res", "16"],
    "warp": ["warp", "{tmp}/target.png", "--from", SIERPINSKI, "--to", SIERPINSKI, "-o", "{tmp}/w.png",
             "--size", "16"],
}


def numeric_actions(parser):
    """(option, action) for every option or positional that takes numbers (choices excluded)."""
    for action in parser._actions:
        if action.type is not None and not action.choices and not isinstance(action, argparse._HelpAction):
            # A positional is named by its metavar in argparse's messages.
            yield (action.option_strings[0] if action.option_strings else action.metavar or action.dest), action


def command_parsers():
    parser = cli.build_parser()
    return parser, parser.commands


def test_every_numeric_option_has_a_checked_domain():
    _, commands = command_parsers()
    assert set(MINIMAL) | {"algorithms", "convert"} == set(commands), "a new command needs a MINIMAL line"
    for name, sub in commands.items():
        for option, action in numeric_actions(sub):
            assert hasattr(action.type, "domain"), f"{name} {option}: not a cli_common checked type"
            low, high = action.type.domain
            # Integers must fit the core's 64-bit types; no domain reaches NaN.
            assert not math.isnan(low) and not math.isnan(high)
            if isinstance(low, int):
                assert -(2**63) <= low and high <= 2**64 - 1, f"{name} {option}: {low}..{high}"


def test_a_bare_int_option_is_refused_when_the_parser_is_built():
    parser = cli.Parser(prog="x")
    with pytest.raises(TypeError, match="checked domain"):
        parser.add_argument("--count", type=int)


def parse(parser, argv):
    """(exit code or None, stderr, namespace) of parsing argv in-process."""
    err = io.StringIO()
    with contextlib.redirect_stderr(err):
        try:
            args = cli.parse_arguments(parser, argv)
        except SystemExit as stop:
            return stop.code, err.getvalue(), None
    return None, err.getvalue(), args


def with_value(argv, option, action, value):
    count = action.nargs if isinstance(action.nargs, int) else 1
    if option.startswith("-"):
        return argv + [option] + [value] * count
    # A positional (address's coordinates): replace the numbers after the system.
    return argv[:2] + [value] * 2


def sweep():
    """Every (command, option, value): parsed in-process; those the parser accepts are kept."""
    parser, commands = command_parsers()
    accepted = []
    for name, sub in commands.items():
        argv = [str(a) for a in MINIMAL.get(name, [name])]
        for option, action in numeric_actions(sub):
            for value in HOSTILE:
                code, err, args = parse(parser, with_value(argv, option, action, value))
                if code is not None:
                    assert code == 2, (name, option, value, err)
                    # The parser names the option (or the positional) and the sub-command's usage.
                    assert option in err and f"ifsforge {name}" in err, (name, option, value, err)
                    continue
                low, high = action.type.domain
                got = getattr(args, action.dest)
                for v in got if isinstance(got, list) else [got]:
                    assert math.isfinite(v) and low <= v <= high, (name, option, value, v)
                accepted.append((name, option, value))
    return accepted


def test_the_parser_refuses_hostile_numbers_by_name():
    accepted = sweep()
    # Only values inside a declared domain are left: 0, -1, 1e308 or 2^63 where they mean something.
    assert all(value in ("0", "-1", "1e308", str(2**63)) for _, _, value in accepted)


@pytest.fixture(scope="module")
def inputs(tmp_path_factory):
    folder = tmp_path_factory.mktemp("inputs")
    system = ifsforge.load(str(SIERPINSKI))
    ifsforge.write_png(str(folder / "target.png"), ifsforge.render(system, "chaos", 32, binary=True), mode="binary")
    ifsforge.write_pifs(str(folder / "code.pifs"), ifsforge.pifs_encode(ifsforge.read_png(str(folder / "target.png"))))
    return folder


# Runs each case of a JSON list [[argv, folder], ...] through the command's main() in this one
# process (an interpreter per case would cost more than the cases), and writes one JSON line per
# case: its exit code and everything it wrote to the stderr file descriptor. A line "started"
# goes first, so a signal that kills the process names the case it came in.
CASES_RUNNER = """
import json, os, sys, tempfile, traceback
from ifsforge import cli
cases, out = json.load(open(sys.argv[1])), open(sys.argv[2], "w")
devnull = os.open(os.devnull, os.O_WRONLY)
for argv, folder in cases:
    print(json.dumps({"started": argv}), file=out, flush=True)
    os.chdir(folder)
    saved = os.dup(1), os.dup(2)
    with tempfile.TemporaryFile() as err:
        os.dup2(devnull, 1)
        os.dup2(err.fileno(), 2)
        try:
            code = cli.main(argv)
        except SystemExit as stop:
            code = stop.code
        except BaseException:
            traceback.print_exc()
            code = None
        sys.stdout.flush()
        sys.stderr.flush()
        os.dup2(saved[0], 1)
        os.dup2(saved[1], 2)
        err.seek(0)
        text = err.read().decode(errors="replace")
    print(json.dumps({"argv": argv, "code": code, "stderr": text}), file=out, flush=True)
"""


def test_accepted_hostile_values_give_a_result_or_a_clear_refusal(inputs, tmp_path):
    """The values the parser lets through, run by the command's entry point (main), one case after
    another in one child process."""
    _, commands = command_parsers()
    cases = []
    for name, option, value in sweep():
        action = dict(numeric_actions(commands[name]))[option]
        work = tmp_path / f"{name}{option}{value}".replace("/", "_")
        work.mkdir()
        for f in inputs.iterdir():
            shutil.copy(f, work / f.name)
        argv = [str(a).replace("{tmp}", str(work)) for a in MINIMAL[name]]
        cases.append((with_value(argv, option, action, value), str(work)))
    (tmp_path / "cases.json").write_text(json.dumps(cases))
    env = {"PYTHONPATH": str(BUILD_PYTHON), "IFSFORGE_MEMORY_BUDGET_MB": "400", "PATH": "/usr/bin:/bin"}
    child = run_group(["/usr/bin/python3", "-c", CASES_RUNNER, tmp_path / "cases.json", tmp_path / "results"],
                      timeout=600, env=env)
    lines = [json.loads(line) for line in (tmp_path / "results").read_text().splitlines()]
    results = [line for line in lines if "argv" in line]
    assert child.returncode == 0 and len(results) == len(cases), (child.returncode, lines[-1:], child.stderr[-2000:])
    for result in results:
        argv, code, err = result["argv"], result["code"], result["stderr"]
        assert code in (0, 2), (argv, code, err[-2000:])
        assert "Traceback" not in err, (argv, err[-2000:])
        if code == 2:
            assert f"ifsforge {argv[0]}: error:" in err, (argv, err)


def test_old_spellings_are_deprecated_aliases_of_the_american_ones():
    parser, commands = command_parsers()
    cases = [(["fit", "t.png", "-o", "f.json", "--no-colour"], "no_color", True),
             (["fit", "t.png", "-o", "f.json", "--colour-tolerance", "0.25"], "color_tolerance", 0.25),
             (["instances", "s.json", "--colour-by", "constant"], "color_by", "constant"),
             (["instances", "s.json", "--normalisation", "constant"], "normalization", "constant")]
    for argv, dest, value in cases:
        code, err, args = parse(parser, argv)
        assert code is None and getattr(args, dest) == value, (argv, err)
        assert "deprecated" in err, err
    # The help shows only the American spelling.
    for name in ("fit", "instances"):
        text = commands[name].format_help()
        assert "colour" not in text and "normalis" not in text, text


def test_no_option_of_any_command_is_spelled_the_british_way():
    _, commands = command_parsers()
    for name, sub in commands.items():
        for action in sub._actions:
            if action.help == argparse.SUPPRESS:
                continue  # a deprecated alias
            for word in [*action.option_strings, action.dest, str(action.help or ""), *(action.choices or [])]:
                assert "colour" not in str(word).lower() and "normalis" not in str(word).lower(), (name, word)


def british(text):
    return "colour" in text.lower() or "normalis" in text.lower()


def test_the_python_api_is_spelled_the_american_way():
    assert not [name for name in dir(ifsforge) if british(name)]
    for name in dir(ifsforge):
        value = getattr(ifsforge, name)
        if isinstance(value, type):
            # InstanceOptions.normalisation is the one deprecated spelling left, for a release.
            assert not [a for a in dir(value) if british(a) and a != "normalisation"], name
    for old, new in (("fit_colour", "fit_color"), ("has_colour", "has_color"),
                     ("colour_foreground", "color_foreground"), ("ColourFitOptions", "ColorFitOptions")):
        with pytest.warns(DeprecationWarning, match=new):
            assert getattr(ifsforge, old) is getattr(ifsforge, new)


def test_the_addon_properties_are_spelled_the_american_way():
    # Every bpy property the add-on declares: its identifier, label and description.
    import re
    declared = re.compile(r"^\s*(\w+)\s*:\s*\w+Property\((.*)$")
    found = 0
    for path in (ROOT / "blender_addon" / "ifsforge_addon").glob("*.py"):
        lines = path.read_text().splitlines()
        for n, line in enumerate(lines):
            m = declared.match(line)
            if not m:
                continue
            found += 1
            text = " ".join([m.group(1), m.group(2), *lines[n + 1:n + 3]])
            assert not british(text), f"{path.name}:{n + 1}: {line.strip()}"
    assert found > 50
