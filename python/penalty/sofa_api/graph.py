"""The scene graph of a SofaPython3 script: Node and Object (Sofa.Core.Node, Sofa.Core.Object).

Before Sofa.Simulation.init a node or object holds the values the script gave; init builds the C++
scene from them (simulation.init) and from then on every Data of a built component or node reads
and writes the live scene by its SOFA path (Scene.data / set_data, live_data.hpp). Python
components (Controller, ForceField, Mapping, DataEngine: components.py) keep their Data in Python.
"""
from __future__ import annotations

import numpy as np

from .. import _core
from .data import Data, Link, LinkPath, data_class, value_text
from .text import parse_value, suggestions

_TYPE_FIELDS: dict = {}


def type_fields(type_name: str, node: bool, rigid: bool) -> dict:
    """The Data SOFA (and penalty's registry) declare for a type: name → field dict."""
    key = (type_name, node, rigid)
    fields = _TYPE_FIELDS.get(key)
    if fields is None:
        fields = {f["name"]: f for f in _core._type_fields(type_name, node, rigid)}
        _TYPE_FIELDS[key] = fields
    return fields


class NodeIterator:
    """node.children / node.objects (SofaPython3's NodeIterator): a sequence also indexed by name."""

    def __init__(self, items):
        self._items = list(items)

    def __len__(self):
        return len(self._items)

    def __iter__(self):
        return iter(self._items)

    def __contains__(self, item):
        if isinstance(item, str):
            return any(i.getName() == item for i in self._items)
        return any(i is item for i in self._items)

    def __getitem__(self, key):
        if isinstance(key, str):
            for i in self._items:
                if i.getName() == key:
                    return i
            raise KeyError(key)
        return self._items[key]

    def at(self, i):
        return self._items[i]

    def __repr__(self):
        return "[" + ", ".join(i.getName() for i in self._items) + "]"


