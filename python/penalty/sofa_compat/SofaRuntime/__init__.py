"""SofaRuntime: importPlugin (every component is built in), Timer (penalty/sofa_api/runtime.py)."""
from penalty.sofa_api import unavailable as _unavailable
from penalty.sofa_api.runtime import Timer, importPlugin, unloadModules  # noqa: F401

_unavailable.install()


def __getattr__(name):
    if name.startswith("__"):
        raise AttributeError(name)
    raise AttributeError(f"SofaRuntime.{name} is not available in penalty's SofaPython3 (see docs/python.md)")
