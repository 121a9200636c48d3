"""SofaPython3's Data and links: `obj.youngModulus` is a Data whose `.value` is the current value
with SOFA's type (numbers as numbers, vectors as numpy arrays, text as str), `obj.topology` a
link. A Data reads and writes through its owner (graph.Base), which knows whether the value lives
in the script (before init, Python components) or in the built scene (docs/python.md)."""
from __future__ import annotations

import numpy as np

from .text import to_sofa_text


class LinkPath:
    """What `obj.linkpath` and `data.linkpath` give (SofaPython3's LinkPath): its text is the link
    ("@/A/obj", "@/A/obj.position"); target() is the object, node or Data it names."""

    def __init__(self, target):
        self._target = target

    def target(self):
        return self._target

    def isPointingToData(self):
        return isinstance(self._target, Data)

    def getLinkPath(self):
        return self._target.getLinkPath()

    def __str__(self):
        return self._target.getLinkPath()

    def __repr__(self):
        return f"LinkPath({self._target.getLinkPath()!r})"


class _WriteableArray:
    """`with data.writeableArray() as wa:` the array, written back on exit when it is a copy."""

    def __init__(self, data):
        self._data = data
        self._array = None
        self._is_view = False

    def __enter__(self):
        self._array, self._is_view = self._data._owner._data_array(self._data._name, writeable=True)
        return self._array

    def __exit__(self, *exc):
        if exc[0] is None and not self._is_view:
            self._data.value = self._array
        return False


class Data:
    """One Data of an object or node (SofaPython3's Sofa.Core.Data)."""

    __slots__ = ("_owner", "_name")

    def __init__(self, owner, name: str):
        object.__setattr__(self, "_owner", owner)
        object.__setattr__(self, "_name", name)

    # --- value ---------------------------------------------------------------------------------
    @property
    def value(self):
        return self._owner._data_get(self._name)

    @value.setter
    def value(self, new):
        self._owner._data_set(self._name, new)

    def getValue(self):
        return self.value

    def setValue(self, new):
        self.value = new

    def array(self):
        """The value as a read-only numpy array (a view of a state's memory, no copy)."""
        arr, _ = self._owner._data_array(self._name, writeable=False)
        return arr

    def writeableArray(self):
        """`with data.writeableArray() as wa: wa[...] = ...` writes into the Data (a state's
        memory directly)."""
        return _WriteableArray(self)

    def toList(self):
        v = self.value
        return v.tolist() if isinstance(v, np.ndarray) else v

    def read(self, text: str):
        """Sets the value from SOFA's text form."""
        self.value = str(text)

    def getValueString(self):
        return self._owner._data_text(self._name)

    def getValueTypeString(self):
        return self._owner._data_field(self._name)["sofa_type"]

    def typeName(self):
        return self.getValueTypeString()

    # --- identity ------------------------------------------------------------------------------
    def getName(self):
        return self._name

    def getOwner(self):
        return self._owner

    def getPathName(self):
        return self._owner.getPathName() + "." + self._name

    def getLinkPath(self):
        return self._owner.getLinkPath() + "." + self._name

    @property
    def linkpath(self):
        return LinkPath(self)

    def getHelp(self):
        return self._owner._data_field(self._name).get("help", "")

    def isSet(self):
        return self._owner._data_is_set(self._name)

    def unset(self):
        self._owner._data_unset(self._name)

    def isReadOnly(self):
        return self._owner._data_field(self._name)["live"] == "read-only"

    def setReadOnly(self, _flag=True):
        return None

    def isRequired(self):
        return False

    def isPersistent(self):
        return True

    def setPersistent(self, _flag):
        return None

    def isDirty(self):
        return False

    def updateIfDirty(self):
        self._owner._data_get(self._name)

    def hasChanged(self):
        return False

    def getCounter(self):
        return self._owner._data_counter(self._name)

    def hasParent(self):
        return self._owner._data_parent(self._name) is not None

    def getParent(self):
        return self._owner._data_parent(self._name)

    def setParent(self, parent):
        self.value = parent if isinstance(parent, str) else (parent.getLinkPath() if hasattr(parent, "getLinkPath") else parent)

    # --- Python protocols (SofaPython3's: str names the Data, repr gives its value) --------------
    def __str__(self):
        return f"Sofa.Core.Data <'{self._name}', {hex(id(self))}>"

    def __repr__(self):
        return repr(self.value)

    def __len__(self):
        return len(self.value)

    def __bool__(self):
        return True

    def __setattr__(self, name, value):
        if name == "value":
            object.__setattr__(self, name, value)  # the property
        else:
            raise AttributeError(f"Data '{self._name}' has no attribute '{name}' to set")

    def __getattr__(self, name):
        if name.startswith("__"):
            raise AttributeError(name)
        raise AttributeError(f"Data '{self._name}' of {self._owner._describe()} has no attribute '{name}'")

    def __eq__(self, other):
        if isinstance(other, Data):
            return self._owner is other._owner and self._name == other._name
        v = self.value
        return bool(np.all(v == other)) if isinstance(v, np.ndarray) else v == other

    __hash__ = object.__hash__


