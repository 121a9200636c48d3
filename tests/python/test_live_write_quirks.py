"""SOFA HEAD's quirks of Data written after init, reproduced by default, each with its switch
(docs/python.md, "Writing a Data after init"; docs/sofa-compatibility.md):

- uniform_mass_lazy_write: UniformMass takes a written totalMass / vertexMass in its update
  callback, which runs at the first isComponentStateValid() of the next step: after addForce (the
  weight keeps vertexMass's value), before addMDx / addMToMatrix / accFromF; the callback
  recomputes from the Data init used.
- mesh_spring_stiffness_write: MeshSpringForceField's `stiffness` / `damping` after init are
  SpringForceField's per-spring lists: every spring takes the written value (not value / rest
  length).

Expected values come from these rules in closed form (one implicit or explicit Euler step of free
particles or of one spring), not from penalty."""
import numpy as np
import pytest

from penalty import sofa_api

G = -9.81
DT = 0.01


def particles(mass_attribute, solver="implicit", fixes=()):
    """Three free particles under gravity (0, G, 0), no force field."""
    root = sofa_api.Node("root")
    root.gravity = [0, G, 0]
    root.dt = DT
    root.addObject("DefaultAnimationLoop")
    n = root.addChild("P")
    if solver == "implicit":
        n.addObject("EulerImplicitSolver", name="ode", rayleighStiffness=0, rayleighMass=0)
        n.addObject("CGLinearSolver", iterations=10, tolerance=1e-20, threshold=1e-20)
    else:
        n.addObject("EulerExplicitSolver", name="ode")
    n.addObject("MechanicalObject", name="mo", position=[[0, 0, 0], [1, 0, 0], [2, 0, 0]])
    n.addObject("UniformMass", name="mass", **mass_attribute)
    sofa_api.init(root, build_options=([], None, 0, False, [], list(fixes)))
    return root


def step(root):
    sofa_api.animate(root, DT)
    return root.P.mo.velocity.value[:, 1].copy()


@pytest.mark.parametrize("solver", ["implicit", "explicit"])
def test_total_mass_write_weighs_the_first_step_with_the_old_mass(solver):
    root = particles(dict(totalMass=3.0), solver)  # 1 kg a particle
    root.P.mass.totalMass.value = 9.0               # 3 kg a particle
    assert root.P.mass.vertexMass.value == 1.0      # SOFA's vertexMass Data: updated lazily
    # step 1: dv = dt·(m_old·g)/m_new; then dv = dt·g
    np.testing.assert_allclose(step(root), DT * G * 1.0 / 3.0, rtol=1e-14)
    assert root.P.mass.vertexMass.value == 3.0
    np.testing.assert_allclose(step(root), DT * G * (1.0 / 3.0 + 1.0), rtol=1e-14)


def test_total_mass_write_with_the_quirk_fixed_is_a_fresh_scene():
    root = particles(dict(totalMass=3.0), fixes=["uniform_mass_lazy_write"])
    root.P.mass.totalMass.value = 9.0
    assert root.P.mass.vertexMass.value == 3.0
    np.testing.assert_allclose(step(root), DT * G, rtol=1e-14)


def test_vertex_mass_write_when_init_used_total_mass_lasts_one_weight():
    """updateFromTotalMass sets vertexMass back to totalMass / n at the first mass use."""
    root = particles(dict(totalMass=3.0))
    root.P.mass.vertexMass.value = 2.0
    np.testing.assert_allclose(step(root), DT * G * 2.0, rtol=1e-14)  # weight 2 kg, mass 1 kg
    assert root.P.mass.vertexMass.value == 1.0
    np.testing.assert_allclose(step(root), DT * G * 3.0, rtol=1e-14)


def test_total_mass_write_when_init_used_vertex_mass_is_dropped():
    """updateFromVertexMass sets totalMass back to vertexMass · n."""
    root = particles(dict(vertexMass=1.0))
    root.P.mass.totalMass.value = 9.0
    np.testing.assert_allclose(step(root), DT * G, rtol=1e-14)
    assert root.P.mass.totalMass.value == 3.0


def spring(stiffness=10.0, damping=0.0, fixes=()):
    """Point 0 fixed, point 1 free on the x axis; one edge of rest length 2: MeshSpringForceField
    gives it ks = stiffness / 2, kd = damping / 2. Explicit Euler, no gravity."""
    root = sofa_api.Node("root")
    root.gravity = [0, 0, 0]
    root.dt = DT
    root.addObject("DefaultAnimationLoop")
    n = root.addChild("S")
    n.addObject("EulerExplicitSolver", name="ode")
    n.addObject("MeshTopology", name="mesh", position=[[0, 0, 0], [2, 0, 0]], edges=[0, 1])
    n.addObject("MechanicalObject", name="mo")
    n.addObject("UniformMass", vertexMass=1.0)
    n.addObject("FixedProjectiveConstraint", indices=[0])
    n.addObject("MeshSpringForceField", name="ff", stiffness=stiffness, damping=damping)
    sofa_api.init(root, build_options=([], None, 0, False, [], list(fixes)))
    with root.S.mo.position.writeableArray() as x:
        x[1] = [3, 0, 0]  # stretched by 1
    return root


def spring_velocity_after_a_step(root):
    sofa_api.animate(root, DT)
    return root.S.mo.velocity.value[1, 0]


def test_mesh_spring_stiffness_write_gives_every_spring_the_value():
    root = spring()
    np.testing.assert_allclose(spring_velocity_after_a_step(spring()), -DT * 5.0, rtol=1e-14)  # ks = 10 / 2
    root.S.ff.stiffness.value = 40.0
    assert np.atleast_1d(root.S.ff.stiffness.value).tolist() == [40.0]
    # f = -ks·(d - L) = -40: the written value, not 40 / L
    np.testing.assert_allclose(spring_velocity_after_a_step(root), -DT * 40.0, rtol=1e-14)
    fixed = spring(fixes=["mesh_spring_stiffness_write"])
    fixed.S.ff.stiffness.value = 40.0
    np.testing.assert_allclose(spring_velocity_after_a_step(fixed), -DT * 20.0, rtol=1e-14)


def test_mesh_spring_damping_write_gives_every_spring_the_value():
    root = spring(damping=2.0)
    with root.S.mo.position.writeableArray() as x:
        x[1] = [2, 0, 0]  # at rest length: only damping acts
    with root.S.mo.velocity.writeableArray() as v:
        v[1] = [1, 0, 0]
    root.S.ff.damping.value = [6.0]
    # f = -kd·(v1 - v0)·u = -6 (not 6 / L = 3); ks stays 10 / 2 (no stretch)
    np.testing.assert_allclose(spring_velocity_after_a_step(root), 1.0 - DT * 6.0, rtol=1e-14)


def test_spring_write_survives_a_later_rebuild():
    root = spring()
    root.S.ff.stiffness.value = 40.0
    root.S.ode.symplectic.value = True  # another write: the scene is built again
    np.testing.assert_allclose(spring_velocity_after_a_step(root), -DT * 40.0, rtol=1e-14)
