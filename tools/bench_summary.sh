#!/usr/bin/env bash
# Regenerates the committed benchmark summary: runs the full `fovea bench` sweep (~4 min on
# lavapipe with 2 cores), writes docs/bench/summary.md, docs/bench/time_vs_error.png (FLIP) and
# docs/bench/time_vs_error_psnr.png (pooled PSNR), and
# replaces the README section between the bench-summary markers with the summary.
#   tools/bench_summary.sh [fovea bench options, e.g. --frames 5]
#   tools/bench_summary.sh --readme-only      # only re-embed docs/bench/summary.md
#   tools/bench_summary.sh --scene FILE [...] # the glTF scene's sweep: docs/bench/scene_summary.md,
#                                             # scene_time_vs_error.png, its own README markers
#   tools/bench_summary.sh --scene-readme-only
# FOVEA_BIN selects the binary (default build/main/tools/fovea).
set -euo pipefail
cd "$(dirname "$0")/.."
summary=docs/bench/summary.md png=time_vs_error.png marker=bench-summary csv_name=fovea_bench.csv
mode=run
case "${1:-}" in
--readme-only) mode=embed ;;
--scene-readme-only | --scene)
    summary=docs/bench/scene_summary.md png=scene_time_vs_error.png marker=bench-scene-summary
    csv_name=fovea_bench_scene.csv
    [[ "$1" == --scene-readme-only ]] && mode=embed
    ;;
esac
if [[ $mode == run ]]; then
    fovea_bin=${FOVEA_BIN:-build/main/tools/fovea}
    mkdir -p docs/bench
    csv=$(dirname "$fovea_bin")/$csv_name
    "$fovea_bin" bench --summary "$summary" --png "docs/bench/$png" --csv "$csv" "$@"
    echo "CSV (not committed): $csv"
fi
# The summary's image path is relative to docs/bench; the README sits at the root.
python3 - "$summary" README.md "$png" "$marker" <<'PY'
import re, sys
summary, readme, png, marker = sys.argv[1:5]
stem = png[: -len(".png")]  # the time-vs-FLIP plot and its _psnr sibling
body = open(summary).read().replace("](%s" % stem, "](docs/bench/%s" % stem)
text = open(readme).read()
begin, end = "<!-- %s:begin -->" % marker, "<!-- %s:end -->" % marker
if begin not in text or end not in text:
    sys.exit("README.md has no %s markers" % marker)
head, rest = text.split(begin, 1)
_, tail = rest.split(end, 1)
open(readme, "w").write(head + begin + "\n" + body.rstrip("\n") + "\n" + end + tail)
PY
echo "README.md bench section updated from $summary"
