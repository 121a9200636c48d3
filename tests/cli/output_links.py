#!/usr/bin/env python3
"""Every output `penalty run` writes replaces a symbolic link at its name instead of writing
through it, and refuses a FIFO there instead of hanging (issue 49, item 1, for the outputs beside
the viewer's): --vtk, --stats, --export-states, --summary-json, --debug-step.

Usage: output_links.py PENALTY_EXECUTABLE WORK_DIR
"""
import os
import shutil
import subprocess
import sys

penalty, work = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)


def check(condition, what):
    if not condition:
        print(f"FAIL: {what}")
        sys.exit(1)
    print(f"ok: {what}")


def run(*args, expect=0):
    p = subprocess.run([penalty, *args], capture_output=True, text=True, timeout=300)
    check(p.returncode == expect, f"penalty {' '.join(args)} -> exit {p.returncode} (expected {expect})\n{p.stdout}{p.stderr}")
    return p


# a first run names the files each output writes
out = os.path.join(work, "out")
outputs = ["--vtk", os.path.join(out, "vtk"), "--stats", os.path.join(out, "stats.csv"),
           "--export-states", os.path.join(out, "states"), "--summary-json", os.path.join(out, "summary.json"),
           "--debug-step", "2", "--debug-file", os.path.join(out, "debug.txt")]
run("run", "--steps", "4", "--quiet", *outputs)
written = [os.path.join(d, f) for d, _, files in os.walk(out) for f in files]
check(len(written) >= 8, f"the outputs wrote {len(written)} files")

# every one of them becomes a link to a precious file outside the output folder
victims = {}
for i, path in enumerate(written):
    victim = os.path.join(work, f"victim-{i}.txt")
    with open(victim, "w") as f:
        f.write(f"precious {i}\n")
    victims[path] = victim
    os.remove(path)
    os.symlink(victim, path)
run("run", "--steps", "4", "--quiet", *outputs)
for path, victim in victims.items():
    check(open(victim).read() == f"precious {os.path.basename(victim)[7:-4]}\n", f"the target of the link {os.path.relpath(path, work)} is untouched")
    check(os.path.isfile(path) and not os.path.islink(path), f"{os.path.relpath(path, work)} is now a regular file")

# a FIFO where the statistics go: refused with the file named (exit 5), no hang
fifo = os.path.join(work, "stats.fifo")
os.mkfifo(fifo)
p = run("run", "--steps", "2", "--quiet", "--stats", fifo, expect=5)
check("stats.fifo" in p.stderr, "a FIFO at --stats is named in the error")
print("all output link checks passed")
