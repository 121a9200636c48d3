"""SofaPython3's Python components: Sofa.Core.Controller, ForceFieldVec3d / ForceFieldRigid3d,
Mapping_Vec3d_Vec3d / Mapping_Rigid3d_Vec3d and DataEngine. Their Data live in Python; force
fields and mappings take part in the C++ solve as ordinary ForceField / Mapping objects that call
their methods (python/src/python_components.cpp) through dispatch() below, with the arguments
SofaPython3 gives (Binding_ForceField.cpp, Binding_Mapping.cpp)."""
from __future__ import annotations

import itertools
import weakref

import numpy as np

from .graph import type_fields
from .text import caller_location
from .tree import Object

#: Python force fields and mappings by id, for the C++ objects that call them (weak: the
#: script's tree owns them).
_registry: dict = {}
_ids = itertools.count(1)


def resolve(object_id: int):
    ref = _registry.get(object_id)
    obj = ref() if ref is not None else None
    if obj is None:
        raise RuntimeError(f"penalty: the Python component {object_id} no longer exists")
    return obj


class _PythonComponent(Object):
    """What SofaPython3's Python components share: created by the script's class, named by its
    `name=` keyword (a positional name for force fields and mappings), Data kept in Python."""

    _python = True
    _listens_by_default = True    # SOFA's f_listening of SofaPython3's components (not data engines)
    _sofa_class = "Controller"   # SofaPython3's class, for its Data (SOFA's catalog)
    _cpp_type = ""                # penalty's component type in the C++ scene ("" when none)
    _positional_name = False
    _python_kind = ""

    def __init__(self, *args, **kwargs):
        file, line = caller_location()
        name = kwargs.pop("name", None)
        if name is None and self._positional_name and args and isinstance(args[0], str):
            name = args[0]
        Object.__init__(self, self._cpp_type or "Python" + self._sofa_class, None if name is None else str(name), {},
                        file, line)
        object.__setattr__(self, "_id", next(_ids))
        _registry[self._id] = weakref.ref(self)
        for key, value in kwargs.items():  # SofaPython3 sets the Data among the keywords, ignores the others
            if self._has_data(key):
                self._data_set(key, value)

    _catalog_class = ""  # the catalog's class for the Data when it has no rows of _sofa_class

    def _fields(self):
        return type_fields(self._catalog_class or self._sofa_class, False, False)

    def _live(self):
        return None

    def getClassName(self):
        return type(self).__name__

    def init(self):
        return None

    def reinit(self):
        return None

    def _time(self) -> float:
        root = self._root()
        scene = getattr(root, "_penalty_scene", None) if root is not None else None
        return scene.time if scene is not None else 0.0

    def _tree(self):
        return None


class Controller(_PythonComponent):
    """Sofa.Core.Controller: receives SOFA's events (onAnimateBeginEvent(event), ...,
    onEvent(event) for those without their own method), in SOFA's visiting order."""

    _sofa_class = "Controller"
    _python_kind = "controller"

    def draw(self, _visual_params=None):
        return None


class DataEngine(_PythonComponent):
    """Sofa.Core.DataEngine: update() runs when one of its outputs is read after one of its
    inputs changed (SOFA's DataEngine, lazily as SOFA's)."""

    _sofa_class = "DataEngine"
    _python_kind = "engine"
    _listens_by_default = False

    def __init__(self, *args, **kwargs):
        object.__setattr__(self, "_inputs", [])
        object.__setattr__(self, "_outputs", set())
        object.__setattr__(self, "_snapshot", None)
        object.__setattr__(self, "_updating", False)
        super().__init__(*args, **kwargs)

    def addInput(self, data):
        self._inputs.append(data)
        object.__setattr__(self, "_snapshot", None)

    def addOutput(self, data):
        self._outputs.add(data.getName() if data.getOwner() is self else id(data))

    def _data_get(self, name):
        if name in self._outputs and not self._updating:
            self._update_if_dirty()
        return super()._data_get(name)

    def _update_if_dirty(self):
        snapshot = [np.array(d.value, copy=True) if isinstance(d.value, np.ndarray) else d.value for d in self._inputs]
        old = self._snapshot
        if old is not None and len(old) == len(snapshot) and all(_same(a, b) for a, b in zip(old, snapshot)):
            return
        object.__setattr__(self, "_snapshot", snapshot)
        object.__setattr__(self, "_updating", True)
        try:
            self.update()
        finally:
            object.__setattr__(self, "_updating", False)

    def update(self):
        return None


def _same(a, b) -> bool:
    if isinstance(a, np.ndarray) or isinstance(b, np.ndarray):
        return np.shape(a) == np.shape(b) and bool(np.all(np.asarray(a) == np.asarray(b)))
    return a == b


class _ForceField(_PythonComponent):
    _cpp_type = "PythonForceField"
    _positional_name = True
    _python_kind = "forcefield"

    def _tree(self):
        return {"type": self._cpp_type, "name": self._name, "template": self._dof_template, "file": self._file,
                "line": self._line, "attributes": [("pythonObject", str(self._id), self._line)]}

    def getTemplateName(self):
        return self._dof_template

    def addForce(self, mparams, f, x, v):
        raise NotImplementedError(f"{type(self).__name__}.addForce is not implemented")

    def addDForce(self, mparams, df, dx):
        raise NotImplementedError(f"{type(self).__name__}.addDForce is not implemented")

    def addKToMatrix(self, mparams, n_nodes, n_dofs):
        raise NotImplementedError(f"{type(self).__name__}.addKToMatrix is not implemented")


