"""`python3 -m penalty run|info SCENE [options]`: the command line's `run` and `info` through the
module, for `.scn` files and SofaPython3 `.py` scripts. `penalty run scene.py` (the C++ command
line) hands `.py` scenes to this (see docs/python.md). Same options, output and exit codes as the
C++ command line: 0 success, 1 invalid scene or input, 2 command-line error, 3 diverged, 5 other.
"""
from __future__ import annotations

import argparse
import math
import os
import shlex
import sys

import penalty


def _parser():
    p = argparse.ArgumentParser(prog="penalty", description="penalty: run SOFA scenes (.scn or SofaPython3 .py)")
    p.add_argument("--version", action="version", version=f"penalty {penalty.__version__}")
    sub = p.add_subparsers(dest="command", required=True)
    run = sub.add_parser("run", help="Run a scene headless")
    run.add_argument("scene")
    run.add_argument("--steps", type=int, default=100, help="Number of time steps (default 100)")
    run.add_argument("--dt", type=float, default=None, help="Time step (s), overrides the scene's")
    run.add_argument("--threads", type=int, default=None,
                     help="Threads for the detection, the contacts' response and independent solvers (default: all cores)")
    run.add_argument("--argv", action="append", default=[], metavar="ARG",
                     help="An argument of a SofaPython3 script: its sys.argv[1:] (repeatable; runSofa's --argv)")
    run.add_argument("--data-dir", action="append", default=[], help="Folder searched for mesh and included files (repeatable)")
    run.add_argument("--set", action="append", default=[], dest="overrides", metavar="PATH.attribute=value",
                     help="Override an attribute before the scene is built (repeatable; docs/sweeps.md)")
    run.add_argument("--vtk", default=None)
    run.add_argument("--vtk-every", type=int, default=1)
    run.add_argument("--export-states", default=None)
    run.add_argument("--export-mapped", action="store_true")
    run.add_argument("--export-every", type=int, default=1)
    run.add_argument("--stats", default=None)
    run.add_argument("--summary-json", default=None, metavar="FILE",
                     help="Write the run's summary to FILE as JSON (what Scene.run returns, without history)")
    run.add_argument("--exhaustive", action="store_true")
    run.add_argument("--fix-sofa-quirk", action="append", default=[], dest="fix_sofa_quirks", metavar="NAME",
                     help="Fix a SOFA quirk penalty reproduces by default (repeatable, 'all'; "
                          "docs/sofa-compatibility.md)")
    run.add_argument("--quiet", action="store_true")
    run.add_argument("--no-tunnelling", default=None, choices=["off", "warn", "substep", "stiffen"],
                     help="Tunnelling guard (docs/no-tunnelling.md); default: the scene's noTunnelling")
    run.add_argument("--divergence-factor", type=float, default=100.0,
                     help="Diverged when a step moves a DOF by more than F times the scene size (default 100; 0: off)")
    script = sub.add_parser("script", help="Run a SofaPython3 script as __main__ (its own main block), with "
                                           "Sofa, Sofa.Core, Sofa.Simulation and SofaRuntime importable")
    script.add_argument("scene")
    script.add_argument("arguments", nargs=argparse.REMAINDER)
    sw = sub.add_parser("sweep", help="Run a scene once per override set, on Dask (docs/sweeps.md)")
    sw.add_argument("scene")
    sw.add_argument("--grid", action="append", default=[], metavar="PATH.attribute=v1,v2,...",
                    help="Values of one attribute (repeatable: the Cartesian product of all --grid)")
    sw.add_argument("--set", action="append", default=[], dest="overrides", metavar="PATH.attribute=value",
                    help="An override of every task (repeatable)")
    sw.add_argument("--steps", type=int, default=100, help="Steps per task (default 100)")
    sw.add_argument("--out", required=True, help="Output folder: results.csv, rows/, trajectories/ (resumes)")
    sw.add_argument("--scheduler", default=None, help="Dask scheduler address (default: a LocalCluster here)")
    sw.add_argument("--workers", type=int, default=None, help="LocalCluster worker processes (default: the cores)")
    sw.add_argument("--save-every", type=int, default=None, metavar="K",
                    help="Write each task's states every K steps and its contacts to an HDF5 file")
    sw.add_argument("--data-dir", action="append", default=[])
    sw.add_argument("--dt", type=float, default=None)
    sw.add_argument("--divergence-factor", type=float, default=100.0)
    sw.add_argument("--retries", type=int, default=2, help=_retries_help())
    sw.add_argument("--no-resume", action="store_true", help="Run every task, even those with rows in --out")
    sw.add_argument("--quiet", action="store_true")
    info = sub.add_parser("info", help="Build a scene and describe it")
    info.add_argument("scene")
    info.add_argument("--data-dir", action="append", default=[])
    info.add_argument("--contact-advice", action="store_true", help="docs/no-tunnelling.md, \"Advice\"")
    info.add_argument("--impact-speed", type=float, default=None)
    return p


def _retries_help() -> str:
    from .sweeps import RETRIES_HELP
    return RETRIES_HELP.replace("%", "%%")


