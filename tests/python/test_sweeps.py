"""Parameter sweeps on Dask (docs/sweeps.md): a 2-worker LocalCluster on 127.0.0.1 runs a grid of
scenes/damped_bounce.scn. Rows equal serial runs bit for bit, an invalid value is a failed row with
the builder's message, a worker killed mid-sweep loses no row, and a resumed sweep runs only the
missing tasks."""
import json
import os
import re
import shlex
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

import numpy as np
import pytest

import penalty

distributed = pytest.importorskip("distributed")
h5py = pytest.importorskip("h5py")
pd = pytest.importorskip("pandas")

from penalty import sweeps  # noqa: E402

SCENE = Path(__file__).resolve().parents[2] / "scenes" / "damped_bounce.scn"
STIFFNESS = "/BallB/ball_b_point.contactStiffness"
GRID = {STIFFNESS: [10, 40], "/.dt": [2.5e-5, 5e-5, 1e-4]}
STEPS = 6000  # the balls reach the plate at t = 0.119 s: every task has contacts


@pytest.fixture(scope="module")
def client():
    cluster = sweeps.local_cluster(2)
    c = distributed.Client(cluster)
    yield c
    c.close()
    cluster.close()


def serial(overrides, steps=STEPS):
    """The same scene with the same overrides, alone in this process, with penalty's defaults."""
    scene = penalty.load_scene(SCENE, overrides=overrides)
    scene.run(steps, progress=False)
    return scene


def test_grid_rows_equal_serial_runs(client, tmp_path):
    df = penalty.sweep(SCENE, GRID, STEPS, out=tmp_path, save=1000, client=client, progress=False)
    assert len(df) == 6
    assert list(df[STIFFNESS]) == [10, 10, 10, 40, 40, 40]
    assert list(df["/.dt"]) == [2.5e-5, 5e-5, 1e-4] * 2
    assert list(df["status"]) == ["ok"] * 6
    assert (df["steps_done"] == STEPS).all()
    assert len(set(df["digest"])) == 6
    assert (df["contacts_max"] == 2).all()
    assert (df["max_penetration"] > 0.004).all() and (df["max_penetration"] < 0.006).all()
    # The tasks ran in the workers, not here.
    assert client.run(os.getpid) and os.getpid() not in client.run(os.getpid).values()
    for _, row in df.iterrows():
        overrides = {STIFFNESS: row[STIFFNESS], "/.dt": row["/.dt"]}
        alone = serial(overrides)
        assert row["digest"] == sweeps.state_digest(alone)
        e = alone.energies()
        for key in ("kinetic", "contact", "dissipated"):
            assert row[key] == e[key]  # bit for bit
        assert row["time"] == alone.time
        # The trajectory: states every 1000 steps from step 0, the last one the final state.
        with h5py.File(tmp_path / row["trajectory"], "r") as f:
            assert list(f["frame_step"][:]) == [0, 1000, 2000, 3000, 4000, 5000, 6000]
            assert f["contacts_per_step"].shape == (STEPS,)
            assert f["contacts_per_step"][:].max() == 2
            g = f["states"]["BallB|ball_b"]
            np.testing.assert_array_equal(g["positions"][-1], alone.states["/BallB/ball_b"].positions)
            np.testing.assert_array_equal(g["velocities"][-1], alone.states["/BallB/ball_b"].velocities)
            assert json.loads(f.attrs["overrides"]) == overrides
    # The CSV holds the same table; no temporary file is left.
    csv = pd.read_csv(tmp_path / "results.csv", float_precision="round_trip")
    assert list(csv["digest"]) == list(df["digest"])
    assert list(csv["kinetic"]) == list(df["kinetic"])  # floats written exactly
    assert not [p for p in tmp_path.rglob(".*tmp-*")]


