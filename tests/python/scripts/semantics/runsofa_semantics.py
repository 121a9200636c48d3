"""Prints what a scene script sees when it is loaded as runSofa loads it (tests/python/test_script_semantics.py)."""
import os
import sys

import Sofa

print("MODULE", __name__, __file__, sys.argv, os.getcwd())


class Where(Sofa.Core.Controller):
    def __init__(self, *args, **kwargs):
        Sofa.Core.Controller.__init__(self, *args, **kwargs)

    def onAnimateBeginEvent(self, event):
        print("STEP", os.getcwd(), sys.argv)


def createScene(root):
    import sibling_helper  # a module beside the script: its folder is on sys.path
    print("CREATE", os.getcwd(), sibling_helper.VALUE, sys.path[0] == "")
    root.addObject("DefaultAnimationLoop")
    root.addObject(Where(name="where"))
