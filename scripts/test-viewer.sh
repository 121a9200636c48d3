#!/usr/bin/env bash
# The browser tests of `penalty view` (viewer/tests/browser_test.mjs) against the release build:
# installs Chromium and the npm packages (scripts/install-viewer-deps.sh), builds the command line
# if needed, runs the tests. Screenshots go to build/viewer-test/.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-viewer-deps.sh
[ -x build/release/bin/penalty ] || { cmake --preset release && cmake --build --preset release --target penalty_cli; }
cd viewer
PENALTY_BIN=../build/release/bin/penalty VIEWER_TEST_OUT=../build/viewer-test node tests/browser_test.mjs
