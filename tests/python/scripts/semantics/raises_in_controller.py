import Sofa


class Broken(Sofa.Core.Controller):
    def __init__(self, *args, **kwargs):
        Sofa.Core.Controller.__init__(self, *args, **kwargs)

    def onAnimateBeginEvent(self, event):
        if self.getContext().getTime() > 0.015:
            raise ValueError("the controller gave up")


def createScene(root):
    root.addObject(Broken(name="broken"))
