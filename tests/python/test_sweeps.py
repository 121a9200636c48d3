"""Parameter sweeps on Dask (docs/sweeps.md): a 2-worker LocalCluster on 127.0.0.1 runs a grid of
scenes/damped_bounce.scn. Rows equal serial runs bit for bit, an invalid value is a failed row with
the builder's message, a worker killed mid-sweep loses no row, and a resumed sweep runs only the
missing tasks."""
import json
import os
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
