#!/bin/sh
# Makes the bundled default model data/models/default.json from the SYNTHETIC demo set (issue 5): runs
# `wish demo-data` (deterministic generator, core/synth) and then `wish train`. The model is trained on synthetic
# nucleus-like shapes, not on real cells: see data/models/README.md.
#   scripts/make-default-model.sh [path/to/wish]     env: PER_CLASS (12), JOBS (0 = all cores), OUT (data/models)
set -eu
here=$(cd "$(dirname "$0")/.." && pwd)
wish=${1:-$here/build/release/cli/wish}
out=${OUT:-$here/data/models}
per_class=${PER_CLASS:-12}
jobs=${JOBS:-0}
[ -x "$wish" ] || { echo "make-default-model: no wish binary at $wish (build it, or pass its path)" >&2; exit 2; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
mkdir -p "$out"
"$wish" demo-data --out "$tmp/demo" --per-class "$per_class" --seed 1 --quiet
# A fixed timestamp keeps the file reproducible (same inputs, same bytes).
# The descriptor recipe is spelled out (issue 12), chosen by bench/descriptor_accuracy_bench on this demo set:
# cMCF maps (every mesh mapped by cMCF alone; xi alone 90.2 % nested CV against 87.0 % for the global features and
# 81.4 % for Willmore maps at the same settings), Lmax 10, log, nu = 1e-1 (paper units; the best xi on the demo set
# and on the UroCell organelles, docs/accuracy.md); off-recipe maps are refused and any class losing more than 10 %
# of its meshes stops the run. Re-checked in issue 25 on every labelled set (demo, UroCell meshes, raw marching-cubes
# UroCell, generated hard shapes; docs/accuracy.md run I, bench/accuracy_table.sh): cMCF keeps the best xi alone
# wherever the methods map the same meshes, so the recipe is kept.
# Novelty calibration cross-validated (--novelty-folds 10, model format 6): with about 10 training samples per class,
# leave-one-out scores flagged 9 of 72 held-out known members leaving each class out in turn, 10-fold ones 3 of 72
# (bench/novelty_open_set.sh on demo-descriptors.csv; docs/benchmarks.md "Novelty").
SOURCE_DATE_EPOCH=${SOURCE_DATE_EPOCH:-1704067200} "$wish" train "$tmp/demo" \
  --method cmcf --lmax 10 --regularization 1e-1 --weights area --log --scale none --features invariants \
  --novelty-folds 10 \
  --off-recipe refuse --max-class-loss 0.1 --seed 42 --jobs "$jobs" --quiet \
  --name wish-default-synthetic \
  --out "$out/default.json" --report "$out/default-report.json" --heatmap "$out/default-grid.svg" \
  --save-descriptors "$tmp/descriptors.csv"
# Descriptor paths are machine-specific temporaries: keep class/file names only.
sed "s#$tmp/demo/##" "$tmp/descriptors.csv" > "$out/demo-descriptors.csv"
# The same for the report: no temporary directory or checkout path in a committed file.
sed -i "s#$tmp/demo/##g; s#\"$tmp/demo\"#\"demo\"#; s#\"$out/default.json\"#\"default.json\"#" "$out/default-report.json"
echo "wrote $out/default.json (SYNTHETIC demo model)"
