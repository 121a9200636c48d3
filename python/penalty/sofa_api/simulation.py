"""Sofa.Simulation: init, animate, reset, load, unload, and SOFA's events as SofaPython3 dispatches
them (Binding_Controller.cpp: on<EventClass>(event), else onEvent(event); SOFA's
PropagateEventVisitor order: a node's objects in order, then its children, depth first; a handler
returning True marks the event handled, and the rest of that node and its subtree skip it)."""
from __future__ import annotations

import os
import weakref

from .. import _core
from .components import dispatch, resolve
from .tree import Node, Object

#: The events of one step, in SOFA HEAD's order (DefaultAnimationLoop::animate, as SofaPython3
#: delivers them; checked against SOFA HEAD): AnimateBegin, then (from the C++ step) CollisionBegin,
#: CollisionEnd, IntegrateBegin, then IntegrateEnd, AnimateEnd, UpdateMappingEnd.
_AFTER_STEP = ("IntegrateEndEvent", "AnimateEndEvent", "UpdateMappingEndEvent")


def _listening(obj) -> bool:
    """The component's `listening` Data (SofaPython3's components listen by default but data
    engines)."""
    value = obj._values.get("listening")
    if value is None:
        return obj._listens_by_default
    return bool(obj._data_get("listening"))


#: (class, method name) → the class's function or None: a handler lookup per event and component.
_class_handlers: dict = {}


def _listener_count(root: Node) -> int:
    """Python components in the tree (cached on the root until the graph changes)."""
    count = getattr(root, "_listener_count", None)
    if count is None:
        count = len(_python_components(root))
        object.__setattr__(root, "_listener_count", count)
    return count


def _graph_changed(node: Node):
    object.__setattr__(node._root(), "_listener_count", None)
    object.__setattr__(node._root(), "_moved_prefixes", None)


def _class_handler(cls, method: str):
    """The class's function for an event (its on<Event>, else its onEvent), or None; cached."""
    key = (cls, method)
    function = _class_handlers.get(key, _class_handlers)
    if function is _class_handlers:
        function = getattr(cls, method, None)
        if not callable(function):
            function = getattr(cls, "onEvent", None)
        function = function if callable(function) else None
        _class_handlers[key] = function
    return function


def send_event(root: Node, event_type: str, **fields):
    """Propagates one event to the Python components below `root`, in SOFA's order."""
    event = {"type": event_type, "isHandled": False, **fields}
    if _listener_count(root._root()) == 0:
        return event
    method = "on" + event_type

    def visit(node):
        for obj in node._objects:
            if obj._python and (obj._listens_by_default if "listening" not in obj._values else _listening(obj)):
                own = obj.__dict__
                handler = own.get(method) if own else None
                if handler is None:
                    function = _class_handler(type(obj), method)
                    if own and "onEvent" in own and getattr(type(obj), method, None) is None:
                        handler = own["onEvent"]  # the instance's onEvent, for an event its class lacks
                    elif function is not None:
                        handler = function.__get__(obj)
                if handler is not None and handler(dict(event)):
                    event["isHandled"] = True
            if event["isHandled"]:
                return  # SOFA prunes the rest of the node and its subtree
        if event["isHandled"]:
            return
        for child in node._scene_children():
            visit(child)

    visit(root)
    return event


def send_script_event(node: Node, user_data, event_name: str):
    """node.sendEvent(userData, name): SofaPython3's PythonScriptEvent, from `node` down."""
    send_event(node, "PythonScriptEvent", sender=node, event_name=str(event_name), userData=user_data)


def _python_components(root: Node):
    out = []

    def visit(node):
        out.extend(o for o in node._objects if getattr(o, "_python", False))
        for c in node._scene_children():
            visit(c)

    visit(root)
    return out


def _mark_built(node: Node, built: bool):
    for o in node._objects:
        object.__setattr__(o, "_unbuilt", not built)
    object.__setattr__(node, "_unbuilt", not built)
    for c in node._children:
        _mark_built(c, built)


def init(root: Node, *, build_options=None):
    """Builds the scene of the tree below `root` (SOFA's Simulation::init): SimulationInitStartEvent,
    the build (C++ components initialised in SOFA's order), init() then bwdInit() of the Python
    components in graph order, SimulationInitDoneEvent."""
    from .. import Scene
    if not isinstance(root, Node):
        raise TypeError("Sofa.Simulation.init: expected a Sofa.Core.Node")
    if root._parent is not None:
        raise ValueError(f"Sofa.Simulation.init: Node '{root._name}' is not a root node")
    if root._penalty_scene is not None:
        return
    options = build_options or getattr(root, "_penalty_build_options", None) or ([], None, 0, False, [])
    options = tuple(options) + ([],) * (5 - len(options))
    send_event(root, "SimulationInitStartEvent")
    object.__setattr__(root, "_moved_prefixes", None)
    path = root._file if root._file != "<unknown>" else ""
    core = _core._build_live_tree(root._tree(), path, *options[:5], dispatch, resolve,
                                  list(options[5]) if len(options) > 5 else [])
    scene = Scene(core, root)
    _live_scenes.add(scene)
    if _threads is not None:
        core._set_threads(_threads)
    object.__setattr__(root, "_penalty_scene", scene)
    object.__setattr__(root, "_penalty_build_options", options)
    _mark_built(root, True)
    _attach_events(root, scene)
    components = _python_components(root)
    for c in components:
        c.init()
    for c in components:
        bwd = getattr(c, "bwdInit", None)
        if callable(bwd):
            try:
                bwd()
            except TypeError:
                pass  # SofaPython3's examples declare bwdInit() without self: SOFA never calls it for Python
    send_event(root, "SimulationInitDoneEvent")


