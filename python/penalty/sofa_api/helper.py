"""Sofa.Helper's messages (msg_info, msg_warning, msg_error, msg_deprecated, msg_fatal) and
MessageHandler, as SofaPython3's: `[INFO]    [sender] message` on the console (errors on stderr,
the others on stdout), and every message to the handlers a `with handler:` block installed, as
{"type", "isEmpty", "sender", "message", "component"}."""
from __future__ import annotations

import sys

_LABELS = {"Info": "[INFO]    ", "Warning": "[WARNING] ", "Error": "[ERROR]   ", "Deprecated": "[DEPRECATED] ",
           "Fatal": "[FATAL]   ", "Advice": "[SUGGESTION] "}

#: The handlers of the `with handler:` blocks in force, innermost last.
_handlers: list = []


def emit(kind: str, args, *, console: bool = True):
    """One message of `kind` from SofaPython3's argument forms: (message), (emitter, message),
    (message, file, line), (emitter, message, file, line); the emitter is a name or an object."""
    if len(args) == 1:
        emitter, message = None, args[0]
    elif len(args) == 2:
        emitter, message = args
    elif len(args) == 3:
        emitter, message = None, args[0]
    elif len(args) == 4:
        emitter, message = args[0], args[1]
    else:
        raise TypeError("Invalid arguments type to function.")
    component = None
    if emitter is None:
        sender = label = "PythonScript"
    elif isinstance(emitter, str):
        sender = label = emitter
    elif hasattr(emitter, "getClassName") and hasattr(emitter, "getName"):
        component = emitter
        sender = emitter.getClassName()
        label = f"{sender}({emitter.getName()})"
    else:
        raise TypeError("The first parameter must be a string or a Sofa.Core.Base object")
    message = str(message)
    if console:
        stream = sys.stderr if kind in ("Error", "Fatal") else sys.stdout
        print(f"{_LABELS.get(kind, '')}[{label}] {message}", file=stream)
    record = {"type": kind, "isEmpty": message == "", "sender": sender, "message": message, "component": component}
    for h in list(_handlers):
        h.process(dict(record))


def msg_info(*args):
    emit("Info", args)


def msg_warning(*args):
    emit("Warning", args)


def msg_error(*args):
    emit("Error", args)


def msg_deprecated(*args):
    emit("Deprecated", args)


def msg_fatal(*args):
    emit("Fatal", args)


class MessageHandler:
    """Sofa.Helper.MessageHandler: subclass it with process(msg); `with handler:` routes every
    message to it (the console still prints them)."""

    def __init__(self):
        pass

    def process(self, msg):
        return None

    def __enter__(self):
        _handlers.append(self)
        return self

    def __exit__(self, *exc):
        if self in _handlers:
            _handlers.remove(self)
        return False
