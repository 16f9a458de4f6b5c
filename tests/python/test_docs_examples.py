"""Every example of the README and docs/*.md runs as written: the ```sh blocks through bash with
the `ifsforge` command users run, the ```python blocks in one interpreter per page (a page reads
like one session), in document order, in a scratch folder where the repository's shipped files
appear under their own paths (samples/, tests/, povray/, and the build folder build/). A block preceded by an HTML comment
`<!-- example: slow ... -->` or `<!-- example: cluster ... -->` is not run (Blender, machines
that are not here); `<!-- example: file NAME -->` before a ```json block writes it to NAME for
the blocks after it, so the format's documented example is read by the real reader."""
import json
import os
import re
import shutil
import subprocess
import sys
import textwrap

import pytest

from conftest import BUILD_PYTHON, ROOT

PAGES = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]
SHIPPED = ("samples", "tests", "povray", "cpp", "blender_addon", "build")
FENCE = re.compile(r"^( *)```(\w*)[^\n]*\n(.*?)^\1```[ \t]*$", re.M | re.S)
MARK = re.compile(r"<!--\s*example:\s*(\w+)\s*([^\s>]*)[^>]*-->\s*$")
SKIPPED = {"slow", "cluster"}


def blocks(page):
    """(language, code, mark, argument) of every fenced block of `page`, in order; the mark is
    the `<!-- example: ... -->` on the lines just before the block (blank lines between allowed)."""
    text = page.read_text(encoding="utf-8")
    found = []
    for m in FENCE.finditer(text):
        before = text[:m.start()].rstrip().splitlines()
        mark = MARK.search(before[-1]) if before else None
        code = textwrap.dedent(m.group(3))
        found.append((m.group(2), code, mark.group(1) if mark else "", mark.group(2) if mark else ""))
    return found


def runnable(page):
    return [b for b in blocks(page) if b[0] in ("sh", "python", "json") and b[2] not in SKIPPED]


#: Runs the ```python blocks of one page in one namespace, each sent as a JSON line; answers
#: "ok" or the traceback as a JSON line after ANSWER (the examples print too).
ANSWER = "@@docs-example@@"
SESSION = r"""
import json, sys, traceback
namespace = {"__name__": "__main__"}
for line in sys.stdin:
    code = json.loads(line)
    try:
        exec(compile(code, "<docs example>", "exec"), namespace)
        answer = "ok"
    except BaseException:
        answer = traceback.format_exc()
    sys.stdout.flush()
    print("\n" + ANSWER + json.dumps(answer), flush=True)
""".replace("ANSWER", repr(ANSWER))


def scratch_folder(tmp_path):
    """A folder where the shipped files sit under their own paths and `ifsforge` is the command
    users run, on the build tree's module."""
    for name in SHIPPED:
        if (ROOT / name).exists():
            (tmp_path / name).symlink_to(ROOT / name)
    bin_dir = tmp_path / ".bin"
    bin_dir.mkdir()
    shim = bin_dir / "ifsforge"
    # The installed command (the set-up puts it on PATH), on the build tree's module; before any
    # install, the module run as a program.
    installed = shutil.which("ifsforge", path="/usr/local/bin" + os.pathsep + os.environ.get("PATH", ""))
    command = [installed] if installed else [sys.executable, "-m", "ifsforge"]
    shim.write_text("#!/bin/sh\nexec " + " ".join(f"'{part}'" for part in command) + ' "$@"\n')
    shim.chmod(0o755)
    env = dict(os.environ, PYTHONPATH=str(BUILD_PYTHON), PATH=f"{bin_dir}{os.pathsep}{os.environ.get('PATH', '')}")
    return env


@pytest.mark.parametrize("page", PAGES, ids=lambda p: p.relative_to(ROOT).as_posix())
def test_examples_run_as_written(page, tmp_path):
    todo = runnable(page)
    if not todo:
        pytest.skip("no runnable example")
    env = scratch_folder(tmp_path)
    session = None
    try:
        for number, (language, code, mark, argument) in enumerate(todo, 1):
            where = f"{page.relative_to(ROOT)} example {number} ({language})"
            if language == "json":
                if mark == "file" and argument:
                    (tmp_path / argument).write_text(code)
                continue
            if language == "sh":
                result = subprocess.run(["bash", "-e", "-o", "pipefail", "-c", code], cwd=tmp_path, env=env,
                                        capture_output=True, text=True, timeout=300)
                assert result.returncode == 0, f"{where} failed ({result.returncode}):\n{code}\n{result.stderr[-3000:]}"
                continue
            if session is None:
                session = subprocess.Popen([sys.executable, "-c", SESSION], cwd=tmp_path, env=env, text=True,
                                           stdin=subprocess.PIPE, stdout=subprocess.PIPE)
            session.stdin.write(json.dumps(code) + "\n")
            session.stdin.flush()
            answer = None
            for line in session.stdout:
                if line.startswith(ANSWER):
                    answer = json.loads(line[len(ANSWER):])
                    break
            assert answer == "ok", f"{where} failed:\n{code}\n{answer}"
    finally:
        if session is not None:
            session.stdin.close()
            session.wait(timeout=60)


def test_the_marks_are_known_and_the_pages_hold_examples():
    """A misspelt mark would silently skip or run a block; every guide shows at least one example."""
    for page in PAGES:
        text = page.read_text(encoding="utf-8")
        for mark in re.findall(r"<!--\s*example:\s*(\w+)", text):
            assert mark in SKIPPED | {"file"}, f"{page.name}: unknown example mark '{mark}'"
        if page.parent.name == "docs":
            assert any(b[0] in ("sh", "python") for b in blocks(page)), f"{page.name} shows no example"


def test_the_readme_keeps_its_two_commands_and_stays_a_front_door():
    text = (ROOT / "README.md").read_text(encoding="utf-8")
    assert "bash samples/gallery.sh" in text and "bash tests/run.sh" in text
    assert len(text.splitlines()) <= 200
    for target in re.findall(r"\]\(((?:docs|cpp)/[^)#]+)", text):
        assert (ROOT / target).exists(), f"README links to a missing {target}"


def test_links_between_the_guides_lead_somewhere():
    for page in PAGES:
        for target in re.findall(r"\]\(([^)#:]+\.(?:md|png|py))(?:#[^)]*)?\)", page.read_text(encoding="utf-8")):
            assert (page.parent / target).exists(), f"{page.relative_to(ROOT)} links to a missing {target}"
