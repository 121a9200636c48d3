"""Sofa.constants: Key (the characters of SOFA's key events) and KeyCode (their codes)."""
from . import Key, KeyCode  # noqa: F401
