"""penalty's implementation of the subset of SofaPython3's API that scene scripts use.

`import Sofa`, `Sofa.Core`, `Sofa.Simulation`, `SofaRuntime` resolve to the thin modules in
sofa_compat/, which re-export this file. A script builds a tree of Node and Object instances;
Sofa.Simulation.init turns it into the same io::SceneFile tree a `.scn` file gives (every value in
SOFA's text form, each object with the file and line of its addObject call) and the one scene
builder builds it. Unsupported API raises NotImplementedError naming the call.
"""
from __future__ import annotations

import math
import numbers
import os
import runpy
import sys
import weakref
from pathlib import Path

import numpy as np

from . import _core
from . import topology as _topology

_THIS_DIR = str(Path(__file__).resolve().parent)

# ------------------------------------------------------------------------------------------------
# values -> SOFA text


def _number_text(x) -> str:
    if isinstance(x, (bool, np.bool_)):
        return "1" if x else "0"
    if isinstance(x, numbers.Integral):
        return str(int(x))
    x = float(x)
    if not math.isfinite(x):
        return repr(x)
    return repr(x)  # shortest text that reads back as the same double


def to_sofa_text(value, what: str) -> str:
    """SOFA's text form of a Python value: numbers, bools ("1"/"0"), strings, links ("@path"),
    objects (their link), nested lists/tuples/numpy arrays (flattened, blank-separated)."""
    if isinstance(value, str):
        return value
    if isinstance(value, Object):
        return value.getLinkPath()
    if isinstance(value, Node):
        return value.getLinkPath()
    if isinstance(value, Data):
        return value.getLinkPath()
    if isinstance(value, (bool, np.bool_, numbers.Number)):
        return _number_text(value)
    if isinstance(value, np.ndarray):
        return " ".join(_number_text(v) for v in value.ravel().tolist())
    if isinstance(value, (list, tuple, range)):
        return " ".join(t for t in (to_sofa_text(v, what) for v in value) if t != "")
    raise TypeError(f"{what}: cannot convert a value of type {type(value).__name__} to a SOFA data value")


def _caller_location():
    """File and line of the nearest frame outside penalty's SofaPython3 modules (the script)."""
    frame = sys._getframe(1)
    while frame is not None:
        filename = frame.f_code.co_filename
        if not filename.startswith(_THIS_DIR):
            return filename, frame.f_lineno
        frame = frame.f_back
    return "<unknown>", 0


def _unsupported(call: str):
    raise NotImplementedError(f"{call} is not supported by penalty's SofaPython3 subset (see docs/python.md)")


# ------------------------------------------------------------------------------------------------
# data fields

# MechanicalObject data that view the built state (SOFA name -> penalty.State attribute).
_STATE_DATA = {
    "position": "positions", "velocity": "velocities", "force": "forces", "rest_position": "rest_positions",
    "externalForce": "external_forces",
}


class _WriteableArray:
    def __init__(self, data):
        self._data = data

    def __enter__(self):
        return self._data._live_array(writeable=True)

    def __exit__(self, *exc):
        arr = self._array if hasattr(self, "_array") else None
        del arr
        return False


