"""penalty's stand-in for SofaPython3's `Sofa` package (penalty/sofa_api, docs/python.md).

penalty.load_scene, `penalty run scene.py` and `python3 -m penalty` put this folder first on
sys.path; an installed penalty appends it to sys.path (a real SofaPython3, if installed, comes
first). A module of SofaPython3 or of a SOFA plugin penalty lacks imports, and fails when used
with an ImportError naming it.
"""
from penalty.sofa_api import unavailable as _unavailable

_unavailable.install()

from . import Core, Gui, Helper, Simulation, constants  # noqa: E402,F401
from penalty.sofa_api import import_sofa_python_scene  # noqa: E402,F401

__penalty__ = True


def __getattr__(name):
    if name.startswith("__"):
        raise AttributeError(name)
    import importlib
    return importlib.import_module(f"Sofa.{name}")  # an UnavailableModule (sofa_api/unavailable.py)
