"""penalty: SOFA's penalty contact from Python.

    import penalty
    scene = penalty.load_scene("scene.scn", data_dirs=["../shared/sofa"])   # or a SofaPython3 .py
    scene.step(10)
    x = scene.states["/Cube/dofs"].positions       # (n, 3) numpy view of the C++ positions
    c = scene.contacts()                             # dict of arrays, one row per contact

The force field alone: penalty.PenaltyForceField; collision detection alone: penalty.collision.
See docs/python.md.
"""
from __future__ import annotations

import os
import sys
from pathlib import Path

from . import _arguments as _check
from . import _core
from ._core import DivergedError, PenaltyForceField, SceneError, State

#: The version of penalty (the CMake project's; `penalty --version` prints the same).
__version__ = _core.__version__

#: The time step range of load_scene(dt=) and builtin_scene(dt=) (s), as `penalty run --dt`.
MIN_DT, MAX_DT = _core.min_dt, _core.max_dt

__all__ = [
    "load_scene", "builtin_scene", "Scene", "States", "State", "PenaltyForceField",
    "SceneError", "DivergedError", "sofa_path", "sweep", "format_overrides", "__version__",
]

#: Folder to put first on sys.path so that `import Sofa`, `import SofaRuntime` resolve to
#: penalty's SofaPython3 subset (load_scene does it for you; `python3 scene.py` needs it).
sofa_path = str(Path(__file__).resolve().parent / "sofa_compat")


class States:
    """The MechanicalObjects of a scene, depth first: by index, by SOFA path ("/Cube/dofs") and by
    name (the name must be unique in the scene)."""

    def __init__(self, states):
        self._list = list(states)
        self._by_path = {s.path: s for s in self._list}
        self._by_name = {}
        for s in self._list:
            self._by_name.setdefault(s.name, []).append(s)

    def __len__(self):
        return len(self._list)

    def __iter__(self):
        return iter(self._list)

    def __contains__(self, key):
        try:
            self[key]
            return True
        except (KeyError, IndexError, TypeError):
            return False

    def keys(self):
        return [s.path for s in self._list]

    def __getitem__(self, key):
        if isinstance(key, int) and not isinstance(key, bool):
            return self._list[key]
        if not isinstance(key, str):
            raise TypeError(f"states: a key is a path, a name or an index, not {type(key).__name__}")
        if key in self._by_path:
            return self._by_path[key]
        if not key.startswith("/") and "/" + key in self._by_path:
            return self._by_path["/" + key]
        found = self._by_name.get(key, [])
        if len(found) == 1:
            return found[0]
        if len(found) > 1:
            raise KeyError(f"state name '{key}' is ambiguous: {', '.join(s.path for s in found)}; use the path")
        raise KeyError(f"no state '{key}'; states: {', '.join(self.keys())}")

    def __repr__(self):
        return "States(" + ", ".join(self.keys()) + ")"


from .topology import TopologyMethods  # noqa: E402