class Data:
    """A data field of an object or a node: `.value`, `.array()`, `writeableArray()`."""

    def __init__(self, owner, name: str):
        self._owner = owner
        self._name = name

    # SofaPython3's names
    def getName(self):
        return self._name

    def getOwner(self):
        return self._owner

    def getLinkPath(self):
        return self._owner.getLinkPath() + "." + self._name

    @property
    def linkpath(self):
        return self.getLinkPath()

    def _state(self):
        owner = self._owner
        if isinstance(owner, Object) and owner._type == "MechanicalObject" and self._name in _STATE_DATA:
            return owner._built_state()
        return None

    def _live_array(self, writeable: bool):
        state = self._state()
        if state is None:
            value = self._owner._values.get(self._name)
            if value is None:
                raise AttributeError(f"{self._owner._describe()}: data '{self._name}' has no value")
            arr = np.array(value, dtype=float)
            if not writeable:
                arr.flags.writeable = False
            return arr
        arr = getattr(state, _STATE_DATA[self._name])
        if state.template == "Rigid3d" and self._name in ("position", "rest_position") and writeable:
            _unsupported(f"writeableArray() on the Rigid3d data '{self._name}' (assign .value instead)")
        if not writeable:
            arr = arr.view()
            arr.flags.writeable = False
        return arr

    @property
    def value(self):
        if self._state() is not None:
            return self._live_array(writeable=False)
        if self._name not in self._owner._values:
            if self._name == "name":
                return self._owner._name
            raise AttributeError(f"{self._owner._describe()}: no data '{self._name}' (penalty knows only the "
                                 "attributes the script gave, and the state vectors after init)")
        v = self._owner._values[self._name]
        if isinstance(v, (list, tuple)):
            try:
                return np.array(v, dtype=float)
            except (TypeError, ValueError):
                return v
        return v

    @value.setter
    def value(self, new):
        if self._name == "name":
            if self._owner._initialised():
                _unsupported(f"renaming {self._owner._describe()} after Sofa.Simulation.init")
            object.__setattr__(self._owner, "_name", str(new))
            return
        state = self._state()
        if state is not None:
            setattr(state, _STATE_DATA[self._name], new)
            return
        if self._owner._initialised():
            _unsupported(f"setting '{self._name}' of {self._owner._describe()} after Sofa.Simulation.init")
        self._owner._values[self._name] = new

    def array(self):
        """Read-only numpy array of the value (a view of the state for MechanicalObject vectors)."""
        return self._live_array(writeable=False)

    def writeableArray(self):
        """`with obj.position.writeableArray() as wa: wa[0] += ...` writes into the state."""
        if self._state() is None:
            _unsupported(f"writeableArray() on '{self._name}' of {self._owner._describe()} (only the "
                         "MechanicalObject vectors position, velocity, force, rest_position, externalForce, after init)")
        return _WriteableArray(self)

    def getValueString(self):
        return to_sofa_text(self.value, self._name)

    def __repr__(self):
        return f"<Data {self._name} of {self._owner._describe()}>"

    def __getattr__(self, name):
        if name.startswith("_"):
            raise AttributeError(name)
        _unsupported(f"Data.{name}()")


# ------------------------------------------------------------------------------------------------
# objects and nodes


class Base:
    def __init__(self):
        object.__setattr__(self, "_values", {})

    def findData(self, name: str) -> Data:
        return Data(self, name)

    def getData(self, name: str) -> Data:
        return Data(self, name)

    def _initialised(self) -> bool:
        root = self._root()
        return root is not None and getattr(root, "_penalty_scene", None) is not None