class Base:
    """What nodes and objects share: Data, links, names."""

    _is_node = False

    def __init__(self):
        object.__setattr__(self, "_values", {})     # Data the script gave, by name
        object.__setattr__(self, "_pydata", {})     # Data added with addData: name → field
        object.__setattr__(self, "_counters", {})   # writes per Data (getCounter)
        object.__setattr__(self, "_messages", [])   # getLoggedMessagesAsString

    # --- to be provided by Node / Object -------------------------------------------------------
    def _fields(self) -> dict:
        raise NotImplementedError

    def _live(self):
        """The core scene when this owner's Data live in the built scene, else None."""
        return None

    def _describe(self) -> str:
        raise NotImplementedError

    def _root(self):
        raise NotImplementedError

    # --- Data ----------------------------------------------------------------------------------
    def _data_field(self, name: str) -> dict:
        f = self._pydata.get(name) or self._fields().get(name)
        if f is None:
            raise AttributeError(f"{self._describe()} has no data '{name}'")
        return f

    def _has_data(self, name: str) -> bool:
        return name in self._pydata or name in self._fields()

    def _data_get(self, name: str):
        field = self._data_field(name)
        live = self._live()
        if live is not None and name not in self._pydata:
            return live._data(self._scene_path(), self._is_node, name, False)
        if name in self._values:
            raw = self._values[name]
            target = _linked(self, raw)
            if target is not None:
                return target.value
            if isinstance(raw, np.ndarray) and field["python_form"].startswith("ndarray"):
                return _shaped(raw, field)
            text = value_text(raw, f"{self._describe()}: data '{name}'")
            return parse_value(text, field["python_form"], field.get("columns", 0))
        return parse_value(field["default"], field["python_form"], field.get("columns", 0))

    def _data_set(self, name: str, value):
        field = self._data_field(name)
        live = self._live()
        self._counters[name] = self._counters.get(name, 0) + 1
        if live is not None and name not in self._pydata:
            path = self._scene_path()
            if field["live"] == "state" and not isinstance(value, str) and not self._is_node:
                live._set_state(path, name, np.asarray(value, dtype=np.float64))
            else:
                live._set_data(path, self._is_node, name, value_text(value, f"{self._describe()}: data '{name}'"))
            return
        if isinstance(value, np.ndarray):
            value = value.copy()
        self._values[name] = value
        self._data_written(name)

    def _data_written(self, name: str):
        """A Data of a Python object was written (DataEngine marks its outputs dirty)."""

    def _data_array(self, name: str, writeable: bool):
        """(array, True when it views the Data's memory)."""
        live = self._live()
        if live is not None and name not in self._pydata and self._data_field(name)["live"] == "state":
            arr = live._data(self._scene_path(), False, name, writeable)
            return arr, arr.base is not None and arr.flags.writeable == writeable
        value = self._data_get(name)
        arr = np.array(value, copy=True)
        if not writeable:
            arr.flags.writeable = False
        return arr, False

    def _data_text(self, name: str) -> str:
        live = self._live()
        if live is not None and name not in self._pydata:
            return live._data_text(self._scene_path(), self._is_node, name)
        v = self._data_get(name)
        if isinstance(v, np.ndarray):
            return " ".join(_sofa_number(x) for x in v.ravel().tolist())
        if isinstance(v, float):
            return _sofa_number(v)
        if isinstance(v, list):
            return " ".join(str(x) for x in v)
        return str(v)

    def _data_is_set(self, name: str) -> bool:
        return name in self._values

    def _data_unset(self, name: str):
        self._values.pop(name, None)

    def _data_counter(self, name: str) -> int:
        return self._counters.get(name, 0)

    def _data_parent(self, name: str):
        raw = self._values.get(name)
        return _linked(self, raw)

    def _link_text(self, name: str) -> str:
        raw = self._values.get(name)
        if raw is None:
            return self._data_field(name)["default"]
        return value_text(raw, name)

    def _link_target(self, name: str, index: int = 0):
        words = self._link_text(name).split()
        if index >= len(words):
            return None
        return resolve_path(self, words[index])

    def findData(self, name: str):
        return self._make_data(name) if self._has_data(name) else None

    def getData(self, name: str):
        return self.findData(name)

    def _make_data(self, name: str):
        field = self._data_field(name)
        if field.get("link"):
            return Link(self, name)
        return data_class(field["python_form"])(self, name)

    def getDataFields(self):
        return [self._make_data(n) for n, f in {**self._fields(), **self._pydata}.items() if not f.get("link")]

    def getLinks(self):
        return [Link(self, n) for n, f in self._fields().items() if f.get("link")]

    def findLink(self, name: str):
        f = self._fields().get(name)
        return Link(self, name) if f is not None and f.get("link") else None

    def addData(self, name, value=None, default=None, help="", group="", type=""):  # noqa: A002 - SofaPython3's names
        """Adds a Data to this object (SofaPython3's Base.addData)."""
        if self._has_data(name) and name not in self._pydata:
            raise ValueError(f"{self._describe()} has a data '{name}' already")
        form, columns = _form_of_type(type, value if value is not None else default)
        self._pydata[name] = {"name": name, "sofa_type": type or "", "python_form": form, "default": "",
                              "live": "next step", "refusal": "", "read_by_penalty": False, "link": False,
                              "columns": columns, "help": help, "group": group}
        initial = value if value is not None else default
        if initial is not None:
            self._values[name] = initial
        return self._make_data(name)

    def addLink(self, name, value=None, help=""):  # noqa: A002
        self._pydata[name] = {"name": name, "sofa_type": "link", "python_form": "link", "default": "",
                              "live": "next step", "refusal": "", "read_by_penalty": False, "link": True,
                              "columns": 0, "help": help}
        if value is not None:
            self._values[name] = value
        return Link(self, name)

    def setDataValues(self, **kwargs):
        for k, v in kwargs.items():
            self._data_set(k, v)

    def __dir__(self):
        return sorted(set(super().__dir__()) | set(self._fields()) | set(self._pydata))

    # --- names ---------------------------------------------------------------------------------
    def getName(self):
        return self._name

    def setName(self, name):
        _NameData(self).value = name

    @property
    def name(self):
        return _NameData(self)

    @name.setter
    def name(self, value):
        _NameData(self).value = value

    def getLinkPath(self):
        return "@" + self.getPathName()

    @property
    def linkpath(self):
        return LinkPath(self)

    @property
    def __data__(self):
        return {d.getName(): d for d in self.getDataFields()}

    # --- messages ------------------------------------------------------------------------------
    def getLoggedMessagesAsString(self):
        return "\n".join(self._messages)

    def countLoggedMessages(self):
        return len(self._messages)

    def clearLoggedMessages(self):
        self._messages.clear()

    # --- attributes ----------------------------------------------------------------------------
    def _attribute_error(self, name, extra=()):
        hint = suggestions(name, list(self._fields()) + list(self._pydata) + list(extra))
        return AttributeError(f"{self._describe()} has no attribute '{name}'{hint}")

    def __setattr__(self, name, value):
        if name.startswith("_") or isinstance(getattr(type(self), name, None), property):
            object.__setattr__(self, name, value)
        elif self._has_data(name):
            self._data_set(name, value)
        else:
            object.__setattr__(self, name, value)


