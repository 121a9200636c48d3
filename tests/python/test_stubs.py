"""The compiled module's type stubs (python/penalty/_core.pyi) are the module's: every function,
class, method and property with pybind11's signature (scripts/generate-python-stubs.py)."""
import importlib.util
import pathlib
import subprocess
import sys

import penalty

ROOT = pathlib.Path(__file__).resolve().parents[2]
SCRIPT = ROOT / "scripts/generate-python-stubs.py"


def _generator():
    spec = importlib.util.spec_from_file_location("generate_python_stubs", SCRIPT)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_committed_stubs_are_the_modules():
    module_dir = pathlib.Path(penalty.__file__).resolve().parent.parent
    run = subprocess.run([sys.executable, str(SCRIPT), "--check", "--module-dir", str(module_dir)],
                         capture_output=True, text=True)
    assert run.returncode == 0, run.stderr


def test_stub_names_every_public_binding_with_its_signature():
    text = _generator().module_stub(penalty._core)
    # a method with defaults and keyword-only arguments, a property, a submodule function
    assert "def step(self: Scene, n: int = 1) -> None: ..." in text
    assert "    @property\n    def time(self) -> float: ..." in text
    assert "class _collision_module:" in text and "collision: _collision_module" in text
    assert "class SceneError(Exception):" in text
    compile(text, "_core.pyi", "exec")  # valid Python syntax


def test_stale_stub_is_reported(tmp_path, monkeypatch):
    generator = _generator()
    monkeypatch.setattr(generator, "root", tmp_path)
    (tmp_path / "python/penalty").mkdir(parents=True)
    (tmp_path / "python/penalty/_core.pyi").write_text("# stale\n")
    monkeypatch.setattr(sys, "argv", ["generate-python-stubs.py", "--check", "--module-dir",
                                      str(pathlib.Path(penalty.__file__).resolve().parent.parent)])
    assert generator.main() == 1
