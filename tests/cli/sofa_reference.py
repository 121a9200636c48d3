#!/usr/bin/env python3
"""SOFA's regression reference of CompositeCollisionPipeline_none.scn (200 steps), reproduced.

Usage: sofa_reference.py PENALTY_EXECUTABLE SOFA_DIR WORK_DIR
The scene and the reference are SOFA's files (../shared/sofa, never committed): without them the
test prints why and exits 77, which CTest reports as skipped.
"""
import os
import re
import subprocess
import sys

penalty, sofa, work = sys.argv[1:4]
scene = os.path.join(sofa, "scenes", "CompositeCollisionPipeline_none.scn")
reference = os.path.join(sofa, "reference")
if not os.path.isfile(scene) or not os.path.isdir(reference):
    print(f"SKIPPED: SOFA's scene and reference are not here ({scene})")
    sys.exit(77)
p = subprocess.run([penalty, "run", scene, "--steps", "200", "--quiet", "--data-dir", sofa, "--export-states", work,
                    "--reference", reference], capture_output=True, text=True, timeout=600)
print(p.stdout, p.stderr)
m = re.search(r"mean error ([0-9.e+-]+) .*(PASS|FAIL)", p.stdout)
if p.returncode != 0 or m is None or m.group(2) != "PASS" or not float(m.group(1)) <= 1e-4:
    print(f"FAIL: exit {p.returncode}")
    sys.exit(1)
print(f"PASS: mean error {m.group(1)} (SOFA's criterion: <= 1e-4)")
