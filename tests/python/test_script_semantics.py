"""Running a scene script as runSofa does (SofaPython3's SceneLoaderPY3, checked with SOFA HEAD):
from its folder with it on sys.path, __name__ its file name, sys.argv = [name, --argv...]; and the
script's own end or error reported as such (`penalty run`): a SyntaxError is exit 1 naming file
and line, sys.exit(n) is the script's exit n with a message, not a divergence, an exception in a
controller is exit 1 with the script's traceback, file and line."""
import os
import subprocess
import sys
from pathlib import Path

import pytest

import penalty

HERE = Path(__file__).resolve().parent
SCRIPTS = HERE / "scripts" / "semantics"
REPO = HERE.parents[1]


def penalty_run(*args, cli=True):
    exe = os.environ.get("PENALTY_CLI", str(REPO / "build" / "release" / "bin" / "penalty"))
    env = dict(os.environ, PYTHONPATH=str(Path(penalty.__file__).parents[1]))
    if cli and not Path(exe).exists():
        pytest.skip("penalty command line not built")
    command = [exe, "run", *args] if cli else [sys.executable, "-m", "penalty", "run", *args]
    return subprocess.run(command, capture_output=True, text=True, env=env, cwd=str(REPO))


@pytest.mark.parametrize("cli", [True, False])
def test_the_script_runs_from_its_folder_as_runsofa(cli):
    script = SCRIPTS / "runsofa_semantics.py"
    r = penalty_run(str(script.relative_to(REPO)), "--steps", "1", "--quiet", "--argv", "a1", "--argv", "a2", cli=cli)
    assert r.returncode == 0, r.stderr
    lines = {l.split()[0]: l for l in r.stdout.splitlines() if l.split() and l.split()[0] in ("MODULE", "CREATE", "STEP")}
    # as SOFA HEAD: module named after the file, absolute __file__, argv from --argv, the script's
    # folder as working directory while it is imported and createScene runs, then back
    assert lines["MODULE"] == f"MODULE runsofa_semantics {script} ['runsofa_semantics', 'a1', 'a2'] {SCRIPTS}"
    assert lines["CREATE"] == f"CREATE {SCRIPTS} sibling imported True"
    assert lines["STEP"] == f"STEP {REPO} ['runsofa_semantics', 'a1', 'a2']"


def test_a_syntax_error_is_exit_1_naming_the_file_and_line():
    r = penalty_run(str(SCRIPTS / "syntax_error.py"), "--steps", "1")
    assert r.returncode == 1
    assert f"{SCRIPTS / 'syntax_error.py'}:3: IndentationError: unexpected indent" in r.stderr


def test_sys_exit_in_create_scene_is_the_scripts_own_exit():
    r = penalty_run(str(SCRIPTS / "exit_in_create_scene.py"), "--steps", "5")
    assert r.returncode == 0
    assert (f"the script ended with sys.exit(0) in createScene ({SCRIPTS / 'exit_in_create_scene.py'}:6): "
            "no scene was run") in r.stderr


@pytest.mark.parametrize("code", [None, "0", "7"])
def test_sys_exit_in_a_controller_is_the_scripts_own_exit_not_a_divergence(code):
    args = ["--argv", code] if code else []
    r = penalty_run(str(SCRIPTS / "exit_in_controller.py"), "--steps", "10", "--quiet", *args)
    expected = int(code) if code else 3
    assert r.returncode == expected
    assert "diverged" not in r.stderr.lower()
    assert (f"the script ended the run with sys.exit({expected}) at {SCRIPTS / 'exit_in_controller.py'}:15 "
            "after 2 steps (t = 0.02 s)") in r.stderr


def test_an_exception_in_a_controller_is_exit_1_with_the_scripts_traceback():
    r = penalty_run(str(SCRIPTS / "raises_in_controller.py"), "--steps", "10", "--quiet")
    assert r.returncode == 1
    assert "Traceback" in r.stderr and "raises_in_controller.py\", line 10, in onAnimateBeginEvent" in r.stderr
    assert f"penalty: error: {SCRIPTS / 'raises_in_controller.py'}:10: ValueError: the controller gave up" in r.stderr


@pytest.mark.parametrize("cli", [True, False])
def test_threads_0_is_refused_for_scripts_as_for_scn_files(cli):
    r = penalty_run(str(SCRIPTS / "raises_in_controller.py"), "--threads", "0", cli=cli)
    assert r.returncode == 2
    assert "--threads: 0 is out of range (1 to" in r.stderr


def test_constraint_based_contact_fails_with_one_clear_line(tmp_path):
    script = tmp_path / "constraints.py"
    script.write_text("def createScene(root):\n    root.addObject('FreeMotionAnimationLoop')\n")
    r = penalty_run(str(script), "--steps", "1")
    assert r.returncode == 1
    errors = [l for l in r.stderr.splitlines() if l.strip()]
    assert errors == [f"penalty: error: {script}:2: FreeMotionAnimationLoop: SOFA's constraint-based contact "
                      "(Lagrange multipliers) is not part of penalty, which reproduces SOFA's penalty contact "
                      "(DefaultAnimationLoop, CollisionResponse response=\"PenalityContactForceField\")"]
