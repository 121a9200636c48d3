"""Sofa.Core: Node, Controller, Data (penalty's SofaPython3 subset)."""
from penalty.sofa_api import Base, Controller, Data, Node, Object  # noqa: F401

BaseObject = Object


def __getattr__(name):
    if name.startswith("__"):
        raise AttributeError(name)
    raise NotImplementedError(f"Sofa.Core.{name} is not supported by penalty's SofaPython3 subset (see docs/python.md)")
