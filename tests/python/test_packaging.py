"""`pip install .` and `python3 -m build --no-isolation` (pyproject.toml, setup.py): offline, with
Debian's setuptools, wheel and build. The package they install imports, steps a scene, knows its
version, and its `penalty` command is the C++ command line. To stay fast, setup.py reuses this
test's build tree (PENALTY_CMAKE_BUILD_DIR: the CMake build is then up to date); a fresh clone
builds in build/pip the same way."""
import os
import re
import subprocess
import sys
import zipfile
from pathlib import Path

import pytest

import penalty

REPO = Path(__file__).resolve().parents[2]
BUILD = Path(penalty.__file__).resolve().parents[2]  # build/<preset>: python/penalty/__init__.py
VERSION = re.search(r"project\(penalty VERSION ([0-9.]+)", (REPO / "CMakeLists.txt").read_text()).group(1)


def tool_available(module):
    return subprocess.run([sys.executable, "-c", f"import {module}"], capture_output=True).returncode == 0


pytestmark = pytest.mark.skipif(not (BUILD / "CMakeCache.txt").exists(), reason="the package is not in a CMake build tree")


def environment():
    env = dict(os.environ, PENALTY_CMAKE_BUILD_DIR=str(BUILD), CMAKE_BUILD_PARALLEL_LEVEL="2",
               PIP_NO_INDEX="1", PIP_DISABLE_PIP_VERSION_CHECK="1")
    env.pop("PYTHONPATH", None)
    return env


def test_version_is_the_cmake_projects():
    assert penalty.__version__ == VERSION
    r = subprocess.run([sys.executable, "-m", "penalty", "--version"], capture_output=True, text=True,
                       env=dict(os.environ, PYTHONPATH=str(BUILD / "python")))
    assert r.stdout.strip() == f"penalty {VERSION}"


@pytest.mark.skipif(not tool_available("pip"), reason="python3-pip is not installed")
def test_pip_install_imports_steps_and_runs_the_command_line(tmp_path):
    target = tmp_path / "site"
    r = subprocess.run([sys.executable, "-m", "pip", "install", "--no-build-isolation", "--no-deps", "--no-index",
                        "--target", str(target), str(REPO)], capture_output=True, text=True, env=environment(),
                       timeout=1800)
    assert r.returncode == 0, r.stdout[-3000:] + r.stderr[-3000:]
    assert list(target.glob("penalty/_core*.so")) and (target / "penalty" / "bin" / "penalty").is_file()
    assert (target / "penalty-sofa-compat.pth").read_text() == "penalty/sofa_compat\n"
    env = dict(os.environ, PYTHONPATH=str(target))
    check = ("import penalty, sys; s = penalty.builtin_scene(); s.step(3); "
             "print(penalty.__version__, penalty.__file__, len(s.contacts()['age']) >= 0, s.time)")
    r = subprocess.run([sys.executable, "-c", check], capture_output=True, text=True, env=env, cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    version, location, _, time = r.stdout.split()
    assert version == VERSION and location.startswith(str(target)) and float(time) == pytest.approx(0.015)
    # the console script: the C++ command line of the wheel, which hands .py scenes to this interpreter
    r = subprocess.run([str(target / "bin" / "penalty"), "--version"], capture_output=True, text=True, env=env)
    assert r.stdout.strip() == f"penalty {VERSION}", r.stderr
    script = REPO / "tests" / "python" / "scripts" / "falling_cube.py"
    if script.exists():
        r = subprocess.run([str(target / "bin" / "penalty"), "run", str(script), "--steps", "5", "--quiet"],
                           capture_output=True, text=True, env=env, cwd=tmp_path)
        assert r.returncode == 0, r.stderr
        assert "steps: 5" in r.stdout


@pytest.mark.skipif(not tool_available("build"), reason="python3-build is not installed")
def test_build_makes_a_wheel_offline(tmp_path):
    r = subprocess.run([sys.executable, "-m", "build", "--no-isolation", "--wheel", "--outdir", str(tmp_path), str(REPO)],
                       capture_output=True, text=True, env=environment(), timeout=1800)
    assert r.returncode == 0, r.stdout[-3000:] + r.stderr[-3000:]
    wheels = list(tmp_path.glob(f"penalty-{VERSION}-*.whl"))
    assert len(wheels) == 1
    names = set(zipfile.ZipFile(wheels[0]).namelist())
    for required in ("penalty/__init__.py", "penalty/sweeps.py", "penalty/_cli.py", "penalty/bin/penalty",
                     "penalty/sofa_compat/Sofa/Core.py", "penalty/sofa_compat/SofaRuntime/__init__.py",
                     "penalty-sofa-compat.pth"):
        assert required in names, sorted(names)
    assert any(re.fullmatch(r"penalty/_core\..*\.so", n) for n in names)
    assert any(n.endswith("entry_points.txt") for n in names)
