"""Parameter sweeps on Dask distributed (docs/sweeps.md).

    import penalty
    df = penalty.sweep("scenes/damped_bounce.scn",
                       {"/BallB/ball_b_point.contactStiffness": [10, 20],
                        "/.dt": [2.5e-5, 5e-5, 1e-4]},
                       steps=2000, out="sweep-out")          # a LocalCluster on this machine
    df = penalty.sweep(..., client="tcp://scheduler:8786")   # the same sweep on a Dask cluster

One Dask task per override set. A task loads the scene with its overrides (penalty.load_scene),
runs it and returns one row of metrics; with save=K it also writes its trajectory (the states
every K steps and the contacts) to an HDF5 file. Every task's row is written into
OUT/rows/<task>.json when it completes (HDF5 first, both under a temporary name renamed when
complete), the table into OUT/results.csv. A re-run with the same OUT reuses the rows it finds
(resume). A task that fails (invalid scene or value, divergence, any exception) is a row with its
status and message; a worker process that dies is replaced and its task re-run by Dask.
"""
from __future__ import annotations

import ast
import hashlib
import itertools
import json
import multiprocessing
import os
import sys
import time
import uuid
from pathlib import Path

#: Metric columns of every row, in order (docs/sweeps.md describes them).
METRICS = ("status", "message", "steps_done", "time", "contacts_mean", "contacts_max", "contacts_final",
           "max_penetration", "kinetic", "contact", "dissipated_damping", "dissipated_friction", "dissipated",
           "dissipated_total", "steps_per_s", "wall_s", "digest")
ROW_VERSION = 1

#: `--retries` of `penalty sweep` and `retries=` of sweep(): the one description of both (docs/sweeps.md
#: quotes it; a test holds them together).
RETRIES_HELP = ("Dask reruns of a task that raised (default 2; a task's failures are rows, so this "
                "matters only for errors outside the task, e.g. in a metric's pickling). A task whose "
                "worker process died is rerun by Dask on another worker up to its allowed-failures (3) "
                "times, whatever --retries says; after that its row says 'lost'.")


class OutputFolderError(OSError):
    """OUT (or a folder in it) cannot be created or written: `penalty sweep` exits 5."""


def expand_grid(grid) -> list:
    """The override sets of a grid: a dict {"PATH.attr": [v1, v2, ...], ...} gives the Cartesian
    product (the first key varies slowest); a list of dicts is taken as it is."""
    if isinstance(grid, dict):
        keys = list(grid)
        values = []
        for k in keys:
            v = grid[k]
            if isinstance(v, (str, bytes)) or not hasattr(v, "__iter__"):
                v = [v]
            v = list(v)
            if not v:
                raise ValueError(f"grid: '{k}' has no values")
            values.append(v)
        return [dict(zip(keys, combo)) for combo in itertools.product(*values)]
    sets = [dict(g) for g in grid]
    for i, g in enumerate(sets):
        if not isinstance(g, dict):
            raise ValueError(f"grid: entry {i} is not a dict of overrides")
    return sets


def parse_grid_option(text: str):
    """`PATH.attr=v1,v2,...` (the command line's --grid) as (key, [values as text])."""
    if "=" not in text:
        raise ValueError(f"--grid '{text}': expected PATH.attribute=v1,v2,... (no '=')")
    key, values = text.split("=", 1)
    items = [v.strip() for v in values.split(",")]
    if not key or any(v == "" for v in items):
        raise ValueError(f"--grid '{text}': expected PATH.attribute=v1,v2,... (an empty key or value)")
    return key, items


def _file_digest(path: Path) -> str:
    h = hashlib.sha256()
    with open(path, "rb") as f:
        for chunk in iter(lambda: f.read(1 << 20), b""):
            h.update(chunk)
    return h.hexdigest()


def task_id(spec: dict) -> str:
    """A name for a task that changes when anything that changes its result changes: the scene
    file's contents, the overrides, steps, dt, data dirs, save interval, divergence factor."""
    from . import format_overrides
    key = {"scene_sha256": spec["scene_sha256"], "overrides": format_overrides(spec["overrides"]),
           "steps": spec["steps"], "dt": spec["dt"], "data_dirs": spec["data_dirs"], "save": spec["save"],
           "divergence_factor": spec["divergence_factor"], "version": ROW_VERSION}
    return "t" + hashlib.sha256(json.dumps(key, sort_keys=True).encode()).hexdigest()[:16]


