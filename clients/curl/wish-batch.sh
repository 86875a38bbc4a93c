#!/usr/bin/env bash
# Classify every mesh under the given files/folders with plain curl, N requests in parallel (xargs -P).
#
#   clients/curl/wish-batch.sh [-s URL] [-j N] [-o OUTDIR] [-m MODEL] PATH...
#
# One request per mesh (raw body). Each answer is saved as OUTDIR/<path with / -> __>.json (a refusal as
# .error.json), and one tab-separated line per mesh is printed: file, HTTP status, label (or the error code).
# Transient failures (503 with Retry-After, 502/504 from a proxy, refused connections) are retried by curl
# (--retry honours Retry-After). Resumable: meshes that already have a .json answer in OUTDIR are skipped.
# Needs only bash, find, xargs, curl (and sed/grep). Exit status 1 when any mesh failed.
set -euo pipefail

server=${WISH_SERVER:-http://127.0.0.1:8080}
jobs=4
outdir=wish-results
model=""
usage() { sed -n '2,12p' "$0" | sed 's/^# \{0,1\}//'; exit 2; }
while getopts "s:j:o:m:h" opt; do
  case $opt in
    s) server=$OPTARG ;;
    j) jobs=$OPTARG ;;
    o) outdir=$OPTARG ;;
    m) model=$OPTARG ;;
    *) usage ;;
  esac
done
shift $((OPTIND - 1))
(($# > 0)) || usage
mkdir -p "$outdir"

# classify_one FILE: runs in a child bash started by xargs; settings come through the environment.
classify_one() {
  local file=$1 key out code label query
  key=${file#./}; key=${key//\//__}
  out="$WISH_OUTDIR/$key.json"
  if [[ -s $out ]]; then return 0; fi                     # done in an earlier run
  query="format=${file##*.}"; query=${query,,}
  [[ -n $WISH_MODEL ]] && query+="&model=$WISH_MODEL"
  code=$(curl -sS -o "$out.part" -w '%{http_code}' --retry 6 --retry-connrefused --retry-max-time 300 \
              --max-time 600 -H 'Content-Type: application/octet-stream' --data-binary "@$file" \
              "$WISH_SERVER/v1/classify?$query" 2>"$out.curl-stderr") || code=${code:-000}
  if [[ $code == 200 ]]; then
    mv "$out.part" "$out"; rm -f "$out.curl-stderr" "$WISH_OUTDIR/$key.error.json"
    label=$(grep -o '"label" *: *"[^"]*"' "$out" | head -n 1 | sed 's/.*: *"\(.*\)"/\1/')
    printf '%s\t%s\t%s\n' "$file" "$code" "$label"
  else
    if [[ -s $out.part ]]; then mv "$out.part" "$WISH_OUTDIR/$key.error.json"; else rm -f "$out.part"; fi
    label=$(grep -o '"code" *: *"[^"]*"' "$WISH_OUTDIR/$key.error.json" 2>/dev/null | head -n 1 |
            sed 's/.*: *"\(.*\)"/\1/' || true)
    [[ -n $label ]] || label="curl: $(tr '\n' ' ' <"$out.curl-stderr")"
    rm -f "$out.curl-stderr"
    printf '%s\t%s\t%s\n' "$file" "$code" "$label"
    return 1
  fi
}
export -f classify_one
export WISH_SERVER=$server WISH_OUTDIR=$outdir WISH_MODEL=$model

find "$@" -type f \( -iname '*.obj' -o -iname '*.ply' -o -iname '*.off' -o -iname '*.stl' \) \
     -not -path '*/.*' -print0 | sort -z |
  xargs -0 -r -n 1 -P "$jobs" bash -c 'classify_one "$1"' _ && exit 0
exit 1
