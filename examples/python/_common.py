"""Shared bits of the examples: where the pictures go, and a non-interactive matplotlib."""
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")  # write files, no window


def output_dir() -> Path:
    """The folder given as first argument, else examples/python/out."""
    out = Path(sys.argv[1]) if len(sys.argv) > 1 else Path(__file__).resolve().parent / "out"
    out.mkdir(parents=True, exist_ok=True)
    return out
