"""The examples in examples/python run and their printed checks hold (pictures in a temp folder)."""
import os
import re
import subprocess
import sys
from pathlib import Path

import penalty

EXAMPLES = Path(__file__).resolve().parents[2] / "examples" / "python"


def run_example(name, tmp_path):
    env = dict(os.environ, PYTHONPATH=str(Path(penalty.__file__).parents[1]))
    r = subprocess.run([sys.executable, str(EXAMPLES / name), str(tmp_path)], capture_output=True, text=True, env=env)
    assert r.returncode == 0, r.stderr
    assert (tmp_path / name.replace(".py", ".png")).stat().st_size > 10000
    return r.stdout


def number(pattern, text):
    return float(re.search(pattern, text).group(1))


def test_restitution_scan_matches_the_spring_dashpot_formula(tmp_path):
    out = run_example("restitution_scan.py", tmp_path)
    assert number(r"largest \|e_sim − e_theory\| = (\S+)", out) < 1e-3


def test_energy_balance_closes(tmp_path):
    out = run_example("energy_balance.py", tmp_path)
    assert number(r"initial energy (\S+) J", out) == 0.981  # m g h = 1 · 9.81 · 0.1
    assert number(r"largest drift (\S+) J", out) < 2e-3       # symplectic Euler, dt = 1e-5 s


def test_contact_force_carries_the_weights(tmp_path):
    out = run_example("contact_force.py", tmp_path)
    assert abs(number(r"last 0.5 s (\S+) N", out) - 1.5 * 9.81) < 0.01 * 1.5 * 9.81


def test_examples_write_into_the_current_folder_by_default(tmp_path):
    """Without an argument the picture goes to ./out (the current folder), never into the source
    tree."""
    env = dict(os.environ, PYTHONPATH=str(Path(penalty.__file__).parents[1]))
    before = {p.name for p in EXAMPLES.iterdir()}
    r = subprocess.run([sys.executable, str(EXAMPLES / "restitution_scan.py")], capture_output=True, text=True,
                       env=env, cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    assert (tmp_path / "out" / "restitution_scan.png").stat().st_size > 10000
    assert str(tmp_path / "out" / "restitution_scan.png") in r.stdout
    assert {p.name for p in EXAMPLES.iterdir()} == before
