#!/usr/bin/python3
"""Benchmark (not a test) of penalty.sweep on this machine: tasks per second with 1 and 2 (or
--workers) LocalCluster workers, against the same tasks in a plain loop in this process, and the
cost of starting the cluster. docs/sweeps.md quotes its output.

    PYTHONPATH=build/release/python /usr/bin/python3 bench/sweep_scaling.py [--tasks 16] [--steps 20000]

The tasks are scenes/damped_bounce.scn with 16 contact stiffnesses (no files written). The
overhead per task is (sweep time with 1 worker - loop time) / tasks: Dask's scheduling, the
transfer of the spec and row, and the worker's import of penalty amortised over the tasks.
"""
import argparse
import os
import time
from pathlib import Path

import distributed

import penalty
from penalty import sweeps

SCENE = Path(__file__).resolve().parents[1] / "scenes" / "damped_bounce.scn"
KEY = "/BallB/ball_b_point.contactStiffness"


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--tasks", type=int, default=16)
    p.add_argument("--steps", type=int, default=20000)
    p.add_argument("--workers", type=int, nargs="*", default=[1, 2])
    a = p.parse_args()
    grid = {KEY: [10 + i for i in range(a.tasks)]}
    print(f"{a.tasks} tasks of {a.steps} steps of {SCENE.name}, {os.cpu_count()} cores")

    # Plain loop: the same task function in this process (load, run, metrics), no Dask.
    specs = []
    for i, s in enumerate(sweeps.expand_grid(grid)):
        specs.append({"scene": str(SCENE), "scene_sha256": "", "overrides": s, "steps": a.steps, "dt": None,
                      "data_dirs": [], "threads": 1, "save": None, "save_contacts": False,
                      "divergence_factor": 100.0, "out": None, "metrics": [], "index": i, "task": f"t{i}"})
    start = time.perf_counter()
    rows = [sweeps.run_task(s) for s in specs]
    loop = time.perf_counter() - start
    assert all(r["status"] == "ok" for r in rows)
    print(f"plain loop:  {loop:6.2f} s  {a.tasks / loop:6.2f} tasks/s")

    for n in a.workers:
        start = time.perf_counter()
        cluster = sweeps.local_cluster(n)
        client = distributed.Client(cluster)
        client.run(lambda: __import__("penalty"))  # workers import penalty once
        startup = time.perf_counter() - start
        start = time.perf_counter()
        df = penalty.sweep(SCENE, grid, a.steps, client=client, progress=False)
        wall = time.perf_counter() - start
        client.close()
        cluster.close()
        assert (df["status"] == "ok").all()
        assert list(df["digest"]) == [r["digest"] for r in rows], "sweep rows differ from the loop"
        line = f"{n} worker(s): {wall:6.2f} s  {a.tasks / wall:6.2f} tasks/s  (cluster start {startup:.2f} s)"
        if n == 1:
            line += f"  overhead {1000 * (wall - loop) / a.tasks:.1f} ms/task"
        print(line, flush=True)


if __name__ == "__main__":
    main()
