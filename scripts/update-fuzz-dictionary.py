#!/usr/bin/python3
"""Adds to fuzz/scene.dict every component tag and attribute of the registry it lacks.

    scripts/update-fuzz-dictionary.py [PENALTY]   (default build/release/bin/penalty)

Reads `penalty info --components` (the component registry, penalty/scene/components.hpp);
tests/scene/test_components.cpp fails while the dictionary lacks one of them.
"""
import pathlib
import re
import subprocess
import sys

root = pathlib.Path(__file__).resolve().parent.parent
penalty = sys.argv[1] if len(sys.argv) > 1 else str(root / "build/release/bin/penalty")
listing = subprocess.run([penalty, "info", "--components"], check=True, capture_output=True, text=True).stdout
path = root / "fuzz/scene.dict"
text = path.read_text()
added = []
for line in listing.splitlines():
    tag = re.match(r"^  (\w+): ", line)
    attribute = re.match(r"^    (\w+) \(", line)
    entry = f'"<{tag.group(1)} "' if tag else f'" {attribute.group(1)}=\\""' if attribute else None
    if entry and entry not in text and entry not in added:
        added.append(entry)
with path.open("a") as out:
    out.writelines(e + "\n" for e in added)
print(f"{path}: {len(added)} entries added")
