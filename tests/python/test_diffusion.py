"""Heat diffusion on a Vec1d state (docs/components/diffusion.md): TetrahedronDiffusionFEMForceField
with MeshMatrixMass<Vec1d,Vec3d> under a first-order implicit Euler, equal to SOFA HEAD's
temperatures to the bit."""
import importlib.util
import json
import os

import numpy as np

import penalty

penalty._install_sofa_path()
import Sofa  # noqa: E402  (penalty's)
import Sofa.Core  # noqa: E402
import Sofa.Simulation  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))


def bar():
    spec = importlib.util.spec_from_file_location("diffusion_bar", os.path.join(HERE, "scripts", "diffusion_bar.py"))
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    root = Sofa.Core.Node("root")
    module.createScene(root)
    Sofa.Simulation.init(root)
    return root


def test_temperatures_equal_sofa_heads():
    ref = json.load(open(os.path.join(HERE, "scripts", "diffusion_bar_sofa_head.json")))["temperatures"]
    root = bar()
    temperatures = root.Bar.Heat.T.position
    assert temperatures.value.shape == (16, 1)  # SofaPython3's Vec1d: one column
    for step, expected in enumerate(ref, start=1):
        Sofa.Simulation.animate(root, root.dt.value)
        assert np.array_equal(temperatures.value.ravel(), np.array(expected)), step


def test_the_heat_spreads_from_the_held_end_and_the_mass_is_the_bars_volume():
    root = bar()
    # ρ·V (the grid's points carry single-precision steps, as SOFA's: 0.2 → 0.2000000030)
    assert abs(root.Bar.Heat.MeshMatrixMass.assembleMMatrix().sum() - 1.0 * 0.2 * 0.2) < 1e-8
    for _ in range(5):
        Sofa.Simulation.animate(root, root.dt.value)
    t = root.Bar.Heat.T.position.value.ravel()
    x = root.Bar.geometry.position.value[:, 0]
    assert t[0] == 1.0  # held
    held_face, far_face = t[(x == 0) & (t < 1.0)], t[x == x.max()]
    assert held_face.mean() > 0.1 > abs(far_face.mean())  # warm beside the held point, not yet at the far end