class ForceFieldVec3d(_ForceField):
    """Sofa.Core.ForceFieldVec3d: addForce(mparams, f, x, v), addDForce(mparams, df, dx),
    addKToMatrix(mparams, nNodes, nDofs) written in Python, in the implicit solve."""

    _sofa_class = "ForceFieldVec3d"
    _dof_template = "Vec3d"


class ForceFieldRigid3d(_ForceField):
    _sofa_class = "ForceFieldRigid3d"
    _dof_template = "Rigid3d"


class _Mapping(_PythonComponent):
    _cpp_type = "PythonMapping"
    _positional_name = True
    _python_kind = "mapping"

    def _tree(self):
        attributes = [("pythonObject", str(self._id), self._line)]
        from .tree import _tree_text
        for end in ("input", "output"):
            if end in self._values:
                attributes.append((end, _tree_text(self._values[end], f"{self._describe()}: {end}", self._root()), self._line))
        return {"type": self._cpp_type, "name": self._name, "template": self.getTemplateName(), "file": self._file,
                "line": self._line, "attributes": attributes}

    _out_template = "Vec3d"

    def getTemplateName(self):
        return self._in_template + "," + self._out_template

    def apply(self, mparams, out, inp):
        raise NotImplementedError(f"{type(self).__name__}.apply is not implemented")

    def applyJ(self, mparams, out, inp):
        raise NotImplementedError(f"{type(self).__name__}.applyJ is not implemented")

    def applyJT(self, mparams, out, inp):
        raise NotImplementedError(f"{type(self).__name__}.applyJT is not implemented")


class Mapping_Vec3d_Vec3d(_Mapping):  # noqa: N801 - SofaPython3's name
    """Sofa.Core.Mapping_Vec3d_Vec3d: apply(mparams, out, in), applyJ, applyJT in Python."""

    _sofa_class = "Mapping_Vec3d_Vec3d"
    _in_template = "Vec3d"


class Mapping_Rigid3d_Vec3d(_Mapping):  # noqa: N801
    _sofa_class = "Mapping_Rigid3d_Vec3d"
    _in_template = "Rigid3d"


class Mapping_Vec3d_Vec1d(_Mapping):  # noqa: N801
    """Sofa.Core.Mapping_Vec3d_Vec1d: onto a Vec1d state, the arrays of the output (n, 1)."""

    _sofa_class = "Mapping_Vec3d_Vec1d"
    _catalog_class = "Mapping_Vec3d_Vec3d"  # the same Data (SofaPython3's Mapping binding)
    _in_template = "Vec3d"
    _out_template = "Vec1d"


class ArrayData:
    """A vector handed to a Python force field or mapping (SofaPython3 hands Data): `.value` reads
    it (read-only), `writeableArray()` writes into it, `.value = array` copies into it."""

    __slots__ = ("_array", "_name", "_writeable")

    def __init__(self, array, name, writeable):
        self._array = array
        self._name = name
        self._writeable = writeable

    @property
    def value(self):
        v = self._array.view()
        v.flags.writeable = False
        return v

    @value.setter
    def value(self, new):
        if not self._writeable:
            raise AttributeError(f"'{self._name}' is read-only here")
        self._array[...] = np.asarray(new, dtype=np.float64).reshape(self._array.shape)

    def array(self):
        return self.value

    def writeableArray(self):
        if not self._writeable:
            raise AttributeError(f"'{self._name}' is read-only here")
        return _ArrayContext(self._array)

    def getValueString(self):
        return " ".join(f"{x:g}" for x in self._array.ravel())

    def getName(self):
        return self._name

    def toList(self):
        return self._array.tolist()

    def __len__(self):
        return len(self._array)

    def __getitem__(self, i):
        return self.value[i]

    def __setitem__(self, i, v):
        self._array[i] = v

    def __array__(self, dtype=None, copy=None):
        return np.asarray(self._array, dtype=dtype)

    @property
    def shape(self):
        return self._array.shape

    @property
    def ndim(self):
        return self._array.ndim

    def __repr__(self):
        return repr(self._array.tolist())

    def __str__(self):
        return f"Sofa.Core.DataContainer <name='{self._name}', address={hex(id(self))}>"


class _ArrayContext:
    def __init__(self, array):
        self._array = array

    def __enter__(self):
        return self._array

    def __exit__(self, *exc):
        return False


def _mparams(obj, **factors):
    d = {"time": obj._time(), "mFactor": 0.0, "bFactor": 0.0, "kFactor": 0.0, "isImplicit": False, "energy": False}
    d.update(factors)
    return d


def dispatch(obj, method, *args):
    """Called by the C++ force field or mapping of `obj`: its Python method with SofaPython3's
    arguments."""
    if method == "addForce":
        f, x, v = args
        return obj.addForce(_mparams(obj), ArrayData(f, "force", True), ArrayData(x, "position", False),
                            ArrayData(v, "velocity", False))
    if method == "addDForce":
        df, dx, k, b = args
        mp = {"time": obj._time(), "nFactor": 0.0, "bFactor": float(b), "kFactor": float(k), "isImplicit": True}
        return obj.addDForce(mp, ArrayData(df, "dforce", True), ArrayData(dx, "dx", False))
    if method == "addKToMatrix":
        factor, n_nodes, n_dofs = args
        return obj.addKToMatrix(_mparams(obj, kFactor=float(factor), isImplicit=True), int(n_nodes), int(n_dofs))
    if method in ("apply", "applyJ", "applyJT"):
        out, inp = args
        names = {"apply": ("position", "position"), "applyJ": ("velocity", "velocity"), "applyJT": ("force", "force")}[method]
        return getattr(obj, method)(_mparams(obj), ArrayData(out, names[0], True), ArrayData(inp, names[1], False))
    raise ValueError(f"penalty: unknown method '{method}' of a Python component")
