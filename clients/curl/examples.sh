#!/usr/bin/env bash
# The README's curl examples, runnable (and run by tests/clients/test_curl_scripts.py):
#   clients/curl/examples.sh [URL] [MESH] [BAD_MESH]
# Every command must succeed (curl --fail-with-body), and the refused uploads must fail with their status: this
# doubles as a smoke test of a running server. BAD_MESH (default: an open tetrahedron, written here) is refused.
set -euo pipefail
server=${1:-${WISH_SERVER:-http://127.0.0.1:8080}}
mesh=${2:-$(dirname "$0")/../../data/meshes/nucleus-example.obj}
run() { printf '\n$ %s\n' "$*"; "$@"; echo; }

# Liveness and readiness (separate: a live server may not be ready while it loads models or drains).
run curl -sS --fail-with-body "$server/healthz"
run curl -sS --fail-with-body "$server/readyz"

# The loaded models: classes, descriptor settings, training summary.
run curl -sS --fail-with-body "$server/v1/models"

# Classify one mesh sent as the raw body (the Content-Type is a hint; the content is detected).
run curl -sS --fail-with-body -H 'Content-Type: application/octet-stream' --data-binary "@$mesh" \
    "$server/v1/classify"

# Classify several meshes in one multipart request: one result per part, each with its own status. The answer is
# 200 when every part succeeded, 207 Multi-Status when the parts differ, the parts' common status when all failed.
run curl -sS --fail-with-body -F "mesh=@$mesh" -F "mesh=@$mesh" "$server/v1/classify"

# A refused mesh fails the request, uploaded either way: `curl -f` exits 22 on the 422, so a batch script sees it.
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
bad=${3:-$tmp/open.off}
[[ -n ${3:-} ]] || printf 'OFF\n4 3 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n' >"$bad"
for form in "-F mesh=@$bad" "--data-binary @$bad -H Content-Type:application/octet-stream"; do
  printf '\n$ curl -sS -f %s %s/v1/classify\n' "$form" "$server"
  rc=0; code=$(curl -sS -f -o /dev/null -w '%{http_code}' $form "$server/v1/classify" 2>/dev/null) || rc=$?
  echo "exit $rc, HTTP $code"
  [[ $rc == 22 && $code == 422 ]] || { echo "expected curl -f to fail with 422 (exit 22), got HTTP $code exit $rc" >&2; exit 1; }
done

# A batch whose parts differ: 207 Multi-Status, read each part's status.
printf '\n$ curl -sS -w "HTTP %%{http_code}" -F mesh=@%s -F mesh=@%s %s/v1/classify\n' "$mesh" "$bad" "$server"
code=$(curl -sS -o "$tmp/mixed.json" -w '%{http_code}' -F "mesh=@$mesh" -F "mesh=@$bad" "$server/v1/classify")
cat "$tmp/mixed.json"; echo " HTTP $code"
[[ $code == 207 ]] || { echo "expected 207 for a good and a bad part, got $code" >&2; exit 1; }

# Describe: the rotation-invariant energies xi(0..Lmax) with a chosen Lmax.
run curl -sS --fail-with-body -F "mesh=@$mesh" "$server/v1/describe?lmax=10"

# Errors come as {"error": {"code", "message", "details"}, "request_id"} with a 4xx/5xx status.
printf '\n$ curl -sS -w "HTTP %%{http_code}" --data-binary @%s "%s/v1/classify?model=no-such-model"\n' "$mesh" "$server"
body=$tmp/error.json
code=$(curl -sS -o "$body" -w '%{http_code}' -H 'Content-Type: application/octet-stream' --data-binary "@$mesh" \
            "$server/v1/classify?model=no-such-model")
cat "$body"; echo " HTTP $code"
[[ $code == 404 ]] || { echo "expected 404 for an unknown model, got $code" >&2; exit 1; }

# Prometheus metrics (first lines).
printf '\n$ curl -sS %s/metrics | head\n' "$server"
curl -sS --fail-with-body "$server/metrics" | head -n 10
