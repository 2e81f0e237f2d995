#!/usr/bin/env bash
# Long libFuzzer runs: run_long.sh <build-dir> [runs-per-target|0] [target ...]
# Default: every fuzz_* target in <build-dir>/tests/fuzz for 10^7 executions each, on one core
# (the machine is shared). Corpora persist in <build-dir>/tests/fuzz/corpus/<target>; crashes
# land in <build-dir>/tests/fuzz/artifacts/. Prints each target's final stats line.
# FUZZ_MAX_SECONDS=N also stops each target after N seconds (its stats line says how far it got).
set -euo pipefail
build=${1:?usage: run_long.sh <build-dir> [runs] [target ...]}
runs=${2:-10000000}
shift $(( $# >= 2 ? 2 : 1 ))
here=$(cd "$(dirname "$0")" && pwd)
fuzzdir=$build/tests/fuzz
mkdir -p "$fuzzdir/artifacts"
targets=("$@")
if [ ${#targets[@]} -eq 0 ]; then
    for exe in "$fuzzdir"/fuzz_*; do [ -x "$exe" ] && targets+=("$(basename "$exe")"); done
fi
for t in "${targets[@]}"; do
    corpus=$fuzzdir/corpus/$t
    mkdir -p "$corpus"
    args=(-runs="$runs" -rss_limit_mb=2048 -print_final_stats=1
          -artifact_prefix="$fuzzdir/artifacts/$t-")
    [ -n "${FUZZ_MAX_SECONDS:-}" ] && args+=(-max_total_time="$FUZZ_MAX_SECONDS")
    [ -f "$here/$t.dict" ] && args+=(-dict="$here/$t.dict")
    dirs=("$corpus")
    for d in "$here/seeds/$t" "$fuzzdir/shared_seeds/$t" "$fuzzdir/pldata_seeds/$t" \
        "$fuzzdir/repo_seeds/$t"; do
        [ -d "$d" ] && dirs+=("$d")
    done
    echo "== $t: $fuzzdir/$t ${args[*]} ${dirs[*]}"
    start=$(date +%s)
    "$fuzzdir/$t" "${args[@]}" "${dirs[@]}" 2>&1 | tee "$fuzzdir/$t.long.log" |
        grep -E "^(stat::|==[0-9]+==|SUMMARY|Done)" || true
    echo "== $t: $(( $(date +%s) - start )) s, exit ${PIPESTATUS[0]}"
done
