"""Sofa.Core.Object and Sofa.Core.Node: the objects and nodes a script creates, built into the C++
scene by Sofa.Simulation.init and live afterwards (graph.py has what they share)."""
from __future__ import annotations

from .. import _core
from .. import topology as _topology
from . import linear_system as _linear_system
from .data import LinkPath
from .graph import Base, NodeIterator, type_fields
from .text import caller_location, to_sofa_text


def _scene_of(base):
    root = base._root()
    return getattr(root, "_penalty_scene", None) if root is not None else None



_SCALAR_FIELDS = {}


def _scalar_state_fields(fields: dict) -> dict:
    """A Vec1d MechanicalObject's Data: its vectors hold one value per point, (n, 1) as
    SofaPython3 presents them (the catalog's rows are the Vec3d state's)."""
    key = id(fields)
    out = _SCALAR_FIELDS.get(key)
    if out is None:
        out = {name: (dict(f, columns=1) if f.get("columns") == 3 and f["python_form"] == "ndarray:float64:2" else f)
               for name, f in fields.items()}
        _SCALAR_FIELDS[key] = out
    return out


class Object(Base):
    """An object added with node.addObject(type, name=..., **data) (Sofa.Core.Object)."""

    _python = False  # a component written in Python (components.py)

    def __init__(self, type_name: str, name: str | None, attributes: dict, file: str, line: int, template: str = ""):
        super().__init__()
        object.__setattr__(self, "_type", type_name)
        object.__setattr__(self, "_name", name or "")
        object.__setattr__(self, "_template", template)
        object.__setattr__(self, "_file", file)
        object.__setattr__(self, "_line", line)
        object.__setattr__(self, "_node", None)
        self._values.update(attributes)

    # --- where the Data live -------------------------------------------------------------------
    def _rigid(self) -> bool:
        t = self._template or ""
        if not t and self._node is not None:
            mo = self._node.getMechanicalState()
            t = mo._template if mo is not None and mo is not self else ""
        return t.startswith("Rigid")

    def _fields(self) -> dict:
        fields = type_fields(self._type, False, self._rigid())
        if self._type == "MechanicalObject" and (self._template or "") in ("Vec1", "Vec1d", "Vec1f"):
            return _scalar_state_fields(fields)
        return fields

    def _live(self):
        scene = _scene_of(self)
        if scene is None or getattr(self, "_unbuilt", False):
            return None
        return scene._scene

    def _root(self):
        return self._node._root() if self._node is not None else None

    def _describe(self):
        return f"{self._type} '{self._name}'" if self._name else self._type

    # --- SofaPython3's Object API --------------------------------------------------------------
    def getClassName(self):
        return self._type

    def getTemplateName(self):
        return self._template or ""

    def getContext(self):
        return self._node

    def getPathName(self):
        if self._node is None:
            return self._name
        base = self._node.getPathName()
        return (base if base != "/" else "") + "/" + self._name

    def _scene_path(self):
        """The object's path in the built scene (getPathName's but through the last parent of a
        node that has several: the scene holds such a node under its last parent)."""
        if self._node is None:
            return self._name
        base = self._node._scene_path()
        return (base if base != "/" else "") + "/" + self._name

    def getAsACreateObjectParameter(self):
        return self.getLinkPath()

    def getMaster(self):
        return None

    def getSlaves(self):
        return []

    def getTarget(self):
        return None

    def getCategories(self):
        return []

    def getInstanciationSourceFileName(self):
        return self._file

    def getInstanciationSourceFilePos(self):
        return self._line

    def init(self):
        """SOFA's init() of a component: after Sofa.Simulation.init, as reinit()."""
        if self._live() is not None:
            self.reinit()

    def reinit(self):
        """SOFA's reinit(): the writes of this component's Data that wait for it take effect."""
        live = self._live()
        if live is not None and not getattr(self, "_python", False):
            live._reinit(self._scene_path(), False)

    def bwdInit(self):
        return None

    def cleanup(self):
        return None

    def reset(self):
        return None

    def storeResetState(self):
        return None

    def computeBBox(self):
        return None

    def addSlave(self, _slave):
        return None

    def setSrc(self, value, loader=None):
        self._data_set("src", loader.getLinkPath() if loader is not None else value)

    def __getitem__(self, path: str):
        if path.startswith("."):
            path = path[1:]
        if not path:
            return self
        if "." in path:
            raise ValueError("Invalid syntax")
        d = self.findData(path) or self.findLink(path)
        if d is None:
            raise self._attribute_error(path)
        return d

    # --- matrices (SofaPython3's ForceField.assembleKMatrix, Mass.assembleMMatrix) --------------
    def assembleKMatrix(self):
        """K = ∂f/∂x of this force field as a scipy.sparse.csr_matrix (kFactor 1), the matrix the
        implicit solve uses: the state's size squared."""
        live = self._require_live("assembleKMatrix")
        return live._stiffness_matrix(self._scene_path())

    def assembleMMatrix(self):
        """M of this mass as a scipy.sparse.csr_matrix, the matrix the implicit solve uses."""
        live = self._require_live("assembleMMatrix")
        return live._mass_matrix(self._scene_path())

    def _require_live(self, call):
        live = self._live()
        if live is None:
            raise RuntimeError(f"{self._describe()}.{call}(): call Sofa.Simulation.init(root) first")
        live._apply_pending()
        return live

    # --- attributes ----------------------------------------------------------------------------
    def __getattr__(self, name):
        if name.startswith("__") or name.startswith("_"):
            raise AttributeError(name)
        if self._has_data(name):
            return self._make_data(name)
        if name in ("linkpath",):
            return LinkPath(self)
        method = _topology.modifier_method(self, name)  # a topology modifier's removeTetrahedra ... (topology.py)
        if method is not None:
            return method
        method = _linear_system.linear_system_method(self, name)  # A(), b(), x() (linear_system.py)
        if method is not None:
            return method
        if not getattr(self, "_python", False) and not self._fields():
            raise AttributeError(f"{self._describe()}: data '{name}': {self._type} is not a component penalty knows "
                                 "(its Data are unknown; the scene will not build)")
        raise self._attribute_error(name)

    def __repr__(self):
        return f"<Sofa.Core.Object {self._describe()} at {self.getPathName() or '?'}>"

    def _tree(self):
        """The object as the C++ builder reads it: SOFA text per attribute."""
        attributes = []
        where = f"{self._file}:{self._line}: {self._describe()}"
        for key, value in self._values.items():
            text = _tree_text(value, f"{where}: attribute '{key}'", self._root())
            attributes.append((key, text, self._line))
        return {"type": self._type, "name": self._name, "template": self._template or "", "file": self._file,
                "line": self._line, "attributes": attributes}


