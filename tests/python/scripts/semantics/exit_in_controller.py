"""A controller that ends the run with sys.exit(CODE) at its second step (CODE: --argv, default 3)."""
import sys

import Sofa


class Stop(Sofa.Core.Controller):
    def __init__(self, *args, **kwargs):
        Sofa.Core.Controller.__init__(self, *args, **kwargs)
        self.steps = 0

    def onAnimateEndEvent(self, event):
        self.steps += 1
        if self.steps == 2:
            sys.exit(int(sys.argv[1]) if len(sys.argv) > 1 else 3)


def createScene(root):
    body = root.addChild("Body")
    body.addObject("EulerImplicitSolver")
    body.addObject("CGLinearSolver", iterations=25, tolerance=1e-9, threshold=1e-9)
    body.addObject("MechanicalObject", name="dofs", position=[0, 1, 0])
    body.addObject("UniformMass", totalMass=1)
    root.addObject(Stop(name="stop"))