def state_digest(scene) -> str:
    """SHA-256 of the final positions and velocities of every state (float64, in state order)."""
    import numpy as np
    h = hashlib.sha256()
    for s in scene.states:
        h.update(s.path.encode() + b"\0")
        h.update(np.ascontiguousarray(s.positions, dtype="<f8").tobytes())
        h.update(np.ascontiguousarray(s.velocities, dtype="<f8").tobytes())
    return h.hexdigest()


def _temporary_name(path: Path) -> Path:
    """Where a file is written before it is renamed to `path` (complete): `.NAME.tmp-PID`."""
    return path.with_name(f".{path.name}.tmp-{os.getpid()}")


def remove_partial_files(out: Path, task: str) -> int:
    """Deletes the temporary files a worker that died mid-write left for `task` in OUT (its row
    and its trajectory, `.NAME.tmp-PID`); returns how many. The task is rerun or already complete,
    so they are never a result."""
    removed = 0
    for folder, name in (("rows", f"{task}.json"), ("trajectories", f"{task}.h5")):
        for partial in (out / folder).glob(f".{name}.tmp-*"):
            try:
                partial.unlink()
                removed += 1
            except FileNotFoundError:
                pass
    return removed


def _atomic_write_text(path: Path, text: str):
    tmp = _temporary_name(path)
    tmp.write_text(text)
    os.replace(tmp, path)


def run_task(spec: dict) -> dict:
    """Runs one task (in a Dask worker, or in this process): loads the scene with the overrides,
    runs spec["steps"] steps and returns its row. Never raises for a scene that fails: the row's
    status is "ok", "invalid" (the scene or a value is refused: the builder's message),
    "diverged" or "error" (any other exception: its type and message)."""
    import numpy as np

    import penalty

    row = {"task": spec["task"], "index": spec["index"]}
    for k, v in spec["overrides"].items():
        row[k] = v
    row.update({m: None for m in METRICS})
    row.update(status="ok", message="", steps_done=0)
    save = spec.get("save")
    out = Path(spec["out"]) if spec.get("out") else None
    h5_path = out / "trajectories" / f"{spec['task']}.h5" if (out is not None and save) else None
    contacts = np.zeros(spec["steps"], dtype=np.int64)
    penetration = np.zeros(spec["steps"])
    dissipated = [0.0, 0.0]  # last value of energies()["dissipated"], sum of its increases
    frames = []  # (step, time, [positions per state], [velocities per state])
    contact_frames = []  # (step, dict of contact arrays)
    scene = None
    start = time.perf_counter()
    try:
        scene = penalty.load_scene(spec["scene"], data_dirs=spec["data_dirs"], dt=spec["dt"],
                                   threads=spec["threads"], overrides=spec["overrides"])

        def snapshot(step):
            frames.append((step, scene.time, [np.array(s.positions) for s in scene.states],
                           [np.array(s.velocities) for s in scene.states]))
            if spec.get("save_contacts", True):
                contact_frames.append((step, {k: np.array(v) for k, v in scene.contacts().items()
                                              if k != "pairs"}))

        if save:
            snapshot(0)

        def callback(done, total):
            # the command line's per-step numbers (--stats, output::summarize_contacts): one definition
            step = scene._scene._contact_summary()
            contacts[done - 1] = step["contacts"]
            penetration[done - 1] = step["max_penetration"]
            row["steps_done"] = done
            d = scene.energies()["dissipated"]
            if d > dissipated[0]:
                dissipated[1] += d - dissipated[0]
            dissipated[0] = d
            if save and (done % save == 0 or done == total):
                snapshot(done)

        scene.run(spec["steps"], callback=callback, progress=False,
                  divergence_factor=spec["divergence_factor"])
    except penalty.DivergedError as e:
        row.update(status="diverged", message=str(e))
    except ValueError as e:  # SceneError (a ValueError) and malformed overrides
        row.update(status="invalid", message=str(e))
    except Exception as e:  # noqa: BLE001 - a row, never a lost task
        row.update(status="error", message=f"{type(e).__name__}: {e}")
    wall = time.perf_counter() - start
    done = row["steps_done"]
    row["wall_s"] = wall
    if scene is not None:
        e = scene.energies()
        for k in ("kinetic", "contact", "dissipated_damping", "dissipated_friction", "dissipated"):
            row[k] = float(e[k])
        row["dissipated_total"] = dissipated[1]
        row["time"] = float(scene.time)
        row["digest"] = state_digest(scene)
        if done:
            row["contacts_mean"] = float(contacts[:done].mean())
            row["contacts_max"] = int(contacts[:done].max())
            row["contacts_final"] = int(contacts[done - 1])
            row["max_penetration"] = float(penetration[:done].max())
            row["steps_per_s"] = done / wall if wall > 0 else None
        for f in spec.get("metrics") or ():
            try:
                row.update(f(scene))
            except Exception as ex:  # noqa: BLE001
                row["status"] = "error" if row["status"] == "ok" else row["status"]
                row["message"] = (row["message"] + "; " if row["message"] else "") + \
                    f"metric {getattr(f, '__name__', f)}: {type(ex).__name__}: {ex}"
    if h5_path is not None:
        _write_h5(h5_path, spec, row, scene, contacts[:done], penetration[:done], frames, contact_frames)
        row["trajectory"] = str(h5_path.relative_to(out))
    if out is not None:
        _atomic_write_text(out / "rows" / f"{spec['task']}.json", json.dumps(row, default=_json_default))
    return row


