"""Sofa.Core: Node, Object, Data, links, Controller, ForceField, Mapping, DataEngine (penalty's
SofaPython3, penalty/sofa_api)."""
from penalty.sofa_api import (Base, Controller, Data, DataContainer, DataEngine, DataString,  # noqa: F401
                              ForceFieldRigid3d, ForceFieldVec3d, Link, LinkPath, Mapping_Rigid3d_Vec3d,
                              Mapping_Vec3d_Vec1d, Mapping_Vec3d_Vec3d, Node, NodeIterator, Object)

BaseObject = Object
BaseComponent = Object
Context = Node
BaseData = Data
DataLink = Data
DataVectorString = Data


class TaskScheduler:
    """Sofa.Core.TaskScheduler: the threads of penalty's scenes (0: TBB's default)."""

    _threads = 0

    @staticmethod
    def GetHardwareThreadsCount():  # noqa: N802 - SofaPython3's names
        import os
        return os.cpu_count() or 1

    @staticmethod
    def init(threads=0):
        TaskScheduler._threads = int(threads)
        from penalty.sofa_api.simulation import set_threads
        set_threads(TaskScheduler._threads)
        return True

    @staticmethod
    def getThreadCount():  # noqa: N802
        return TaskScheduler._threads or TaskScheduler.GetHardwareThreadsCount()

    @staticmethod
    def stop():
        return None


def __getattr__(name):
    if name.startswith("__"):
        raise AttributeError(name)
    raise AttributeError(f"Sofa.Core.{name} is not available in penalty's SofaPython3 (see docs/python.md)")
