"""The build of `pip install .` / `python3 -m build --no-isolation` (pyproject.toml): CMake
configures and builds the compiled module `penalty._core` and the `penalty` command line from
Debian's packages (scripts/install-deps.sh), offline, then the wheel gets the package's Python
files, both binaries and the .pth file that makes `import Sofa` find penalty's SofaPython3 subset.

Environment:
  PENALTY_CMAKE_BUILD_DIR   build in (or reuse) this CMake build folder (default build/pip)
  CMAKE_BUILD_PARALLEL_LEVEL  parallel compile jobs (CMake's own variable; default: the cores)
The version is the CMake project's (CMakeLists.txt), as `penalty --version` prints it.
"""
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

ROOT = Path(__file__).resolve().parent


def project_version() -> str:
    return re.search(r"project\(penalty VERSION ([0-9.]+)", (ROOT / "CMakeLists.txt").read_text()).group(1)


class CMakeBuild(build_ext):
    """Builds the CMake targets penalty_python and penalty_cli and copies them into the wheel."""

    def build_extension(self, ext):
        build = Path(os.environ.get("PENALTY_CMAKE_BUILD_DIR") or ROOT / "build" / "pip").resolve()
        if not (build / "CMakeCache.txt").exists():
            configure = ["cmake", "-S", str(ROOT), "-B", str(build), "-DCMAKE_BUILD_TYPE=Release",
                         "-DPENALTY_BUILD_PYTHON=ON", "-DPENALTY_BUILD_TESTS=OFF", "-DPENALTY_BUILD_BENCH=OFF",
                         "-DPENALTY_BUILD_APPS=ON", f"-DPython3_EXECUTABLE={sys.executable}"]
            if shutil.which("ninja"):
                configure += ["-G", "Ninja"]
            if shutil.which("ccache"):
                configure.append("-DCMAKE_CXX_COMPILER_LAUNCHER=ccache")
            subprocess.run(configure, check=True)
        jobs = os.environ.get("CMAKE_BUILD_PARALLEL_LEVEL") or str(os.cpu_count() or 1)
        subprocess.run(["cmake", "--build", str(build), "--target", "penalty_python", "penalty_cli", "--parallel", jobs],
                       check=True)
        module = next((build / "python" / "penalty").glob("_core*.so"))
        target = Path(self.get_ext_fullpath(ext.name))
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copy2(module, target)
        package = target.parent
        (package / "bin").mkdir(exist_ok=True)
        shutil.copy2(build / "bin" / "penalty", package / "bin" / "penalty")
        # `import Sofa` for standalone SofaPython3 scripts: a .pth at the site folder's top
        (package.parent / "penalty-sofa-compat.pth").write_text("penalty/sofa_compat\n")


setup(
    version=project_version(),
    packages=["penalty"],
    package_dir={"": "python"},
    package_data={"penalty": ["py.typed", "_core.pyi", "sofa_compat/Sofa/*.py", "sofa_compat/SofaRuntime/*.py"]},
    ext_modules=[Extension("penalty._core", sources=[])],
    cmdclass={"build_ext": CMakeBuild},
    options={"build": {"build_base": "build/setuptools"}, "egg_info": {"egg_base": "build/setuptools"}},
    zip_safe=False,
)