def test_invalid_value_is_a_failed_row(client):
    df = penalty.sweep(SCENE, [{STIFFNESS: "abc"}, {STIFFNESS: 30}, {"/BallC/ball.radius": 1},
                               {STIFFNESS: 1e9, "/.dt": 1e-3}],
                       2000, client=client, progress=False)
    assert list(df["status"]) == ["invalid", "ok", "invalid", "diverged"]
    # A diverging task: the divergence check's message, the metrics up to the step where it stopped.
    assert df["message"][3].startswith("simulation diverged at step 143 (t = 0.144")
    assert df["steps_done"][3] == 143 and df["contacts_max"][3] == 2
    assert df["message"][0] == (f"{SCENE}:37: PointCollisionModel 'ball_b_point': attribute 'contactStiffness': "
                                "expected a number, found 'abc'")
    assert df["message"][2].startswith(f"{SCENE}: --set '/BallC/ball.radius=1': no node 'BallC' in '/'")
    assert df["steps_done"][0] == 0 and df["steps_done"][1] == 2000
    assert df["digest"][1] == sweeps.state_digest(serial({STIFFNESS: 30}, 2000))


def test_killed_worker_loses_no_row(client, tmp_path):
    steps = 150_000  # about 1.5 s a task: the kill lands mid-sweep
    grid = {STIFFNESS: [10, 20], "/.dt": [2.5e-5, 5e-5]}
    done = []
    result = {}
    thread = threading.Thread(target=lambda: result.update(df=penalty.sweep(
        SCENE, grid, steps, out=tmp_path, client=client, progress=lambda d, total, row: done.append(d))))
    thread.start()
    deadline = time.monotonic() + 60
    while not any(client.processing().values()):
        assert time.monotonic() < deadline, "no task started"
        time.sleep(0.05)
    time.sleep(0.3)
    busy = next(addr for addr, keys in client.processing().items() if keys)
    pid = client.run(os.getpid)[busy]
    done_at_kill = len(done)
    os.kill(pid, signal.SIGKILL)
    thread.join(timeout=120)
    assert not thread.is_alive()
    df = result["df"]
    assert done_at_kill < 4
    assert list(df["status"]) == ["ok"] * 4
    assert (df["steps_done"] == steps).all()
    assert pid not in client.run(os.getpid).values()  # the nanny started a new worker process
    # The rerun task's result is still the serial one.
    for _, row in df.iterrows():
        assert row["digest"] == sweeps.state_digest(serial({STIFFNESS: row[STIFFNESS], "/.dt": row["/.dt"]}, steps))


def test_resume_runs_only_missing_tasks(client, tmp_path):
    grid = {STIFFNESS: [10, 20, 30]}
    first = penalty.sweep(SCENE, grid, 3000, out=tmp_path, client=client, progress=False)
    assert not first["resumed"].any()
    rows = {t: tmp_path / "rows" / f"{t}.json" for t in first["task"]}
    missing = first["task"][1]
    rows[missing].unlink()
    # A partial file of a dead task is not a result.
    (tmp_path / "rows" / f".{missing}.json.tmp-12345").write_text('{"task": "partial"')
    kept = {t: p.stat().st_mtime_ns for t, p in rows.items() if t != missing}
    ran = []
    second = penalty.sweep(SCENE, grid, 3000, out=tmp_path, client=client,
                           progress=lambda d, total, row: ran.append(row["task"]))
    assert ran == [missing]
    assert list(second["resumed"]) == [True, False, True]
    assert {t: rows[t].stat().st_mtime_ns for t in kept} == kept
    assert list(second["digest"]) == list(first["digest"])
    # Another step count is another task: nothing is reused.
    third = penalty.sweep(SCENE, grid, 3001, out=tmp_path, client=client, progress=False)
    assert not third["resumed"].any()


def test_grid_expansion_and_option():
    assert sweeps.expand_grid({"/a.x": [1, 2], "/b.y": [3, 4, 5]}) == [
        {"/a.x": 1, "/b.y": 3}, {"/a.x": 1, "/b.y": 4}, {"/a.x": 1, "/b.y": 5},
        {"/a.x": 2, "/b.y": 3}, {"/a.x": 2, "/b.y": 4}, {"/a.x": 2, "/b.y": 5}]
    assert sweeps.parse_grid_option("/.dt=1e-3, 2e-3") == ("/.dt", ["1e-3", "2e-3"])
    with pytest.raises(ValueError, match=r"--grid '/.dt=1,': expected PATH.attribute=v1,v2,..."):
        sweeps.parse_grid_option("/.dt=1,")
    with pytest.raises(ValueError, match="the same override set twice"):
        penalty.sweep(SCENE, [{"/.dt": 1e-4}, {"/.dt": 1e-4}], 10)


