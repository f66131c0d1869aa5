"""setuptools glue for `pip install --no-build-isolation .`: the extension gmotion._core is built
by the project's CMake (target gmotion_py, tests off) for the Python that runs pip, then copied
into the wheel beside python/gmotion/__init__.py. Needs what tools/install-deps.sh installs
(cmake, ninja, a C++20 compiler, pybind11-dev, python3-dev and the C++ libraries). Set
GMOTION_PIP_BUILD_DIR to reuse a build directory (default: build/pip in the source tree)."""

import os
import shutil
import subprocess
import sys
import sysconfig

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

HERE = os.path.dirname(os.path.abspath(__file__))


class CMakeExtension(Extension):
    def __init__(self, name):
        super().__init__(name, sources=[])


class CMakeBuild(build_ext):
    def build_extension(self, ext):
        build = os.environ.get("GMOTION_PIP_BUILD_DIR", os.path.join(HERE, "build", "pip"))
        subprocess.run(["cmake", "-S", HERE, "-B", build, "-G", "Ninja",
                        "-DCMAKE_BUILD_TYPE=Release", "-DGMOTION_BUILD_TESTS=OFF",
                        f"-DGMOTION_PYTHON_EXECUTABLE={sys.executable}"], check=True)
        subprocess.run(["cmake", "--build", build, "--target", "gmotion_py"], check=True)
        suffix = sysconfig.get_config_var("EXT_SUFFIX")
        built = os.path.join(build, "python", "gmotion", "_core" + suffix)
        if not os.path.exists(built):
            raise RuntimeError(f"CMake did not build {built} (is pybind11-dev installed?)")
        target = self.get_ext_fullpath(ext.name)
        os.makedirs(os.path.dirname(target), exist_ok=True)
        shutil.copyfile(built, target)


# setuptools' own scratch (build/lib.*, bdist.*) goes beside the CMake build, not into the
# source tree's build/ (the default preset's build directory).
_scratch = os.path.join(os.environ.get("GMOTION_PIP_BUILD_DIR", os.path.join(HERE, "build", "pip")),
                        "setuptools")
os.makedirs(_scratch, exist_ok=True)
setup(ext_modules=[CMakeExtension("gmotion._core")], cmdclass={"build_ext": CMakeBuild},
      options={"build": {"build_base": _scratch}, "egg_info": {"egg_base": _scratch}})