def _json_default(v):
    import numpy as np
    if isinstance(v, np.generic):
        return v.item()
    if isinstance(v, np.ndarray):
        return v.tolist()
    raise TypeError(f"cannot write {type(v).__name__} into a row")


def _write_h5(path: Path, spec, row, scene, contacts, penetration, frames, contact_frames):
    import h5py
    import numpy as np
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = _temporary_name(path)
    with h5py.File(tmp, "w") as f:
        f.attrs["scene"] = spec["scene"]
        f.attrs["overrides"] = json.dumps(spec["overrides"], default=_json_default)
        f.attrs["status"] = row["status"]
        f.attrs["message"] = row["message"]
        f.attrs["save_every"] = spec["save"]
        f["contacts_per_step"] = contacts
        f["max_penetration_per_step"] = penetration
        f["frame_step"] = np.array([fr[0] for fr in frames], dtype=np.int64)
        f["frame_time"] = np.array([fr[1] for fr in frames])
        if scene is not None and frames:
            states = f.create_group("states")
            for i, s in enumerate(scene.states):
                g = states.create_group(s.path.strip("/").replace("/", "|") or s.name)
                g.attrs["path"] = s.path
                g["positions"] = np.stack([fr[2][i] for fr in frames])
                g["velocities"] = np.stack([fr[3][i] for fr in frames])
        if contact_frames:
            cg = f.create_group("contacts")
            for step, c in contact_frames:
                g = cg.create_group(f"{step:09d}")
                for k, v in c.items():
                    g[k] = v
    os.replace(tmp, path)


def _complete_row(out: Path, task: str, save) -> dict | None:
    """The row of a task completed by an earlier run, or None (missing, partial or unreadable)."""
    p = out / "rows" / f"{task}.json"
    if not p.is_file():
        return None
    try:
        row = json.loads(p.read_text())
    except (OSError, ValueError):
        return None
    if save and not (out / row.get("trajectory", "")).is_file():
        return None
    return row


def _ensure_worker_path():
    """LocalCluster's worker processes import penalty as this process does: its folder goes on
    PYTHONPATH (they inherit the environment)."""
    here = str(Path(__file__).resolve().parent.parent)
    parts = [p for p in os.environ.get("PYTHONPATH", "").split(os.pathsep) if p]
    if here not in parts:
        os.environ["PYTHONPATH"] = os.pathsep.join([here, *parts])


def _is_main_test(test) -> bool:
    """`__name__ == "__main__"` (either order)."""
    if not (isinstance(test, ast.Compare) and len(test.ops) == 1 and isinstance(test.ops[0], ast.Eq)):
        return False
    sides = [test.left, test.comparators[0]]
    return (any(isinstance(x, ast.Name) and x.id == "__name__" for x in sides)
            and any(isinstance(x, ast.Constant) and x.value == "__main__" for x in sides))