class Scene(TopologyMethods):
    """A built scene. `states` views the C++ memory; step() runs the solvers (and the SofaPython3
    controllers of a script)."""

    def __init__(self, core_scene, root=None):
        self._scene = core_scene
        self.root = root  #: the Sofa.Core.Node root of a SofaPython3 script (None for .scn)
        self._states = States(core_scene._state_list())
        self._states_generation = core_scene._generation
        self._dt_of_step = None  # Sofa.Simulation.animate(root, dt) with another dt
        self._last_dt = core_scene.dt

    @property
    def states(self) -> States:
        """Every MechanicalObject (see States); the list follows nodes added or removed after
        init."""
        if self._scene._generation != self._states_generation:
            self._states = States(self._scene._state_list())
            self._states_generation = self._scene._generation
        return self._states

    def step(self, n: int = 1):
        """Runs n steps (collision detection at the start of each, then the solvers)."""
        n = _check.integer("Scene.step", "n", n, 0, 1_000_000_000)
        self._last_dt = self._scene.dt
        self._scene.step(n)

    def _next_dt(self) -> float:
        return self._dt_of_step if self._dt_of_step is not None else self._scene.dt

    def _step_once(self, dt=None):
        """One step, with `dt` instead of the root's (Sofa.Simulation.animate(root, dt))."""
        if dt is None or dt == self._scene.dt:
            self._last_dt = self._scene.dt
            self._scene.step(1)
            return
        self._dt_of_step = self._last_dt = float(dt)
        try:
            self._scene._run_hooks(True)
            self._scene._step_with_dt(float(dt))
            self._scene._run_hooks(False)
        finally:
            self._dt_of_step = None

    def data(self, path: str, name: str, node: bool = False):
        """The current value of Data `name` of the component (or node) at SOFA path `path`, with
        SOFA's type (docs/python.md, "The object model")."""
        return self._scene._data(path, node, name)

    def set_data(self, path: str, name: str, value, node: bool = False):
        """Writes Data `name` of the component (or node) at `path`, with the effect SOFA gives the
        write after init (at once for a state, at the next step or at reinit() for the others;
        refused with the reason when SOFA ignores it)."""
        from .sofa_api.text import to_sofa_text
        self._scene._set_data(path, node, name, to_sofa_text(value, f"{path}.{name}"))

    def data_fields(self, path: str, node: bool = False) -> list:
        """Every Data of the component (or node) at `path`: name, SOFA type, default, how a write
        after init takes effect."""
        return self._scene._data_fields(path, node)

    def reinit(self, path: str, node: bool = False):
        """SOFA's reinit() of the component at `path` (init() of every component below a node)."""
        self._scene._reinit(path, node)

    @property
    def time(self) -> float:
        """Simulated time (s)."""
        return self._scene.time

    @property
    def dt(self) -> float:
        """Time step (s)."""
        return self._scene.dt

    @property
    def file(self):
        return self._scene.file

    def contacts(self) -> dict:
        """The live contacts after the last step, one row per contact (dict of numpy arrays):
        pairs (names "<model1>-<model2>") and pair_index into it, element1/element2 (collision
        elements), dof1/dof2 (contact-point DOFs), point1/point2 (m), normal (side 1 -> 2), dist (m),
        stiffness (N/m), penetration (m, at the last force evaluation), normal_force (N),
        tangential_force (N, on side 2), friction_state (0 none, 1 sticking, 2 sliding), age (steps)."""
        return self._scene.contacts()

    def energies(self) -> dict:
        """kinetic, contact (stored in the contact springs), dissipated_damping,
        dissipated_friction, dissipated (J; dissipation cumulative over the live contact pairs)."""
        return self._scene.energies()

    def info(self) -> dict:
        """What `penalty info` prints, as data: nodes (path, dt, gravity), components (type, name,
        file, line, role), pipelines, warnings, and the text itself."""
        return self._scene.info()

    @property
    def no_tunnelling(self) -> str:
        """The tunnelling guard's mode: "off" (SOFA's step), "warn" (report crossings), "substep"
        or "stiffen" (prevent them); assign to change it (docs/no-tunnelling.md)."""
        return self._scene.no_tunnelling

    @no_tunnelling.setter
    def no_tunnelling(self, mode: str):
        self._scene.no_tunnelling = mode

    @property
    def reduction(self) -> str:
        """The CG's dot products: "sofa" (SOFA's single chain, the default) or "blocked" (beyond
        SOFA: fixed blocks of 4 096 DOFs on several threads, the same bits at any thread count;
        docs/performance.md, "Blocked reductions"). Set: from the next step on."""
        return self._scene.reduction

    @reduction.setter
    def reduction(self, mode: str):
        self._scene.reduction = mode

    def tunnelling(self):
        """The guard's report of the last step: crossings (list of dicts: kind, model1, model2,
        dofs1, dofs2, element1, element2, toi, depth, point, text), prevented, solves,
        undone_solves, deepest_halving, stiffened_contacts, max_stiffening, stiffening_energy,
        guard_seconds; None without a guard."""
        return self._scene.tunnelling()

    def contact_advice(self, impact_speed=None) -> list:
        """`penalty info --contact-advice` per model pair (dicts: the largest dt and smallest ks
        that keep its bodies from tunnelling; docs/no-tunnelling.md)."""
        return self._scene.contact_advice(impact_speed)

    def warnings(self):
        return self._scene.warnings()

    def run(self, steps: int, *, vtk=None, vtk_every: int = 1, export_states=None, export_mapped: bool = False,
            export_every: int = 1, stats=None, progress=None, callback=None, record: bool = False,
            divergence_factor: float = 100.0, view=None, view_every: int = 1, no_tunnelling=None) -> dict:
        """Runs `steps` steps with the CLI's writers (`penalty run`'s --vtk, --export-states,
        --stats): VTK series into `vtk`, SOFA state files into `export_states`, per-step CSV into
        `stats`. A progress bar is drawn on stderr when it is a terminal (progress=None) or when
        progress=True. callback(done, total) is called after each step. Returns the summary
        (the CLI's numbers, and its text under "text"); with record=True it also holds
        "history": per-step arrays time, kinetic, contact, dissipated_damping,
        dissipated_friction (J) and contacts (count), after each step. divergence_factor is the
        CLI's --divergence-factor (docs/reliability.md; 0 turns the check off). view writes the
        browser viewer into that folder (`penalty run --view`, one frame in view_every); serve it
        with `penalty view DIR` (docs/viewer.md). no_tunnelling sets the tunnelling guard's mode
        first (Scene.no_tunnelling); the summary's "tunnelling" holds its totals (None without a
        guard)."""
        function = "Scene.run"
        steps = _check.integer(function, "steps", steps, 0, 1_000_000_000)
        vtk_every = _check.integer(function, "vtk_every", vtk_every, 1, 1_000_000_000)
        export_every = _check.integer(function, "export_every", export_every, 1, 1_000_000_000)
        view_every = _check.integer(function, "view_every", view_every, 1, 1_000_000_000)
        divergence_factor = _check.real(function, "divergence_factor", divergence_factor, 0.0, 1e100)
        export_mapped = _check.boolean(function, "export_mapped", export_mapped)
        record = _check.boolean(function, "record", record)
        if progress is not None:
            progress = _check.boolean(function, "progress", progress)
        if callback is not None and not callable(callback):
            raise TypeError(f"{function}: callback must be callable, not {type(callback).__name__}")
        vtk, export_states, stats, view = (_check.path(function, name, value) for name, value in
                                           (("vtk", vtk), ("export_states", export_states), ("stats", stats),
                                            ("view", view)))
        as_path = lambda p: p  # noqa: E731 - already str or None
        if no_tunnelling is not None:
            self.no_tunnelling = no_tunnelling
        history = None
        step_callback = callback
        if record:
            import numpy as np
            history = {key: np.zeros(steps) for key in ("time", "kinetic", "contact", "dissipated_damping",
                                                        "dissipated_friction", "contacts")}

            def step_callback(done, total):
                e = self._scene.energies()
                row = done - 1
                history["time"][row] = self._scene.time
                for key in ("kinetic", "contact", "dissipated_damping", "dissipated_friction"):
                    history[key][row] = e[key]
                history["contacts"][row] = len(self._scene.contacts()["age"])
                if callback is not None:
                    callback(done, total)
        summary = self._scene._run(steps, as_path(vtk), vtk_every, as_path(export_states), export_mapped,
                                   export_every, as_path(stats), progress, step_callback, float(divergence_factor),
                                   as_path(view), view_every)
        if history is not None:
            summary["history"] = history
        return summary

    def __repr__(self):
        return f"<penalty.Scene {self.file} t={self.time:g} s, {len(self.states)} states>"