class Object(Base):
    """An object added with node.addObject(type, name=..., **attributes)."""

    def __init__(self, type_name: str, name: str | None, attributes: dict, file: str, line: int):
        super().__init__()
        object.__setattr__(self, "_type", type_name)
        object.__setattr__(self, "_name", name or "")
        object.__setattr__(self, "_file", file)
        object.__setattr__(self, "_line", line)
        object.__setattr__(self, "_node", None)
        self._values.update(attributes)

    # SofaPython3's names
    @property
    def name(self):
        return Data(self, "name")

    def getName(self):
        return self._name

    def getClassName(self):
        return self._type

    def getTemplateName(self):
        return str(self._values.get("template", ""))

    def getContext(self):
        return self._node

    def getPathName(self):
        base = self._node.getPathName() if self._node is not None else ""
        return (base.rstrip("/") + "/" + self._name) if base else self._name

    def getLinkPath(self):
        return "@" + self.getPathName()

    def _root(self):
        return self._node._root() if self._node is not None else None

    def _describe(self):
        return f"{self._type} '{self._name}'" if self._name else self._type

    def _built_state(self):
        root = self._root()
        scene = getattr(root, "_penalty_scene", None) if root is not None else None
        if scene is None:
            return None
        return scene.states[self.getPathName() if self.getPathName().startswith("/") else "/" + self.getPathName()]

    def __getattr__(self, name):
        if name.startswith("__"):
            raise AttributeError(name)
        if name in self._values or (self._type == "MechanicalObject" and name in _STATE_DATA):
            return Data(self, name)
        if self._type.endswith("Loader"):  # a loader's outputs (position, triangles, listRadius...), for links
            return Data(self, name)
        method = _topology.modifier_method(self, name)  # a topology modifier's removeTetrahedra ... (topology.py)
        if method is not None:
            return method
        raise AttributeError(f"{self._describe()} has no data or method '{name}' in penalty's SofaPython3 subset")

    def __setattr__(self, name, value):
        if name.startswith("_") or name in type(self).__dict__:
            object.__setattr__(self, name, value)
        else:
            Data(self, name).value = value

    def _tree(self):
        attributes = []
        template = ""
        for key, value in self._values.items():
            if key == "template":
                template = to_sofa_text(value, f"{self._file}:{self._line}: {self._describe()}: attribute 'template'")
                continue
            text = to_sofa_text(value, f"{self._file}:{self._line}: {self._describe()}: attribute '{key}'")
            attributes.append((key, text, self._line))
        return {"type": self._type, "name": self._name, "template": template, "file": self._file,
                "line": self._line, "attributes": attributes}


class Controller(Object):
    """Sofa.Core.Controller: subclass it and define onAnimateBeginEvent(event) and/or
    onAnimateEndEvent(event); they are called before and after every step. Not part of the built
    scene (penalty's builder never sees it)."""

    def __init__(self, *args, **kwargs):
        file, line = _caller_location()
        name = kwargs.pop("name", args[0] if args and isinstance(args[0], str) else None)
        Object.__init__(self, "PythonController", name or type(self).__name__, {}, file, line)
        for key, value in kwargs.items():
            object.__setattr__(self, key, value)

    def __setattr__(self, name, value):
        object.__setattr__(self, name, value)

    def __getattr__(self, name):
        if name.startswith("__"):
            raise AttributeError(name)
        raise AttributeError(f"controller {self._describe()} has no attribute '{name}'")

    def _tree(self):
        return None


