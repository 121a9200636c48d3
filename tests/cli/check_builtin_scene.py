#!/usr/bin/env python3
"""The built-in scene (`penalty run` without a scene, what scripts/run.sh runs) settles: every
contact holds once the bodies are at rest, and no contact is much deeper than the others.

Usage: check_builtin_scene.py PENALTY_EXECUTABLE WORK_DIR

Per-step statistics (--stats) of the 400 steps: from t = 0.75 s on, the number of contacts never
changes (a contact that comes and goes makes the plots jagged) and the deepest contact stays
under 0.5 mm (the springs' ks is 5000 N/m for every pair: the cube's bottom points carry about
0.6 N each, the ball's four points about 1.2 N each along a slanted normal); over the whole run,
the ball's impact included, under 5 mm. Before the scene was fixed, the ball hung on one cube point
at a time (MinProximity: one contact per sphere) with a rest length beyond the alarm distance
(SOFA HEAD counts a rigid sphere's radius twice): 25 and 26 contacts alternated and one contact
reached 83 mm.
"""
import csv
import os
import shutil
import subprocess
import sys

penalty, work = sys.argv[1], sys.argv[2]
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)
stats = os.path.join(work, "stats.csv")
p = subprocess.run([penalty, "run", "--quiet", "--stats", stats], capture_output=True, text=True, timeout=600)
if p.returncode != 0:
    print(f"FAIL: penalty run (built-in scene): exit {p.returncode}\n{p.stdout}{p.stderr}")
    sys.exit(1)
with open(stats) as f:
    rows = list(csv.DictReader(f))
failures = []
if len(rows) != 400:
    failures.append(f"{len(rows)} rows, expected 400")
settled = [r for r in rows if float(r["time"]) >= 0.75]
counts = sorted({int(r["contacts"]) for r in settled})
if len(counts) != 1:
    failures.append(f"the contact count changes after t = 0.75 s: {counts}")
deepest_settled = max(float(r["max_penetration"]) for r in settled)
deepest = max(float(r["max_penetration"]) for r in rows)
if not deepest_settled < 5e-4:
    failures.append(f"deepest contact after t = 0.75 s: {deepest_settled} m, expected under 0.5 mm")
if not deepest < 5e-3:
    failures.append(f"deepest contact of the run: {deepest} m, expected under 5 mm")
print(f"contacts after t = 0.75 s: {counts}; deepest contact {deepest_settled:.3g} m at rest, {deepest:.3g} m over the run")
if failures:
    print("FAIL: " + "; ".join(failures))
    sys.exit(1)
print("built-in scene checks passed")