class DataString(Data):
    """A text Data (SofaPython3's DataString): compares as its text."""

    __slots__ = ()

    def __str__(self):
        return f"Sofa.Core.DataString<name='{self._name}', value='{self.value}', address='{hex(id(self))}'>"

    def __repr__(self):
        return repr(self.value)

    def __getitem__(self, i):
        return self.value[i]

    def __len__(self):
        return len(self.value)

    def __eq__(self, other):
        if isinstance(other, Data):
            return super().__eq__(other)
        return self.value == other

    __hash__ = object.__hash__


class DataContainer(Data):
    """A vector or matrix Data (SofaPython3's DataContainer): indexing, shape, arithmetic on its
    numpy value; in-place operators and item assignment write back."""

    __slots__ = ()

    def __array__(self, dtype=None, copy=None):
        v = self.value
        return np.asarray(v, dtype=dtype) if dtype is not None else np.asarray(v)

    def __getitem__(self, i):
        return self.value[i]

    def __setitem__(self, i, v):
        with self.writeableArray() as wa:
            wa[i] = v

    @property
    def shape(self):
        return np.shape(self.value)

    @property
    def ndim(self):
        return np.ndim(self.value)

    @property
    def size(self):
        return np.size(self.value)

    def apply(self, f):
        with self.writeableArray() as wa:
            f(wa)

    def __add__(self, other):
        return self.value + np.asarray(other)

    def __sub__(self, other):
        return self.value - np.asarray(other)

    def __mul__(self, other):
        return self.value * np.asarray(other)

    def __iadd__(self, other):
        with self.writeableArray() as wa:
            wa += np.asarray(other)
        return self

    def __isub__(self, other):
        with self.writeableArray() as wa:
            wa -= np.asarray(other)
        return self

    def __imul__(self, other):
        with self.writeableArray() as wa:
            wa *= np.asarray(other)
        return self

    def __str__(self):
        return f"Sofa.Core.DataContainer <name='{self._name}', address={hex(id(self))}>"

    def __repr__(self):
        v = self.value
        return repr(v.tolist()) if isinstance(v, np.ndarray) else repr(v)


class Link:
    """A link of an object (SofaPython3's BaseLink): its text (`@/path`), the object it names."""

    __slots__ = ("_owner", "_name")

    def __init__(self, owner, name: str):
        object.__setattr__(self, "_owner", owner)
        object.__setattr__(self, "_name", name)

    def getName(self):
        return self._name

    def getOwnerBase(self):
        return self._owner

    def getValueString(self):
        return self._owner._link_text(self._name)

    def getValueTypeString(self):
        return "link"

    def getLinkedPath(self, index=0):
        text = self.getValueString().split()
        return text[index] if index < len(text) else ""

    def getPathName(self):
        return self.getLinkedPath()

    def getLinkedBase(self, index=0):
        return self._owner._link_target(self._name, index)

    def setLinkedBase(self, target):
        self._owner._data_set(self._name, target.getLinkPath())

    def read(self, text):
        self._owner._data_set(self._name, str(text))

    def isMultiLink(self):
        return len(self.getValueString().split()) > 1

    def getSize(self):
        return len(self.getValueString().split())

    def isPersistent(self):
        return True

    def isReadOnly(self):
        return False

    def getHelp(self):
        return ""

    def __getattr__(self, name):
        if name.startswith("__"):
            raise AttributeError(name)
        target = self.getLinkedBase()
        if target is None:
            raise RuntimeError("Unable to find attribute on an empty link.")
        return getattr(target, name)

    def __str__(self):
        return self.getValueString()

    def __repr__(self):
        return f"<Link {self._name} {self.getValueString()!r}>"


def data_class(form: str):
    """The Data class SofaPython3 uses for a value of this Python form."""
    if form.startswith("ndarray"):
        return DataContainer
    if form == "str":
        return DataString
    return Data


def value_text(value, what: str) -> str:
    """A written value as SOFA text (a Data or a LinkPath becomes its link)."""
    if isinstance(value, LinkPath):
        return value.getLinkPath()
    if isinstance(value, Data):
        return value.getLinkPath()
    return to_sofa_text(value, what)
