#!/bin/sh
# The open-set measurement of issue 25 item 3 on a labelled descriptor CSV (default: the synthetic demo set's,
# data/models/demo-descriptors.csv), leave-one-class-out: for each class in turn, `wish train` on the other
# classes (default training; nested CV and the family comparison off, they do not touch the novelty figure), then
# count the left-out class's members that `wish predict` flags novel, and the held-out test split of the known
# classes that the training report says are flagged. Prints a markdown table for docs/benchmarks.md.
#   bench/novelty_open_set.sh [path/to/wish] [descriptors.csv] [extra wish train options...]
# Descriptor CSVs: `wish train DIR --save-descriptors D.csv` (see docs/benchmarks.md "Novelty" for the sets).
set -eu
here=$(cd "$(dirname "$0")/.." && pwd)
wish=${1:-$here/build/release/cli/wish}
csv=${2:-$here/data/models/demo-descriptors.csv}
[ $# -ge 2 ] && shift 2 || shift $#
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
total_u=0 flagged_u=0 total_k=0 flagged_k=0
echo "| left-out class | its members flagged novel | held-out known members flagged |"
echo "|---|---|---|"
for cls in $(tail -n +2 "$csv" | cut -d, -f2 | sort -u); do
  head -1 "$csv" > "$tmp/known.csv"; tail -n +2 "$csv" | awk -F, -v c="$cls" '$2 != c' >> "$tmp/known.csv"
  head -1 "$csv" > "$tmp/unknown.csv"; tail -n +2 "$csv" | awk -F, -v c="$cls" '$2 == c' >> "$tmp/unknown.csv"
  "$wish" train "$tmp/known.csv" --no-compare --nested-repeats 0 --quiet --out "$tmp/m.json" --report "$tmp/r.json" "$@" > /dev/null 2>&1
  u=$(($(wc -l < "$tmp/unknown.csv") - 1))
  fu=$("$wish" predict --model "$tmp/m.json" --descriptors "$tmp/unknown.csv" --csv | tail -n +2 | awk -F, '$5 == "true"' | wc -l)
  k=$(python3 -c "import json; print(json.load(open('$tmp/r.json'))['novelty']['test_samples'])")
  fk=$(python3 -c "import json; print(json.load(open('$tmp/r.json'))['novelty']['test_flagged'])")
  echo "| $cls | $fu of $u ($(awk -v a="$fu" -v b="$u" 'BEGIN { printf "%.0f", 100 * a / b }') %) | $fk of $k |"
  total_u=$((total_u + u)); flagged_u=$((flagged_u + fu)); total_k=$((total_k + k)); flagged_k=$((flagged_k + fk))
done
echo "| all | $flagged_u of $total_u ($(awk -v a="$flagged_u" -v b="$total_u" 'BEGIN { printf "%.0f", 100 * a / b }') %) | $flagged_k of $total_k ($(awk -v a="$flagged_k" -v b="$total_k" 'BEGIN { printf "%.1f", 100 * a / b }') %) |"
