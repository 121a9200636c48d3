"""Running a SofaPython3 scene script as runSofa does (SofaPython3's SceneLoaderPY3): the script is
imported as a module named after its file (not `__main__`), from its own folder (the working
directory during the import and createScene, then back), with `''` first on sys.path (that folder)
and sys.argv = [name without .py, arguments...]; then createScene(root) on a new root node named
"root", then Sofa.Simulation.init."""
from __future__ import annotations

import importlib.util
import os
import sys
import traceback
import types
from pathlib import Path

from .. import _core
from .tree import Node


class ScriptError(_core.SceneError):
    """A script that cannot be compiled (SyntaxError, IndentationError): `file:line: message`."""


class ScriptExit(Exception):
    """The script called sys.exit(code) while it was loaded (in createScene or its module code)."""

    def __init__(self, code, where: str, location: str):
        self.code = code
        self.where = where
        self.location = location
        super().__init__(f"the script called sys.exit({code!r}) {where} ({location})")


def script_frame(tb, script: str):
    """(file, line) of the innermost frame of a traceback in `script`, else of the innermost frame
    outside penalty's package, else None."""
    frames = traceback.extract_tb(tb)
    own = str(Path(__file__).resolve().parents[1])
    for f in reversed(frames):
        if os.path.abspath(f.filename) == os.path.abspath(script):
            return f.filename, f.lineno
    for f in reversed(frames):
        if not os.path.abspath(f.filename).startswith(own):
            return f.filename, f.lineno
    return None


def compile_script(path: Path):
    """The code of a script; ScriptError naming the file and line for a SyntaxError."""
    try:
        source = path.read_bytes()
    except OSError as e:
        raise _core.SceneError(f"{path}: cannot open file ({e.strerror})") from None
    try:
        return compile(source, str(path), "exec")
    except SyntaxError as e:
        line = e.lineno or 0
        where = f"{e.filename or path}:{line}"
        text = f"\n    {e.text.rstrip()}" if e.text else ""
        raise ScriptError(f"{where}: {type(e).__name__}: {e.msg}{text}") from None


def run_scene_script(path, options, argv=()) -> Node:
    """Loads a scene script as runSofa does and builds it; returns the root (root._penalty_scene is
    the penalty.Scene). ScriptExit when the script calls sys.exit while it is loaded."""
    from .. import _install_sofa_path
    from .simulation import init
    _install_sofa_path()
    path = Path(path)
    if not path.is_file():
        raise _core.SceneError(f"{path}: cannot open file")
    path = path.resolve()
    code = compile_script(path)
    module_name = path.stem
    sys.argv = [module_name, *[str(a) for a in argv]]
    if "" not in sys.path:
        sys.path.insert(0, "")
    script_dir = str(path.parent)
    if script_dir not in sys.path:
        sys.path.insert(1, script_dir)  # the folder, also once the working directory is back
    old_cwd = os.getcwd()
    os.chdir(script_dir)
    try:
        module = types.ModuleType(module_name)
        module.__file__ = str(path)
        try:
            exec(code, module.__dict__)  # noqa: S102 - running the user's scene is the point
        except SystemExit as e:
            where = script_frame(e.__traceback__, str(path))
            raise ScriptExit(e.code, "while the script was imported", f"{where[0]}:{where[1]}" if where else str(path)) from None
        create = module.__dict__.get("createScene")
        if create is None:
            raise _core.SceneError(f"{path}: no createScene(rootNode) function")
        root = Node("root")
        object.__setattr__(root, "_file", str(path))
        object.__setattr__(root, "_line", create.__code__.co_firstlineno)
        object.__setattr__(root, "_penalty_build_options", options)
        try:
            result = create(root)
        except SystemExit as e:
            where = script_frame(e.__traceback__, str(path))
            raise ScriptExit(e.code, "in createScene", f"{where[0]}:{where[1]}" if where else str(path)) from None
    finally:
        os.chdir(old_cwd)
    if isinstance(result, Node) and result is not root and result._parent is None:
        root = result
        object.__setattr__(root, "_penalty_build_options", options)
    object.__setattr__(root, "_penalty_module", module)
    init(root, build_options=options)
    return root


def import_sofa_python_scene(path_to_scene: str):
    """Sofa.import_sofa_python_scene: a scene script imported as a module (its createScene is
    required)."""
    path = Path(path_to_scene)
    spec = importlib.util.spec_from_file_location("sofa.scene", str(path))
    if spec is None or spec.loader is None or not path.is_file():
        raise FileNotFoundError(f"Sofa.import_sofa_python_scene: cannot open '{path_to_scene}'")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    if not hasattr(module, "createScene"):
        raise Exception("Unable to find 'createScene' in module " + path_to_scene)  # noqa: TRY002 - SofaPython3's
    return module
