#!/usr/bin/env bash
# Fails (exit 1, one line per file) when a C++ source differs from what clang-format makes of it
# with the project's .clang-format. Run by scripts/test.sh (and so by CI) before the build.
# Shaders are not formatted: clang-format has no GLSL mode.
#   scripts/check-format.sh          check
#   scripts/check-format.sh --fix    reformat the files in place
set -euo pipefail
cd "$(dirname "$0")/.."
command -v clang-format > /dev/null || { echo "check-format.sh: clang-format not found (scripts/install-deps.sh installs it)" >&2; exit 1; }
mapfile -t files < <(git ls-files '*.cpp' '*.h')
if [ "${1:-}" = "--fix" ]; then
  clang-format -i "${files[@]}"
  exit 0
fi
bad=0
for f in "${files[@]}"; do
  if ! clang-format --dry-run --Werror "$f" > /dev/null 2>&1; then
    echo "$f: not formatted (scripts/check-format.sh --fix)"
    bad=$((bad + 1))
  fi
done
if [ "$bad" -gt 0 ]; then
  echo "check-format.sh: $bad file(s) differ from .clang-format" >&2
  exit 1
fi
echo "check-format.sh: ok (${#files[@]} files)"