def main(argv=None) -> int:
    parser = _parser()
    try:
        args = parser.parse_args(argv)
    except SystemExit as e:
        return 0 if e.code == 0 else 2
    if args.command == "run":
        # The same limits as the C++ command line (docs/reliability.md).
        max_threads = penalty._core.max_threads  # penalty::kMaxThreads, as the C++ command line
        problems = []
        if not 0 <= args.steps <= 1_000_000_000:
            problems.append(f"--steps: {args.steps} is out of range (0 to 1000000000)")
        if args.dt is not None and not (math.isfinite(args.dt) and penalty.MIN_DT <= args.dt <= penalty.MAX_DT):
            problems.append(f"--dt: '{args.dt}' is out of range [1e-100, 86400]")
        if args.threads is not None and not 1 <= args.threads <= max_threads:
            problems.append(f"--threads: {args.threads} is out of range (1 to {max_threads})")
        for name, value in (("--vtk-every", args.vtk_every), ("--export-every", args.export_every)):
            if not 1 <= value <= 1_000_000_000:
                problems.append(f"{name}: {value} is out of range (1 to 1000000000)")
        if not (math.isfinite(args.divergence_factor) and args.divergence_factor >= 0):
            problems.append(f"--divergence-factor: '{args.divergence_factor}' is out of range [0, 1e100]")
        known_quirks = penalty._core._sofa_quirk_names()
        for name in getattr(args, "fix_sofa_quirks", []):
            if name not in known_quirks:
                problems.append(f"--fix-sofa-quirk: unknown SOFA quirk '{name}' ({', '.join(known_quirks)})")
        for o in args.overrides:
            try:
                penalty._core._check_override(o)
            except ValueError as e:
                problems.append(str(e))
        if problems:
            for p in problems:
                print(f"penalty: error: {p}", file=sys.stderr)
            print("Run 'penalty --help' or 'penalty run --help' for the options.", file=sys.stderr)
            return 2
    if args.command == "sweep":
        return _sweep_command(args, argv)
    if args.command == "script":
        import runpy
        penalty._install_sofa_path()
        sys.argv = [args.scene, *args.arguments]
        sys.path.insert(0, os.path.dirname(os.path.abspath(args.scene)))
        runpy.run_path(args.scene, run_name="__main__")
        return 0
    from .sofa_api.cli import run_or_info
    return run_or_info(args)


def _sweep_command(args, argv=None) -> int:
    """`penalty sweep`: exit 0 when every task ran (even when some rows failed: they are results),
    1 for an invalid scene path or grid, 2 for a command-line error, 5 when the sweep itself
    failed (e.g. no scheduler at the address)."""
    from . import sweeps
    problems = []
    if not os.path.isfile(args.scene):
        problems.append(f"scene '{args.scene}' not found")
    if not 0 <= args.steps <= 1_000_000_000:
        problems.append(f"--steps: {args.steps} is out of range (0 to 1000000000)")
    if args.workers is not None and not 1 <= args.workers <= 1024:
        problems.append(f"--workers: {args.workers} is out of range (1 to 1024)")
    if args.save_every is not None and args.save_every < 1:
        problems.append(f"--save-every: {args.save_every} is out of range (1 to 1000000000)")
    if args.workers is not None and args.scheduler is not None:
        problems.append("--workers starts a LocalCluster: not with --scheduler (start workers on the cluster)")
    grid = {}
    for g in args.grid:
        try:
            key, values = sweeps.parse_grid_option(g)
            penalty._core._check_override(f"{key}={values[0]}")
            grid[key] = values
        except ValueError as e:
            problems.append(str(e))
    fixed = {}
    for o in args.overrides:
        try:
            path_, attribute, value = penalty._core._check_override(o)
            fixed[o.split("=", 1)[0]] = value
        except ValueError as e:
            problems.append(str(e))
    if problems:
        for p in problems:
            print(f"penalty: error: {p}", file=sys.stderr)
        return 2
    sets = sweeps.expand_grid(grid) if grid else [{}]
    sets = [{**fixed, **s} for s in sets]
    if not 0 <= args.retries <= 100:
        print(f"penalty: error: --retries: {args.retries} is out of range (0 to 100)", file=sys.stderr)
        return 2
    print(f"penalty sweep: {args.scene}, {len(sets)} task(s) of {args.steps} steps, "
          + (f"scheduler {args.scheduler}" if args.scheduler else f"LocalCluster of {args.workers or os.cpu_count()} workers")
          + f", results in {args.out}", flush=True)
    try:
        df = sweeps.sweep(args.scene, sets, args.steps, out=args.out, save=args.save_every, client=args.scheduler,
                          workers=args.workers, data_dirs=args.data_dir, dt=args.dt,
                          divergence_factor=args.divergence_factor, retries=args.retries,
                          resume=not args.no_resume, progress=False if args.quiet else None)
    except KeyboardInterrupt:
        # Ctrl-C: the rows of the tasks that completed are in OUT/rows; the same command resumes.
        done = len(list(os.scandir(os.path.join(args.out, "rows")))) if os.path.isdir(os.path.join(args.out, "rows")) else 0
        command = shlex.join(["penalty", *(sys.argv[1:] if argv is None else argv)])
        print(f"\npenalty sweep: interrupted; {done} completed row(s) kept in {os.path.join(args.out, 'rows')}.\n"
              f"Resume (completed tasks are not run again) with:\n  {command}", file=sys.stderr)
        return 130
    except sweeps.OutputFolderError as e:
        print(f"penalty: error: {e.strerror}", file=sys.stderr)
        return 5
    except (ValueError, FileNotFoundError) as e:
        print(f"penalty: error: {e}", file=sys.stderr)
        return 1
    except Exception as e:  # noqa: BLE001 - e.g. no scheduler at the address
        print(f"penalty: error: sweep failed: {type(e).__name__}: {e}", file=sys.stderr)
        return 5
    print(sweeps.summary_table(df))
    resumed = int(df["resumed"].sum()) if "resumed" in df else 0
    print(f"results: {os.path.join(args.out, 'results.csv')}" + (f" ({resumed} row(s) from an earlier run)" if resumed else ""))
    return 0


if __name__ == "__main__":
    sys.exit(main())
