"""ParallelHexahedronFEMForceField (SOFA's MultiThreading plugin, SofaPython3's taskScheduler.py) is
HexahedronFEMForceField computed in parallel: penalty builds the same force field, so the two give
the same trajectory bit for bit (docs/sofa-compatibility.md)."""
import numpy as np

import penalty

SCENE = """<Node name="root" dt="0.01" gravity="0 -9.81 0">
  <DefaultAnimationLoop/>
  <EulerImplicitSolver rayleighStiffness="0.1" rayleighMass="0.1"/>
  <CGLinearSolver iterations="25" tolerance="1e-9" threshold="1e-9"/>
  <MechanicalObject name="dofs"/>
  <UniformMass vertexMass="1"/>
  <RegularGridTopology nx="3" ny="3" nz="5" xmin="-1" xmax="1" ymin="-1" ymax="1" zmin="0" zmax="4"/>
  <BoxROI name="box" box="-1 -1 0 1 1 0.0001"/>
  <FixedProjectiveConstraint indices="@box.indices"/>
  <{fem} youngModulus="{young}" poissonRatio="0.4" method="large"/>
</Node>
"""


def positions(tmp_path, fem, young="4000"):
    path = tmp_path / f"{fem}{young}.scn"
    path.write_text(SCENE.format(fem=fem, young=young))
    scene = penalty.load_scene(path)
    scene.step(5)
    return scene.states["dofs"].positions.copy()


def test_parallel_hexahedron_fem_is_hexahedron_fem(tmp_path):
    parallel = positions(tmp_path, "ParallelHexahedronFEMForceField")
    serial = positions(tmp_path, "HexahedronFEMForceField")
    assert np.array_equal(parallel, serial)
    assert not np.array_equal(positions(tmp_path, "HexahedronFEMForceField", "8000"), serial)  # the FEM acts
