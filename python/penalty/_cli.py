"""The `penalty` command of a pip-installed package: the C++ command line built into the wheel
(penalty/bin/penalty), told which interpreter runs the SofaPython3 scenes and sweeps it hands to
`python3 -m penalty` (this one, with this package importable)."""
import os
import sys
from pathlib import Path


def main():
    executable = Path(__file__).resolve().parent / "bin" / "penalty"
    if not executable.is_file():
        sys.exit(f"penalty: error: the command line is not part of this installation ({executable} is missing); "
                 "use python3 -m penalty")
    package_parent = str(Path(__file__).resolve().parent.parent)
    path = os.environ.get("PYTHONPATH", "")
    env = dict(os.environ, PENALTY_PYTHON=sys.executable,
               PYTHONPATH=package_parent + (os.pathsep + path if path else ""))
    os.execve(executable, [str(executable), *sys.argv[1:]], env)
