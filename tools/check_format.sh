#!/usr/bin/env bash
# The format promise of STYLE.md, kept by CI: every tracked C/C++ file is as clang-format
# (.clang-format at the root) would write it. `tools/check_format.sh --fix` rewrites them.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
mapfile -t files < <(git ls-files '*.c' '*.h' '*.cpp' '*.hpp')
if [ "${1:-}" = "--fix" ]; then
    clang-format -i "${files[@]}"
    exit 0
fi
if ! clang-format --dry-run --Werror "${files[@]}" 2> build/format.log; then
    grep -E '^[^ ]+:[0-9]+:[0-9]+: error' build/format.log | cut -d: -f1 | sort -u |
        sed 's/^/format: not clang-formatted: /'
    echo "format: run tools/check_format.sh --fix" >&2
    exit 1
fi
echo "format: ${#files[@]} files clang-formatted"
