#!/usr/bin/env bash
# Installs the Debian 12 packages that building and testing `penalty` needs (clang and its
# runtime libraries build the libFuzzer targets, scripts/fuzz.sh; clang-format-14 and
# clang-tidy-14 check the layout and the lint rules, scripts/check-format.sh and
# scripts/check-tidy.sh; libbullet-dev the optional Bullet comparison of penalty_bench_detection;
# pip, setuptools, wheel and build for `pip install .` and `python3 -m build --no-isolation`,
# offline: pyproject.toml).
# Idempotent: packages already present are left alone. Runs as root or through sudo.
set -euo pipefail

packages=(
  build-essential cmake ninja-build git pkg-config
  libeigen3-dev libtinyxml2-dev libcli11-dev libtbb-dev
  libgtest-dev libgmock-dev libbenchmark-dev zlib1g-dev
  libbullet-dev
  pybind11-dev python3-dev python3-numpy python3-scipy python3-pytest python3-matplotlib
  python3-distributed python3-h5py python3-pandas
  python3-pip python3-setuptools python3-wheel python3-build python3-venv
  clang libclang-rt-14-dev clang-format-14 clang-tidy-14
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages already installed"
  exit 0
fi

if [ "$(id -u)" -eq 0 ]; then sudo_cmd=(); else sudo_cmd=(sudo); fi
echo "install-deps: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
"${sudo_cmd[@]}" apt-get update -qq
"${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
