#!/usr/bin/env bash
# Installs the build dependencies (Debian 12), builds the `penalty` command line and runs it.
# Without arguments it runs the built-in demonstration; arguments are passed to `penalty`.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
cmake --preset release > /dev/null
cmake --build --preset release --target penalty_cli
exec ./build/release/bin/penalty "$@"
