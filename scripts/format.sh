#!/bin/sh
# Formats every C++ file of the tree with clang-format and the project's .clang-format
# (Debian: clang-format). --check: change nothing, list the files that differ, exit 1 if any.
set -e
cd "$(dirname "$0")/.."
command -v clang-format >/dev/null || { echo "format.sh: clang-format not found (apt-get install clang-format)" >&2; exit 2; }
files=$(git ls-files '*.cpp' '*.hpp' '*.h')
if [ "$1" = "--check" ]; then
  # shellcheck disable=SC2086
  clang-format --dry-run -Werror $files
else
  # shellcheck disable=SC2086
  clang-format -i $files
fi
