"""A controller writes a BoxROI's `box` (or `orientedBox`) at each AnimateBeginEvent, the way SOFA
users move a box (docs/python.md, "Engines over moving states"), for penalty's Sofa modules and for
SOFA HEAD's SofaPython3 alike. A falling beam's points in the box are fixed:

- `box`: the box goes down 0.02 a step;
- `inverted`: the same box written with its corners swapped: SOFA's BoxROI orders the corners in
  roiInit only (init), so the written box selects nothing;
- `oriented`: an oriented box going down: SOFA computes the oriented boxes in roiInit only, so the
  box of init stays the one tested.

`run(mode)` returns the positions and the indices every 10 steps over 60 steps; `python3
box_writes.py OUT.json` writes the three (tests/python/scripts/box_writes_sofa_head.json is SOFA
HEAD's, through `sofa-head-python`)."""
import json
import sys

import Sofa
import Sofa.Core
import Sofa.Simulation

STEPS = 60


class Mover(Sofa.Core.Controller):
    def __init__(self, *args, **kwargs):
        Sofa.Core.Controller.__init__(self, *args, **kwargs)
        self.roi = kwargs["roi"]
        self.mode = kwargs["mode"]
        self.k = 0

    def onAnimateBeginEvent(self, event):
        self.k += 1
        y = -0.02 * self.k
        if self.mode == "box":
            self.roi.box.value = [[-0.1, y - 0.1, -0.1, 1.1, y + 0.1, 0.6]]
        elif self.mode == "inverted":
            self.roi.box.value = [[1.1, y + 0.1, 0.6, -0.1, y - 0.1, -0.1]]
        elif self.mode == "oriented":
            self.roi.orientedBox.value = [[-0.1, y - 0.1, -0.1, 1.1, y - 0.1, -0.1, 1.1, y + 0.1, -0.1, 0.7]]


def createScene(root, mode):
    root.dt = 0.01
    root.gravity = [0, -9.81, 0]
    root.addObject("RequiredPlugin", pluginName="Sofa.Component")
    root.addObject("DefaultAnimationLoop")
    node = root.addChild("Beam")
    node.addObject("EulerImplicitSolver", rayleighStiffness=0.1, rayleighMass=0.1)
    node.addObject("CGLinearSolver", iterations=40, tolerance=1e-12, threshold=1e-12)
    node.addObject("RegularGridTopology", name="grid", nx=5, ny=2, nz=2, xmin=0, xmax=2, ymin=0, ymax=0.5,
                   zmin=0, zmax=0.5)
    node.addObject("MechanicalObject", name="dofs")
    node.addObject("UniformMass", totalMass=1)
    node.addObject("MeshSpringForceField", stiffness=200, damping=0.1)
    if mode == "oriented":
        roi = node.addObject("BoxROI", name="box", orientedBox=[-0.1, -0.1, -0.1, 1.1, -0.1, -0.1, 1.1, 0.1, -0.1, 0.7],
                             position="@dofs.position")
    else:
        roi = node.addObject("BoxROI", name="box", box=[-0.1, -0.1, -0.1, 1.1, 0.1, 0.6], position="@dofs.position")
    node.addObject("FixedProjectiveConstraint", name="fix", indices="@box.indices")
    root.addObject(Mover(name="mover", roi=roi, mode=mode))


def run(mode, init=Sofa.Simulation.init):
    root = Sofa.Core.Node("root")
    createScene(root, mode)
    init(root)
    out = {"x": [], "indices": []}
    for step in range(1, STEPS + 1):
        Sofa.Simulation.animate(root, root.dt.value)
        if step % 10 == 0:
            out["x"].append(root.Beam.dofs.position.value.tolist())
            out["indices"].append([int(i) for i in root.Beam.box.indices.value])
    return out


if __name__ == "__main__":
    json.dump({mode: run(mode) for mode in ("box", "inverted", "oriented")}, open(sys.argv[1], "w"))
