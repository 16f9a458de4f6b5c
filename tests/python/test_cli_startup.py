"""The CLI imports only the sub-command it runs, so a small command's time is its work, not its start-up."""
import os
import subprocess

from conftest import BUILD_PYTHON, SAMPLES

PROBE = """
import sys
import ifsforge.cli
code = ifsforge.cli.main(sys.argv[1:])
print(sorted(m for m in sys.modules if m.startswith('ifsforge.commands.')))
print('numpy' in sys.modules)
sys.exit(code)
"""


def run_probe(*args):
    env = dict(os.environ, PYTHONPATH=str(BUILD_PYTHON))
    return subprocess.run(["/usr/bin/python3", "-c", PROBE, *map(str, args)],
                          capture_output=True, text=True, env=env)


def test_a_command_imports_only_itself():
    result = run_probe("algorithms")
    assert result.returncode == 0, result.stderr
    lines = result.stdout.strip().splitlines()
    assert lines[-2] == "['ifsforge.commands.algorithms']"
    # compare (the only command needing numpy at import) was not loaded.
    assert "ifsforge.commands.compare" not in result.stdout


def test_help_still_lists_every_command():
    result = run_probe("--help")
    assert result.returncode == 0
    for name in ("render", "volume", "terrain", "compare", "info"):
        assert name in result.stdout


def test_an_unknown_command_is_refused_with_the_list():
    result = run_probe("rendr", SAMPLES / "barnsley_fern.json")
    assert result.returncode == 2
    assert "invalid choice: 'rendr'" in result.stderr and "render" in result.stderr
