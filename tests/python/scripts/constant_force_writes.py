"""A controller writes a ConstantForceField's `indices` and `forces` while the scene runs, with
counts that do not fit each other, for penalty's Sofa modules and for SOFA HEAD's SofaPython3 alike
(docs/python.md, "Writing a Data after init"). SOFA's update callbacks
(ConstantForceField::updateFromIndices, updateFromForcesVector, updateFromTotalForce) run at the
next step: a list of forces that does not number the indices makes the component Invalid (no
force) until a write makes the counts fit again.

Four free particles (no gravity) under `forces`, one per index; the controller writes, at the
AnimateBeginEvent of step:
- 6: `indices` [0, 1] (4 forces for 2 indices: Invalid, the particles coast);
- 11: `forces`, two of them (valid again, on points 0 and 1);
- 16: `indices` [1, 2, 3] (2 forces for 3 indices: Invalid);
- 21: `forces`, one (spread over the 3 indices: valid);
- 26: `forces`, four (4 for 3: Invalid).

`run()` returns the positions after each of the 30 steps and the Data (`indices`, `forces`,
`totalForce`) read after each step; `python3 constant_force_writes.py OUT.json` writes them
(tests/python/scripts/constant_force_writes_sofa_head.json is SOFA HEAD's, through
`sofa-head-python`)."""
import json
import sys

import Sofa
import Sofa.Core
import Sofa.Simulation

STEPS = 30
WRITES = {
    6: ("indices", [0, 1]),
    11: ("forces", [[0.5, -1.0, 0.25], [-0.75, 0.5, 1.0]]),
    16: ("indices", [1, 2, 3]),
    21: ("forces", [[0.1, 0.2, -0.3]]),
    26: ("forces", [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [1.0, 1.0, 1.0]]),
}


class Writer(Sofa.Core.Controller):
    def __init__(self, *args, **kwargs):
        Sofa.Core.Controller.__init__(self, *args, **kwargs)
        self.push = kwargs["push"]
        self.k = 0

    def onAnimateBeginEvent(self, event):
        self.k += 1
        if self.k in WRITES:
            name, value = WRITES[self.k]
            getattr(self.push, name).value = value


def createScene(root):
    root.dt = 0.01
    root.gravity = [0, 0, 0]
    root.addObject("RequiredPlugin", pluginName="Sofa.Component")
    root.addObject("DefaultAnimationLoop")
    node = root.addChild("Particles")
    node.addObject("EulerImplicitSolver", rayleighStiffness=0, rayleighMass=0)
    node.addObject("CGLinearSolver", iterations=40, tolerance=1e-12, threshold=1e-12)
    node.addObject("MechanicalObject", name="dofs", position=[[i, 0, 0] for i in range(4)])
    node.addObject("UniformMass", totalMass=2)
    push = node.addObject("ConstantForceField", name="push", indices=[0, 1, 2, 3],
                          forces=[[1, 0, 0], [0, 1, 0], [0, 0, 1], [1, -1, 0.5]])
    root.addObject(Writer(name="writer", push=push))


def run():
    root = Sofa.Core.Node("root")
    createScene(root)
    Sofa.Simulation.init(root)
    push = root.Particles.push
    out = {"x": [], "indices": [], "forces": [], "totalForce": []}
    for _ in range(STEPS):
        Sofa.Simulation.animate(root, root.dt.value)
        out["x"].append(root.Particles.dofs.position.value.tolist())
        out["indices"].append([int(i) for i in push.indices.value])
        out["forces"].append(push.forces.value.tolist())
        out["totalForce"].append(push.totalForce.value.tolist())
    return out


if __name__ == "__main__":
    json.dump(run(), open(sys.argv[1], "w"))
