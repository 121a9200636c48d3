"""Engines whose input is a state's moving positions (docs/python.md, "Engines over moving
states"), for penalty's Sofa modules and for SOFA HEAD's SofaPython3 alike:

- `box`: a BoxROI over `@dofs.position` feeds a FixedProjectiveConstraint: the points that fall
  into the box stop accelerating, then leave it and fall again;
- `copy`: a free MechanicalObject whose position links a TransformEngine over the falling beam's
  positions;
- `lowest`: a Python DataEngine whose input is the falling beam's positions, read by a controller
  at each AnimateEndEvent (its update count: once per step, at the read).

`run()` returns what each records every 10 steps over 60 steps; `python3 moving_engines.py OUT.json`
writes it (tests/python/scripts/moving_engines_sofa_head.json is SOFA HEAD's, through
`sofa-head-python`)."""
import json
import sys

import numpy as np

import Sofa
import Sofa.Core
import Sofa.Simulation

STEPS = 60
EVERY = 10


class Lowest(Sofa.Core.DataEngine):
    """The lowest height of the points."""

    def __init__(self, *args, **kwargs):
        Sofa.Core.DataEngine.__init__(self, *args, **kwargs)
        self.addData(name="points", value=kwargs["points"], type="vector<Vec3d>", help="input")
        self.addData(name="lowest", value=0.0, type="double", help="output")
        self.counter = 0

    def init(self):
        self.addInput(self.points)
        self.addOutput(self.lowest)

    def update(self):
        self.counter += 1
        self.lowest = float(np.min(np.asarray(self.points.value)[:, 1]))


class Reader(Sofa.Core.Controller):
    def __init__(self, *args, **kwargs):
        Sofa.Core.Controller.__init__(self, *args, **kwargs)
        self.engine = kwargs["engine"]
        self.rows = []

    def onAnimateEndEvent(self, event):
        self.rows.append([self.engine.lowest.value, self.engine.counter])


def beam(node, fixed=None):
    node.addObject("EulerImplicitSolver", rayleighStiffness=0.1, rayleighMass=0.1)
    node.addObject("CGLinearSolver", iterations=40, tolerance=1e-12, threshold=1e-12)
    node.addObject("RegularGridTopology", name="grid", nx=5, ny=2, nz=2, xmin=0, xmax=2, ymin=0, ymax=0.5,
                   zmin=0, zmax=0.5)
    dofs = node.addObject("MechanicalObject", name="dofs")
    node.addObject("UniformMass", totalMass=1)
    node.addObject("MeshSpringForceField", stiffness=200, damping=0.1)
    if fixed is not None:
        node.addObject("FixedProjectiveConstraint", indices=fixed)
    return dofs


def createScene(root):
    root.dt = 0.01
    root.gravity = [0, -9.81, 0]
    root.addObject("RequiredPlugin", pluginName="Sofa.Component")
    root.addObject("DefaultAnimationLoop")
    box = root.addChild("Box")
    beam(box)
    box.addObject("BoxROI", name="box", box=[-0.1, -0.6, -0.1, 1.1, -0.2, 0.6], position="@dofs.position")
    box.addObject("FixedProjectiveConstraint", name="fix", indices="@box.indices")
    image = root.addChild("Beam")
    dofs = beam(image, fixed=[0, 10])
    image.addObject("TransformEngine", name="transform", input_position="@dofs.position", translation=[3, 0, 0],
                    rotation=[0, 0, 30], scale=[1, 2, 1])
    copy = root.addChild("Copy")
    copy.addObject("MechanicalObject", name="copy", position="@../Beam/transform.output_position")
    engine = image.addObject(Lowest(name="lowest", points=dofs.position))
    root.addObject(Reader(name="reader", engine=engine))


def run():
    root = Sofa.Core.Node("root")
    createScene(root)
    Sofa.Simulation.init(root)
    out = {"box": [], "box_indices": [], "copy": []}
    for step in range(1, STEPS + 1):
        Sofa.Simulation.animate(root, root.dt.value)
        if step % EVERY == 0:
            out["box"].append(root.Box.dofs.position.value.tolist())
            out["box_indices"].append([int(i) for i in root.Box.box.indices.value])
            out["copy"].append(root.Copy.copy.position.value.tolist())
    out["lowest"] = root.reader.rows
    return out


if __name__ == "__main__":
    json.dump(run(), open(sys.argv[1], "w"))