def unguarded_main_call():
    """(file, line) of the statement of the `__main__` script that is calling sweep() at its top
    level outside `if __name__ == "__main__":`, or None. Dask's LocalCluster starts each worker in
    a new process that imports `__main__` again (multiprocessing's "spawn"): such a call would
    start a cluster from every worker, whose workers would do the same, for ever."""
    main = sys.modules.get("__main__")
    path = getattr(main, "__file__", None)
    if main is None or not path:
        return None  # python3 -c, an interactive session, a notebook: nothing is imported again
    frame = sys._getframe(1)
    while frame is not None and not (frame.f_code.co_name == "<module>" and frame.f_globals is vars(main)):
        frame = frame.f_back
    if frame is None:
        return None
    line = frame.f_lineno
    try:
        tree = ast.parse(Path(path).read_text(), filename=path)
    except (OSError, SyntaxError, ValueError):
        return None
    for node in ast.walk(tree):
        if isinstance(node, ast.If) and _is_main_test(node.test) and node.body:
            if node.body[0].lineno <= line <= (node.body[-1].end_lineno or node.body[-1].lineno):
                return None
    return path, line


def _refuse_unguarded_main():
    """Raises RuntimeError (before any process is started) when a LocalCluster would make every
    worker run the caller's script again (unguarded_main_call), or when this is such a worker."""
    where = unguarded_main_call()
    spawned = multiprocessing.parent_process() is not None and getattr(sys.modules.get("__main__"), "__name__", "") != "__main__"
    if where is None and not spawned:
        return
    at = f"{where[0]}:{where[1]}: " if where else ""
    raise RuntimeError(
        f"{at}penalty.sweep is called at the top level of the script, outside `if __name__ == \"__main__\":`. "
        "Its LocalCluster starts each worker as a new Python process that imports the script again, "
        "which would start a sweep in every worker, for ever. Put the call under `if __name__ == \"__main__\":` "
        "(docs/sweeps.md), or pass client= a running cluster's address.")


class IgnoreInterrupts:
    """A Dask worker plugin: the worker process ignores SIGINT (set when the worker joins, also
    for a worker its nanny restarts)."""

    name = "penalty-ignore-interrupts"

    def setup(self, worker):
        import signal
        import threading
        if threading.current_thread() is threading.main_thread():
            signal.signal(signal.SIGINT, signal.SIG_IGN)

    def teardown(self, worker):
        pass

    def transition(self, key, start, finish, **kwargs):
        pass

    def release_key(self, key, state, cause, reason, report):
        pass


def _cluster_without_interrupts(workers):
    """A LocalCluster whose worker processes ignore SIGINT. Ctrl-C in a terminal signals every
    process of the foreground group: the workers would print KeyboardInterrupt tracebacks of their
    own (or die while importing). The processes started with the cluster inherit SIGINT ignored
    (it is ignored in this process while they start, from the main thread; a Python that starts
    with SIGINT ignored keeps it so); the caller registers IgnoreInterrupts for the workers a
    nanny starts later. A Ctrl-C during the cluster's start (a second or two) is ignored."""
    import signal
    import threading
    if threading.current_thread() is not threading.main_thread():
        return local_cluster(workers)
    previous = signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:
        return local_cluster(workers)
    finally:
        signal.signal(signal.SIGINT, previous)


def local_cluster(workers=None, **kwargs):
    """A LocalCluster of `workers` single-threaded processes bound to 127.0.0.1, no dashboard (the
    scheduler's and workers' small HTTP servers, /health and /metrics, take free ports on 127.0.0.1)."""
    import logging

    from distributed import LocalCluster
    _ensure_worker_path()
    options = dict(n_workers=workers or os.cpu_count() or 1, threads_per_worker=1, processes=True,
                   host="127.0.0.1", dashboard_address=None, silence_logs=logging.ERROR,
                   scheduler_kwargs={"dashboard_address": "127.0.0.1:0"}, worker_dashboard_address="127.0.0.1:0")
    options.update(kwargs)
    return LocalCluster(**options)


