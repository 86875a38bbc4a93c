#!/usr/bin/env bash
# The README's curl examples, runnable (and run by tests/clients/test_curl_scripts.py):
#   clients/curl/examples.sh [URL] [MESH]
# Every command must succeed (curl --fail-with-body): this doubles as a smoke test of a running server.
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

# Classify several meshes in one multipart request: one result per part, each with its own status.
run curl -sS --fail-with-body -F "mesh=@$mesh" -F "mesh=@$mesh" "$server/v1/classify"

# Describe: the rotation-invariant energies xi(0..Lmax) with a chosen Lmax.
run curl -sS --fail-with-body -F "mesh=@$mesh" "$server/v1/describe?lmax=10"

# Errors come as {"error": {"code", "message", "details"}, "request_id"} with a 4xx/5xx status.
printf '\n$ curl -sS -w "HTTP %%{http_code}" --data-binary @%s "%s/v1/classify?model=no-such-model"\n' "$mesh" "$server"
body=$(mktemp); trap 'rm -f "$body"' EXIT
code=$(curl -sS -o "$body" -w '%{http_code}' -H 'Content-Type: application/octet-stream' --data-binary "@$mesh" \
            "$server/v1/classify?model=no-such-model")
cat "$body"; echo " HTTP $code"
[[ $code == 404 ]] || { echo "expected 404 for an unknown model, got $code" >&2; exit 1; }

# Prometheus metrics (first lines).
printf '\n$ curl -sS %s/metrics | head\n' "$server"
curl -sS --fail-with-body "$server/metrics" | head -n 10
