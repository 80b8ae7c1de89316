"""`pip install .` for the cgamesh Python module.

The extension is built by CMake, not by setuptools: in the build directory $CGAMESH_BUILD_DIR
(default ./build), configured first if it has no CMakeCache.txt. An existing build is reused:
`cmake --build --target _cgamesh` then only checks that it is up to date, so the library is not
compiled twice. The package (python/cgamesh plus the built _cgamesh extension) is copied from
<build>/python/cgamesh. setuptools' own files go to <build>/python/setuptools.
"""

import os
import pathlib
import shutil
import subprocess
import sys

from setuptools import Distribution, setup
from setuptools.command.build_py import build_py

ROOT = pathlib.Path(__file__).resolve().parent
BUILD = pathlib.Path(os.environ.get("CGAMESH_BUILD_DIR", ROOT / "build")).resolve()
WORK = BUILD / "python" / "setuptools"


def build_extension():
    """The package directory of the CMake build, with _cgamesh built and up to date."""
    if not (BUILD / "CMakeCache.txt").exists():
        subprocess.check_call(["cmake", "-S", str(ROOT), "-B", str(BUILD), "-DCMAKE_BUILD_TYPE=Release",
                               "-DCGAMESH_BUILD_TESTS=OFF", "-DCGAMESH_BUILD_BENCH=OFF", "-DCGAMESH_BUILD_VIEWER=OFF",
                               "-DCGAMESH_BUILD_PYTHON=ON", f"-DPython3_EXECUTABLE={sys.executable}"])
    subprocess.check_call(["cmake", "--build", str(BUILD), "--target", "_cgamesh", "-j", str(os.cpu_count() or 1)])
    return BUILD / "python" / "cgamesh"


class BuildWithCMake(build_py):
    """Copies the pure-Python files as usual, then the extension built by CMake."""

    def run(self):
        super().run()
        package = build_extension()
        target = pathlib.Path(self.build_lib) / "cgamesh"
        target.mkdir(parents=True, exist_ok=True)
        for f in package.glob("_cgamesh*.so"):
            shutil.copy2(f, target / f.name)


class BinaryDistribution(Distribution):
    """A wheel with a compiled extension (platform tag), though setuptools builds none itself."""

    def has_ext_modules(self):
        return True


WORK.mkdir(parents=True, exist_ok=True)
setup(
    name="cgamesh",
    version="0.1.0",
    description="Conformal Geometric Algebra animation, surgery and deformation of rigged 3D models",
    packages=["cgamesh"],
    package_dir={"cgamesh": "python/cgamesh"},
    package_data={"cgamesh": ["*.pyi", "py.typed"]},
    python_requires=">=3.9",
    install_requires=["numpy"],
    cmdclass={"build_py": BuildWithCMake},
    distclass=BinaryDistribution,
    options={"build": {"build_base": str(WORK / "build")}, "egg_info": {"egg_base": str(WORK)},
             "bdist_wheel": {"bdist_dir": str(WORK / "bdist")}},
    zip_safe=False,
)
