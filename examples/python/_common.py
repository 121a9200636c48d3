"""Shared bits of the examples: where the pictures go, and a non-interactive matplotlib."""
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")  # write files, no window


def output_dir() -> Path:
    """The folder given as first argument, else `out/` in the current folder (never the source
    tree: the examples may be run from an installed or read-only copy)."""
    out = Path(sys.argv[1]) if len(sys.argv) > 1 else Path.cwd() / "out"
    out.mkdir(parents=True, exist_ok=True)
    return out