def sweep(scene, grid, steps: int, *, out=None, metrics=None, save=None, save_contacts: bool = True,
          client=None, workers=None, data_dirs=(), dt=None, threads: int = 1, divergence_factor: float = 100.0,
          retries: int = 2, resume: bool = True, progress=None):
    """Runs `scene` once per override set of `grid` on Dask and returns a pandas DataFrame, one row
    per task in grid order (docs/sweeps.md).

    grid: {"PATH.attr": [values], ...} (Cartesian product) or a list of override dicts.
    steps: steps per task. out: output folder (rows/, trajectories/, results.csv; None: nothing is
    written, no resume). metrics: callables f(scene) -> dict of extra columns, called at the end.
    save: K > 0 writes each task's states every K steps (and the last) and its contacts at those
    steps to OUT/trajectories/<task>.h5 (needs out). client: a distributed.Client, a scheduler
    address ("tcp://host:8786"), or None for a LocalCluster of `workers` processes (default: the
    cores) on 127.0.0.1. threads: threads per task (detection, response and independent solvers) (1: one task per core).
    retries: Dask reruns of a task that raised (RETRIES_HELP). resume: reuse the complete rows
    found in OUT (the partial files of dead workers are deleted). progress: callable(done, total, row), True for a line per task on stderr, None
    for a bar when stderr is a terminal."""
    import pandas as pd

    from . import format_overrides

    scene_path = Path(scene).resolve()
    if not scene_path.is_file():
        raise FileNotFoundError(f"sweep: scene '{scene}' not found")
    if not (isinstance(steps, int) and 0 <= steps <= 1_000_000_000):
        raise ValueError(f"sweep: steps {steps!r} is out of range (0 to 1000000000)")
    if save is not None and save is not False:
        if out is None:
            raise ValueError("sweep: save= needs out= (the folder of the HDF5 files)")
        if not (isinstance(save, int) and save >= 1):
            raise ValueError(f"sweep: save={save!r}: expected the interval K >= 1 (steps between saved states)")
    else:
        save = None
    sets = expand_grid(grid)
    for s in sets:
        format_overrides(s)  # strings, so that a bad key fails here and values are JSON-able
    scene_sha = _file_digest(scene_path)
    out_dir = Path(out).resolve() if out is not None else None
    if out_dir is not None:
        try:
            (out_dir / "rows").mkdir(parents=True, exist_ok=True)
            if save:
                (out_dir / "trajectories").mkdir(exist_ok=True)
            probe = _temporary_name(out_dir / "rows" / "write-test")
            probe.write_text("")
            probe.unlink()
        except OSError as e:
            raise OutputFolderError(e.errno, f"sweep: cannot write the output folder '{out}': "
                                             f"{e.strerror or e}") from None
    specs = []
    for i, s in enumerate(sets):
        spec = {"scene": str(scene_path), "scene_sha256": scene_sha, "overrides": s, "steps": steps,
                "dt": dt, "data_dirs": [os.fspath(Path(d).resolve()) for d in data_dirs], "threads": int(threads),
                "save": save, "save_contacts": bool(save_contacts), "divergence_factor": float(divergence_factor),
                "out": str(out_dir) if out_dir is not None else None, "metrics": list(metrics or []), "index": i}
        spec["task"] = task_id(spec)
        specs.append(spec)
    if len({s["task"] for s in specs}) != len(specs):
        raise ValueError("sweep: the grid has the same override set twice")

    if out_dir is not None:
        for spec in specs:  # what a worker killed mid-write left (a resumed or rerun sweep)
            remove_partial_files(out_dir, spec["task"])

    rows = [None] * len(specs)
    todo = []
    for i, spec in enumerate(specs):
        row = _complete_row(out_dir, spec["task"], save) if (out_dir is not None and resume) else None
        if row is not None:
            row["index"] = i
            row["resumed"] = True
            rows[i] = row
        else:
            todo.append(spec)

    report = _progress_reporter(progress, len(specs))
    if todo:
        _run_on_dask(todo, rows, client, workers, retries, report, out_dir)
    report(None, None)

    df = pd.DataFrame(rows)
    keys = list(dict.fromkeys(k for s in sets for k in s))
    first = ["task", *keys, *METRICS]
    columns = [c for c in first if c in df.columns] + [c for c in df.columns if c not in first and c != "index"]
    df = df[columns]
    if out_dir is not None:
        # %.17g: every float written exactly (read it back with float_precision="round_trip").
        df.to_csv(out_dir / "results.csv", index=False, float_format="%.17g")
    return df


