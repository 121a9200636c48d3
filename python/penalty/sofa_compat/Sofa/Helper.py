"""Sofa.Helper: the message functions (printed on stderr)."""
import sys


def _message(kind):
    def emit(*args):
        print(f"[{kind}] " + " ".join(str(a) for a in args), file=sys.stderr)
    return emit


msg_info = _message("INFO")
msg_warning = _message("WARNING")
msg_error = _message("ERROR")
msg_deprecated = _message("DEPRECATED")


def __getattr__(name):
    if name.startswith("__"):
        raise AttributeError(name)
    raise NotImplementedError(f"Sofa.Helper.{name} is not supported by penalty's SofaPython3 subset (see docs/python.md)")
