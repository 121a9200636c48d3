"""Sofa.Simulation: init, initRoot, animate, animateNSteps, reset, load, unload (penalty's
SofaPython3, penalty/sofa_api/simulation.py)."""
from penalty.sofa_api.simulation import (animate, animateNSteps, init, initRoot, load, reset,  # noqa: F401
                                         unload)
from penalty.sofa_api.simulation import print_tree as print  # noqa: F401,A001 - SofaPython3's name


def initVisual(root):  # noqa: N802
    return None


def updateVisual(root):  # noqa: N802
    return None


def initTextures(root):  # noqa: N802
    return None


class SceneCheckMainRegistry:
    """SOFA's registry of scene checks: penalty runs its own checks when it builds a scene (unknown
    components, broken links, attributes it does not read), not SOFA's."""

    @staticmethod
    def getRegisteredSceneChecks():  # noqa: N802
        return []


def __getattr__(name):
    if name.startswith("__"):
        raise AttributeError(name)
    raise AttributeError(f"Sofa.Simulation.{name} is not available in penalty's SofaPython3 (see docs/python.md)")
