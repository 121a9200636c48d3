"""Sofa.Gui headless, as SOFA's batch GUI (sofa::gui::batch::BatchGUI): GUIManager.MainLoop(root)
runs the simulation for BatchGUI's default 1000 iterations (PENALTY_GUI_ITERATIONS sets another
count) and, when PENALTY_VIEW names a folder, writes penalty's browser viewer of the run there
(`penalty view FOLDER` serves it)."""
from __future__ import annotations

import os
import sys
import time

from .helper import msg_info

#: BatchGUI::DEFAULT_NUMBER_OF_ITERATIONS.
DEFAULT_ITERATIONS = 1000


class GUIManager:
    _gui = "batch"
    _root = None

    @staticmethod
    def Init(program_name="", gui_name=""):  # noqa: N802 - SofaPython3's names
        if gui_name and gui_name != "batch":
            print(f"[INFO]    [penalty] the '{gui_name}' GUI is not available headless: MainLoop runs the "
                  "simulation as SOFA's batch GUI", file=sys.stderr)
        GUIManager._gui = "batch"
        return 0

    @staticmethod
    def ListSupportedGUI(separator=" "):  # noqa: N802
        return "batch"

    @staticmethod
    def GetGUIName():  # noqa: N802
        return GUIManager._gui

    @staticmethod
    def createGUI(root, filename=""):  # noqa: N802
        GUIManager._root = root
        return 0

    @staticmethod
    def SetDimension(width, height):  # noqa: N802
        return None

    @staticmethod
    def SetFullScreen():  # noqa: N802
        return None

    @staticmethod
    def SaveScreenshot(filename):  # noqa: N802
        raise RuntimeError("Sofa.Gui.GUIManager.SaveScreenshot: penalty renders no screen (PENALTY_VIEW writes "
                           "the browser viewer of a run)")

    @staticmethod
    def MainLoop(root=None, filename=""):  # noqa: N802
        root = root if root is not None else GUIManager._root
        if root is None:
            return 0
        scene = getattr(root, "_penalty_scene", None)
        if scene is None:
            from .simulation import init
            init(root)
            scene = root._penalty_scene
        steps = int(os.environ.get("PENALTY_GUI_ITERATIONS", DEFAULT_ITERATIONS))
        msg_info("BatchGUI", f"Computing {steps} iterations.")
        start = time.perf_counter()
        view = os.environ.get("PENALTY_VIEW")
        if view:
            scene.run(steps, view=view, progress=False)
            print(f"[INFO]    [penalty] the run's browser viewer is in {view} (penalty view {view})")
        else:
            for _ in range(steps):
                scene._step_once(None)
        elapsed = max(time.perf_counter() - start, 1e-12)
        msg_info("BatchGUI", f"{steps} iterations done in {elapsed:g} s ( {steps / elapsed:g} FPS).")
        return 0

    @staticmethod
    def closeGUI():  # noqa: N802
        GUIManager._root = None
        return None
