#!/usr/bin/env bash
# The accuracy table of docs/accuracy.md (issue 25 item 1) in one command: nested-CV accuracy (RBF SVM, the paper's
# grid C 1e-2..1e10 x gamma 1e-9..1e3, 2 x 5 outer folds, 5 inner splits) of the project's default descriptor
# settings (nu 1e-1 in paper units, Lmax 10, log, no scale normalisation) on every labelled set, across map method
# (each with the chain a model of that recipe runs; maps by another method are lost as off-recipe, as `wish train`
# refuses them), area correction (none / density-equalising "dem") and features (xi alone, global, combined), with
# the meshes each configuration loses. Re-run it after map changes: every set is re-mapped with the current code.
#   bench/accuracy_table.sh [WORK=/work/acc-data]
# env: BUILD (build/release), JOBS (2), SETS (demo raw_mc urocell hard), METHODS (cmcf,willmore,progressive),
#      CORRECTIONS (none,dem), CAP_UROCELL (30), CAP_RAW_MC (30), HARD_PER_CLASS (15), RUN_SECONDS (1800, per set),
#      FV_VOLUMES (2: the fusiform vesicles of the first 2 of 4 volumes, 256 of 715 objects; empty: all),
#      WISH_SHARED_DATA (../shared/data)
# Sets (class folders of meshes; made here when missing, deterministic):
#   demo    `wish demo-data --per-class 12 --seed 1` (the bundled model's synthetic set, 6 classes)
#   raw_mc  ../shared/data/urocell_raw_mc (raw marching-cubes organelles, 3 classes), at most CAP_RAW_MC per class
#   urocell bench/make_urocell_meshes.sh (UroCell label volumes meshed by `wish mesh-labels`; fv from FV_VOLUMES
#           volumes), at most CAP_UROCELL
#           per class
#   hard    bench/hard_shapes_labelled --per-class HARD_PER_CLASS --seed 1 (5 generated families, random poses)
# A per-class cap takes files evenly spaced over the sorted list (descriptor_accuracy_bench --max-per-class): a fixed
# subset, the same on every run. Writes WORK/<set>.out, .err, .csv and prints the markdown table
# (bench/accuracy_table.py WORK).
set -euo pipefail
cd "$(dirname "$0")/.."
work=${1:-/work/acc-data}
build=${BUILD:-build/release}
jobs=${JOBS:-2}
sets=${SETS:-demo raw_mc urocell hard}
methods=${METHODS:-cmcf,willmore,progressive}
corrections=${CORRECTIONS:-none,dem}
shared=${WISH_SHARED_DATA:-../shared/data}
run_seconds=${RUN_SECONDS:-1800}
export OPENBLAS_NUM_THREADS=1 OMP_NUM_THREADS=1
mkdir -p "$work"
for tool in cli/wish bench/descriptor_accuracy_bench bench/hard_shapes_labelled; do
  [[ -x "$build/$tool" ]] || { echo "accuracy_table: build $build/$tool first" >&2; exit 2; }
done

for set in $sets; do
  cap=0
  case $set in
    demo)
      dir=$work/demo
      [[ -f "$dir/DONE" ]] || { rm -rf "$dir"; "$build/cli/wish" demo-data --out "$dir" --per-class 12 --seed 1 --quiet && touch "$dir/DONE"; } ;;
    raw_mc)
      dir=$shared/urocell_raw_mc; cap=${CAP_RAW_MC:-30}
      [[ -d "$dir" ]] || { echo "accuracy_table: no $dir, skipping raw_mc" >&2; continue; } ;;
    urocell)
      dir=$work/urocell-meshes; cap=${CAP_UROCELL:-30}
      [[ -f "$dir/DONE" ]] || FV_VOLUMES=${FV_VOLUMES-2} bench/make_urocell_meshes.sh "$dir" "$build/cli/wish" ;;
    hard)
      dir=$work/hard-shapes
      [[ -f "$dir/DONE" ]] || { rm -rf "$dir"; "$build/bench/hard_shapes_labelled" "$dir" --per-class "${HARD_PER_CLASS:-15}" --seed 1 && touch "$dir/DONE"; } ;;
    *) echo "accuracy_table: unknown set $set" >&2; exit 2 ;;
  esac
  echo "== $set: $dir (cap $cap per class; at most $run_seconds s)" >&2
  # A run stopped by the time bound keeps the rows it printed (the table marks the missing ones).
  timeout "$run_seconds" nice -n 5 "$build/bench/descriptor_accuracy_bench" --data "$dir" --methods "$methods" \
    --area-correction "$corrections" --nu 10000 --lmax 10 --log on --scale none --c-range -2 10 --gamma-range -9 3 \
    --max-per-class "$cap" --jobs "$jobs" --map-seconds 60 --csv "$work/$set.csv" >"$work/$set.out" 2>"$work/$set.err" ||
    echo "accuracy_table: $set stopped with status $? (time bound or error; see $work/$set.err)" >&2
done
python3 bench/accuracy_table.py "$work" $sets
