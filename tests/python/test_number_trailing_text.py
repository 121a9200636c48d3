"""SOFA's Data<T>::read ignores the text after a number (`tolerance="10-3"` reads 10, SofaPython3's
emptyForceField.py): penalty reads the same by default with a warning, and the SOFA quirk fix
`number_trailing_text` makes it an error (docs/sofa-compatibility.md, "SOFA quirk switches")."""
import numpy as np
import pytest

import penalty

SCENE = """<Node name="root" dt="0.01" gravity="0 -9.81 0">
  <DefaultAnimationLoop/>
  <Node name="Body">
    <EulerImplicitSolver rayleighStiffness="0.1" rayleighMass="0.1"/>
    <CGLinearSolver iterations="{iterations}" tolerance="{tolerance}" threshold="1e-9"/>
    <RegularGridTopology nx="2" ny="2" nz="3" xmin="0" xmax="1" ymin="0" ymax="1" zmin="0" zmax="2"/>
    <MechanicalObject name="dofs"/>
    <UniformMass totalMass="{mass}"/>
    <FixedProjectiveConstraint indices="0 1 2 3"/>
    <HexahedronFEMForceField youngModulus="300" poissonRatio="0.3"/>
  </Node>
</Node>
"""


def run(tmp_path, name, steps=5, **values):
    text = dict(iterations="25", tolerance="1e-9", mass="1")
    text.update(values)
    path = tmp_path / f"{name}.scn"
    path.write_text(SCENE.format(**text))
    return path


def positions(path, steps=5, **kwargs):
    scene = penalty.load_scene(path, **kwargs)
    scene.step(steps)
    return scene, scene.states["dofs"].positions.copy()


def test_a_number_followed_by_text_reads_as_its_number_with_a_warning(tmp_path):
    quirky, x_quirky = positions(run(tmp_path, "quirky", mass="2-3", tolerance="1e-9abc"))
    _, x_plain = positions(run(tmp_path, "plain", mass="2", tolerance="1e-9"))
    assert np.array_equal(x_quirky, x_plain)  # bit for bit: 2 and 1e-9 were read
    notes = [w for w in quirky.warnings() if "SOFA's Data<T>::read" in w]
    assert len(notes) == 2, quirky.warnings()
    assert any("quirky.scn:8: UniformMass" in n and "attribute 'totalMass' = '2-3' read as 2," in n for n in notes)
    assert "attribute 'tolerance' = '1e-9abc' read as 1e-9" in " ".join(notes)
    _, x_other = positions(run(tmp_path, "other", mass="3"))
    assert not np.array_equal(x_other, x_plain)  # the mass changes the trajectory: the test can fail


def test_the_fix_makes_it_an_error_and_unreadable_numbers_stay_errors(tmp_path):
    with pytest.raises(penalty.SceneError, match=r"attribute 'totalMass': expected a number, found '2-3'"):
        penalty.load_scene(run(tmp_path, "fixed", mass="2-3"), fix_sofa_quirks=["number_trailing_text"])
    # no number at its start, or an exponent without digits (istream's read fails): errors as before
    for text in ("abc", "1e-x", "-"):
        with pytest.raises(penalty.SceneError, match="expected a number"):
            penalty.load_scene(run(tmp_path, "bad", mass=text))
    with pytest.raises(ValueError, match="unknown SOFA quirk 'nope'"):
        penalty.load_scene(run(tmp_path, "plain"), fix_sofa_quirks=["nope"])


def test_a_script_gets_the_same_read(tmp_path):
    script = tmp_path / "solver.py"
    script.write_text(
        "def createScene(root):\n"
        "    root.dt = 0.01\n"
        "    root.addObject('DefaultAnimationLoop')\n"
        "    body = root.addChild('Body')\n"
        "    body.addObject('EulerImplicitSolver')\n"
        "    body.addObject('CGLinearSolver', iterations=25, tolerance='10-3', threshold=1e-9)\n"
        "    body.addObject('MechanicalObject', name='dofs', position=[0, 0, 0])\n"
        "    body.addObject('UniformMass', totalMass=1)\n")
    scene = penalty.load_scene(script)
    assert any("attribute 'tolerance' = '10-3' read as 10" in w for w in scene.warnings())
    with pytest.raises(penalty.SceneError, match="expected a number, found '10-3'"):
        penalty.load_scene(script, fix_sofa_quirks=["number_trailing_text"])


def test_the_command_line_switch_reaches_a_script(tmp_path):
    import os
    import subprocess
    import sys
    script = tmp_path / "solver.py"
    script.write_text(
        "def createScene(root):\n"
        "    root.addObject('DefaultAnimationLoop')\n"
        "    root.addObject('EulerImplicitSolver')\n"
        "    root.addObject('CGLinearSolver', iterations=25, tolerance='10-3', threshold=1e-9)\n"
        "    root.addObject('MechanicalObject', position=[0, 0, 0])\n"
        "    root.addObject('UniformMass', totalMass=1)\n")
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(p for p in sys.path if p))

    def run(*extra):
        return subprocess.run([sys.executable, "-m", "penalty", "run", str(script), "--steps", "1", "--quiet", *extra],
                              capture_output=True, text=True, env=env, timeout=60)
    assert run().returncode == 0
    fixed = run("--fix-sofa-quirk", "number_trailing_text")
    assert fixed.returncode == 1 and "expected a number, found '10-3'" in fixed.stderr
    unknown = run("--fix-sofa-quirk", "nope")
    assert unknown.returncode == 2 and "unknown SOFA quirk 'nope'" in unknown.stderr