def _tree_text(value, what, root=None):
    """A value for the C++ builder: a Data of a Python object gives its value; an object, node,
    Data or LinkPath its link in the built scene; an absolute link written as text goes through
    the built scene's paths (a node with several parents sits under its last one)."""
    from .data import Data
    if isinstance(value, Data) and getattr(value._owner, "_python", False):
        value = value.value
    if isinstance(value, LinkPath) and value.isPointingToData() and getattr(value.target()._owner, "_python", False):
        value = value.target().value
    if isinstance(value, LinkPath):
        value = value.target()
    if isinstance(value, Data):
        return "@" + value._owner._scene_path() + "." + value._name
    if isinstance(value, (Object, Node)) and not isinstance(value, type):
        return "@" + value._scene_path()
    text = to_sofa_text(value, what)
    if root is not None and text.startswith("@/"):
        text = _scene_link(root, text)
    return text


def _scene_link(root, link: str) -> str:
    """An absolute link's SOFA path made the built scene's (the prefix of a node with several
    parents moves under its last parent)."""
    moved = getattr(root, "_moved_prefixes", None)
    if moved is None:
        moved = []
        todo = [root]
        while todo:
            n = todo.pop()
            for c in n._children:
                if c._scene_parent() is n:
                    todo.append(c)
                    if len(c._parents) > 1:
                        moved.append((c.getPathName(), c._scene_path()))
        moved.sort(key=lambda m: -len(m[0]))
        object.__setattr__(root, "_moved_prefixes", moved)
    path = link[1:]
    for sofa_path, scene_path in moved:
        if path == sofa_path or path.startswith(sofa_path + "/") or path.startswith(sofa_path + "."):
            return "@" + scene_path + path[len(sofa_path):]
    return link


