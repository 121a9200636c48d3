"""Python values as SOFA's text form, SOFA's text as typed Python values, and the script line of a
call (penalty's SofaPython3, docs/python.md)."""
from __future__ import annotations

import difflib
import math
import numbers
import sys
from pathlib import Path

import numpy as np

#: penalty's own folders: frames there are not the script's.
_OWN_DIRS = (str(Path(__file__).resolve().parent), str(Path(__file__).resolve().parents[1] / "sofa_compat"))


def number_text(x) -> str:
    """The shortest text that reads back as the same number (repr), bools as 1 and 0."""
    if isinstance(x, (bool, np.bool_)):
        return "1" if x else "0"
    if isinstance(x, numbers.Integral):
        return str(int(x))
    x = float(x)
    return repr(x) if math.isfinite(x) else repr(x)


def to_sofa_text(value, what: str) -> str:
    """SOFA's text form of a Python value: numbers, bools ("1"/"0"), strings, links ("@path"),
    objects and nodes (their link), Data (their link), nested lists/tuples/numpy arrays (flattened,
    blank-separated)."""
    link = getattr(value, "getLinkPath", None)
    if isinstance(value, str):
        return value
    if link is not None and not isinstance(value, (list, tuple, np.ndarray)):
        return link()
    if isinstance(value, (bool, np.bool_, numbers.Number)):
        return number_text(value)
    if isinstance(value, np.ndarray):
        return " ".join(number_text(v) for v in value.ravel().tolist())
    if isinstance(value, (list, tuple, range)):
        return " ".join(t for t in (to_sofa_text(v, what) for v in value) if t != "")
    raise TypeError(f"{what}: cannot convert a value of type {type(value).__name__} to a SOFA data value")


def parse_value(text: str, form: str, columns: int = 0):
    """SOFA's text `text` as SofaPython3 presents a Data of Python form `form` ("float", "int",
    "str", "list", "link", "ndarray:<dtype>:<ndim>")."""
    if form in ("str", "link", "none"):
        return text
    if form == "list":
        return text.split()
    words = text.split()
    values = []
    if "int" in form and any("-" in w[1:] for w in words):
        words = _expand_ranges(words)
    for w in words:
        if w in ("true", "True"):
            values.append(1.0)
        elif w in ("false", "False"):
            values.append(0.0)
        else:
            try:
                values.append(float(w))
            except ValueError:
                values = []
                break
    if form == "float":
        return float(values[0]) if values else 0.0
    if form == "int":
        return int(values[0]) if values else 0
    _, dtype, ndim = form.split(":")
    if dtype == "int32":  # SOFA's unsigned values as SofaPython3's int32 (4294967295 reads -1)
        array = np.array([int(v) & 0xFFFFFFFF for v in values], dtype=np.uint32).astype(np.int32)
    else:
        array = np.array(values, dtype=np.float64).astype(dtype)
    if ndim == "2":
        width = columns or max(1, len(values))
        array = array[: len(array) - len(array) % width].reshape(-1, width)
    return array


def _expand_ranges(words):
    """SOFA's index ranges of a vector of integers: "A-B" (down when B < A), "A-B-S" (step S)."""
    out = []
    for w in words:
        parts = w[1:].split("-") if w.startswith("-") else w.split("-")
        if len(parts) < 2 or not all(p.lstrip("+").isdigit() for p in parts[:2]):
            out.append(w)
            continue
        first, last = int(parts[0]), int(parts[1])
        step = int(parts[2]) if len(parts) > 2 and parts[2].lstrip("+-").isdigit() and int(parts[2]) != 0 else (1 if first <= last else -1)
        if (last - first) * step < 0:
            first, last = last, first
        out.extend(str(i) for i in range(first, last + (1 if step > 0 else -1), step))
    return out


def caller_location():
    """File and line of the nearest frame outside penalty's SofaPython3 modules (the script)."""
    frame = sys._getframe(1)
    while frame is not None:
        filename = frame.f_code.co_filename
        if not filename.startswith(_OWN_DIRS):
            return filename, frame.f_lineno
        frame = frame.f_back
    return "<unknown>", 0


def suggestions(name: str, candidates) -> str:
    """` (did you mean 'x' or 'y'?)` for the close matches of `name`, or ""."""
    close = difflib.get_close_matches(name, list(candidates), n=3, cutoff=0.6)
    if not close:
        return ""
    return " (did you mean " + " or ".join(f"'{c}'" for c in close) + "?)"