def _format_value(value) -> str:
    """An override value as scene text: numbers exactly (repr round-trips a float), booleans as
    1/0, sequences blank-separated, strings as they are."""
    if isinstance(value, bool):
        return "1" if value else "0"
    if isinstance(value, str):
        return value
    if isinstance(value, (int, float)):
        return repr(value) if isinstance(value, float) else str(value)
    try:
        import numpy as np
        if isinstance(value, np.generic):
            return _format_value(value.item())
    except ImportError:  # pragma: no cover
        pass
    if hasattr(value, "__iter__"):
        return " ".join(_format_value(v) for v in value)
    return str(value)


def format_overrides(overrides) -> list:
    """Overrides as `PATH.attribute=value` strings: from a dict {"/Floor/tri.contactStiffness": 200}
    or an iterable of "PATH.attribute=value" strings (kept as they are)."""
    if overrides is None:
        return []
    if isinstance(overrides, dict):
        for key in overrides:
            if not isinstance(key, str):
                raise TypeError(f"overrides: a key must be a 'PATH.attribute' string, not {key!r}")
        return [f"{key}={_format_value(value)}" for key, value in overrides.items()]
    if isinstance(overrides, str):
        return [overrides]
    try:
        items = list(overrides)
    except TypeError:
        raise TypeError("overrides: expected a dict {'PATH.attribute': value} or a list of "
                        f"'PATH.attribute=value' strings, not {type(overrides).__name__}") from None
    for item in items:
        if not isinstance(item, str):
            raise TypeError(f"overrides: expected 'PATH.attribute=value' strings, found {item!r}")
    return items