@pytest.mark.skipif(not os.environ.get("PENALTY_CLI"), reason="PENALTY_CLI (the C++ command line) not set")
def test_command_line_sweep(tmp_path):
    """`penalty sweep` (the C++ command line hands it to python3 -m penalty): a LocalCluster of 2."""
    out = tmp_path / "out"
    cmd = [os.environ["PENALTY_CLI"], "sweep", str(SCENE), "--grid", f"{STIFFNESS}=10,abc", "--set", "/.dt=5e-5",
           "--steps", "2000", "--out", str(out), "--workers", "2", "--quiet"]
    r = subprocess.run(cmd, capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr
    assert "1 ok, 1 invalid (2 tasks)" in r.stdout
    assert "attribute 'contactStiffness': expected a number, found 'abc'" in r.stdout
    csv = pd.read_csv(out / "results.csv")
    assert list(csv["status"]) == ["ok", "invalid"]
    assert csv["digest"][0] == sweeps.state_digest(serial({STIFFNESS: 10, "/.dt": 5e-5}, 2000))
    bad = subprocess.run([*cmd[:4], "/.dt", "--out", str(out)], capture_output=True, text=True, timeout=60)
    assert bad.returncode == 2
    assert "--grid '/.dt': expected PATH.attribute=v1,v2,... (no '=')" in bad.stderr


def test_partial_files_of_a_killed_worker_are_deleted_on_resume(client, tmp_path):
    """A worker killed mid-write leaves `.NAME.tmp-PID` files in rows/ and trajectories/; the
    resumed sweep deletes them (reruns their task) and its rows are the first run's."""
    grid = {STIFFNESS: [10, 20]}
    first = penalty.sweep(SCENE, grid, 2000, out=tmp_path, save=500, client=client, progress=False)
    victim = first["task"][0]
    (tmp_path / "rows" / f"{victim}.json").unlink()
    (tmp_path / "trajectories" / f"{victim}.h5").unlink()
    partial = [tmp_path / "trajectories" / f".{victim}.h5.tmp-4242", tmp_path / "rows" / f".{victim}.json.tmp-4242",
               tmp_path / "trajectories" / f".{first['task'][1]}.h5.tmp-77"]  # a complete task's leftover too
    for p in partial:
        p.write_bytes(b"\x89HDF partial")
    other = tmp_path / "rows" / ".unrelated.json.tmp-1"  # another sweep's file in the same OUT: left alone
    other.write_text("{")
    second = penalty.sweep(SCENE, grid, 2000, out=tmp_path, save=500, client=client, progress=False)
    assert list(second["resumed"]) == [False, True]
    assert not any(p.exists() for p in partial)
    assert other.exists()
    assert list(second["digest"]) == list(first["digest"])
    for column in ("max_penetration", "kinetic", "contacts_mean", "dissipated_total"):
        assert list(second[column]) == list(first[column])
    with h5py.File(tmp_path / second["trajectory"][0], "r") as f:
        assert list(f["frame_step"][:]) == [0, 500, 1000, 1500, 2000]


def test_max_penetration_is_the_command_line_statistic(client, tmp_path):
    """One definition: the sweep's per-step max_penetration and contact count are `penalty run
    --stats`' columns (output::summarize_contacts: positions after the step, 0 without a
    penetrating contact), bit for bit, in every step."""
    steps = 6000
    df = penalty.sweep(SCENE, [{}], steps, out=tmp_path / "sweep", save=steps, client=client, progress=False)
    stats = tmp_path / "stats.csv"
    penalty.load_scene(SCENE).run(steps, stats=stats, progress=False)
    csv = pd.read_csv(stats, float_precision="round_trip")
    with h5py.File(tmp_path / "sweep" / df["trajectory"][0], "r") as f:
        np.testing.assert_array_equal(f["max_penetration_per_step"][:], csv["max_penetration"].to_numpy())
        np.testing.assert_array_equal(f["contacts_per_step"][:], csv["contacts"].to_numpy())
    assert df["max_penetration"][0] == csv["max_penetration"].max()
    summary = penalty.load_scene(SCENE).run(steps, progress=False)
    assert df["max_penetration"][0] == summary["max_penetration"]


def test_output_folder_that_cannot_be_written(tmp_path):
    blocker = tmp_path / "a_file"
    blocker.write_text("x")
    with pytest.raises(sweeps.OutputFolderError, match=r"sweep: cannot write the output folder"):
        penalty.sweep(SCENE, [{}], 10, out=blocker / "out", progress=False)


@pytest.mark.skipif(not os.environ.get("PENALTY_CLI"), reason="PENALTY_CLI (the C++ command line) not set")
def test_command_line_sweep_output_folder_that_cannot_be_written_is_exit_5(tmp_path):
    blocker = tmp_path / "a_file"
    blocker.write_text("x")
    r = subprocess.run([os.environ["PENALTY_CLI"], "sweep", str(SCENE), "--steps", "10", "--out", str(blocker / "out"),
                        "--quiet"], capture_output=True, text=True, timeout=120)
    assert r.returncode == 5, r.stderr
    assert "penalty: error: sweep: cannot write the output folder" in r.stderr and "Traceback" not in r.stderr


def test_retries_help_and_docs_say_the_same():
    """`penalty sweep --help`'s --retries is docs/sweeps.md's (one text: sweeps.RETRIES_HELP)."""
    squeeze = lambda text: "".join(text.replace(">", "").split())  # noqa: E731 - line breaks, quote marks
    docs = (Path(__file__).resolve().parents[2] / "docs" / "sweeps.md").read_text()
    assert squeeze(sweeps.RETRIES_HELP) in squeeze(docs)
    r = subprocess.run([sys.executable, "-m", "penalty", "sweep", "--help"], capture_output=True, text=True,
                       env=dict(os.environ, PYTHONPATH=str(Path(penalty.__file__).parents[1])))
    assert squeeze(sweeps.RETRIES_HELP) in squeeze(r.stdout)


UNGUARDED = """
import penalty
df = penalty.sweep({scene!r}, [{{}}], 10, workers=1, progress=False)
print("ran", len(df))
"""

GUARDED = """
import penalty


def main():
    return penalty.sweep({scene!r}, [{{}}], 10, workers=1, progress=False)


if __name__ == "__main__":
    print("ran", len(main()))
"""


def test_a_script_without_main_guard_fails_with_a_clear_message(tmp_path):
    """Dask's LocalCluster starts its workers as processes that import the script again: an
    unguarded call would respawn sweeps for ever. It is refused before any process starts."""
    env = dict(os.environ, PYTHONPATH=str(Path(penalty.__file__).parents[1]))
    script = tmp_path / "unguarded.py"
    script.write_text(UNGUARDED.format(scene=str(SCENE)))
    r = subprocess.run([sys.executable, str(script)], capture_output=True, text=True, env=env, timeout=120)
    assert r.returncode == 1
    assert f"{script}:3: penalty.sweep is called at the top level of the script" in r.stderr
    assert 'if __name__ == "__main__":' in r.stderr and "ran" not in r.stdout
    script = tmp_path / "guarded.py"
    script.write_text(GUARDED.format(scene=str(SCENE)))
    r = subprocess.run([sys.executable, str(script)], capture_output=True, text=True, env=env, timeout=120)
    assert r.returncode == 0, r.stderr
    assert "ran 1" in r.stdout


def _wait_for_started_cluster(pid, workers, timeout=120):
    """Until `workers` worker processes (multiprocessing's spawn children) run under `pid` and
    `pid` catches SIGINT again (it ignores it while its LocalCluster starts)."""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        spawned = [c for c in _children(pid) if "spawn_main" in _cmdline(c)]
        status = Path(f"/proc/{pid}/status").read_text()
        ignored = int(status.split("SigIgn:")[1].split()[0], 16)
        if len(spawned) >= workers and not ignored & (1 << (signal.SIGINT - 1)):
            return
        time.sleep(0.1)
    raise AssertionError("the sweep's LocalCluster did not start")


@pytest.mark.skipif(not os.environ.get("PENALTY_CLI"), reason="PENALTY_CLI (the C++ command line) not set")
@pytest.mark.parametrize("delay", [0.0, 5.0], ids=["as the cluster is up", "while tasks run"])
def test_ctrl_c_on_a_sweep_exits_cleanly_with_the_resume_command(tmp_path, delay):
    out = tmp_path / "out"
    cmd = [os.environ["PENALTY_CLI"], "sweep", str(SCENE), "--grid", f"{STIFFNESS}=10,11,12,13,14,15,16,17",
           "--steps", "20000000", "--out", str(out), "--workers", "2", "--quiet"]
    p = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, start_new_session=True)
    try:
        assert p.stdout.readline().startswith("penalty sweep:")
        _wait_for_started_cluster(p.pid, workers=2)  # a Ctrl-C during its start is ignored
        time.sleep(delay)
        os.killpg(p.pid, signal.SIGINT)  # Ctrl-C: the terminal signals the whole foreground group
        stdout, stderr = p.communicate(timeout=120)
    finally:
        if p.poll() is None:
            os.killpg(p.pid, signal.SIGKILL)
    assert p.returncode == 130, stderr
    assert "Traceback" not in stderr and "KeyboardInterrupt" not in stderr, stderr
    assert "penalty sweep: interrupted;" in stderr
    assert f"penalty sweep {SCENE} --grid" in stderr and f"--out {out}" in stderr


