"""setuptools driving the project's CMake build (pyproject.toml says why).

The wheel holds the pure-Python package (python/hydrolux), the extension modules CMake builds
(_core, _image, _video) and the hydrolux CLI with its three plugins in hydrolux/bin/, which the
`hydrolux` console script runs. The CMake build folder is $HYDROLUX_BUILD_DIR, else the one `make`
uses (build/): configured if it is not yet (missing Debian packages installed first by
scripts/install-deps, as `make` does), then brought up to date; with it current nothing is
recompiled.
"""
import os
import re
import shutil
import subprocess
import sys
import sysconfig

from setuptools import Distribution, setup
from setuptools.command.build_py import build_py

ROOT = os.path.dirname(os.path.abspath(__file__))


def version() -> str:
    """The project's version: CMakeLists.txt's project(hydrolux VERSION x.y.z), its one place."""
    with open(os.path.join(ROOT, "CMakeLists.txt"), encoding="utf-8") as f:
        m = re.search(r"project\(hydrolux\s+VERSION\s+([0-9][0-9.]*)", f.read())
    if not m:
        raise RuntimeError("CMakeLists.txt: no project(hydrolux VERSION ...)")
    return m.group(1)


class BuildWithCMake(build_py):
    """The pure-Python files as setuptools copies them, then CMake's modules, CLI and plugins."""

    def run(self):
        super().run()
        build = os.path.abspath(os.environ.get("HYDROLUX_BUILD_DIR") or os.path.join(ROOT, "build"))
        if not os.path.exists(os.path.join(build, "CMakeCache.txt")):
            subprocess.check_call([os.path.join(ROOT, "scripts", "install-deps")])
            subprocess.check_call(["cmake", "-S", ROOT, "-B", build, "-G", "Ninja", "-DCMAKE_BUILD_TYPE=Release",
                                   f"-DPython3_EXECUTABLE={sys.executable}"])
        subprocess.check_call(["cmake", "--build", build, "--target", "hydrolux_python", "hydrolux_cli",
                               "hydrolux_image_plugin", "hydrolux_video_plugin", "hydrolux_netcdf_plugin"])
        suffix = sysconfig.get_config_var("EXT_SUFFIX")
        built = os.path.join(build, "python", "hydrolux")
        modules = [n for n in os.listdir(built) if n.endswith(".so")]
        if not any(n == "_core" + suffix for n in modules):
            raise RuntimeError(f"{built}: the extension modules were built for another Python ({', '.join(modules)}); "
                               f"this one ({sys.executable}) loads *{suffix}: set HYDROLUX_BUILD_DIR to a build "
                               "folder of its own")
        dest = os.path.join(self.build_lib, "hydrolux")
        for name in modules:
            shutil.copy2(os.path.join(built, name), os.path.join(dest, name))
        os.makedirs(os.path.join(dest, "bin"), exist_ok=True)
        for name in ("hydrolux", "libhydrolux_image_plugin.so", "libhydrolux_video_plugin.so",
                     "libhydrolux_netcdf_plugin.so"):
            shutil.copy2(os.path.join(build, "bin", name), os.path.join(dest, "bin", name))


class BinaryDistribution(Distribution):
    """A wheel for this Python and platform: the package carries compiled code."""

    def has_ext_modules(self):
        return True


SCRATCH = os.path.join(ROOT, "build", "setuptools")
os.makedirs(SCRATCH, exist_ok=True)

setup(
    version=version(),
    packages=["hydrolux", "hydrolux.batch"],
    package_dir={"": "python"},
    package_data={"hydrolux": ["py.typed", "*.pyi"]},
    cmdclass={"build_py": BuildWithCMake},
    distclass=BinaryDistribution,
    # setuptools' own scratch folder inside CMake's ignored build folder, not a build/ beside the sources.
    options={"build": {"build_base": SCRATCH}, "egg_info": {"egg_base": SCRATCH}},
    zip_safe=False,
)
