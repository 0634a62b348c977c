"""The Python package clothlab for pip: setuptools drives the CMake build (the one build of the
module) and packs the module with the plugins it finds beside itself (clothlab/plugins).

CLOTHLAB_BUILD_DIR names a configured build tree to reuse; otherwise build/pip is configured
(Release, no tests or benchmarks) for the running interpreter.
"""

import os
import pathlib
import shutil
import subprocess
import sys

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

SOURCE = pathlib.Path(__file__).resolve().parent


class CMakeBuild(build_ext):
    def build_extension(self, ext):
        build = pathlib.Path(os.environ.get("CLOTHLAB_BUILD_DIR") or SOURCE / "build" / "pip")
        if not (build / "CMakeCache.txt").exists():
            subprocess.run(["cmake", "-S", str(SOURCE), "-B", str(build),
                            "-DCMAKE_BUILD_TYPE=Release", "-DCLOTHLAB_BUILD_TESTS=OFF",
                            "-DCLOTHLAB_BUILD_BENCH=OFF",
                            f"-DPython3_EXECUTABLE={sys.executable}"], check=True)
        subprocess.run(["cmake", "--build", str(build), "-j", str(os.cpu_count() or 1),
                        "--target", "clothlab_python_package"], check=True)
        target = pathlib.Path(self.get_ext_fullpath(ext.name))
        target.parent.mkdir(parents=True, exist_ok=True)
        modules = sorted((build / "python" / "clothlab").glob("_clothlab*.so"))
        if not modules:
            sys.exit(f"setup.py: no _clothlab module in {build}/python/clothlab "
                     "(needs python3-dev, python3-numpy and pybind11-dev)")
        shutil.copy2(modules[0], target)
        plugins = target.parent / "plugins"
        plugins.mkdir(exist_ok=True)
        for library in (build / "lib" / "clothlab" / "plugins").glob("*.so"):
            shutil.copy2(library, plugins)
        # clothlab.view's page: the viewer's assets, as `clothlab view` finds them beside itself.
        shutil.copytree(build / "share" / "clothlab" / "viewer", target.parent / "viewer",
                        dirs_exist_ok=True)


# setuptools' own folders inside the CMake build folder, not beside the sources.
(SOURCE / "build" / "setuptools").mkdir(parents=True, exist_ok=True)
setup(
    name="clothlab",
    version="0.1.0",
    description="ClothLab's cloth simulation session stepped from Python",
    packages=["clothlab"],
    package_dir={"clothlab": "python/clothlab"},
    ext_modules=[Extension("clothlab._clothlab", sources=[])],
    cmdclass={"build_ext": CMakeBuild},
    install_requires=["numpy"],
    options={"build": {"build_base": "build/setuptools"},
             "egg_info": {"egg_base": "build/setuptools"}},
    zip_safe=False,
)
