"""Sofa.Simulation: init, initRoot, animate, reset, unload (penalty's SofaPython3 subset)."""
from penalty.sofa_api import animate, init, initRoot, reset, unload  # noqa: F401


def __getattr__(name):
    if name.startswith("__"):
        raise AttributeError(name)
    raise NotImplementedError(
        f"Sofa.Simulation.{name} is not supported by penalty's SofaPython3 subset (see docs/python.md)")
