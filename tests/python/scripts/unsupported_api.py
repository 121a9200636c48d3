import Sofa.Core


def createScene(rootNode):
    rootNode.addObject(Sofa.Core.ForceFieldVec3d)
