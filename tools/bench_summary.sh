#!/usr/bin/env bash
# Regenerates the committed benchmark summary: runs the full `fovea bench` sweep (~4 min on
# lavapipe with 2 cores), writes docs/bench/summary.md and docs/bench/time_vs_error.png, and
# replaces the README section between the bench-summary markers with the summary.
#   tools/bench_summary.sh [fovea bench options, e.g. --frames 5]
#   tools/bench_summary.sh --readme-only      # only re-embed docs/bench/summary.md
# FOVEA_BIN selects the binary (default build/main/tools/fovea).
set -euo pipefail
cd "$(dirname "$0")/.."
summary=docs/bench/summary.md
if [[ "${1:-}" != "--readme-only" ]]; then
    fovea_bin=${FOVEA_BIN:-build/main/tools/fovea}
    mkdir -p docs/bench
    csv=$(dirname "$fovea_bin")/fovea_bench.csv
    "$fovea_bin" bench --summary "$summary" --png docs/bench/time_vs_error.png --csv "$csv" "$@"
    echo "CSV (not committed): $csv"
fi
# The summary's image path is relative to docs/bench; the README sits at the root.
python3 - "$summary" README.md <<'PY'
import re, sys
summary, readme = sys.argv[1], sys.argv[2]
body = open(summary).read().replace("](time_vs_error.png)", "](docs/bench/time_vs_error.png)")
text = open(readme).read()
begin, end = "<!-- bench-summary:begin -->", "<!-- bench-summary:end -->"
if begin not in text or end not in text:
    sys.exit("README.md has no bench-summary markers")
head, rest = text.split(begin, 1)
_, tail = rest.split(end, 1)
open(readme, "w").write(head + begin + "\n" + body.rstrip("\n") + "\n" + end + tail)
PY
echo "README.md bench section updated from $summary"
