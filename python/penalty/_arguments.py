"""Checks of the public functions' arguments: a TypeError for a value of the wrong kind, a
ValueError for one out of range, each naming the function and the argument (never a message about
a command-line option, never a C++ cast error)."""
from __future__ import annotations

import math
import numbers
import os


def integer(function: str, name: str, value, lo: int, hi: int) -> int:
    """A whole number in [lo, hi] (a bool is not one; 3.0 is not one either)."""
    if isinstance(value, bool) or not isinstance(value, numbers.Integral):
        raise TypeError(f"{function}: {name} must be an integer, not {type(value).__name__} ({value!r})")
    value = int(value)
    if not lo <= value <= hi:
        raise ValueError(f"{function}: {name} = {value} is out of range ({lo} to {hi})")
    return value


def real(function: str, name: str, value, lo: float, hi: float, unit: str = "") -> float:
    """A finite number in [lo, hi]."""
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise TypeError(f"{function}: {name} must be a number, not {type(value).__name__} ({value!r})")
    value = float(value)
    if not (math.isfinite(value) and lo <= value <= hi):
        raise ValueError(f"{function}: {name} = {value!r} is out of range [{lo:g}, {hi:g}]{' ' + unit if unit else ''}")
    return value


def boolean(function: str, name: str, value) -> bool:
    if not isinstance(value, (bool, numbers.Integral)) or value not in (0, 1):
        raise TypeError(f"{function}: {name} must be True or False, not {value!r}")
    return bool(value)


def path(function: str, name: str, value, optional: bool = True):
    """A file or folder name (str or os.PathLike) as str; None passes when optional."""
    if value is None and optional:
        return None
    if not isinstance(value, (str, os.PathLike)):
        raise TypeError(f"{function}: {name} must be a path (str or os.PathLike), not {type(value).__name__}")
    text = os.fspath(value)
    if isinstance(text, bytes) or text == "" or "\0" in text:
        raise ValueError(f"{function}: {name} must be a non-empty path, not {value!r}")
    return text


def paths(function: str, name: str, value) -> list:
    """A list of paths; one path alone is taken as a list of one (a str is not iterated letter by
    letter)."""
    if value is None:
        return []
    if isinstance(value, (str, os.PathLike)):
        value = [value]
    try:
        items = list(value)
    except TypeError:
        raise TypeError(f"{function}: {name} must be a path or a list of paths, not {type(value).__name__}") from None
    return [path(function, f"{name}[{i}]", v, optional=False) for i, v in enumerate(items)]