class Node(Base):
    """Sofa.Core.Node: children, objects, Data (dt, gravity, time, ...), context."""

    _is_node = True

    def __init__(self, name: str = "root"):
        super().__init__()
        object.__setattr__(self, "_name", str(name))
        object.__setattr__(self, "_parent", None)   # the first parent (SOFA's paths go through it)
        object.__setattr__(self, "_parents", [])     # every parent, in the order they added this node
        object.__setattr__(self, "_children", [])
        object.__setattr__(self, "_objects", [])
        file, line = caller_location()
        object.__setattr__(self, "_file", file)
        object.__setattr__(self, "_line", line)
        object.__setattr__(self, "_penalty_scene", None)

    # --- where the Data live -------------------------------------------------------------------
    def _fields(self) -> dict:
        return type_fields("Node", True, False)

    def _live(self):
        scene = _scene_of(self)
        if scene is None or getattr(self, "_unbuilt", False):
            return None
        return scene._scene

    def _root(self):
        n = self
        while n._parent is not None:
            n = n._parent
        return n

    def _describe(self):
        return f"Node '{self._name}'"

    def _data_get(self, name):
        if self._live() is None and name in ("dt", "gravity") and name not in self._values and self._parent is not None:
            return self._parent._data_get(name)  # SOFA copies the parent's context over a child's
        return super()._data_get(name)

    # --- tree ----------------------------------------------------------------------------------
    @property
    def children(self):
        return NodeIterator(self._children)

    @property
    def objects(self):
        return NodeIterator(self._objects)

    @property
    def parents(self):
        return NodeIterator(self._parents)

    def getPathName(self):
        if self._parent is None:
            return "/"
        up = self._parent.getPathName()
        return (up if up != "/" else "") + "/" + self._name

    def _scene_parent(self):
        """A node with several parents (SOFA's graph is a DAG) is built once, under its last parent:
        SOFA visits it after all its parents, in the last one's solver."""
        return self._parents[-1] if self._parents else None

    def _scene_path(self):
        parent = self._scene_parent()
        if parent is None:
            return "/"
        up = parent._scene_path()
        return (up if up != "/" else "") + "/" + self._name

    def _scene_children(self):
        return [c for c in self._children if c._scene_parent() is self]

    def getRootPath(self):
        return self.getPathName()

    def getRoot(self):
        return self._root()

    def getContext(self):
        return self

    def getRootContext(self):
        return self._root()

    def _child_or_object(self, name):
        for o in self._objects:
            if o._name == name:
                return o
        for c in self._children:
            if c._name == name:
                return c
        return None

    def addChild(self, child, **attributes):
        from .simulation import on_child_added
        if isinstance(child, Node):
            node = child
            if node is self or any(node is p for p in self._ancestors()):
                raise ValueError(f"Node.addChild: Node '{node._name}' cannot be a child of itself")
        elif isinstance(child, str):
            node = Node(child)
            file, line = caller_location()
            object.__setattr__(node, "_file", file)
            object.__setattr__(node, "_line", line)
        else:
            raise TypeError(f"Node.addChild: expected a name or a Node, found {type(child).__name__}")
        if node._parent is None:
            object.__setattr__(node, "_parent", self)
        elif node._live() is not None:
            raise ValueError(f"Node.addChild: a second parent for Node '{node._name}' after init is not supported")
        node._parents.append(self)
        for k, v in attributes.items():
            node._data_set(k, v) if node._has_data(k) else node._values.__setitem__(k, v)
        self._children.append(node)
        on_child_added(self, node)
        return node

    def createChild(self, name, **attributes):
        return self.addChild(name, **attributes)

    def addObject(self, type_or_object, *args, **attributes):
        from .simulation import on_object_added
        if isinstance(type_or_object, Object):
            obj = type_or_object
            if obj._node is not None:
                raise ValueError(f"{obj._describe()} is in a node already")
            if not obj._name:
                object.__setattr__(obj, "_name", type(obj).__name__)
        elif isinstance(type_or_object, str):
            if args:
                raise TypeError(f"Node.addObject('{type_or_object}', ...): data must be keyword arguments")
            file, line = caller_location()
            _refuse_constraint_based(type_or_object, file, line)
            name = attributes.pop("name", None)
            template = attributes.pop("template", "")
            template = to_sofa_text(template, f"{file}:{line}: {type_or_object}: attribute 'template'")
            obj = Object(type_or_object, None if name is None else str(name), attributes, file, line, template)
            if not obj._name:
                object.__setattr__(obj, "_name", _default_name(type_or_object))
        elif isinstance(type_or_object, type):
            raise TypeError(f"Node.addObject({type_or_object.__name__}): pass an instance or a type name")
        else:
            raise TypeError(f"Node.addObject: expected a type name or an object, found {type(type_or_object).__name__}")
        object.__setattr__(obj, "_node", self)
        self._objects.append(obj)
        on_object_added(self, obj)
        return obj

    def createObject(self, type_name, **attributes):
        return self.addObject(type_name, **attributes)

    def add(self, item, **kwargs):
        if isinstance(item, Node):
            return self.addChild(item)
        if callable(item) and not isinstance(item, (str, Object)):
            return item(self, **kwargs)  # a prefab function
        return self.addObject(item, **kwargs)

    def removeObject(self, obj):
        from .simulation import on_removed
        if obj in self._objects:
            on_removed(self, obj)
            self._objects.remove(obj)
            object.__setattr__(obj, "_node", None)

    def _ancestors(self):
        out, todo = [], list(self._parents)
        while todo:
            n = todo.pop()
            if any(n is o for o in out):
                continue
            out.append(n)
            todo.extend(n._parents)
        return out

    def removeChild(self, child):
        from .simulation import on_removed
        if isinstance(child, str):
            child = self.getChild(child)
        if child is not None and any(child is c for c in self._children):
            on_removed(self, child)
            self._children.remove(child)
            child._parents.remove(self)
            object.__setattr__(child, "_parent", child._parents[0] if child._parents else None)

    def moveChild(self, child, new_parent):
        self.removeChild(child)
        new_parent.addChild(child)

    def detachFromGraph(self):
        if self._parent is not None:
            self._parent.removeChild(self)

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

    def hasObject(self, name):
        return self.getObject(name) is not None

    def getMechanicalState(self):
        for o in self._objects:
            if o._type == "MechanicalObject":
                return o
        return None

    def getMass(self):
        for o in self._objects:
            if o._type.endswith("Mass"):
                return o
        return None

    def getMechanicalMapping(self):
        for o in self._objects:
            if o._type.endswith("Mapping") or getattr(o, "_python_kind", "") == "mapping":
                return o
        return None

    def getForceField(self, index=0):
        fields = [o for o in self._objects if "ForceField" in o._type or getattr(o, "_python_kind", "") == "forcefield"]
        return fields[index] if index < len(fields) else None

    def hasODESolver(self):
        return any(o._type.endswith("Solver") and "Linear" not in o._type and "CG" not in o._type for o in self._objects)

    def getTopology(self):
        for o in reversed(self._objects):
            if "Topology" in o._type and "Modifier" not in o._type and "Mapping" not in o._type:
                return o
        return None

    getMeshTopology = getTopology

    def getState(self):
        return self.getMechanicalState()

    # --- context -------------------------------------------------------------------------------
    def getTime(self):
        return self._root()._data_get("time")

    def getDt(self):
        return self._root()._data_get("dt")

    def getGravity(self):
        return self._data_get("gravity")

    def setGravity(self, g):
        self._data_set("gravity", g)

    def setDt(self, dt):
        self._data_set("dt", dt)

    def getAnimate(self):
        return bool(self._data_get("animate"))

    def setAnimate(self, flag):
        self._values["animate"] = bool(flag)

    def isActive(self):
        return True

    def isSleeping(self):
        return False

    def isInitialized(self):
        return self._live() is not None

    def init(self):
        """SOFA's init() of a node: after Sofa.Simulation.init, what was added below it and the
        writes waiting for a reinit() of its components take effect."""
        from .simulation import init_node
        init_node(self)

    def sendEvent(self, user_data, event_name):
        """SofaPython3's PythonScriptEvent (sender: this node) to the components below it."""
        from .simulation import send_script_event
        send_script_event(self, user_data, event_name)

    def computeEnergy(self):
        """(kinetic, potential) energy of the scene (J): SOFA's Node.computeEnergy."""
        scene = _scene_of(self)
        if scene is None:
            return 0.0, 0.0
        return scene._scene._energy_pair()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        return False

    def __getitem__(self, path: str):
        target = self
        parts = [p for p in path.split(".") if p]
        for i, p in enumerate(parts):
            if target._is_node:
                found = target._child_or_object(p)
                if found is None and target._has_data(p):
                    found = target._make_data(p)
            else:
                found = target.findData(p) or target.findLink(p)
            if found is None:
                raise KeyError(f"{path}: no '{p}' in {target._describe()}")
            target = found
        return target

    def __getattr__(self, name):
        if name.startswith("_"):
            raise AttributeError(name)
        found = self._child_or_object(name)
        if found is not None:
            return found
        if self._has_data(name):
            return self._make_data(name)
        raise self._attribute_error(name, [o._name for o in self._objects] + [c._name for c in self._children])

    def __repr__(self):
        return f"<Sofa.Core.Node '{self._name}' at {self.getPathName()}>"

    def _tree(self):
        attributes = []
        for key, value in self._values.items():
            attributes.append((key, _tree_text(value, f"{self._file}:{self._line}: Node '{self._name}': attribute '{key}'",
                                               self._root()),
                               self._line))
        objects = [t for t in (o._tree() for o in self._objects) if t is not None]
        return {"name": self._name, "file": self._file, "line": self._line, "attributes": attributes,
                "objects": objects, "children": [c._tree() for c in self._scene_children()]}


