import sys


def createScene(root):
    root.addObject("DefaultAnimationLoop")
    sys.exit(0)
