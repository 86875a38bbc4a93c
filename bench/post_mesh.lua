-- wrk script for bench/server_load.py --client wrk: POSTs the mesh named by WISH_MESH as the raw body, and prints one
-- machine-readable summary line (latencies in microseconds; errors = non-2xx responses + socket errors).
local f = assert(io.open(os.getenv("WISH_MESH"), "rb"))
wrk.method = "POST"
wrk.body = f:read("*all")
f:close()
wrk.headers["Content-Type"] = "application/octet-stream"

done = function(summary, latency, requests)
  local e = summary.errors
  io.write(string.format("WRK requests=%d errors=%d duration_us=%d p50=%d p95=%d p99=%d\n", summary.requests,
                         e.status + e.connect + e.read + e.write + e.timeout, summary.duration,
                         latency:percentile(50), latency:percentile(95), latency:percentile(99)))
end
