"""penalty's stand-in for SofaPython3's `Sofa` package (the subset scene scripts use).

Put penalty.sofa_path first on sys.path to use it (penalty.load_scene and `penalty run scene.py`
do). Anything outside the subset raises NotImplementedError naming the call.
"""
from . import Core, Helper, Simulation  # noqa: F401

__penalty__ = True


def __getattr__(name):
    if name.startswith("__"):
        raise AttributeError(name)
    raise NotImplementedError(f"Sofa.{name} is not supported by penalty's SofaPython3 subset (see docs/python.md)")