def test_a_cancelled_dask_client_task_is_kept_off_the_last_resort_handler():
    # After Ctrl-C, distributed's log_errors logged the client's cancelled reconnection under the
    # caller's module (asyncio.events): a process without handlers printed a bare traceback through
    # logging.lastResort after the resume message, on a loaded machine (python.sweeps failed so).
    import asyncio
    import logging

    def record_of(filename):
        namespace = {"asyncio": asyncio}
        exec(compile("def reconnect():\n    raise asyncio.CancelledError()\n", filename, "exec"), namespace)
        try:
            namespace["reconnect"]()
        except asyncio.CancelledError:
            return logging.LogRecord("asyncio.events", logging.ERROR, __file__, 1, "", None, sys.exc_info())

    keep = sweeps._CancelledDaskTaskFilter()
    inside = os.path.join(os.sep, "usr", "lib", "python3", "dist-packages", "distributed", "client.py")
    assert not keep.filter(record_of(inside))
    assert keep.filter(record_of(os.path.join(os.sep, "home", "user", "my_script.py")))  # the user's own
    try:
        raise ValueError("a worker's error")
    except ValueError:
        assert keep.filter(logging.LogRecord("distributed.client", logging.ERROR, __file__, 1, "x", None,
                                             sys.exc_info()))
    assert keep.filter(logging.LogRecord("distributed", logging.WARNING, __file__, 1, "no exception", None, None))
    before = list(logging.lastResort.filters)
    try:
        sweeps._drop_cancelled_client_tasks_from_last_resort()
        sweeps._drop_cancelled_client_tasks_from_last_resort()  # once
        added = [f for f in logging.lastResort.filters if f not in before]
        assert len(added) == 1 and isinstance(added[0], sweeps._CancelledDaskTaskFilter)
    finally:
        logging.lastResort.filters[:] = before


