"""ValuesFromPositions over a falling beam, read through SofaPython3's Data at each step, for
penalty's Sofa modules and for SOFA HEAD's SofaPython3 alike (docs/python.md, "Engines over moving
states"). The scene is a `.scn` file (written next to the output) whose root node gives a fixed
`bbox`: a scalar field over several values is interpolated over the bounding box's x extent
(ValuesFromPositions::doUpdate), which SOFA takes as parsed (Node::parse: bboxIsFixed).

- `vfp`: a scalar field over the beam's moving positions (`position="@dofs.position"`), along a
  direction that is not an axis (the engine runs again when the points move);
- `still`: the same over the rest positions (the default input): it runs once;
- `vec`: a vector field (one vector per point and element).

`run(folder)` returns the Data read after init and after steps 1, 10, 20, 30 and 40; `python3
values_from_positions.py OUT.json` writes them (tests/python/scripts/values_from_positions_sofa_head.json
is SOFA HEAD's, through `sofa-head-python`)."""
import json
import os
import sys
import tempfile

import Sofa
import Sofa.Core
import Sofa.Simulation

SCENE = """<Node name="root" dt="0.01" gravity="0 -9.81 0" bbox="-1 -2 -3 4 5 6">
  <RequiredPlugin pluginName="Sofa.Component"/>
  <DefaultAnimationLoop/>
  <Node name="Beam">
    <EulerImplicitSolver rayleighStiffness="0.1" rayleighMass="0.1"/>
    <CGLinearSolver iterations="40" tolerance="1e-12" threshold="1e-12"/>
    <RegularGridTopology name="grid" nx="5" ny="2" nz="2" xmin="0" xmax="2" ymin="0" ymax="0.5" zmin="0" zmax="0.5"/>
    <MechanicalObject name="dofs"/>
    <UniformMass totalMass="1"/>
    <MeshSpringForceField stiffness="200" damping="0.1"/>
    <BoxROI name="box" box="-0.1 -0.1 -0.1 0.1 0.6 0.6"/>
    <FixedProjectiveConstraint indices="@box.indices"/>
    <ValuesFromPositions name="vfp" inputValues="1 3 2 7" direction="0.3 1 0.2" position="@dofs.position"/>
    <ValuesFromPositions name="still" inputValues="1 3 2 7" direction="1 0 0"/>
    <ValuesFromPositions name="vec" fieldType="Vector" direction="1 1 0" position="@dofs.position"/>
  </Node>
</Node>
"""
READ_AFTER = (0, 1, 10, 20, 30, 40)
OUTPUTS = {"vfp": ("values", "edgeValues"), "still": ("values",), "vec": ("pointVectors", "edgeVectors")}


def run(folder=None):
    folder = folder or tempfile.mkdtemp()
    path = os.path.join(folder, "values_from_positions.scn")
    with open(path, "w") as f:
        f.write(SCENE)
    root = Sofa.Simulation.load(path)
    Sofa.Simulation.init(root)
    out = []
    for step in range(max(READ_AFTER) + 1):
        if step in READ_AFTER:
            row = {"x": root.Beam.dofs.position.value.tolist()}
            for engine, names in OUTPUTS.items():
                for name in names:
                    row[f"{engine}.{name}"] = getattr(getattr(root.Beam, engine), name).value.tolist()
            out.append(row)
        Sofa.Simulation.animate(root, root.dt.value)
    return out


if __name__ == "__main__":
    json.dump(run(), open(sys.argv[1], "w"))
