"""Builds the ifsforge wheel with CMake: the wheel carries what `cmake --install --component
python` installs (the ifsforge package with its _core and _vdb modules, byte for byte the files a
root install puts under /usr/local), plus the `ifsforge` command as an entry point.

    pip install --no-build-isolation .

Environment:
  IFSFORGE_CMAKE_BUILD_DIR  a CMake build folder already configured and built (such as build/ from
                            cpp/bootstrap.sh): the package is installed from it, nothing compiles.
                            Without it, a fresh folder below build-wheel/ is configured and built.
  IFSFORGE_CMAKE_ARGS       more arguments for that fresh configure, e.g. -DIFSFORGE_NATIVE=ON
  CMAKE_BUILD_PARALLEL_LEVEL  compile jobs (default: one per CPU)
"""
import os
import re
import shlex
import shutil
import subprocess
import sys
import sysconfig
from pathlib import Path

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

ROOT = Path(__file__).resolve().parent
# setuptools' own folders: build/ is the CMake build folder of cpp/bootstrap.sh.
BUILD_BASE = "build-wheel"  # ignored by git, like every /build*/
MODULES = ("_core", "_vdb")


def project_version():
    text = (ROOT / "CMakeLists.txt").read_text()
    return re.search(r"project\(ifsforge\s+VERSION\s+([0-9][0-9.]*)", text).group(1)


class CMakeBuild(build_ext):
    """Installs the package from a CMake build (configured and built here unless
    IFSFORGE_CMAKE_BUILD_DIR names one) into build_lib."""

    def run(self):
        if self.inplace:
            raise SystemExit("ifsforge: editable installs are not supported; build with CMake and "
                             "put <build>/python on PYTHONPATH instead")
        build = self.cmake_build()
        staging = Path(self.build_temp).resolve() / "install"
        shutil.rmtree(staging, ignore_errors=True)
        subprocess.run(["cmake", "--install", str(build), "--component", "python",
                        "--prefix", str(staging)], check=True, stdout=subprocess.DEVNULL)
        package = next((p.parent for p in staging.rglob("ifsforge/__init__.py")), None)
        if package is None:
            raise SystemExit(f"ifsforge: `cmake --install {build}` installed no ifsforge package")
        suffix = sysconfig.get_config_var("EXT_SUFFIX")
        missing = [m + suffix for m in MODULES if not (package / (m + suffix)).is_file()]
        if missing:
            raise SystemExit(f"ifsforge: {build} has no {', '.join(missing)}: it was built for "
                             f"another Python (configure it with -DPython_EXECUTABLE={sys.executable})")
        target = Path(self.build_lib) / "ifsforge"
        shutil.rmtree(target, ignore_errors=True)
        shutil.copytree(package, target, ignore=shutil.ignore_patterns("__pycache__"))

    def cmake_build(self):
        given = os.environ.get("IFSFORGE_CMAKE_BUILD_DIR")
        if given:
            build = Path(given).resolve()
            if not (build / "CMakeCache.txt").is_file():
                raise SystemExit(f"ifsforge: IFSFORGE_CMAKE_BUILD_DIR={given} is not a CMake build folder")
            return build
        build = Path(self.build_temp).resolve() / "cmake"
        subprocess.run(["cmake", "-S", str(ROOT), "-B", str(build), "-DCMAKE_BUILD_TYPE=Release",
                        f"-DPython_EXECUTABLE={sys.executable}", "-DIFSFORGE_BUILD_TESTS=OFF",
                        "-DIFSFORGE_BUILD_BENCHMARKS=OFF", "-DIFSFORGE_INSTALL=OFF",
                        "-DCMAKE_INTERPROCEDURAL_OPTIMIZATION=OFF",
                        *shlex.split(os.environ.get("IFSFORGE_CMAKE_ARGS", ""))], check=True)
        jobs = os.environ.get("CMAKE_BUILD_PARALLEL_LEVEL") or str(os.cpu_count() or 1)
        subprocess.run(["cmake", "--build", str(build), "--target", *MODULES, "-j", jobs], check=True)
        return build


(ROOT / BUILD_BASE).mkdir(exist_ok=True)
setup(
    version=project_version(),
    packages=[],  # the package comes whole from CMake's install (CMakeBuild), not from discovery
    ext_modules=[Extension(f"ifsforge.{m}", sources=[]) for m in MODULES],
    cmdclass={"build_ext": CMakeBuild},
    options={"build": {"build_base": str(ROOT / BUILD_BASE)}, "egg_info": {"egg_base": str(ROOT / BUILD_BASE)}},
)
