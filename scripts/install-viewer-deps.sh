#!/usr/bin/env bash
# Installs what the browser tests of the viewer need (docs/viewer.md): Debian's Chromium and
# Node.js/npm (Debian 12 packages, left alone when present), then playwright-core and three.js
# from the npm registry at the versions viewer/package-lock.json pins (`npm ci`).
# Playwright's own browser download is never used: the tests drive /usr/bin/chromium.
# Building and running `penalty` needs none of this (the page is embedded in the binary).
set -euo pipefail
cd "$(dirname "$0")/.."

missing=()
[ -x /usr/bin/chromium ] || missing+=(chromium)
command -v node >/dev/null 2>&1 || missing+=(nodejs)
command -v npm >/dev/null 2>&1 || missing+=(npm)
if [ ${#missing[@]} -gt 0 ]; then
  if [ "$(id -u)" -eq 0 ]; then sudo_cmd=(); else sudo_cmd=(sudo); fi
  echo "install-viewer-deps: installing ${missing[*]}"
  export DEBIAN_FRONTEND=noninteractive
  "${sudo_cmd[@]}" apt-get update -qq
  "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
else
  echo "install-viewer-deps: chromium, node and npm already installed"
fi

# playwright-core would otherwise try to download browsers on install; we use Debian's.
export PLAYWRIGHT_SKIP_BROWSER_DOWNLOAD=1
(cd viewer && npm ci --no-audit --no-fund --loglevel=error)