def _load_options(data_dirs, dt, threads, exhaustive, overrides=None, function="load_scene", fix_sofa_quirks=()):
    """The checked arguments of load_scene, in the compiled functions' order."""
    if dt is not None:
        dt = _check.real(function, "dt", dt, MIN_DT, MAX_DT, "s")
    if isinstance(fix_sofa_quirks, str) or not all(isinstance(q, str) for q in fix_sofa_quirks):
        raise TypeError(f"{function}: fix_sofa_quirks: expected a list of quirk names")
    return (_check.paths(function, "data_dirs", data_dirs), dt,
            _check.integer(function, "threads", threads, 0, _core.max_threads),
            _check.boolean(function, "exhaustive", exhaustive), format_overrides(overrides), list(fix_sofa_quirks))


def load_scene(path, data_dirs=(), *, dt=None, threads: int = 0, exhaustive: bool = _core.default_exhaustive_detection,
               overrides=None, argv=(), no_tunnelling=None, fix_sofa_quirks=(), reduction=None) -> Scene:
    """Builds a scene from a SOFA `.scn` file or a SofaPython3 `.py` script (its createScene(root)
    is called, then Sofa.Simulation.init). data_dirs are searched for mesh files after the scene's
    folder; dt overrides the root node's time step. overrides sets attributes of the parsed scene
    before it is built, as `penalty run --set` (docs/sweeps.md): {"/Floor/tri.contactStiffness": 200,
    "/.dt": 0.005} or ["/Floor/tri.contactStiffness=200"]; a path or attribute the scene does not
    have raises SceneError naming it, a malformed key ValueError. A script runs as runSofa runs it
    (from its folder, sys.argv = [its name, *argv]; docs/python.md). no_tunnelling ("off", "warn",
    "substep", "stiffen") sets the tunnelling guard over the pipelines' noTunnelling attributes
    (docs/no-tunnelling.md). fix_sofa_quirks names SOFA quirks to fix (`--fix-sofa-quirk`,
    docs/sofa-compatibility.md): ["number_trailing_text"], ["uniform_mass_lazy_write"], ["all"].
    reduction ("sofa", "blocked") sets Scene.reduction (`--reduction`, docs/performance.md)."""
    path = Path(_check.path("load_scene", "path", path, optional=False))
    options = _load_options(data_dirs, dt, threads, exhaustive, overrides, fix_sofa_quirks=fix_sofa_quirks)
    if path.suffix == ".py":
        from . import sofa_api
        root = sofa_api.run_scene_script(path, options, argv)
        scene = root._penalty_scene
    else:
        scene = Scene(_core._load_scene(os.fspath(path), *options))
    if no_tunnelling is not None:
        scene.no_tunnelling = no_tunnelling
    if reduction is not None:
        scene.reduction = reduction
    return scene


def builtin_scene(*, dt=None) -> Scene:
    """The built-in scene of `penalty run` (a soft FEM cube and a rigid ball dropped on a floor)."""
    if dt is not None:
        dt = _check.real("builtin_scene", "dt", dt, MIN_DT, MAX_DT, "s")
    return Scene(_core._builtin_scene(dt))


def sweep(scene, grid, steps, **kwargs):
    """Parameter sweep on Dask: see penalty.sweeps.sweep and docs/sweeps.md."""
    from .sweeps import sweep as _sweep
    return _sweep(scene, grid, steps, **kwargs)


def _install_sofa_path():
    if sofa_path not in sys.path:
        sys.path.insert(0, sofa_path)
