"""`python3 -m penalty run|info SCENE` (and `penalty run scene.py`, which hands SofaPython3 scripts
to it): the run, and how a script's own end or error is reported (docs/python.md, "Running a
script"). Exit codes as the C++ command line: 0 success, 1 invalid scene or input (a script's
error, with its file and line), 3 diverged, 5 other; a script's sys.exit(n) ends with n, said as
the script's own exit."""
from __future__ import annotations

import json
import os
import sys
import traceback

import penalty

from .script import ScriptExit, script_frame


def _exit_status(code) -> int:
    """Python's status of sys.exit(code): None 0, an int itself (modulo 256), else 1 (the code is
    printed)."""
    if code is None:
        return 0
    if isinstance(code, int):
        return code % 256
    print(code, file=sys.stderr)
    return 1


def _script_location(error, script):
    where = script_frame(error.__traceback__, os.path.abspath(script)) if script.endswith(".py") else None
    return f"{where[0]}:{where[1]}" if where else None


def run_or_info(args) -> int:
    scene = None
    try:
        if args.command == "info":
            scene = penalty.load_scene(args.scene, data_dirs=args.data_dir)
            if getattr(args, "contact_advice", False):
                print(scene._scene._contact_advice_text(args.impact_speed), end="")
                return 0
            print(scene.info()["text"], end="")
            return 0
        scene = penalty.load_scene(args.scene, data_dirs=args.data_dir, dt=args.dt, threads=args.threads or 0,
                                   exhaustive=args.exhaustive, overrides=args.overrides, argv=args.argv,
                                   no_tunnelling=getattr(args, "no_tunnelling", None),
                                   fix_sofa_quirks=getattr(args, "fix_sofa_quirks", ()))
        print(f"penalty run: {args.scene}")
        info = scene.info()
        print(f"{len(scene.states)} states, {sum(1 for c in info['components'] if c['type'].endswith('CollisionModel'))}"
              f" collision models, {len(info['pipelines'])} collision pipeline(s)")
        for w in scene.warnings():
            print(f"note: {w}")
        summary = scene.run(args.steps, vtk=args.vtk, vtk_every=args.vtk_every, export_states=args.export_states,
                            divergence_factor=args.divergence_factor, export_mapped=args.export_mapped,
                            export_every=args.export_every, stats=args.stats, progress=False if args.quiet else None)
        print(summary["text"], end="")
        if args.export_states:
            print(f"states: {len(summary['state_files'])} files in {args.export_states}")
        if args.vtk:
            print(f"vtk: series in {args.vtk} (open the .pvd files in ParaView)")
        if args.stats:
            print(f"stats: {args.stats}")
        if getattr(args, "summary_json", None):
            try:
                with open(args.summary_json, "w") as f:
                    json.dump({k: v for k, v in summary.items() if k != "history"}, f, indent=2)
            except OSError as e:
                print(f"penalty: error: cannot write '{args.summary_json}': {e.strerror or e}", file=sys.stderr)
                return 5
            print(f"summary: {args.summary_json}")
        return 0
    except BrokenPipeError:  # output piped into e.g. `head`: stop quietly, as the C++ command line
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 0
    except ScriptExit as e:
        print(f"penalty: the script ended with sys.exit({e.code!r}) {e.where} ({e.location}): no scene was run",
              file=sys.stderr)
        return _exit_status(e.code)
    except SystemExit as e:  # sys.exit in a controller, during the run
        where = _script_location(e, args.scene) or args.scene
        done = f" after {round(scene.time / scene.dt)} steps (t = {scene.time:g} s)" if scene is not None else ""
        print(f"penalty: the script ended the run with sys.exit({e.code!r}) at {where}{done}; the outputs hold "
              "the steps before it", file=sys.stderr)
        return _exit_status(e.code)
    except penalty.SceneError as e:
        print(f"penalty: error: {e}", file=sys.stderr)
        return 1
    except penalty.DivergedError as e:
        print(f"penalty: error: {e}", file=sys.stderr)
        return 3
    except KeyboardInterrupt:
        print("penalty: interrupted", file=sys.stderr)
        return 130
    except Exception as e:  # noqa: BLE001 - a script's error (exit 1, its file and line), or another
        where = _script_location(e, args.scene)
        if where is not None:
            traceback.print_exc()
            print(f"penalty: error: {where}: {type(e).__name__}: {e}", file=sys.stderr)
            return 1
        if isinstance(e, OSError):  # an output that cannot be written (the C++ writers raise RuntimeError)
            print(f"penalty: error: {e}", file=sys.stderr)
            return 5
        if isinstance(e, (ValueError, TypeError, NotImplementedError, AttributeError, ImportError)):
            print(f"penalty: error: {type(e).__name__}: {e}" if not isinstance(e, ValueError) else f"penalty: error: {e}",
                  file=sys.stderr)
            return 1
        traceback.print_exc()
        print(f"penalty: error: {type(e).__name__}: {e}", file=sys.stderr)
        return 5
