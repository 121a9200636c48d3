"""Sofa.Core: Node, Object, Data, links, Controller, ForceField, Mapping, DataEngine (penalty's
SofaPython3, penalty/sofa_api)."""
from penalty.sofa_api import (Base, Controller, Data, DataContainer, DataEngine, DataString,  # noqa: F401
                              ForceFieldRigid3d, ForceFieldVec3d, Link, LinkPath, Mapping_Rigid3d_Vec3d,
                              Mapping_Vec3d_Vec3d, Node, NodeIterator, Object)

BaseObject = Object
BaseComponent = Object
Context = Node
BaseData = Data
DataLink = Data
DataVectorString = Data


def __getattr__(name):
    if name.startswith("__"):
        raise AttributeError(name)
    raise AttributeError(f"Sofa.Core.{name} is not available in penalty's SofaPython3 (see docs/python.md)")
