#!/usr/bin/env bash
# Fails if any C++ file of the project differs from what clang-format (.clang-format) makes of it.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
mapfile -t files < <(git ls-files '*.cpp' '*.h')
unformatted=()
for file in "${files[@]}"; do
  clang-format --dry-run -Werror "$file" > /dev/null 2>&1 || unformatted+=("$file")
done
if (( ${#unformatted[@]} > 0 )); then
  echo "check-format: not clang-formatted (run clang-format -i on them): ${unformatted[*]}" >&2
  exit 1
fi
echo "check-format: ${#files[@]} files formatted"
