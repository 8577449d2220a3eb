"""setup.py — the build of `pip install --no-build-isolation .` (pyproject.toml, docs/python.md).

The package is python/octray/ (__init__.py, the stubs, py.typed); its compiled module
_octray is built by this project's CMake, as the normal build makes it, for the
interpreter pip runs under: only the module's target (octray_python) and only this
machine's kernel units (OCTRAY_ISAS=host: it runs where it is built, the way pip
installs it), in build-pip/ so that re-installing rebuilds what changed alone and the
CMake build trees (build/, build-*/) are not touched. OCTRAY_PIP_JOBS sets the build's
parallelism (default 2).
"""
import os
import pathlib
import shutil
import subprocess
import sys

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

ROOT = pathlib.Path(__file__).resolve().parent


class CMakeBuild(build_ext):
    """Builds octray._octray with CMake instead of compiling sources itself."""

    def build_extension(self, ext):
        tree = pathlib.Path(self.build_temp).resolve() / "cmake"
        configure = [
            "cmake", "-S", str(ROOT), "-B", str(tree),
            "-DCMAKE_BUILD_TYPE=Release",
            "-DOCTRAY_ISAS=host",
            "-DOCTRAY_PYTHON=ON",
            "-DPython3_EXECUTABLE=" + sys.executable,
            "-DOCTRAY_BUILD_TESTS=OFF", "-DOCTRAY_BUILD_BENCH=OFF", "-DOCTRAY_INSTALL=OFF",
        ]
        subprocess.run(configure, check=True)
        jobs = os.environ.get("OCTRAY_PIP_JOBS", "2")
        subprocess.run(["cmake", "--build", str(tree), "--target", "octray_python", "-j", jobs], check=True)
        built = sorted((tree / "python" / "octray").glob("_octray*.so"))
        if len(built) != 1:
            sys.exit("setup.py: expected one _octray module in %s, found %s" % (tree / "python" / "octray", built))
        target = pathlib.Path(self.get_ext_fullpath(ext.name))
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(built[0], target)


setup(
    packages=["octray"],
    package_dir={"": "python"},
    package_data={"octray": ["__init__.pyi", "py.typed"]},
    ext_modules=[Extension("octray._octray", sources=[])],
    cmdclass={"build_ext": CMakeBuild},
    options={"build": {"build_base": "build-pip"}},
    zip_safe=False,
)
