"""States whose Data link a TransformEngine's output while a controller writes the engine's inputs
(SOFA's Data links and lazy engine update; docs/python.md, "Data linked to an engine output").
Runs with SOFA HEAD (sofa-head-python) and with penalty (PYTHONPATH with penalty's sofa_compat):
`python3 engine_links.py out.json` writes the positions and velocities after each step."""
import json
import sys

import numpy as np
import Sofa
import Sofa.Core
import Sofa.Simulation

POINTS = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1], [1, 1, 1]]


class Turn(Sofa.Core.Controller):
    """Rotates the free points' engine by 10 degrees about x at every step, and moves the falling
    points' engine up by 0.1 every other step (the steps between leave the solve's positions)."""

    def __init__(self, *args, **kwargs):
        Sofa.Core.Controller.__init__(self, *args, **kwargs)
        self.turn = kwargs["turn"]
        self.lift = kwargs["lift"]
        self.steps = 0

    def onAnimateBeginEvent(self, event):
        self.steps += 1
        self.turn.rotation[0] += 10
        if self.steps % 2 == 1:
            self.lift.translation[1] += 0.1


def createScene(root):
    root.dt = 0.01
    root.gravity = [0, -9.81, 0]
    root.addObject("RequiredPlugin", pluginName=["Sofa.Component.ODESolver.Backward", "Sofa.Component.LinearSolver.Iterative",
                                                 "Sofa.Component.Engine.Transform", "Sofa.Component.Mass",
                                                 "Sofa.Component.StateContainer", "Sofa.Component.Topology.Container.Constant"])
    root.addObject("DefaultAnimationLoop")
    root.addObject("MeshTopology", name="mesh", position=POINTS)
    free = root.addChild("Free")
    turn = free.addObject("TransformEngine", name="turn", input_position="@../mesh.position", rotation=[0, 0, 0])
    free.addObject("MechanicalObject", name="points", position="@turn.output_position")
    falling = root.addChild("Falling")
    falling.addObject("EulerImplicitSolver", rayleighStiffness=0, rayleighMass=0)
    falling.addObject("CGLinearSolver", iterations=10, tolerance=1e-12, threshold=1e-12)
    lift = falling.addObject("TransformEngine", name="lift", input_position="@../mesh.position", translation=[0, 0, 0])
    falling.addObject("MechanicalObject", name="points", position="@lift.output_position")
    falling.addObject("UniformMass", totalMass=1.0)
    root.addObject(Turn(name="controller", turn=turn, lift=lift))


def run(steps=4):
    root = Sofa.Core.Node("root")
    createScene(root)
    Sofa.Simulation.init(root)
    out = {"free": [], "falling": [], "falling_velocity": []}
    for _ in range(steps):
        Sofa.Simulation.animate(root, root.dt.value)
        out["free"].append(np.array(root.Free.points.position.value).tolist())
        out["falling"].append(np.array(root.Falling.points.position.value).tolist())
        out["falling_velocity"].append(np.array(root.Falling.points.velocity.value).tolist())
    # a write between steps, read at once (SOFA's read pulls the engine)
    root.Free.turn.rotation[0] += 5
    out["free_after_write"] = np.array(root.Free.points.position.value).tolist()
    return out


if __name__ == "__main__":
    result = run()
    with open(sys.argv[1], "w") as f:
        json.dump(result, f)
