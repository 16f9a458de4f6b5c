"""The project as others pick it up: a CMake project outside the tree builds against the
installed C++ package (find_package(ifsforge)), the build configures without the optional test
and benchmark libraries, and `pip install .` puts the module and the command into a fresh
virtual environment. Every step reuses the build folder the suite runs against (nothing is
compiled again but the small consumer program)."""
import os
import re
import struct
import subprocess

import pytest

from conftest import BUILD_PYTHON, ROOT, SAMPLES

BUILD = BUILD_PYTHON.parent  # the CMake build folder whose python/ the suite imports
VERSION = re.search(r"project\(ifsforge\s+VERSION\s+([0-9.]+)", (ROOT / "CMakeLists.txt").read_text()).group(1)


def isolated_env(**extra):
    """The environment minus what would let a step see the build tree or another prefix."""
    env = {k: v for k, v in os.environ.items()
           if k not in ("PYTHONPATH", "PYTHONHOME", "VIRTUAL_ENV", "CMAKE_PREFIX_PATH", "PIP_REQUIRE_VIRTUALENV")}
    env.update(PIP_DISABLE_PIP_VERSION_CHECK="1", PIP_NO_INPUT="1", **extra)
    return env


def run(args, **kwargs):
    result = subprocess.run([str(a) for a in args], capture_output=True, text=True,
                            env=kwargs.pop("env", isolated_env()), **kwargs)
    assert result.returncode == 0, f"{args} failed:\n{result.stdout}\n{result.stderr}"
    return result


def png_size(path):
    data = path.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n" and data[12:16] == b"IHDR"
    return struct.unpack(">II", data[16:24])


@pytest.fixture(scope="module")
def build_tree():
    if not (BUILD / "CMakeCache.txt").is_file():
        pytest.fail(f"{BUILD} is not a CMake build folder (the suite runs against BUILD/python)")
    return BUILD


def test_a_cmake_project_outside_the_tree_links_the_installed_library(build_tree, tmp_path):
    prefix = tmp_path / "prefix"
    run(["cmake", "--install", build_tree, "--prefix", prefix])
    assert (prefix / "include/ifsforge/io/system_file.h").is_file()
    assert len(list(prefix.glob("lib*/**/libifsforge.a"))) == 1
    configs = sorted(p.name for p in prefix.glob("lib*/**/cmake/ifsforge/*.cmake"))
    assert {"ifsforgeConfig.cmake", "ifsforgeConfigVersion.cmake", "ifsforgeTargets.cmake"} <= set(configs)

    consumer = tmp_path / "consumer"
    configured = run(["cmake", "-S", ROOT / "tests/consumer", "-B", consumer, "-DCMAKE_BUILD_TYPE=Release",
                      f"-DCMAKE_PREFIX_PATH={prefix}"])
    found = re.search(r"-- ifsforge (\S+) from (\S+), interface options: (.*)", configured.stdout)
    assert found, configured.stdout
    assert found.group(1) == VERSION
    assert found.group(2).startswith(str(prefix))  # the temporary install, not /usr/local's
    assert "-march" not in found.group(3)  # the library's build flags stay its own
    run(["cmake", "--build", consumer])
    out = run([consumer / "consumer", SAMPLES / "sierpinski_triangle.json"]).stdout.splitlines()
    assert out == [f"version {VERSION}", "name Sierpinski triangle", "maps 3",
                   "contraction 0.500000 0.500000 0.500000"]


def configure(tmp_path, source, *args):
    build = tmp_path / "configured"
    result = run(["cmake", "-S", source, "-B", build, "-DIFSFORGE_BUILD_PYTHON=OFF", *args])
    return build, result.stdout


def test_the_build_configures_without_googletest_and_google_benchmark(tmp_path):
    build, out = configure(tmp_path, ROOT, "-DCMAKE_DISABLE_FIND_PACKAGE_GTest=ON",
                           "-DCMAKE_DISABLE_FIND_PACKAGE_benchmark=ON")
    assert "GoogleTest not found, the C++ test suite is skipped" in out
    assert "Google Benchmark not found, its benchmark programs are skipped" in out
    makefile = (build / "Makefile").read_text()
    assert "ifsforge_tests" not in makefile and "bench_render" not in makefile
    assert re.search(r"^ifsforge:", makefile, re.M)  # the library still builds
    assert "-march" not in (build / "cpp/CMakeFiles/ifsforge.dir/flags.make").read_text()  # portable by default


def test_a_project_that_adds_ifsforge_as_a_subdirectory_builds_no_tests_or_benchmarks(tmp_path):
    parent = tmp_path / "parent"
    parent.mkdir()
    (parent / "CMakeLists.txt").write_text(
        "cmake_minimum_required(VERSION 3.20)\nproject(parent LANGUAGES CXX)\n"
        f'add_subdirectory("{ROOT}" ifsforge)\n')
    build, out = configure(tmp_path, parent)
    cache = (build / "CMakeCache.txt").read_text()
    for option in ("IFSFORGE_BUILD_TESTS", "IFSFORGE_BUILD_BENCHMARKS", "IFSFORGE_INSTALL"):
        assert f"{option}:BOOL=OFF" in cache
    assert "bench_render" not in (build / "Makefile").read_text()


def test_pip_installs_the_module_and_the_command_into_a_fresh_virtual_environment(build_tree, tmp_path, cli):
    venv = tmp_path / "venv"
    run(["/usr/bin/python3", "-m", "venv", "--system-site-packages", venv])  # numpy from Debian
    python = venv / "bin/python"
    run([python, "-m", "pip", "install", "--no-build-isolation", "--no-index", "--quiet", ROOT],
        env=isolated_env(IFSFORGE_CMAKE_BUILD_DIR=str(build_tree)), cwd=tmp_path)

    assert run([python, "-m", "pip", "show", "ifsforge"]).stdout.count(f"Version: {VERSION}\n") == 1
    *files, site = run([python, "-c", "import sysconfig, ifsforge, ifsforge._core, ifsforge._vdb; "
                        "print(ifsforge.__file__, ifsforge._core.__file__, ifsforge._vdb.__file__, "
                        "sysconfig.get_path('platlib'))"], cwd=tmp_path).stdout.split()
    assert site.startswith(str(venv) + os.sep)
    assert [os.path.dirname(f) for f in files] == [os.path.join(site, "ifsforge")] * 3
    command = venv / "bin/ifsforge"
    assert command.read_text().splitlines()[0] == f"#!{python}"

    info = run([command, "info", SAMPLES / "barnsley_fern.json"], cwd=tmp_path).stdout
    assert info.splitlines()[0] == "Barnsley fern  (xy, 4 maps)"
    assert len(re.findall(r"^  map \d: p=", info, re.M)) == 4
    assert info == cli("info", SAMPLES / "barnsley_fern.json", check=True).stdout  # the build tree's

    run([command, "render", SAMPLES / "barnsley_fern.json", "-o", "venv.png", "--size", "96x64"], cwd=tmp_path)
    cli("render", SAMPLES / "barnsley_fern.json", "-o", tmp_path / "tree.png", "--size", "96x64", check=True)
    assert png_size(tmp_path / "venv.png") == (96, 64)
    assert (tmp_path / "venv.png").read_bytes() == (tmp_path / "tree.png").read_bytes()
