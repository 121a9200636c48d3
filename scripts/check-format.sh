#!/usr/bin/env bash
# Checks that every C++ file under version control is laid out as .clang-format says
# (clang-format 14). With --fix, rewrites the files that are not. Exit 0: all laid out;
# 1: some are not (their names and the first differences are printed); 77: clang-format-14 missing
# (CTest reports the test as skipped, not passed).
set -euo pipefail
cd "$(dirname "$0")/.."
tool="$(command -v clang-format-14 || true)"
if [ -z "$tool" ]; then
  echo "check-format: clang-format-14 is missing (scripts/install-deps.sh installs it)"
  exit 77
fi
mapfile -t files < <(git ls-files '*.cpp' '*.hpp' '*.h' 2>/dev/null || find apps bench fuzz include python src tests \( -name '*.cpp' -o -name '*.hpp' -o -name '*.h' \))
if [ "${1:-}" = "--fix" ]; then
  "$tool" -i --style=file "${files[@]}"
  exit 0
fi
"$tool" --style=file --dry-run -Werror "${files[@]}" 2>/dev/null && {
  echo "check-format: ${#files[@]} files laid out as .clang-format says"; exit 0; }
bad=0
for f in "${files[@]}"; do
  if ! "$tool" --style=file --dry-run -Werror "$f" 2>/dev/null; then
    echo "check-format: $f is not laid out as .clang-format says; the first differences:"
    "$tool" --style=file "$f" | diff "$f" - | head -n 12 || true
    bad=1
  fi
done
exit "$bad"
