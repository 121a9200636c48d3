"""Sofa.Gui headless: GUIManager as SOFA's batch GUI (penalty/sofa_api/gui.py)."""
from penalty.sofa_api.gui import GUIManager  # noqa: F401