#: SOFA's constraint-based (Lagrange multiplier) contact and its solvers: not in penalty.
CONSTRAINT_BASED = {"FreeMotionAnimationLoop", "ConstraintAnimationLoop", "GenericConstraintSolver",
                    "BlockGaussSeidelConstraintSolver", "LCPConstraintSolver", "ProjectedGaussSeidelConstraintSolver",
                    "UnbuiltGaussSeidelConstraintSolver", "ImprovedJacobiConstraintSolver",
                    "UncoupledConstraintCorrection", "LinearSolverConstraintCorrection",
                    "PrecomputedConstraintCorrection", "GenericConstraintCorrection"}


def _refuse_constraint_based(type_name: str, file: str, line: int):
    """One clear line, at the addObject call, for SOFA's constraint-based contact."""
    if type_name in CONSTRAINT_BASED:
        raise _core.SceneError(f"{file}:{line}: {type_name}: SOFA's constraint-based contact (Lagrange multipliers) is "
                               "not part of penalty, which reproduces SOFA's penalty contact (DefaultAnimationLoop, "
                               "CollisionResponse response=\"PenalityContactForceField\")")


def _default_name(type_name: str) -> str:
    """SofaPython3's name of an unnamed object: its SOFA class (FixedConstraint's is
    FixedProjectiveConstraint)."""
    return _core._sofa_class_name(type_name)
