"""Benchmark (not a test): cost of stepping the shared SOFA scenes from Python vs the C++ command
line. For each scene: the CLI's own wall time of `penalty run --steps N` (loop only, from its
summary), and from Python scene.step(N), and a Python loop of N single steps reading every state's
positions after each (views: no copy).

    PYTHONPATH=build/release/python /usr/bin/python3 bench/python_step_overhead.py \
        build/release/bin/penalty ../shared/sofa [STEPS]
"""
import re
import subprocess
import sys
import time
from pathlib import Path

import penalty

cli, shared = sys.argv[1], Path(sys.argv[2])
steps = int(sys.argv[3]) if len(sys.argv) > 3 else 300


def best_of(n, f):
    return min(f() for _ in range(n))


def cli_seconds(scene):
    out = subprocess.run([cli, "run", str(scene), "--data-dir", str(shared), "--steps", str(steps), "--quiet"],
                         capture_output=True, text=True, check=True).stdout
    return float(re.search(r"in ([0-9.]+) s wall", out).group(1))


def python_seconds(scene, per_step_read):
    s = penalty.load_scene(scene, data_dirs=[shared])
    states = list(s.states)
    t0 = time.perf_counter()
    if per_step_read:
        for _ in range(steps):
            s.step()
            for st in states:
                st.positions
    else:
        s.step(steps)
    return time.perf_counter() - t0


print(f"{'scene':40s} {'CLI s':>8s} {'step(N) s':>10s} {'loop+read s':>12s} {'overhead':>9s}")
for scene in sorted((shared / "scenes").glob("*.scn")):
    c = best_of(3, lambda: cli_seconds(scene))
    p = best_of(3, lambda: python_seconds(scene, False))
    r = best_of(3, lambda: python_seconds(scene, True))
    print(f"{scene.stem:40s} {c:8.3f} {p:10.3f} {r:12.3f} {100 * (p - c) / c:+8.1f}%")
