"""Builds the Python module rigidae for `pip install .` (pyproject.toml).

The compiled part, rigidae._core, is CMake's target rigidae_python_core
(python/CMakeLists.txt): this script configures and builds it, then puts it
into the wheel beside the pure-Python files of python/rigidae/.

    RIGIDAE_BUILD_DIR=build pip install --no-build-isolation --no-index .

reuses an already configured CMake build folder (only what changed is
rebuilt: nothing after tools/build.sh). Without it the module is built in
build-pip/ (with ccache when installed, whose cache tools/build.sh's objects
may already fill). RIGIDAE_CMAKE_ARGS adds arguments to that configure step.
"""
import os
import re
import shlex
import shutil
import subprocess
import sys
from pathlib import Path

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

SOURCE = Path(__file__).resolve().parent
# The CMake build folder: RIGIDAE_BUILD_DIR, else build-pip/ (ignored by git),
# beside build/ at the same depth so that ccache, with CCACHE_BASEDIR set to the
# source tree as tools/build.sh sets it, finds build/'s objects under the same
# relative paths. setuptools' own folders go into its pip/ (never CMake's build/).
CMAKE_DIR = Path(os.environ.get("RIGIDAE_BUILD_DIR") or SOURCE / "build-pip").resolve()
PIP_DIR = CMAKE_DIR / "pip"
PIP_DIR.mkdir(parents=True, exist_ok=True)


def version():
    text = (SOURCE / "CMakeLists.txt").read_text()
    return re.search(r"project\(rigidae VERSION ([0-9.]+)", text).group(1)


class CMakeBuild(build_ext):
    def build_extension(self, ext):
        build_dir = CMAKE_DIR
        env = dict(os.environ)
        if os.environ.get("RIGIDAE_BUILD_DIR"):
            if not (build_dir / "CMakeCache.txt").is_file():
                sys.exit(f"RIGIDAE_BUILD_DIR={build_dir}: no CMake build folder (run tools/build.sh first)")
        else:
            configure = ["cmake", "-S", str(SOURCE), "-B", str(build_dir), "-DCMAKE_BUILD_TYPE=Release",
                         f"-DPython3_EXECUTABLE={sys.executable}"]
            if shutil.which("ninja"):
                configure += ["-G", "Ninja"]
            if shutil.which("ccache"):
                configure.append("-DCMAKE_CXX_COMPILER_LAUNCHER=ccache")
                env.setdefault("CCACHE_BASEDIR", str(SOURCE))  # hits for build/'s objects
            configure += shlex.split(os.environ.get("RIGIDAE_CMAKE_ARGS", ""))
            subprocess.run(configure, check=True, env=env)
        subprocess.run(["cmake", "--build", str(build_dir), "--target", "rigidae_python_core",
                        "-j", str(os.cpu_count() or 1)], check=True, env=env)
        built = sorted((build_dir / "python" / "rigidae").glob("_core*.so"))
        if not built:
            sys.exit(f"no rigidae/_core*.so in {build_dir / 'python'}")
        target = Path(self.get_ext_fullpath(ext.name))
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(built[-1], target)


setup(
    version=version(),
    packages=["rigidae"],
    package_dir={"": "python"},
    ext_modules=[Extension("rigidae._core", sources=[])],
    cmdclass={"build_ext": CMakeBuild},
    zip_safe=False,
    options={"build": {"build_base": str(PIP_DIR)}, "egg_info": {"egg_base": str(PIP_DIR)}},
)