class _NameData(Data):
    """The `name` Data: renames before init (after init a component keeps its path)."""

    __slots__ = ()

    def __init__(self, owner):
        super().__init__(owner, "name")

    @property
    def value(self):
        return self._owner._name

    @value.setter
    def value(self, new):
        owner = self._owner
        if owner._live() is not None:
            owner._live()._set_data(owner._scene_path(), owner._is_node, "name", str(new))  # refused, with the reason
        object.__setattr__(owner, "_name", str(new))

    def getValueString(self):
        return self._owner._name

    def getValueTypeString(self):
        return "string"

    def __str__(self):
        return f"Sofa.Core.DataString<name='name', value='{self._owner._name}', address='{hex(id(self))}'>"

    def __repr__(self):
        return repr(self._owner._name)

    def __eq__(self, other):
        return self._owner._name == (str(other) if isinstance(other, Data) else other)

    __hash__ = object.__hash__


def _sofa_number(x) -> str:
    """A number as SOFA writes it (std::ostream's 6 significant digits)."""
    if isinstance(x, (int, np.integer)):
        return str(int(x))
    return f"{float(x):g}"


def _shaped(raw: np.ndarray, field: dict):
    arr = np.asarray(raw)
    form = field["python_form"]
    dtype = form.split(":")[1]
    arr = arr.astype(dtype)
    if form.endswith(":2") and arr.ndim == 1:
        width = field.get("columns", 0) or max(1, arr.size)
        arr = arr[: arr.size - arr.size % width].reshape(-1, width)
    return arr


def _form_of_type(type_name: str, value):
    """Python form and row width of a Data added with addData(type=...)."""
    t = (type_name or "").strip()
    forms = {"float": "float", "double": "float", "d": "float", "f": "float", "Real": "float",
             "int": "int", "i": "int", "unsigned int": "int", "I": "int", "bool": "int",
             "string": "str", "str": "str", "Vec3d": "ndarray:float64:1", "Vec3": "ndarray:float64:1",
             "vector<double>": "ndarray:float64:1", "vector<float>": "ndarray:float64:1",
             "vector<int>": "ndarray:int32:1", "vector<unsigned int>": "ndarray:int32:1",
             "Vec3d[]": "ndarray:float64:2", "vector<Vec3d>": "ndarray:float64:2",
             "Vec3d::VecCoord": "ndarray:float64:2", "Rigid3d::VecCoord": "ndarray:float64:2"}
    if t in forms:
        form = forms[t]
        columns = 7 if t.startswith("Rigid3d") else (3 if form.endswith(":2") else 0)
        return form, columns
    if isinstance(value, bool):
        return "int", 0
    if isinstance(value, int):
        return "int", 0
    if isinstance(value, float):
        return "float", 0
    if isinstance(value, str) and not value.startswith("@"):
        return "str", 0
    if isinstance(value, (list, tuple, np.ndarray)):
        arr = np.asarray(value)
        if arr.ndim == 2:
            return "ndarray:float64:2", arr.shape[1]
        return "ndarray:float64:1", 0
    return "str", 0


def _linked(owner, raw):
    """The Data a value links to (a Data, a LinkPath to a Data, or "@path.data"), else None."""
    if isinstance(raw, Data):
        return raw
    if isinstance(raw, LinkPath) and raw.isPointingToData():
        return raw.target()
    if isinstance(raw, str) and raw.startswith("@") and "." in raw.rsplit("/", 1)[-1]:
        target = resolve_path(owner, raw)
        return target if isinstance(target, Data) else None
    return None


def resolve_path(owner, link: str):
    """The node, object or Data a SOFA link names from `owner` ("@/A/b", "@../b.position",
    "@b"), or None."""
    text = link[1:] if link.startswith("@") else link
    data_name = None
    last = text.rsplit("/", 1)[-1]
    if "." in last and last not in (".", ".."):
        text, data_name = text[: len(text) - len(last)] + last.split(".", 1)[0], last.split(".", 1)[1]
    node = owner if owner._is_node else owner.getContext()
    if node is None:
        return None
    if text.startswith("/"):
        node, text = node.getRoot(), text[1:]
        parts = [p for p in text.split("/") if p]
    else:
        parts = [p for p in text.split("/") if p]
        if len(parts) == 1 and parts[0] not in (".", ".."):
            # `@name`: a child or object of the node, else of its ancestors (SOFA's search)
            n = node
            while n is not None:
                found = n._child_or_object(parts[0])
                if found is not None:
                    return found.findData(data_name) if data_name else found
                n = n._parent
            return None
    target = node
    for p in parts:
        if p == ".":
            continue
        if p == "..":
            target = target._parent if target._is_node else target.getContext()
        else:
            target = target._child_or_object(p) if target is not None and target._is_node else None
        if target is None:
            return None
    if data_name:
        return target.findData(data_name)
    return target
