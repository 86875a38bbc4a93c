#!/bin/sh
# The open-set check of issue 25 item 3 on a labelled descriptor CSV (default: the synthetic demo set's,
# data/models/demo-descriptors.csv): for each class in turn, `wish train` on the other classes (default training,
# nested CV and family comparison off), then count the left-out class's members that `wish predict` flags
# novel, and the held-out test samples of the known classes the training report says are flagged.
#   bench/novelty_open_set.sh [path/to/wish] [descriptors.csv]
set -eu
here=$(cd "$(dirname "$0")/.." && pwd)
wish=${1:-$here/build/release/cli/wish}
csv=${2:-$here/data/models/demo-descriptors.csv}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
total_u=0 flagged_u=0 total_k=0 flagged_k=0
for cls in $(tail -n +2 "$csv" | cut -d, -f2 | sort -u); do
  head -1 "$csv" > "$tmp/known.csv"; tail -n +2 "$csv" | awk -F, -v c="$cls" '$2 != c' >> "$tmp/known.csv"
  head -1 "$csv" > "$tmp/unknown.csv"; tail -n +2 "$csv" | awk -F, -v c="$cls" '$2 == c' >> "$tmp/unknown.csv"
  "$wish" train "$tmp/known.csv" --no-compare --nested-repeats 0 --quiet --out "$tmp/m.json" --report "$tmp/r.json" > /dev/null 2>&1
  u=$(($(wc -l < "$tmp/unknown.csv") - 1))
  fu=$("$wish" predict --model "$tmp/m.json" --descriptors "$tmp/unknown.csv" --csv | tail -n +2 | awk -F, '$5 == "true"' | wc -l)
  k=$(python3 -c "import json; print(json.load(open('$tmp/r.json'))['novelty']['test_samples'])")
  fk=$(python3 -c "import json; print(json.load(open('$tmp/r.json'))['novelty']['test_flagged'])")
  echo "left out $cls: $fu of $u flagged novel; held-out known: $fk of $k flagged"
  total_u=$((total_u + u)); flagged_u=$((flagged_u + fu)); total_k=$((total_k + k)); flagged_k=$((flagged_k + fk))
done
echo "all: left-out members flagged $flagged_u of $total_u; held-out known flagged $flagged_k of $total_k"
