#!/usr/bin/env bash
# Installs the build dependencies (Debian 12), builds the `penalty` command line and runs it.
# Without arguments it runs `penalty run`: the built-in scene (a soft FEM cube and a rigid ball
# dropped on a floor, penalty contacts between all three). Arguments are passed to `penalty`,
# e.g. `./scripts/run.sh run scenes/friction_incline.scn --steps 500 --vtk out/`.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
cmake --preset release > /dev/null
cmake --build --preset release --target penalty_cli
if [ "$#" -eq 0 ]; then
  exec ./build/release/bin/penalty run
fi
exec ./build/release/bin/penalty "$@"
