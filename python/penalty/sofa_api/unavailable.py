"""Modules of SofaPython3 and SOFA's Python plugins that penalty does not provide: importing one
succeeds, using it raises an ImportError naming the module (a script that imports a GUI plugin in
a code path it never runs still runs)."""
from __future__ import annotations

import importlib.abc
import importlib.machinery
import sys
import types

#: Why a module is missing, by name (the others: "not part of penalty's SofaPython3").
REASONS = {
    "SofaImGui": "SOFA's ImGui GUI plugin: penalty runs headless (Sofa.Gui.GUIManager runs as SOFA's batch GUI)",
    "SofaQt": "SOFA's Qt GUI plugin: penalty runs headless (Sofa.Gui.GUIManager runs as SOFA's batch GUI)",
    "SofaGLFW": "SOFA's GLFW GUI plugin: penalty runs headless (Sofa.Gui.GUIManager runs as SOFA's batch GUI)",
    "Sofa.SofaGL": "SOFA's OpenGL drawing: penalty draws nothing (penalty run --view writes the browser viewer)",
    "SofaExporter": "SOFA's exporters: use penalty run --vtk / --export-states",
}

#: Top-level SOFA plugin modules a script may import.
TOP_LEVEL = ("SofaImGui", "SofaQt", "SofaGLFW", "SofaExporter", "SofaTypes", "SofaValidation", "Sofa3D",
             "SofaMatrix", "SofaCUDA", "SoftRobots", "STLIB", "splib", "stlib3")


def _error(module: str, what: str) -> ImportError:
    reason = REASONS.get(module, "not part of penalty's SofaPython3, see docs/python.md")
    return ImportError(f"{what}: {module} is not available in penalty ({reason})", name=module)


class UnavailableName:
    """A name of an unavailable module (`from Sofa.Types import RGBAColor`): importing it
    succeeds; calling it or reading its attributes raises ImportError naming the module."""

    __slots__ = ("_module", "_name")

    def __init__(self, module: str, name: str):
        object.__setattr__(self, "_module", module)
        object.__setattr__(self, "_name", name)

    def __call__(self, *args, **kwargs):
        raise _error(self._module, f"{self._module}.{self._name}(...)")

    def __getattr__(self, attribute):
        if attribute.startswith("__"):
            raise AttributeError(attribute)
        raise _error(self._module, f"{self._module}.{self._name}.{attribute}")

    def __repr__(self):
        return f"<unavailable {self._module}.{self._name}>"


class UnavailableModule(types.ModuleType):
    """A module penalty does not provide: importing it (or a name from it) succeeds, using it
    raises ImportError naming it."""

    def __init__(self, name: str):
        super().__init__(name)
        self.__dict__["__penalty_unavailable__"] = True

    def __getattr__(self, attribute):
        if attribute.startswith("__"):
            raise AttributeError(attribute)
        return UnavailableName(self.__name__, attribute)


class _Finder(importlib.abc.MetaPathFinder, importlib.abc.Loader):
    """Finds, after every other finder, Sofa.X submodules and SOFA plugin modules penalty lacks."""

    def find_spec(self, fullname, path=None, target=None):
        if fullname in TOP_LEVEL or (fullname.startswith(("Sofa.", "SofaRuntime.")) and fullname.count(".") == 1):
            return importlib.machinery.ModuleSpec(fullname, self)
        return None

    def create_module(self, spec):
        return UnavailableModule(spec.name)

    def exec_module(self, module):
        return None


def install():
    if not any(isinstance(f, _Finder) for f in sys.meta_path):
        sys.meta_path.append(_Finder())
