#!/usr/bin/env bash
# The tables of issue 38 in one command (docs/accuracy.md "Feature families and open set"): every labelled set is
# described by the CURRENT build with every feature family (`wish train --features all`: xi, global, the
# Laplace-Beltrami spectrum, the canonical SH coefficients), then bench/open_set_bench.py measures
#   * nested-CV accuracy per feature family (outer 5 folds, inner 3-fold grid), and
#   * the open-set scores, every class left out in turn, with the supervised ceiling, per family.
# Re-run it after a descriptor change (issue 37's canonical map): the sets are re-described, not re-used.
#   bench/open_set_table.sh [WORK=/work/open-set]
# env: BUILD (build/release), SETS (demo rawmc urocell hard), CAP (40: at most this many meshes per class, evenly
#      spaced over the sorted file list), DEMO_PER_CLASS (40), HARD_PER_CLASS (8), LMAX (10), SPECTRUM (30),
#      FAMILIES (xi,global,combined,lb,lb_global,csh,csh_global,xi_lb_global),
#      OPEN_FAMILIES (combined,lb_global,xi_lb_global), WISH_SHARED_DATA (../shared/data), JOBS (1),
#      TABLES (1; 0: describe only, e.g. to describe sets in parallel runs and tabulate them together later)
# Sets (made here when missing, deterministic): demo `wish demo-data --per-class DEMO_PER_CLASS --seed 2`;
# rawmc ../shared/data/urocell_raw_mc; urocell bench/make_urocell_meshes.sh with FV_VOLUMES=1; hard
# bench/hard_shapes_labelled --per-class HARD_PER_CLASS --seed 1 (slow: minutes per octopus).
# Writes WORK/<set>.csv (the descriptors), WORK/<set>.err (the describe log) and WORK/table.md.
set -euo pipefail
cd "$(dirname "$0")/.."
work=${1:-/work/open-set}
build=${BUILD:-build/release}
sets=${SETS:-demo rawmc urocell hard}
cap=${CAP:-40}
lmax=${LMAX:-10}
spectrum=${SPECTRUM:-30}
families=${FAMILIES:-xi,global,combined,lb,lb_global,csh,csh_global,xi_lb_global}
open_families=${OPEN_FAMILIES:-combined,lb_global,xi_lb_global}
shared=${WISH_SHARED_DATA:-../shared/data}
wish=$build/cli/wish
export OPENBLAS_NUM_THREADS=1 OMP_NUM_THREADS=1
mkdir -p "$work"

# A class-folder tree of at most $cap files per class (symbolic links, evenly spaced over the sorted list).
capped() {
  local src=$1 dst=$2
  rm -rf "$dst"
  for dir in "$src"/*/; do
    local class; class=$(basename "$dir")
    mkdir -p "$dst/$class"
    mapfile -t files < <(find "$dir" -maxdepth 1 -type f \( -name '*.ply' -o -name '*.obj' -o -name '*.off' -o -name '*.stl' \) | sort)
    local n=${#files[@]}
    for ((j = 0; j < (n < cap ? n : cap); j++)); do
      local i=$(( n <= cap ? j : (j * (n - 1) * 2 / (cap - 1) + 1) / 2 ))
      ln -s "$(realpath "${files[$i]}")" "$dst/$class/"
    done
  done
}

csvs=()
for set in $sets; do
  case $set in
    demo) [[ -d $work/demo-meshes ]] || "$wish" demo-data --out "$work/demo-meshes" --per-class "${DEMO_PER_CLASS:-40}" --seed 2 --quiet
          src=$work/demo-meshes ;;
    rawmc) src=$shared/urocell_raw_mc ;;
    urocell) [[ -f $work/urocell-meshes/DONE ]] || FV_VOLUMES=1 bash bench/make_urocell_meshes.sh "$work/urocell-meshes" "$wish"
             src=$work/urocell-meshes ;;
    hard) [[ -d $work/hard-meshes ]] || "$build/bench/hard_shapes_labelled" "$work/hard-meshes" --per-class "${HARD_PER_CLASS:-8}" --seed 1
          src=$work/hard-meshes ;;
    *) echo "open_set_table: unknown set $set" >&2; exit 2 ;;
  esac
  capped "$src" "$work/$set-capped"
  nice -n 10 "$wish" train "$work/$set-capped" --features all --spectrum-count "$spectrum" --lmax "$lmax" --allow-losses \
      --off-recipe accept_flagged --save-descriptors "$work/$set.csv" --no-compare --nested-repeats 0 --grid-splits 2 \
      --jobs "${JOBS:-1}" --out "$work/$set-model.json" > "$work/$set.out" 2> "$work/$set.err" || true
  [[ -s $work/$set.csv ]] && csvs+=("$work/$set.csv")
done
[[ ${TABLES:-1} == 1 ]] || exit 0
{
  echo "## nested-CV accuracy (%) by feature family"
  nice -n 10 /usr/bin/python3 bench/open_set_bench.py "${csvs[@]}" --mode accuracy --families "$families"
  echo
  echo "## open set (every class left out in turn), with the supervised ceiling"
  nice -n 10 /usr/bin/python3 bench/open_set_bench.py "${csvs[@]}" --mode open --families "$open_families" --ceiling
} | tee "$work/table.md"
