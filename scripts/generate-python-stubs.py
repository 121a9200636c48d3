#!/usr/bin/python3
"""Writes the type stubs of the compiled module, python/penalty/_core.pyi, from the signatures
pybind11 puts in its docstrings (no stub generator is packaged in Debian 12).

    scripts/generate-python-stubs.py [--check] [--module-dir build/release/python]

--check: exit 1 when the committed stubs differ from the module's (tests/python/test_stubs.py).
The stubs cover the module's functions, classes (methods, properties, constants) and the
`collision` submodule (as a class of static methods: a single-file stub cannot hold a submodule).
"""
import argparse
import importlib
import pathlib
import re
import sys

root = pathlib.Path(__file__).resolve().parent.parent
HEADER = '"""Type stubs of penalty._core (scripts/generate-python-stubs.py writes them; do not edit)."""\n'

# pybind11's spelling -> typing's
REWRITES = [
    (r"numpy\.ndarray\[[^\]]*\]", "numpy.typing.NDArray[typing.Any]"),
    (r"\bpenalty\._core\.collision\.", ""),
    (r"\bpenalty\._core\.", ""),
    (r"\bList\[", "list["),
    (r"\bDict\[", "dict["),
    (r"\bTuple\[", "tuple["),
    (r"\bOptional\[", "typing.Optional["),
    (r"\bCallable\[", "typing.Callable["),
    (r"\bUnion\[", "typing.Union["),
    (r"\bhandle\b", "typing.Any"),
    (r"\bobject\b", "typing.Any"),
    (r"\bos\.PathLike\b", "os.PathLike[str]"),
]


def typed(text):
    for pattern, replacement in REWRITES:
        text = re.sub(pattern, replacement, text)
    return text


def signatures(name, doc):
    """The signature lines `name(...) -> T` of a pybind11 docstring (several when overloaded)."""
    found = re.findall(r"^(?:\d+\. )?" + re.escape(name) + r"(\(.*\)(?: -> .*)?)$", doc or "", re.M)
    return [typed(s) for s in found]


def defaults_fixed(params):
    # pybind11 prints defaults by repr: values that are not Python literals become `...`
    return re.sub(r"= <[^>]*>", "= ...", re.sub(r"= \[\]", "= ...", params))


def function_lines(name, doc, indent, decorator=None):
    sigs = signatures(name, doc)
    if not sigs:
        return [f"{indent}def {name}(*args: typing.Any, **kwargs: typing.Any) -> typing.Any: ..."]
    out = []
    for s in sigs:
        if len(sigs) > 1:
            out.append(f"{indent}@typing.overload")
        if decorator:
            out.append(f"{indent}{decorator}")
        s = defaults_fixed(s)
        if " -> " not in s:
            s += " -> typing.Any"
        out.append(f"{indent}def {name}{s}: ...")
    return out


def class_lines(name, cls, indent=""):
    base = "Exception" if isinstance(cls, type) and issubclass(cls, BaseException) else ""
    out = [f"{indent}class {name}({base}):" if base else f"{indent}class {name}:"]
    body = []
    for attr, value in sorted(vars(cls).items()):
        if attr.startswith("__") and attr not in ("__init__", "__len__", "__getitem__", "__repr__", "__iter__"):
            continue
        kind = type(value).__name__
        if kind == "property":
            getter = signatures(getattr(value.fget, "__name__", ""), getattr(value.fget, "__doc__", ""))
            ret = getter[0].split(" -> ", 1)[1] if getter and " -> " in getter[0] else "typing.Any"
            body.append(f"{indent}    @property")
            body.append(f"{indent}    def {attr}(self) -> {ret}: ...")
            if value.fset is not None:
                body.append(f"{indent}    @{attr}.setter")
                body.append(f"{indent}    def {attr}(self, value: {ret}) -> None: ...")
        elif kind in ("instancemethod", "builtin_function_or_method", "function", "wrapper_descriptor"):
            if kind == "wrapper_descriptor":
                continue  # object's own slots
            decorator = "@staticmethod" if kind == "builtin_function_or_method" else None
            body += function_lines(attr, value.__doc__, indent + "    ", decorator)
        elif kind == "staticmethod":
            body += function_lines(attr, value.__func__.__doc__, indent + "    ", "@staticmethod")
        elif isinstance(value, (int, float, str, bool)):
            body.append(f"{indent}    {attr}: {type(value).__name__}")
    return out + (body or [f"{indent}    ..."])


def module_stub(module):
    lines = [HEADER, "import os", "import typing", "", "import numpy", "import numpy.typing", ""]
    for name, value in sorted(vars(module).items()):
        if name.startswith("__"):
            continue
        kind = type(value).__name__
        if isinstance(value, type):
            lines += class_lines(name, value) + [""]
        elif kind == "builtin_function_or_method":
            lines += function_lines(name, value.__doc__, "") + [""]
        elif kind == "module":
            lines.append(f"class _{name}_module:")
            for sub, fn in sorted(vars(value).items()):
                if sub.startswith("__"):
                    continue
                if isinstance(fn, type):
                    lines += class_lines(sub, fn, "    ")
                elif type(fn).__name__ == "builtin_function_or_method":
                    lines += function_lines(sub, fn.__doc__, "    ", "@staticmethod")
            lines += ["", f"{name}: _{name}_module", ""]
        elif isinstance(value, (int, float, str, bool)):
            lines.append(f"{name}: {type(value).__name__}")
    return "\n".join(lines).rstrip() + "\n"


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--check", action="store_true", help="exit 1 when the committed stubs are stale")
    parser.add_argument("--module-dir", default=str(root / "build/release/python"))
    args = parser.parse_args()
    sys.path.insert(0, args.module_dir)
    text = module_stub(importlib.import_module("penalty._core"))
    path = root / "python/penalty/_core.pyi"
    if args.check:
        if not path.exists() or path.read_text() != text:
            print(f"{path}: stale; run scripts/generate-python-stubs.py", file=sys.stderr)
            return 1
        return 0
    path.write_text(text)
    print(f"{path}: written")
    return 0


if __name__ == "__main__":
    sys.exit(main())