def _listening_sockets(pids):
    """(address, port) of every TCP socket in LISTEN state owned by one of `pids`."""
    import ipaddress
    inodes = set()
    for pid in pids:
        try:
            for fd in os.listdir(f"/proc/{pid}/fd"):
                target = os.readlink(f"/proc/{pid}/fd/{fd}")
                if target.startswith("socket:["):
                    inodes.add(target[8:-1])
        except OSError:
            pass
    found = []
    for table, width in (("/proc/net/tcp", 8), ("/proc/net/tcp6", 32)):
        with open(table) as f:
            for line in list(f)[1:]:
                fields = line.split()
                if fields[3] != "0A" or fields[9] not in inodes:  # 0A: LISTEN
                    continue
                hex_address, hex_port = fields[1].split(":")
                raw = bytes.fromhex(hex_address)
                # /proc writes each 32-bit word in host (little-endian) order
                raw = b"".join(raw[i:i + 4][::-1] for i in range(0, len(raw), 4))
                found.append((str(ipaddress.ip_address(raw)), int(hex_port, 16)))
    return found


def _cmdline(pid):
    """The command line of process `pid`, or "" when it has ended since it was listed."""
    try:
        return Path(f"/proc/{pid}/cmdline").read_text(errors="replace")
    except OSError:
        return ""


