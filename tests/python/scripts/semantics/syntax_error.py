def createScene(root):
    root.addObject("DefaultAnimationLoop")
      root.addChild("A")
