import Sofa.Core


def createScene(rootNode):
    rootNode.addObject("DefaultAnimationLoop")
    node = rootNode.addChild("Body")
    node.addObject("MechanicalObject", position=[0, 0, 0])
    node.addObject("UniformMass", name="mass", totalMass="abc")  # line 8: not a number