class Node(Base):
    """Sofa.Core.Node: children, objects, data (dt, gravity, ...)."""

    def __init__(self, name: str = "root"):
        super().__init__()
        object.__setattr__(self, "_name", name)
        object.__setattr__(self, "_parent", None)
        object.__setattr__(self, "_children", [])
        object.__setattr__(self, "_objects", [])
        file, line = _caller_location()
        object.__setattr__(self, "_file", file)
        object.__setattr__(self, "_line", line)
        object.__setattr__(self, "_penalty_scene", None)

    # SofaPython3's names
    @property
    def name(self):
        return Data(self, "name")

    @property
    def children(self):
        return list(self._children)

    @property
    def objects(self):
        return list(self._objects)

    def getName(self):
        return self._name

    def getPathName(self):
        if self._parent is None:
            return "/"
        up = self._parent.getPathName()
        return (up if up != "/" else "") + "/" + self._name

    def getLinkPath(self):
        return "@" + self.getPathName()

    def getRoot(self):
        return self._root()

    def _root(self):
        n = self
        while n._parent is not None:
            n = n._parent
        return n

    def _describe(self):
        return f"Node '{self._name}'"

    def addChild(self, child, **attributes):
        if self._initialised():
            _unsupported("Node.addChild after Sofa.Simulation.init")
        if isinstance(child, Node):
            node = child
        elif isinstance(child, str):
            node = Node(child)
            file, line = _caller_location()
            object.__setattr__(node, "_file", file)
            object.__setattr__(node, "_line", line)
        else:
            raise TypeError(f"Node.addChild: expected a name or a Node, found {type(child).__name__}")
        object.__setattr__(node, "_parent", self)
        node._values.update(attributes)
        self._children.append(node)
        return node

    def createChild(self, name, **attributes):
        return self.addChild(name, **attributes)

    def addObject(self, type_or_object, *args, **attributes):
        if self._initialised():
            _unsupported("Node.addObject after Sofa.Simulation.init")
        if isinstance(type_or_object, Object):
            obj = type_or_object
        elif isinstance(type_or_object, str):
            if args:
                raise TypeError(f"Node.addObject('{type_or_object}', ...): attributes must be keyword arguments")
            file, line = _caller_location()
            name = attributes.pop("name", None)
            obj = Object(type_or_object, None if name is None else str(name), attributes, file, line)
        elif isinstance(type_or_object, type):
            _unsupported(f"Node.addObject({type_or_object.__name__}) with a class (pass an instance or a type name)")
        else:
            raise TypeError(f"Node.addObject: expected a type name or an object, found {type(type_or_object).__name__}")
        object.__setattr__(obj, "_node", self)
        self._objects.append(obj)
        return obj

    def createObject(self, type_name, **attributes):
        return self.addObject(type_name, **attributes)

    def getChild(self, name):
        for c in self._children:
            if c._name == name:
                return c
        return None

    def getObject(self, name):
        for o in self._objects:
            if o._name == name:
                return o
        return None

    def getMechanicalState(self):
        for o in self._objects:
            if o._type == "MechanicalObject":
                return o
        return None

    def __getattr__(self, name):
        if name.startswith("__"):
            raise AttributeError(name)
        for c in self._children:
            if c._name == name:
                return c
        for o in self._objects:
            if o._name == name:
                return o
        if name in self._values or name in ("dt", "gravity", "time"):
            return Data(self, name)
        raise AttributeError(f"Node '{self._name}' has no child, object or data '{name}' "
                             "(penalty's SofaPython3 subset)")

    def __setattr__(self, name, value):
        if name.startswith("_"):
            object.__setattr__(self, name, value)
        else:
            Data(self, name).value = value

    def _tree(self):
        attributes = []
        for key, value in self._values.items():
            attributes.append((key, to_sofa_text(value, f"{self._file}:{self._line}: Node '{self._name}': "
                                                        f"attribute '{key}'"), self._line))
        objects = [t for t in (o._tree() for o in self._objects) if t is not None]
        return {"name": self._name, "file": self._file, "line": self._line, "attributes": attributes,
                "objects": objects, "children": [c._tree() for c in self._children]}

    def _controllers(self):
        found = [o for o in self._objects if isinstance(o, Controller)]
        for c in self._children:
            found += c._controllers()
        return found


# Node data that a script reads (dt, gravity, time) once the scene is built.
_node_data_value = Data.value.fget


def _data_value(self):
    owner = self._owner
    if isinstance(owner, Node) and owner._initialised():
        scene = owner._root()._penalty_scene
        if self._name == "time":
            return scene.time
        if self._name == "dt" and owner._parent is None:
            return scene.dt
    if isinstance(owner, Node) and self._name == "dt" and "dt" not in owner._values:
        return 0.01 if owner._parent is None else owner._parent.dt.value
    if isinstance(owner, Node) and self._name == "gravity" and "gravity" not in owner._values:
        return np.array([0.0, -9.81, 0.0]) if owner._parent is None else owner._parent.gravity.value
    if isinstance(owner, Node) and self._name == "time" and not owner._initialised():
        return 0.0
    return _node_data_value(self)


Data.value = property(_data_value, Data.value.fset)


# ------------------------------------------------------------------------------------------------
# Sofa.Simulation


class _Event(dict):
    """What onAnimateBeginEvent / onAnimateEndEvent receive (SofaPython3 passes a dict)."""