def _attach_events(root: Node, scene):
    """The events around each step of `scene` go to the Python components of `root`. The hooks live
    in the C++ scene, which the garbage collector cannot traverse: they hold the tree weakly, so
    that no reference cycle keeps a scene alive."""
    root_ref = weakref.ref(root)
    scene_ref = weakref.ref(scene)

    def before():
        r, s = root_ref(), scene_ref()
        if r is not None and s is not None:
            send_event(r, "AnimateBeginEvent", dt=s._next_dt())

    def after():
        r, s = root_ref(), scene_ref()
        if r is not None and s is not None:
            for event_type in _AFTER_STEP:
                if event_type == "AnimateEndEvent":
                    send_event(r, event_type, dt=s._last_dt)
                else:
                    send_event(r, event_type)

    def during(event_type):
        r = root_ref()
        if r is not None:
            send_event(r, event_type)

    scene._scene._add_hooks(before, after)
    scene._scene._set_event_listener(during)


def initRoot(root: Node):  # noqa: N802 - SofaPython3's name
    init(root)


def animate(root: Node, dt=0.0):
    """One step of the scene (SOFA's animate): with `dt`, or the root's dt when 0."""
    scene = _scene_of_root(root, "animate")
    scene._step_once(None if dt is None or float(dt) == 0.0 else float(dt))


def animateNSteps(root: Node, n_steps=1, dt=0.0):  # noqa: N802
    for _ in range(int(n_steps)):
        animate(root, dt)


def _scene_of_root(root, call):
    scene = getattr(root, "_penalty_scene", None) if root is not None else None
    if scene is None:
        raise RuntimeError(f"Sofa.Simulation.{call}: call Sofa.Simulation.init(root) first")
    return scene


def reset(root: Node):
    """SOFA's reset: the states back to their values at init, time 0; written Data stay written."""
    scene = getattr(root, "_penalty_scene", None)
    if scene is None:
        return
    scene._scene._reset()


def unload(root: Node):
    """Removes everything below `root` (SOFA's unload)."""
    object.__setattr__(root, "_penalty_scene", None)
    for c in list(root._children):
        object.__setattr__(c, "_parent", None)
        c._parents.clear()
    root._children.clear()
    for o in list(root._objects):
        object.__setattr__(o, "_node", None)
    root._objects.clear()
    root._values.clear()


def load(path):
    """A scene file as a tree of nodes (SOFA's load): a .scn/.xml file, or a SofaPython3 script
    (its createScene on a new root)."""
    path = os.fspath(path)
    if path.endswith(".py") or path.endswith(".pyscn"):
        from .script import import_sofa_python_scene
        module = import_sofa_python_scene(path)
        root = Node("root")
        module.createScene(root)
        return root
    tree = _core._parse_scene_tree(path, [])
    return _node_from_tree(tree)


def _node_from_tree(tree: dict) -> Node:
    node = Node(tree["name"] or "root")
    object.__setattr__(node, "_file", tree["file"])
    object.__setattr__(node, "_line", tree["line"])
    for name, value, _line in tree["attributes"]:
        node._values[name] = value
    for o in tree["objects"]:
        obj = Object(o["type"], o["name"] or None, {k: v for k, v, _ in o["attributes"]}, o["file"], o["line"], o["template"])
        object.__setattr__(obj, "_node", node)
        if not obj._name:
            object.__setattr__(obj, "_name", _core._sofa_class_name(o["type"]))
        node._objects.append(obj)
    for c in tree["children"]:
        child = _node_from_tree(c)
        object.__setattr__(child, "_parent", node)
        child._parents.append(node)
        node._children.append(child)
    return node


_threads = None


def set_threads(threads: int):
    """Sofa.Core.TaskScheduler.init(n): the threads of the scenes built from now on, and of the
    live ones (0: TBB's default)."""
    global _threads
    _threads = int(threads)
    for scene in list(_live_scenes):
        scene._scene._set_threads(_threads)


#: Scenes built by init, weakly (TaskScheduler.init reaches them).
_live_scenes = weakref.WeakSet()


def print_tree(node: Node, indent: str = ""):  # Sofa.Simulation.print
    print(f"{indent}{node._name}")
    for o in node._objects:
        print(f"{indent}  {o._name} ({o.getClassName()})")
    for c in node._children:
        print_tree(c, indent + "  ")


# ---- the graph changed after init (SOFA: addObject/addChild then init()) ---------------------

def _live_scene(node):
    root = node._root()
    scene = getattr(root, "_penalty_scene", None)
    return scene._scene if scene is not None else None


def on_object_added(node: Node, obj):
    _graph_changed(node)
    live = _live_scene(node)
    if live is None:
        return
    tree = obj._tree()
    if tree is not None:
        live._add_component(node._scene_path(), tree)


def on_child_added(parent: Node, child: Node):
    _graph_changed(parent)
    live = _live_scene(parent)
    if live is None:
        return
    live._add_node(parent._scene_path(), child._name)
    for o in child._objects:
        on_object_added(child, o)
    for c in list(child._children):
        on_child_added(child, c)


def on_removed(node: Node, item):
    _graph_changed(node)
    live = _live_scene(node)
    if live is None:
        return
    if isinstance(item, Node):
        live._remove(item._scene_path(), True)
    elif item._tree() is not None:
        live._remove(item._scene_path(), False)


def init_node(node: Node):
    """node.init() after Sofa.Simulation.init: what was added below it is built, the writes waiting
    for its components' reinit() take effect, and its new Python components are initialised."""
    live = _live_scene(node)
    if live is None:
        return
    live._reinit(node._scene_path(), True)
    for c in _python_components(node):
        if not getattr(c, "_initialised", False):
            c.init()
            object.__setattr__(c, "_initialised", True)
