"""Every code block of README.md and docs/ that can be run is run, so an example cannot drift
from the code (the README once read a state key that does not exist).

- A ```python block runs as a script of its own (so a sweep's `if __name__ == "__main__":` works)
  with the package and its SofaPython3 subset importable. A block that continues the previous one
  of its file says so on the line above its fence: `<!-- doc-test: continues -->`; a block that
  cannot run (an API listing over the reader's arrays, a cluster we do not have) says why:
  `<!-- doc-test: not run (reason) -->`. Every other python block must run.
- A ```sh block runs when every command in it is `penalty ...` (or ./build/release/bin/penalty)
  and none serves the viewer (until Ctrl-C); blocks of build, install or server commands are not
  run (nothing marks them).
- Blocks run in a scratch copy of the repository's layout (scenes/, examples/, build/ and
  ../shared/sofa linked), so the files they write stay out of the source tree. Blocks that use
  SOFA's shared files are skipped when those are absent.
"""
import os
import re
import shlex
import subprocess
import sys
from pathlib import Path

import pytest

import penalty

REPO = Path(__file__).resolve().parents[2]
SHARED = REPO.parent / "shared" / "sofa"
DOCS = [REPO / "README.md", *sorted((REPO / "docs").rglob("*.md"))]
FENCE = re.compile(r"^```(\w*)\s*$")
MARK = re.compile(r"<!--\s*doc-test:\s*(continues|not run)\b")


def blocks():
    """(file, line, language, code, mark) of every fenced block."""
    out = []
    for path in DOCS:
        lines = path.read_text().splitlines()
        i = 0
        while i < len(lines):
            m = FENCE.match(lines[i])
            if not m or not m.group(1):
                i += 1
                continue
            j = i + 1
            while j < len(lines) and lines[j].strip() != "```":
                j += 1
            mark = MARK.search(lines[i - 1]) if i > 0 else None
            out.append((path, i + 1, m.group(1), "\n".join(lines[i + 1:j]) + "\n", mark.group(1) if mark else None))
            i = j + 1
    return out


def python_scripts():
    """The python blocks to run, continuations joined to their first block."""
    scripts = []
    for path, line, language, code, mark in blocks():
        if language != "python":
            continue
        if mark == "continues":
            assert scripts and scripts[-1][0] == path, f"{path}:{line}: continues no python block of its file"
            scripts[-1] = (path, scripts[-1][1], scripts[-1][2] + code, scripts[-1][3])
        else:
            scripts.append((path, line, code, mark))
    return [s for s in scripts if s[3] != "not run"]


def shell_commands(code):
    """The commands of a sh block (continuation lines joined, comments and blanks dropped), or None
    when one of them is not a `penalty` command."""
    commands, current = [], ""
    for raw in code.splitlines():
        text = raw.split(" #", 1)[0].rstrip() if not raw.lstrip().startswith("#") else ""
        current += " " + text.rstrip("\\").strip() if current else text.rstrip("\\").strip()
        if text.endswith("\\"):
            continue
        if current:
            commands.append(current)
        current = ""
    programs = {"penalty", "./build/release/bin/penalty"}
    if not commands or any(shlex.split(c)[0] not in programs for c in commands):
        return None
    # a server (penalty view, run --view) runs until Ctrl-C: the viewer's own tests cover it
    if any((" view " in f" {c} " or "--view" in c) and "--no-serve" not in c for c in commands):
        return None
    return commands


def shell_blocks():
    return [(path, line, cmds) for path, line, language, code, mark in blocks()
            if language in ("sh", "bash") and mark != "not run" and (cmds := shell_commands(code))]


@pytest.fixture(scope="module")
def sandbox(tmp_path_factory):
    """A scratch `repo/` beside a `shared/` link, with the repository's inputs linked in."""
    root = tmp_path_factory.mktemp("docs")
    repo = root / "repo"
    repo.mkdir()
    for name in ("scenes", "examples", "tests", "build", "docs"):
        (repo / name).symlink_to(REPO / name)
    if SHARED.is_dir():
        (root / "shared").mkdir()
        (root / "shared" / "sofa").symlink_to(SHARED)
    bin_dir = root / "bin"
    bin_dir.mkdir()
    cli = os.environ.get("PENALTY_CLI", str(REPO / "build" / "release" / "bin" / "penalty"))
    (bin_dir / "penalty").symlink_to(cli)
    package = Path(penalty.__file__).parents[1]
    env = dict(os.environ, PATH=f"{bin_dir}{os.pathsep}{os.environ.get('PATH', '')}",
               PYTHONPATH=os.pathsep.join([str(package), str(package / "penalty" / "sofa_compat")]), MPLBACKEND="Agg")
    return repo, env


def needs_shared(text):
    return "../shared/sofa" in text and not SHARED.is_dir()


def block_id(item):
    return f"{item[0].relative_to(REPO)}:{item[1]}"


def test_the_docs_have_runnable_blocks():
    assert len(python_scripts()) >= 5 and len(shell_blocks()) >= 2


@pytest.mark.parametrize("script", python_scripts(), ids=block_id)
def test_python_block_runs(script, sandbox, tmp_path):
    path, line, code, _ = script
    if needs_shared(code):
        pytest.skip("SOFA's shared files are absent")
    repo, env = sandbox
    file = repo / f"block_{path.stem}_{line}.py"
    file.write_text(code)
    r = subprocess.run([sys.executable, str(file)], cwd=repo, env=env, capture_output=True, text=True, timeout=600)
    assert r.returncode == 0, f"{path.relative_to(REPO)}:{line}: the block fails\n{r.stdout[-2000:]}\n{r.stderr[-4000:]}"


@pytest.mark.parametrize("block", shell_blocks(), ids=block_id)
def test_shell_block_runs(block, sandbox):
    path, line, commands = block
    if needs_shared(" ".join(commands)):
        pytest.skip("SOFA's shared files are absent")
    repo, env = sandbox
    for command in commands:
        argv = shlex.split(command)
        argv[0] = "penalty"
        if argv[1] == "run" and "--quiet" not in argv:
            argv.append("--quiet")
        r = subprocess.run(argv, cwd=repo, env=env, capture_output=True, text=True, timeout=600)
        assert r.returncode == 0, f"{path.relative_to(REPO)}:{line}: `{command}` exits {r.returncode}\n{r.stderr[-3000:]}"
