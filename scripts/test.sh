#!/usr/bin/env bash
# Installs the build dependencies (Debian 12), builds the release preset and runs every test:
# the C++ suites and, as the CTest tests python.<file>, the Python tests (pytest on tests/python
# with Debian's /usr/bin/python3). PENALTY_BUILD_PYTHON=ON makes a missing Python setup an error
# instead of a silently skipped module.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
cmake --preset release -DPENALTY_BUILD_PYTHON=ON
cmake --build --preset release
ctest --preset release
