#!/usr/bin/python3
"""Runs SofaPython3 scripts with penalty and with SOFA HEAD, and prints a table (docs/python.md,
"SofaPython3's examples"):
  - `penalty run SCRIPT --steps N` (exit code, the error's first line);
  - `python3 SCRIPT` with penalty's Sofa modules (scripts with a main block; Sofa.Gui's MainLoop
    runs PENALTY_GUI_ITERATIONS=N steps);
  - SOFA's criterion against SOFA HEAD (`../shared/sofa-head/sofa-head SCRIPT N OUT --every 1`):
    mean over the exported states of sum over the steps of sum_i |x_i - x_SOFA,i| / values / DOFs
    (<= 1e-4 passes), and the largest |x - x_SOFA|.

usage: scripts/sofapython3-examples.py [SCRIPT ...] [--steps N] [--penalty EXE] [--no-sofa]
Default scripts: SofaPython3's examples (/work/sp3-src/examples or SOFAPYTHON3_EXAMPLES) and SOFA's
examples/Benchmark/Performance scripts (/work/sofa-src/examples/Benchmark/Performance or
SOFA_BENCHMARKS). Data files: ../shared/sofa (mesh/).
"""
import argparse
import glob
import os
import subprocess
import sys
import tempfile

REPO = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
SHARED = os.path.normpath(os.path.join(REPO, "..", "shared"))
SOFA_HEAD = os.path.join(SHARED, "sofa-head", "sofa-head")
SOFA_CRITERION = 1e-4


def read_states(path):
    frames = []
    t = None
    with open(path) as f:
        for line in f:
            w = line.split()
            if not w:
                continue
            if w[0] == "T=":
                t = float(w[1])
            elif w[0] == "X=" and t is not None:
                frames.append((t, [float(v) for v in w[1:]]))
    return frames


def compare(sofa_dir, penalty_dir):
    """(criterion, largest difference, note) between the state files of two folders."""
    refs = sorted(glob.glob(os.path.join(sofa_dir, "*_mstate.txt")), key=lambda p: int(os.path.basename(p).split("_")[0]))
    if not refs:
        return None, None, "SOFA exports no state"
    criterion, largest = 0.0, 0.0
    for ref in refs:
        k = os.path.basename(ref).split("_")[0]
        ours = glob.glob(os.path.join(penalty_dir, f"{k}_*_mstate.txt"))
        if not ours:
            return float("inf"), None, f"state {k} not exported by penalty"
        theirs = read_states(ref)
        mine = {round(t, 9): x for t, x in read_states(ours[0])}
        err = 0.0
        for t, xr in theirs:
            xo = mine.get(round(t, 9))
            if xo is None or len(xo) != len(xr):
                return float("inf"), None, f"state {k}: no frame at t = {t:g}"
            d = [abs(a - b) for a, b in zip(xr, xo)]
            largest = max(largest, max(d) if d else 0.0)
            ndof = len(xr) // (7 if len(xr) % 7 == 0 and len(xr) % 3 else 3)
            err += sum(d) / max(len(xr), 1) / max(ndof, 1)
        criterion += err / max(len(theirs), 1)
    return criterion / len(refs), largest, ""


def last_line(text):
    lines = [l for l in text.strip().splitlines() if l.strip()]
    return lines[-1][:160] if lines else ""


def run(cmd, env=None, cwd=None, timeout=600):
    try:
        r = subprocess.run(cmd, capture_output=True, text=True, env=env, cwd=cwd, timeout=timeout)
        return r.returncode, r.stdout, r.stderr
    except subprocess.TimeoutExpired:
        return None, "", "timed out"


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("scripts", nargs="*")
    p.add_argument("--steps", type=int, default=20)
    p.add_argument("--penalty", default=os.path.join(REPO, "build", "release", "bin", "penalty"))
    p.add_argument("--no-sofa", action="store_true")
    args = p.parse_args()
    args.penalty = os.path.abspath(args.penalty)
    scripts = [os.path.abspath(s) for s in args.scripts]
    if not scripts:
        examples = os.environ.get("SOFAPYTHON3_EXAMPLES", "/work/sp3-src/examples")
        benchmarks = os.environ.get("SOFA_BENCHMARKS", "/work/sofa-src/examples/Benchmark/Performance")
        scripts = sorted(glob.glob(os.path.join(examples, "**", "*.py"), recursive=True))
        scripts += sorted(glob.glob(os.path.join(benchmarks, "*.py")))
    python_path = os.pathsep.join([os.path.join(REPO, "build", "release", "python", "penalty", "sofa_compat"),
                                   os.path.join(REPO, "build", "release", "python")])
    env = dict(os.environ, PYTHONPATH=python_path, PENALTY_GUI_ITERATIONS=str(args.steps), MPLBACKEND="Agg",
               PENALTY_DATA_PATH=os.path.join(SHARED, "sofa"))
    print("| script | `penalty run` | `python3 script.py` | SOFA's criterion (largest \\|dx\\|) |")
    print("| --- | --- | --- | --- |")
    for script in scripts:
        name = os.path.relpath(script, os.path.dirname(os.path.dirname(script)))
        with tempfile.TemporaryDirectory() as tmp:
            ours = os.path.join(tmp, "penalty")
            code, out, err = run([args.penalty, "run", script, "--steps", str(args.steps + 1), "--quiet",
                                  "--data-dir", os.path.join(SHARED, "sofa"), "--export-states", ours,
                                  "--export-every", "1"], cwd=tmp)
            run_cell = "exit 0" if code == 0 else f"exit {code}: {last_line(err or out)}"
            source = open(script, encoding="utf-8", errors="replace").read()
            if "__main__" in source:
                pcode, pout, perr = run([sys.executable, script], env=env, cwd=os.path.dirname(script), timeout=300)
                py_cell = "exit 0" if pcode == 0 else f"exit {pcode}: {last_line(perr or pout)}"
            else:
                py_cell = "(no main block)"
            sofa_cell = ""
            if not args.no_sofa and code == 0 and os.path.exists(SOFA_HEAD):
                theirs = os.path.join(tmp, "sofa")
                scode, sout, serr = run([SOFA_HEAD, script, str(args.steps), theirs, "--every", "1"],
                                        env=dict(os.environ, PYTHONIOENCODING="utf-8"), cwd=tmp)
                if scode != 0:
                    sofa_cell = f"SOFA fails: {last_line(serr or sout)}"
                else:
                    crit, largest, note = compare(theirs, ours)
                    if crit is None:
                        sofa_cell = note
                    else:
                        verdict = "yes" if crit <= SOFA_CRITERION else "no"
                        sofa_cell = f"{verdict}: {crit:.3g} ({largest:.3g})" + (f" {note}" if note else "")
            print(f"| {name} | {run_cell} | {py_cell} | {sofa_cell} |", flush=True)


if __name__ == "__main__":
    main()
