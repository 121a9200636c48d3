"""Scene.reduction and load_scene(reduction=) (`--reduction`, docs/performance.md "Blocked
reductions"): the CG's dot products in fixed blocks of 4 096 DOFs give the same positions at any
thread count, within rounding of SOFA's single chain, and SOFA's bits for a solver of one block."""
import numpy as np
import pytest

import penalty


def beam(tmp_path, nz):
    """A grid beam of 5 x 5 x nz points on springs, its x = 0 end fixed, under gravity."""
    path = tmp_path / f"beam_{nz}.scn"
    path.write_text(f"""<Node name="root" gravity="0 -9.81 0" dt="0.01"><Node name="beam">
  <EulerImplicitSolver rayleighStiffness="0.1" rayleighMass="0.1"/>
  <CGLinearSolver iterations="40" tolerance="1e-12" threshold="1e-14"/>
  <RegularGridTopology nx="5" ny="5" nz="{nz}" min="0 0 0" max="4 4 {nz - 1}"/>
  <MechanicalObject name="dofs"/><UniformMass totalMass="10"/><RegularGridSpringForceField stiffness="500"/>
  <BoxROI name="end" box="-0.1 -0.1 -0.1 0.1 100 1000"/><FixedProjectiveConstraint indices="@end.indices"/>
</Node></Node>
""")
    return path


def positions(path, steps=3, **options):
    scene = penalty.load_scene(path, **options)
    scene.step(steps)
    return np.array(scene.states["/beam/dofs"].positions, copy=True), scene


def test_blocked_is_the_same_at_any_thread_count_and_near_sofas(tmp_path):
    path = beam(tmp_path, 180)  # 4 500 DOFs: two blocks
    sofa, scene = positions(path)
    assert scene.reduction == "sofa"
    one, scene = positions(path, threads=1, reduction="blocked")
    assert scene.reduction == "blocked"
    two, _ = positions(path, threads=2, reduction="blocked")
    assert np.array_equal(one, two)
    difference = np.abs(one - sofa).max()
    assert 0 < difference < 1e-10


def test_one_block_is_sofas_bits_and_the_setter_takes_effect(tmp_path):
    path = beam(tmp_path, 40)  # 1 000 DOFs: one block
    sofa, _ = positions(path)
    scene = penalty.load_scene(path)
    scene.reduction = "blocked"
    scene.step(3)
    assert np.array_equal(np.asarray(scene.states["/beam/dofs"].positions), sofa)
    with pytest.raises(ValueError, match="reduction: 'fast' is not one of sofa, blocked"):
        scene.reduction = "fast"