def _run_on_dask(todo, rows, client, workers, retries, report, out_dir):
    """Runs the specs of `todo` as Dask tasks and puts each row into rows[spec["index"]] as it
    completes (a task Dask gave up on is a "lost" row); `client` None starts (and closes) a
    LocalCluster of `workers` processes, a string connects to that scheduler."""
    from distributed import Client, as_completed
    own_cluster = None
    own_client = None
    if client is None:
        _refuse_unguarded_main()
        own_cluster = _cluster_without_interrupts(workers)
    done_count = sum(r is not None for r in rows)
    try:
        if own_cluster is not None:
            own_client = client = Client(own_cluster)
            client.register_worker_plugin(IgnoreInterrupts())
        elif isinstance(client, str):
            own_client = client = Client(client)
        futures = {}
        submission = uuid.uuid4().hex[:8]  # a key of its own: never an earlier sweep's result kept in memory
        for spec in todo:
            f = client.submit(run_task, spec, key=f"penalty-sweep-{spec['task']}-{submission}", pure=False,
                              retries=retries)
            futures[f] = spec
        for f in as_completed(list(futures)):
            spec = futures[f]
            try:
                row = f.result()
            except Exception as e:  # noqa: BLE001 - e.g. KilledWorker after the retries: still a row
                row = {"task": spec["task"], **spec["overrides"], **{m: None for m in METRICS},
                       "status": "lost", "message": f"{type(e).__name__}: {e}", "steps_done": 0}
            row["index"] = spec["index"]
            row["resumed"] = False
            rows[spec["index"]] = row
            done_count += 1
            report(done_count, row)
    finally:
        if own_cluster is not None and isinstance(sys.exc_info()[1], KeyboardInterrupt):
            # Ctrl-C: the workers are being stopped on purpose; a nanny slow to stop its worker
            # (a loaded machine), or the client's thread reconnecting to a scheduler already gone,
            # would log an ERROR with a traceback over the resume message. Every distributed
            # logger: Dask's configuration gives some (distributed.client, ...) their own level.
            import logging
            for name in ["distributed", *logging.root.manager.loggerDict]:
                if name == "distributed" or name.startswith("distributed."):
                    logging.getLogger(name).setLevel(logging.CRITICAL)
            _drop_cancelled_client_tasks_from_last_resort()
        if own_client is not None:
            own_client.close()
        if own_cluster is not None:
            own_cluster.close()
        if out_dir is not None:  # a worker that died during this sweep left its partial files
            for spec in todo:
                remove_partial_files(out_dir, spec["task"])


class _CancelledDaskTaskFilter:
    """A logging filter that drops the record of a Dask task cancelled inside `distributed` (the
    client's reconnection to a scheduler stopped by Ctrl-C, cancelled by the client's close).
    distributed's log_errors names its logger after the caller's module (asyncio.events, not a
    distributed logger), so a process without logging handlers printed it, a bare traceback, through
    logging.lastResort after the resume message."""

    def filter(self, record) -> bool:
        import asyncio
        exc = record.exc_info[1] if record.exc_info else None
        if not isinstance(exc, asyncio.CancelledError):
            return True
        tb = exc.__traceback__
        while tb is not None:
            if f"{os.sep}distributed{os.sep}" in tb.tb_frame.f_code.co_filename:
                return False
            tb = tb.tb_next
        return True


def _drop_cancelled_client_tasks_from_last_resort():
    """After Ctrl-C: _CancelledDaskTaskFilter on logging.lastResort (the handler of a process that
    configured none), once."""
    import logging
    last_resort = logging.lastResort
    if last_resort is not None and not any(isinstance(f, _CancelledDaskTaskFilter) for f in last_resort.filters):
        last_resort.addFilter(_CancelledDaskTaskFilter())


def _progress_reporter(progress, total):
    if callable(progress):
        return lambda done, row: progress(done, total, row) if done is not None else None
    bar = progress is None and sys.stderr.isatty()
    lines = progress is True

    def report(done, row):
        if done is None:
            if bar:
                sys.stderr.write("\n")
            return
        if lines:
            print(f"[{done}/{total}] {row['task']} {row['status']}"
                  + (f": {row['message']}" if row.get("message") else ""), file=sys.stderr, flush=True)
        elif bar:
            width = 30
            filled = int(width * done / max(total, 1))
            sys.stderr.write(f"\r[{'#' * filled}{'.' * (width - filled)}] {done}/{total} tasks ")
            sys.stderr.flush()
    return report


def summary_table(df, limit: int = 50) -> str:
    """The command line's table: overrides, status, a few metrics."""
    shown = [c for c in df.columns if c not in ("message", "digest", "trajectory", "resumed", "wall_s",
                                                "dissipated_damping", "dissipated_friction", "contacts_final")]
    text = df[shown].head(limit).to_string(index=False)
    counts = df["status"].value_counts().to_dict()
    text += "\n" + ", ".join(f"{n} {s}" for s, n in counts.items()) + f" ({len(df)} tasks)"
    failed = df[df["status"] != "ok"]
    for _, r in failed.head(10).iterrows():
        text += f"\n{r['task']} {r['status']}: {r['message']}"
    return text