def init(root: Node, *, build_options=None):
    """Builds the scene of the tree below `root` with penalty's scene builder."""
    from . import Scene
    if not isinstance(root, Node):
        raise TypeError("Sofa.Simulation.init: expected a Sofa.Core.Node")
    if root._penalty_scene is not None:
        return
    options = build_options or getattr(root, "_penalty_build_options", None) or ([], None, 0, False)
    tree = root._tree()
    core = _core._build_tree(tree, root._file if root._file != "<unknown>" else "", *options)
    scene = Scene(core, root)
    object.__setattr__(root, "_penalty_scene", scene)
    object.__setattr__(root, "_penalty_build_options", options)
    controllers = root._controllers()
    for c in controllers:
        if hasattr(c, "init") and callable(getattr(type(c), "init", None)):
            c.init()

    # The hooks live in the C++ scene, which the garbage collector cannot traverse: they hold the
    # scene and the controllers weakly so that no reference cycle keeps a scene alive.
    scene_ref = weakref.ref(scene)
    controller_refs = [weakref.ref(c) for c in controllers]

    def send(event_type, method):
        live = scene_ref()
        if live is None:
            return
        ev = _Event(type=event_type, dt=live.dt, time=live.time)
        for ref in controller_refs:
            c = ref()
            handler = getattr(type(c), method, None) if c is not None else None
            if handler is not None:
                handler(c, ev)

    def before():
        send("AnimateBeginEvent", "onAnimateBeginEvent")

    def after():
        send("AnimateEndEvent", "onAnimateEndEvent")

    if any(getattr(type(c), "onAnimateBeginEvent", None) or getattr(type(c), "onAnimateEndEvent", None)
           for c in controllers):
        core._add_hooks(before, after)


def initRoot(root: Node):
    init(root)


def animate(root: Node, dt=None):
    """One step of the scene (dt must be the scene's time step: penalty steps with the root's dt)."""
    if root._penalty_scene is None:
        raise RuntimeError("Sofa.Simulation.animate: call Sofa.Simulation.init(root) first")
    scene = root._penalty_scene
    if dt is not None and float(dt) != scene.dt:
        _unsupported(f"Sofa.Simulation.animate(root, {dt}) with a dt other than the root's ({scene.dt})")
    scene.step(1)


def reset(root: Node):
    """Rebuilds the scene from the script's tree (time 0, initial states)."""
    options = getattr(root, "_penalty_build_options", None)
    object.__setattr__(root, "_penalty_scene", None)
    init(root, build_options=options)


def unload(root: Node):
    object.__setattr__(root, "_penalty_scene", None)


# ------------------------------------------------------------------------------------------------
# running a script


def run_scene_script(path: Path, options) -> Node:
    """Executes a SofaPython3 scene script (not as __main__), calls createScene(root) on a new root
    node, builds it; returns the root (root._penalty_scene is the penalty.Scene)."""
    from . import _install_sofa_path
    _install_sofa_path()
    path = Path(path)
    if not path.is_file():
        raise _core.SceneError(f"{path}: cannot open file")
    script_dir = str(path.resolve().parent)
    added = script_dir not in sys.path
    if added:
        sys.path.insert(0, script_dir)
    try:
        namespace = runpy.run_path(os.fspath(path), run_name="__penalty_scene__")
    finally:
        if added and script_dir in sys.path:
            sys.path.remove(script_dir)
    create = namespace.get("createScene")
    if create is None:
        raise _core.SceneError(f"{path}: no createScene(rootNode) function")
    root = Node("root")
    object.__setattr__(root, "_file", os.fspath(path))
    object.__setattr__(root, "_line", create.__code__.co_firstlineno)
    object.__setattr__(root, "_penalty_build_options", options)
    result = create(root)
    if isinstance(result, Node) and result is not root:
        root = result
    init(root, build_options=options)
    return root
