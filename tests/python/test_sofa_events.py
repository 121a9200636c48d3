"""SOFA's events as SofaPython3 delivers them to Python components: the events of init and of each
step in SOFA HEAD's order (recorded from SOFA HEAD through SofaPython3), SOFA's visiting order (a
node's objects, then its children, depth first), on<Event> else onEvent, handlers reassigned on
the instance, handled events pruned as SOFA's PropagateEventVisitor does, and an exception in a
handler stopping the run."""
import pytest

from penalty import sofa_api

#: What SOFA HEAD delivers to controllers c_root1, c_root2 (root), c_A (/A) and c_B (/A/B), from
#: init to the end of the first step (SofaPython3 over SOFA HEAD, tests of issue 55).
SOFA_ORDER = [(c, e) for e in ("SimulationInitStartEvent", "SimulationInitDoneEvent", "AnimateBeginEvent",
                               "CollisionBeginEvent", "CollisionEndEvent", "IntegrateBeginEvent", "IntegrateEndEvent",
                               "AnimateEndEvent", "UpdateMappingEndEvent")
              for c in ("c_root1", "c_root2", "c_A", "c_B")]


class Recorder(sofa_api.Controller):
    def __init__(self, *args, **kwargs):
        sofa_api.Controller.__init__(self, *args, **kwargs)
        self.log = kwargs["log"]

    def onEvent(self, event):
        self.log.append((self.name.value, event["type"], dict(event)))


def tree(log):
    root = sofa_api.Node("root")
    a = root.addChild("A")
    root.addObject(Recorder(name="c_root1", log=log))
    a.addObject(Recorder(name="c_A", log=log))
    root.addObject(Recorder(name="c_root2", log=log))
    a.addChild("B").addObject(Recorder(name="c_B", log=log))
    return root


def test_events_in_sofas_order():
    log = []
    root = tree(log)
    sofa_api.init(root)
    sofa_api.animate(root, root.dt.value)
    assert [(c, e) for c, e, _ in log] == SOFA_ORDER
    begin = [ev for c, e, ev in log if e == "AnimateBeginEvent"][0]
    assert begin == {"type": "AnimateBeginEvent", "isHandled": False, "dt": 0.01}
    assert [ev for c, e, ev in log if e == "CollisionBeginEvent"][0] == {"type": "CollisionBeginEvent", "isHandled": False}


def test_animate_with_a_dt_steps_with_it_and_keeps_the_roots():
    log = []
    root = tree(log)
    sofa_api.init(root)
    sofa_api.animate(root, 0.05)
    assert [ev["dt"] for c, e, ev in log if e == "AnimateEndEvent"] == [0.05] * 4
    assert root.time.value == pytest.approx(0.05) and root.dt.value == 0.01


def test_specific_handler_first_then_on_event_and_reassigned_handlers():
    calls = []

    class C(sofa_api.Controller):
        def onAnimateBeginEvent(self, event):
            calls.append((self.name.value, "begin"))

        def modified(self, event):
            calls.append((self.name.value, "modified"))

        def onEvent(self, event):
            calls.append((self.name.value, event["type"]))

    root = sofa_api.Node("root")
    c = root.addObject(C(name="c"))
    sofa_api.init(root)
    calls.clear()
    sofa_api.animate(root)
    assert calls[0] == ("c", "begin") and ("c", "AnimateBeginEvent") not in calls
    calls.clear()
    c.onAnimateBeginEvent = c.modified  # SofaPython3 takes the instance's handler
    sofa_api.animate(root)
    assert calls[0] == ("c", "modified")
    c.listening = False
    calls.clear()
    sofa_api.animate(root)
    assert calls == []


def test_a_handled_event_skips_the_rest_of_the_node_and_its_subtree():
    """SOFA's PropagateEventVisitor: after a handler returns True, the node's next objects and its
    children are pruned; other branches go on, their first object still gets it (recorded from
    SOFA HEAD for this tree)."""
    seen = []

    class C(sofa_api.Controller):
        def __init__(self, *args, **kwargs):
            sofa_api.Controller.__init__(self, *args, **kwargs)
            self.handles = kwargs.get("handles", False)

        def onPythonScriptEvent(self, event):
            seen.append((self.name.value, event["isHandled"]))
            return self.handles

    root = sofa_api.Node("root")
    a, b = root.addChild("A"), root.addChild("B")
    a.addObject(C(name="a1", handles=True))
    a.addObject(C(name="a2"))
    a.addChild("A1").addObject(C(name="a11"))
    b.addObject(C(name="b1"))
    b.addObject(C(name="b2"))
    sofa_api.init(root)
    root.sendEvent({"any": "data"}, "hello")
    assert seen == [("a1", False), ("b1", True)]  # as SOFA HEAD (SofaPython3's Node.sendEvent)


def test_an_exception_in_a_handler_stops_the_run():
    class Stop(sofa_api.Controller):
        def onAnimateEndEvent(self, event):
            if self.getContext().getTime() >= 0.05 - 1e-12:
                raise StopIteration("enough")

    root = sofa_api.Node("root")
    body = root.addChild("Body")
    body.addObject("EulerImplicitSolver")
    body.addObject("CGLinearSolver", iterations=25, tolerance=1e-9, threshold=1e-9)
    body.addObject("MechanicalObject", name="dofs", position=[0, 1, 0])
    body.addObject("UniformMass", totalMass=1)
    root.addObject(Stop(name="stop"))
    sofa_api.init(root)
    with pytest.raises(StopIteration, match="enough"):
        root._penalty_scene.run(100, progress=False)
    assert root._penalty_scene.time == pytest.approx(0.05)


def test_init_of_python_components_in_graph_order():
    order = []

    class C(sofa_api.Controller):
        def init(self):
            order.append(self.name.value)

    root = sofa_api.Node("root")
    root.addChild("A").addObject(C(name="a"))
    root.addObject(C(name="r"))
    sofa_api.init(root)
    assert order == ["r", "a"]
