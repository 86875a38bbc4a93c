#!/usr/bin/python3
"""Load run of `wish serve`: POST /v1/describe (or /v1/classify) of one mesh at concurrency 1, 2, 4, 8.

Prints per concurrency: throughput (req/s), p50/p95/p99 latency, errors, server RSS (min/max during the run), and
the single-request pipeline time (timings.total reported by the server, median over the concurrency-1 run) plus
the target of issue 6: throughput at concurrency = cores >= 0.9 * cores / single-request time; p99 < 2 x p50.

  /usr/bin/python3 bench/server_load.py --wish build/server/cli/wish --mesh ../shared/data/cgal/genus0_closed/bear_bis.off \
      --duration 20 [--route /v1/classify --models data/models] [--soak 300]
"""
import argparse
import http.client
import json
import os
import re
import statistics
import subprocess
import sys
import tempfile
import threading
import time


def rss_kib(pid):
    with open("/proc/%d/status" % pid) as f:
        for line in f:
            if line.startswith("VmRSS:"):
                return int(line.split()[1])
    return 0


def percentile(values, q):
    s = sorted(values)
    if not s:
        return float("nan")
    k = min(len(s) - 1, max(0, int(round(q * (len(s) - 1)))))
    return s[k]


def run_level(port, route, mesh, concurrency, duration, pid):
    latencies, totals, errors = [], [], []
    lock = threading.Lock()
    stop_at = time.time() + duration
    rss = [rss_kib(pid)]

    def client():
        conn = http.client.HTTPConnection("127.0.0.1", port, timeout=300)
        while time.time() < stop_at:
            t = time.perf_counter()
            conn.request("POST", route, body=mesh, headers={"Content-Type": "application/octet-stream"})
            r = conn.getresponse()
            body = r.read()
            dt = time.perf_counter() - t
            with lock:
                if r.status == 200:
                    latencies.append(dt)
                    totals.append(json.loads(body)["timings"]["total"])
                else:
                    errors.append(r.status)
        conn.close()

    threads = [threading.Thread(target=client) for _ in range(concurrency)]
    t0 = time.time()
    for t in threads:
        t.start()
    while any(t.is_alive() for t in threads):
        rss.append(rss_kib(pid))
        time.sleep(0.5)
    for t in threads:
        t.join()
    elapsed = time.time() - t0
    return {"concurrency": concurrency, "requests": len(latencies), "errors": len(errors),
            "throughput": len(latencies) / elapsed, "p50": percentile(latencies, 0.5),
            "p95": percentile(latencies, 0.95), "p99": percentile(latencies, 0.99),
            "pipeline_median": statistics.median(totals) if totals else float("nan"),
            "rss_min_mib": min(rss) / 1024, "rss_max_mib": max(rss) / 1024}


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    root = os.path.dirname(here)
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--wish", default=os.path.join(root, "build", "server", "cli", "wish"))
    ap.add_argument("--mesh", default=os.path.join(root, "..", "shared", "data", "cgal", "genus0_closed", "bear_bis.off"))
    ap.add_argument("--route", default="/v1/describe")
    ap.add_argument("--models", default=None, help="models directory (default: an empty one)")
    ap.add_argument("--levels", default="1,2,4,8")
    ap.add_argument("--duration", type=float, default=20.0, help="seconds per concurrency level")
    ap.add_argument("--soak", type=float, default=0.0, help="extra seconds at concurrency = cores, RSS sampled")
    ap.add_argument("--workers", type=int, default=0)
    args = ap.parse_args()

    mesh = open(args.mesh, "rb").read()
    cores = os.cpu_count() or 1
    tmp = tempfile.mkdtemp(prefix="wish-bench-")
    models = args.models or tmp
    log = open(os.path.join(tmp, "server.log"), "wb")
    proc = subprocess.Popen([args.wish, "serve", "--models", models, "--port", "0", "--workers", str(args.workers),
                             "--queue-size", "64"], stdout=log, stderr=subprocess.STDOUT)
    port = None
    for _ in range(600):
        m = re.search(r"listening on http://127\.0\.0\.1:(\d+)", open(log.name, errors="replace").read())
        if m:
            port = int(m.group(1))
            break
        time.sleep(0.05)
    if port is None:
        proc.kill()
        sys.exit("server did not start; log in " + log.name)
    try:
        # Warm-up and the single-request pipeline time measured in the same run.
        run_level(port, args.route, mesh, 1, 2.0, proc.pid)
        print("mesh %s (%d bytes), route %s, cores %d, %.0f s per level" % (os.path.basename(args.mesh), len(mesh),
              args.route, cores, args.duration))
        print("%5s %8s %6s %9s %8s %8s %8s %10s %14s" % ("conc", "requests", "errors", "req/s", "p50 s", "p95 s",
              "p99 s", "pipeline s", "RSS MiB min-max"))
        rows = []
        for c in [int(x) for x in args.levels.split(",")]:
            r = run_level(port, args.route, mesh, c, args.duration, proc.pid)
            rows.append(r)
            print("%5d %8d %6d %9.2f %8.3f %8.3f %8.3f %10.3f %7.0f-%-6.0f" % (
                c, r["requests"], r["errors"], r["throughput"], r["p50"], r["p95"], r["p99"], r["pipeline_median"],
                r["rss_min_mib"], r["rss_max_mib"]))
        single = rows[0]["pipeline_median"] if rows and rows[0]["concurrency"] == 1 else float("nan")
        at_cores = [r for r in rows if r["concurrency"] == cores]
        if at_cores:
            r = at_cores[0]
            target = 0.9 * cores / single
            print("target: throughput at concurrency %d = %.2f req/s vs 0.9 x cores / single (%.3f s) = %.2f -> %s; "
                  "p99/p50 = %.2f (< 2 -> %s)" % (cores, r["throughput"], single, target,
                                                   "met" if r["throughput"] >= target else "NOT met",
                                                   r["p99"] / r["p50"], "met" if r["p99"] < 2 * r["p50"] else "NOT met"))
        if args.soak > 0:
            r = run_level(port, args.route, mesh, cores, args.soak, proc.pid)
            print("soak %.0f s at concurrency %d: %d requests, RSS %.0f-%.0f MiB" % (
                args.soak, cores, r["requests"], r["rss_min_mib"], r["rss_max_mib"]))
    finally:
        proc.terminate()
        proc.wait(timeout=120)


if __name__ == "__main__":
    main()