def _children(pid):
    out = []
    for p in os.listdir("/proc"):
        if p.isdigit():
            try:
                with open(f"/proc/{p}/stat") as f:
                    if int(f.read().rsplit(")", 1)[1].split()[1]) == pid:
                        out.append(int(p))
            except OSError:
                pass
    return out


def _free_port():
    import socket
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


@pytest.mark.skipif(not os.environ.get("PENALTY_CLI") or not Path("/proc/net/tcp").exists(),
                    reason="needs PENALTY_CLI and Linux's /proc")
def test_hand_started_cluster_of_the_docs_listens_on_loopback_only(tmp_path):
    """docs/sweeps.md's one-machine commands, run as written (on free ports): every socket the
    scheduler and the workers listen on is on 127.0.0.1, and the sweep runs on them."""
    docs = (Path(__file__).resolve().parents[2] / "docs" / "sweeps.md").read_text()
    block = docs.split("# one machine: the scheduler, the workers and every HTTP server on 127.0.0.1\n", 1)[1]
    block = block.split("```", 1)[0].replace("\\\n", " ")
    commands = [shlex.split(line) for line in block.splitlines() if line.strip()]
    assert [c[:2] for c in commands] == [["dask", "scheduler"], ["PYTHONPATH=build/release/python", "dask"],
                                         ["penalty", "sweep"]]
    port, dashboard = _free_port(), _free_port()
    ports = {"8786": str(port), "8787": str(dashboard)}
    fix = lambda c: [re.sub(r"\b(8786|8787)\b", lambda m: ports[m.group(1)], a) for a in c]  # noqa: E731
    env = dict(os.environ, PYTHONPATH=str(Path(penalty.__file__).parents[1]))
    repo = Path(__file__).resolve().parents[2]
    scheduler = subprocess.Popen(fix(commands[0]), env=env, cwd=repo, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                                 text=True, start_new_session=True)
    worker = subprocess.Popen(fix(commands[1][1:]), env=env, cwd=repo, stdout=subprocess.DEVNULL,
                              stderr=subprocess.PIPE, text=True, start_new_session=True)
    try:
        sweep = fix(commands[2])
        sweep[0] = os.environ["PENALTY_CLI"]
        sweep[sweep.index("--out") + 1] = str(tmp_path / "out")
        sweep.append("--quiet")
        deadline = time.monotonic() + 60
        while True:  # the workers take a few seconds to register
            r = subprocess.run(sweep, capture_output=True, text=True, timeout=120, cwd=repo)
            if r.returncode == 0 or time.monotonic() > deadline:
                break
            time.sleep(1)
        assert r.returncode == 0, r.stderr
        assert "2 ok (2 tasks)" in r.stdout
        pids = [scheduler.pid, worker.pid, *_children(worker.pid)]
        sockets = _listening_sockets(pids)
        assert len(sockets) >= 6  # scheduler: tcp + http; each of 2 workers: tcp + http; their nanny
        assert all(address == "127.0.0.1" for address, _ in sockets), sockets
        assert ("127.0.0.1", dashboard) in sockets
    finally:
        for p in (worker, scheduler):
            os.killpg(p.pid, signal.SIGTERM)
            try:
                p.wait(timeout=30)
            except subprocess.TimeoutExpired:
                os.killpg(p.pid, signal.SIGKILL)
