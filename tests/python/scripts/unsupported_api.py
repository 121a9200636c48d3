import Sofa.Core


def createScene(rootNode):
    rootNode.addObject(Sofa.Core.Mapping_Vec1d_Vec1d(name="loss"))
