"""pytest setup: import penalty from the build tree (CTest sets PYTHONPATH; a plain `pytest
tests/python` from the repository falls back to build/release/python)."""
import os
import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
if not any(Path(p, "penalty", "__init__.py").exists() for p in sys.path if p):
    sys.path.insert(0, str(REPO / "build" / "release" / "python"))

#: SOFA's files beside the repository (never committed); tests using them skip when absent.
SHARED_SOFA = Path(os.environ.get("PENALTY_SHARED_SOFA", REPO.parent / "shared" / "sofa"))
HERE = Path(__file__).resolve().parent


@pytest.fixture
def output_dir(tmp_path):
    return tmp_path


@pytest.fixture(scope="session")
def shared_sofa():
    if not (SHARED_SOFA / "scenes").is_dir():
        pytest.skip(f"SOFA's shared files not found at {SHARED_SOFA}")
    return SHARED_SOFA
