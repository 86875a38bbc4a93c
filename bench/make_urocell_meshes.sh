#!/usr/bin/env bash
# Meshes the UroCell organelles (../shared/data/urocell: real FIB-SEM label volumes) into one class folder each,
# the labelled set that bench/descriptor_accuracy_bench and bench/map_collection_bench read:
#   bench/make_urocell_meshes.sh [OUT=/work/urocell-meshes] [WISH=build/release/cli/wish]
# Complete objects only (--drop-truncated), ≥ 500 voxels, voxel 16 × 16 × 15 nm (the data README). Writes OUT/DONE
# when every class is done; objects.csv in each class folder lists the refused ones with their reason.
# FV_VOLUMES=N meshes the fusiform vesicles of the first N of their 4 volumes only (sorted; all by default): fv has
# 715 complete objects, and meshing them all takes most of the run on a shared machine (bench/accuracy_table.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:-/work/urocell-meshes}
wish=${2:-build/release/cli/wish}
data=${WISH_SHARED_DATA:-../shared/data}/urocell
[[ -d "$data" ]] || { echo "make_urocell_meshes: no UroCell data at $data" >&2; exit 1; }
rm -f "$out/DONE"
for pair in fv:instance lyso:binary mito:instance; do
  class=${pair%%:*}; kind=${pair##*:}
  mkdir -p "$out/$class"
  volumes=("$data/$class/$kind"/*.nii.gz)
  [[ $class == fv && -n ${FV_VOLUMES:-} ]] && volumes=("${volumes[@]:0:$FV_VOLUMES}")
  # exit status 1 means some objects were refused (listed in objects.csv); the others are written
  "$wish" mesh-labels "${volumes[@]}" --out "$out/$class" --spacing 16,16,15 --unit nm \
      --min-voxels 500 --drop-truncated || [[ $? -eq 1 ]]
  echo "$class: $(ls "$out/$class"/*.ply | wc -l) meshes"
done
touch "$out/DONE"
