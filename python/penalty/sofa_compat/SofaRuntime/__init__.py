"""SofaRuntime: plugin loading is accepted and does nothing (penalty has every component built in)."""


def importPlugin(name):
    """Accepted for any SOFA plugin name: penalty's components need no plugin."""
    return True


def __getattr__(name):
    if name.startswith("__"):
        raise AttributeError(name)
    raise NotImplementedError(f"SofaRuntime.{name} is not supported by penalty's SofaPython3 subset (see docs/python.md)")
