#!/usr/bin/env python3
"""Tests named after their sources: each src/STAGE/**/NAME.cpp has a tests/STAGE/**/test_NAME.cpp
(or tests/scene/test_NAME.cpp, where it needs a built scene).

The sources that do not yet have one are listed, one a line, in tests/sources_without_named_tests.txt
with, after '#', the test files (under tests/) that exercise them under other names. The list may
only shrink: this check fails, naming the file and line,
  - for a source that has no test_NAME.cpp and is not listed (a new source comes with its test),
  - for a listed source that has one, or no longer exists (take it off the list),
  - for a listed source without test files after '#', or naming one that does not exist.
Prints the count of sources with and without named tests. Exit 0 when consistent, 1 otherwise.
"""
import pathlib
import sys

root = pathlib.Path(__file__).resolve().parent.parent
listing = root / "tests" / "sources_without_named_tests.txt"

# (stage, name) of each tests/<stage>/**/test_<name>.cpp; a source's stage is its folder under src/
tests = {(p.relative_to(root / "tests").parts[0], p.stem.removeprefix("test_"))
         for p in (root / "tests").rglob("test_*.cpp")}


def has_named_test(source):
    """tests/<its stage>/test_<name>.cpp, or tests/scene/test_<name>.cpp: a stage's behaviour that
    needs a built scene (the fused contact block, the blocked reductions) is tested there."""
    path = pathlib.PurePosixPath(source)
    return (path.parts[1], path.stem) in tests or ("scene", path.stem) in tests


sources = sorted(p.relative_to(root).as_posix() for p in (root / "src").rglob("*.cpp"))
listed = {}
errors = []
for number, line in enumerate(listing.read_text().splitlines(), 1):
    entry, _, tested_by = line.partition("#")
    if not entry.strip():
        continue
    source = entry.split()[0]
    if source in listed:
        errors.append(f"{listing.relative_to(root)}:{number}: {source} listed twice")
    listed[source] = number
    # the tests named after '#' (tests/<path>), which exercise the source under other names
    named_tests = [t.strip() for t in tested_by.split(",") if t.strip()]
    if not named_tests:
        errors.append(f"{listing.relative_to(root)}:{number}: {source}: name the tests that exercise it after '#'")
    for t in named_tests:
        if not (root / "tests" / t).is_file():
            errors.append(f"{listing.relative_to(root)}:{number}: {source}: no test file tests/{t}")

for source in sources:
    named = has_named_test(source)
    if not named and source not in listed:
        errors.append(f"{source}: no tests/{pathlib.PurePosixPath(source).parts[1]}/test_{pathlib.PurePosixPath(source).stem}.cpp "
                      f"(write one; the list {listing.name} only shrinks)")
    if named and source in listed:
        errors.append(f"{listing.relative_to(root)}:{listed[source]}: {source} has its named test now: "
                      "take it off the list")
for source, number in listed.items():
    if source not in sources:
        errors.append(f"{listing.relative_to(root)}:{number}: {source} does not exist: take it off the list")

without = sum(1 for s in sources if not has_named_test(s))
print(f"{len(sources) - without} of {len(sources)} sources have a test named after them; {without} listed without")
for e in errors:
    print(f"check-test-names: {e}", file=sys.stderr)
sys.exit(1 if errors else 0)
