#!/usr/bin/python3
"""The service at its CPU bound: `wish serve` on N workers, POST /v1/classify of a mesh at 1, 2, 8, 64 concurrent
clients, against the bound cores / (server CPU seconds per request, measured alone).

For each mesh (the NeuroMorphoVis nucleus, ~10.8K vertices, and the same nucleus midpoint-subdivided twice, ~172K
vertices, made here and written as binary PLY into a temporary folder: never committed) a fresh server is started
on 127.0.0.1 with --workers W and --queue-size Q, then:

  alone    S sequential requests: the server's CPU seconds per request (utime + stime of the process, from
           /proc/PID/stat, over the S requests) and the median latency. bound = min(cores, workers) / CPU s per request.
  levels   for each concurrency C: exactly M requests (bounded count; M a multiple of C and of W, so no worker idles
           at the end for want of work), C client threads taking them from a shared counter. A 503 must carry
           Retry-After; the client waits that long and sends the same request again (counted, not lost). Any other
           answer, a 503 without Retry-After or a socket error is a lost request. Each level is also bounded in time
           (--level-timeout): past it the clients stop and the level is reported as cut short.
           Reported: throughput (M / wall time of the level) and its share of the bound; p50 / p99 latency of the
           answered requests (the last attempt: queue wait included); 503s; 504s (time limit passed: lost too);
           lost; server CPU seconds per answered
           request and CPU use (share of the cores); peak RSS and threads sampled every 0.1 s; the load generator's
           own CPU share (it shares the cores with the server). The server's own counters
           (wish_http_requests_total) are checked against what the clients saw: a request the client counts as
           answered 200 or 503 must be in the server's counts, and nothing else.

  /usr/bin/python3 bench/server_load.py [--wish build/release/cli/wish] [--levels 1,2,8,64] [--workers 2]
      [--queue-size 32] [--meshes nucleus,subdivided] [--soak 300] [--server-args '--admit-fraction 0']
      [--vs OTHER_WISH]

--vs: the same levels against a second executable (e.g. a build of another commit), each mesh's two servers one
after the other in this run, so the two tables are measured under the same load (rows marked A and B).

--soak S: afterwards, S seconds at concurrency W on the first mesh with the RSS peak per minute (a memory leak
shows as a rising peak). Everything runs on 127.0.0.1; the server is stopped by its pid.
"""
import argparse
import http.client
import json
import math
import os
import re
import statistics
import struct
import subprocess
import sys
import tempfile
import threading
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
NUCLEUS = os.path.join(ROOT, "..", "shared", "data", "nmv_nuclei", "nuclei-meshes", "hq", "nucleus-1.obj")
CLOCK_TICKS = os.sysconf("SC_CLK_TCK")


# ---- meshes -------------------------------------------------------------------------------------------------------

def read_obj(path):
    vertices, faces = [], []
    with open(path) as f:
        for line in f:
            if line.startswith("v "):
                vertices.append(tuple(float(x) for x in line.split()[1:4]))
            elif line.startswith("f "):
                idx = [int(tok.split("/")[0]) for tok in line.split()[1:]]
                idx = [i - 1 if i > 0 else len(vertices) + i for i in idx]
                faces.extend((idx[0], idx[k], idx[k + 1]) for k in range(1, len(idx) - 1))  # fan
    return vertices, faces


def midpoint_subdivide(vertices, faces):
    """Each triangle into four through its edge midpoints: the same surface, about 4x the vertices (V + E)."""
    vertices = list(vertices)
    midpoint = {}

    def mid(a, b):
        key = (a, b) if a < b else (b, a)
        m = midpoint.get(key)
        if m is None:
            p, q = vertices[a], vertices[b]
            m = midpoint[key] = len(vertices)
            vertices.append(((p[0] + q[0]) / 2, (p[1] + q[1]) / 2, (p[2] + q[2]) / 2))
        return m

    out = []
    for a, b, c in faces:
        ab, bc, ca = mid(a, b), mid(b, c), mid(c, a)
        out += [(a, ab, ca), (ab, b, bc), (ca, bc, c), (ab, bc, ca)]
    return vertices, out


def binary_ply(vertices, faces):
    header = ("ply\nformat binary_little_endian 1.0\nelement vertex %d\nproperty double x\nproperty double y\n"
              "property double z\nelement face %d\nproperty list uchar int vertex_indices\nend_header\n"
              % (len(vertices), len(faces))).encode()
    body = bytearray(header)
    body += b"".join(struct.pack("<3d", *v) for v in vertices)
    body += b"".join(struct.pack("<B3i", 3, *f) for f in faces)
    return bytes(body)


def make_meshes(names, nucleus_path, tmp):
    """{name: (path, vertices)}: the nucleus as it is, its subdivision (twice) as binary PLY in tmp."""
    vertices, faces = read_obj(nucleus_path)
    meshes = {}
    if "nucleus" in names:
        meshes["nucleus"] = (nucleus_path, len(vertices))
    if "subdivided" in names:
        for _ in range(2):
            vertices, faces = midpoint_subdivide(vertices, faces)
        path = os.path.join(tmp, "nucleus-1-subdivided-x2.ply")
        with open(path, "wb") as f:
            f.write(binary_ply(vertices, faces))
        meshes["subdivided"] = (path, len(vertices))
    return meshes


# ---- the server process -------------------------------------------------------------------------------------------

def cpu_seconds(pid):
    """utime + stime of a process, seconds (all its threads)."""
    with open("/proc/%d/stat" % pid) as f:
        fields = f.read().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / CLOCK_TICKS


def status_fields(pid):
    out = {}
    with open("/proc/%d/status" % pid) as f:
        for line in f:
            key, _, value = line.partition(":")
            if key in ("VmRSS", "VmHWM", "Threads"):
                out[key] = int(value.split()[0])
    return out


class Server:
    def __init__(self, wish, models, workers, queue_size, tmp, extra_args=()):
        self.seen = {}  # {status: count} of the answers the bench's clients have read from this server
        self.log_path = os.path.join(tmp, "server-%d.log" % time.time_ns())
        self.log = open(self.log_path, "wb")
        # `wish serve ...` or the service executable itself (`wish-server ...`: what `wish serve` runs).
        command = [wish] if os.path.basename(wish) == "wish-server" else [wish, "serve"]
        self.proc = subprocess.Popen(command + ["--models", models, "--host", "127.0.0.1", "--port", "0",
                                                "--workers", str(workers), "--queue-size", str(queue_size)]
                                     + list(extra_args),
                                     stdout=self.log, stderr=subprocess.STDOUT)
        self.port = None
        for _ in range(600):
            m = re.search(r"listening on http://127\.0\.0\.1:(\d+)", open(self.log_path, errors="replace").read())
            if m:
                self.port = int(m.group(1))
                break
            if self.proc.poll() is not None:
                break
            time.sleep(0.05)
        if self.port is None:
            self.stop()
            sys.exit("server did not start; log in " + self.log_path)

    def cpu(self):
        return cpu_seconds(self.proc.pid)

    def status_counts(self, route):
        """{status: count} of wish_http_requests_total for one route (the server's own view)."""
        conn = http.client.HTTPConnection("127.0.0.1", self.port, timeout=30)
        conn.request("GET", "/metrics")
        text = conn.getresponse().read().decode()
        conn.close()
        out = {}
        for m in re.finditer(r'wish_http_requests_total\{route="([^"]*)",status="(\d+)"\} (\d+)', text):
            if m.group(1) == route:
                out[int(m.group(2))] = int(m.group(3))
        return out

    def settled_counts(self, route, seen_by_clients, wait=5.0):
        """status_counts once they include every answer the clients have read (`seen_by_clients`, {status: count}
        since the server started). The server counts a request after writing its answer, so a read right after the
        client's last answer can miss it, and the next level would count it as its own. Past `wait` seconds the last
        read is returned as it is (a real disagreement then shows as DIFFER)."""
        deadline = time.time() + wait
        while True:
            counts = self.status_counts(route)
            if all(counts.get(s, 0) >= n for s, n in seen_by_clients.items()) or time.time() > deadline:
                return counts
            time.sleep(0.02)

    def stop(self):
        self.proc.terminate()
        self.proc.wait(timeout=120)
        self.log.close()


def post(conn, route, body):
    conn.request("POST", route, body=body, headers={"Content-Type": "application/octet-stream"})
    r = conn.getresponse()
    return r.status, r.getheader("Retry-After"), r.read()


# ---- measurements -------------------------------------------------------------------------------------------------

def alone(server, route, body, count):
    """Sequential requests on an idle server: (CPU s per request, median latency s)."""
    conn = http.client.HTTPConnection("127.0.0.1", server.port, timeout=600)
    latencies = []
    cpu0 = server.cpu()
    for _ in range(count):
        t = time.perf_counter()
        status, _, answer = post(conn, route, body)
        latencies.append(time.perf_counter() - t)
        if status != 200:
            sys.exit("a request alone failed with %d: %s" % (status, answer[:300]))
    cpu = (server.cpu() - cpu0) / count
    conn.close()
    server.seen[200] = server.seen.get(200, 0) + count
    return cpu, statistics.median(latencies)


class Sampler:
    """Peak RSS and thread count of the server every 0.1 s while running."""

    def __init__(self, pid):
        self.pid, self.rss_kib, self.threads, self.trace = pid, 0, 0, []
        self.running = True
        self.t0 = time.time()
        self.thread = threading.Thread(target=self.run, daemon=True)
        self.thread.start()

    def run(self):
        while self.running:
            s = status_fields(self.pid)
            self.rss_kib = max(self.rss_kib, s["VmRSS"])
            self.threads = max(self.threads, s["Threads"])
            self.trace.append((time.time() - self.t0, s["VmRSS"]))
            time.sleep(0.1)

    def stop(self):
        self.running = False
        self.thread.join()


def run_level(server, route, body, clients, requests, timeout):
    """`requests` requests by `clients` threads; 503 + Retry-After is waited out and sent again."""
    lock = threading.Lock()
    state = {"next": 0, "latencies": [], "rejected": 0, "lost": [], "answered": 0, "statuses": {}}
    deadline = time.time() + timeout

    def client():
        conn = http.client.HTTPConnection("127.0.0.1", server.port, timeout=timeout)
        while True:
            with lock:
                if state["next"] >= requests or time.time() > deadline:
                    break
                state["next"] += 1
            while True:
                t = time.perf_counter()
                try:
                    status, retry_after, _ = post(conn, route, body)
                except (OSError, http.client.HTTPException) as e:
                    with lock:
                        state["lost"].append(type(e).__name__)
                    conn.close()
                    break
                dt = time.perf_counter() - t
                if status == 503 and retry_after is not None and time.time() < deadline:
                    with lock:
                        state["rejected"] += 1
                        state["statuses"][503] = state["statuses"].get(503, 0) + 1
                    time.sleep(float(retry_after))
                    continue
                with lock:
                    state["statuses"][status] = state["statuses"].get(status, 0) + 1
                    if status == 200:
                        state["latencies"].append(dt)
                        state["answered"] += 1
                    elif status == 503 and retry_after is not None:
                        state["lost"].append("503 after the level's time limit")
                    else:
                        state["lost"].append("%d%s" % (status, " without Retry-After" if status == 503 else ""))
                break
        conn.close()

    counts0 = server.settled_counts(route, server.seen)
    sampler = Sampler(server.proc.pid)
    cpu0, own0 = server.cpu(), os.times()
    t0 = time.perf_counter()
    threads = [threading.Thread(target=client) for _ in range(clients)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    wall = time.perf_counter() - t0
    cpu, own1 = server.cpu() - cpu0, os.times()
    sampler.stop()
    for status, n in state["statuses"].items():
        server.seen[status] = server.seen.get(status, 0) + n
    counts1 = server.settled_counts(route, server.seen)
    seen = {s: counts1.get(s, 0) - counts0.get(s, 0) for s in set(counts0) | set(counts1)}
    seen = {s: n for s, n in seen.items() if n}
    expected = {s: n for s, n in state["statuses"].items() if n}
    lat = sorted(state["latencies"])
    return {"clients": clients, "requests": requests, "answered": state["answered"], "rejected": state["rejected"],
            "timeouts": state["statuses"].get(504, 0),
            "lost": state["lost"], "cut_short": state["answered"] + len(state["lost"]) < requests, "wall": wall,
            "throughput": state["answered"] / wall, "p50": percentile(lat, 0.50), "p99": percentile(lat, 0.99),
            "cpu_per_request": cpu / max(1, state["answered"]), "cpu_use": cpu / wall,
            "client_cpu": (own1.user + own1.system - own0.user - own0.system) / wall,
            "rss_mib": sampler.rss_kib / 1024, "threads": sampler.threads,
            "server_counts_agree": seen == expected, "server_counts": seen, "rss_trace": sampler.trace}


def percentile(sorted_values, q):
    """Nearest-rank percentile of an ascending list."""
    if not sorted_values:
        return float("nan")
    k = max(0, min(len(sorted_values) - 1, math.ceil(q * len(sorted_values)) - 1))
    return sorted_values[k]


def requests_for(clients, workers, seconds_per_request, target_seconds):
    """A multiple of both the clients and the workers, about target_seconds of work at the bound, >= clients."""
    step = math.lcm(clients, workers)
    per_second = workers / seconds_per_request
    return max(step, step * round(target_seconds * per_second / step))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--wish", default=os.path.join(ROOT, "build", "release", "cli", "wish"),
                    help="the wish executable, or wish-server")
    ap.add_argument("--models", default=os.path.join(ROOT, "data", "models"))
    ap.add_argument("--route", default="/v1/classify")
    ap.add_argument("--nucleus", default=NUCLEUS, help="the ~10.8K-vertex nucleus OBJ")
    ap.add_argument("--meshes", default="nucleus,subdivided")
    ap.add_argument("--levels", default="1,2,8,64")
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--queue-size", type=int, default=32)
    ap.add_argument("--seconds", type=float, default=20.0,
                    help="about this much work at the bound per level (count rounded to the clients and workers)")
    ap.add_argument("--level-timeout", type=float, default=600.0, help="seconds a level may take at most")
    ap.add_argument("--single", type=int, default=0, help="sequential requests alone (0: about 10 s of them)")
    ap.add_argument("--soak", type=float, default=0.0, help="extra seconds at concurrency = workers, RSS per minute")
    ap.add_argument("--server-args", default="", help="more arguments for the server (split on spaces)")
    ap.add_argument("--vs", default="", help="a second wish executable measured the same way in this run (rows B)")
    args = ap.parse_args()
    if not os.path.isfile(args.nucleus):
        sys.exit("nucleus mesh not found: %s (../shared/data/nmv_nuclei)" % args.nucleus)

    cores = os.cpu_count() or 1
    levels = [int(x) for x in args.levels.split(",")]
    tmp = tempfile.mkdtemp(prefix="wish-load-")
    meshes = make_meshes(args.meshes.split(","), args.nucleus, tmp)
    print("POST %s, %d workers, queue %d, %d cores; bound = min(cores, workers) / server CPU s per request alone"
          % (args.route, args.workers, args.queue_size, cores))
    header = ("%-1s %-10s %7s %5s %4s %5s %4s %4s %7s %6s %8s %8s %7s %6s %6s %7s %4s %s"
              % ("", "mesh", "vertices", "conc", "reqs", "503s", "504s", "lost", "req/s", "bound", "p50 s", "p99 s",
                 "CPU s/r", "CPU %", "client", "RSS MiB", "thr", "server counts"))
    servers = [("A", args.wish)] + ([("B", args.vs)] if args.vs else [])
    for label, wish in servers:
        print("%s = %s %s" % (label, wish, args.server_args))
    rows, soaked, soak_line = [], False, None
    for (name, (path, vertices)), (label, wish) in ((m, w) for m in meshes.items() for w in servers):
        body = open(path, "rb").read()
        server = Server(wish, args.models, args.workers, args.queue_size, tmp, args.server_args.split())
        try:
            cpu1, _ = alone(server, args.route, body, 1)  # also the warm-up
            single = args.single or max(3, min(20, int(10 / cpu1)))
            cpu_alone, latency_alone = alone(server, args.route, body, single)
            bound = min(cores, args.workers) / cpu_alone
            print("%s %s: %d vertices, %d bytes; alone (%d requests): %.3f CPU s and %.3f s per request -> bound %.2f "
                  "req/s" % (label, name, vertices, len(body), single, cpu_alone, latency_alone, bound))
            for c in levels:
                r = run_level(server, args.route, body, c, requests_for(c, args.workers, cpu_alone, args.seconds),
                              args.level_timeout)
                r.update(mesh=name, vertices=vertices, bound=bound, label=label)
                rows.append(r)
            if args.soak > 0 and not soaked:
                soaked = True
                r = run_level(server, args.route, body, args.workers, 10 ** 9, args.soak)  # bounded by time
                minutes = {}
                for t, kib in r["rss_trace"]:
                    minutes.setdefault(int(t // 60), []).append(kib / 1024)
                peaks = [max(v) for _, v in sorted(minutes.items())]
                soak_line = "soak %.0f s at concurrency %d on %s: %d answered, %d lost; RSS peak per minute (MiB): %s" % (
                    args.soak, args.workers, name, r["answered"], len(r["lost"]), " ".join("%.0f" % p for p in peaks))
        finally:
            server.stop()
    print()
    print(header)
    for r in rows:
        print("%-1s %-10s %7d %5d %4d %5d %4d %4d %7.2f %5.0f%% %8.3f %8.3f %7.3f %5.0f%% %5.1f%% %7.0f %4d %s%s" % (
            r["label"], r["mesh"], r["vertices"], r["clients"], r["requests"], r["rejected"], r["timeouts"],
            len(r["lost"]), r["throughput"],
            100 * r["throughput"] / r["bound"], r["p50"], r["p99"], r["cpu_per_request"], 100 * r["cpu_use"] / cores,
            100 * r["client_cpu"] / cores, r["rss_mib"], r["threads"],
            "agree" if r["server_counts_agree"] else "DIFFER %s" % r["server_counts"],
            " (cut short by --level-timeout)" if r["cut_short"] else ""))
    lost = sum(len(r["lost"]) for r in rows)
    print("lost requests: %d%s" % (lost, "" if not lost else " " + str([r["lost"] for r in rows if r["lost"]])))
    for label, _ in servers:
        saturated = [r for r in rows if r["clients"] >= 2 * args.workers and r["label"] == label]
        if saturated:
            worst = min(r["throughput"] / r["bound"] for r in saturated)
            print("%s at saturation (>= %d clients): %.0f %% of the bound at worst -> target 90 %% %s" % (
                label, 2 * args.workers, 100 * worst, "met" if worst >= 0.9 else "NOT met"))

    if soak_line:
        print(soak_line)


if __name__ == "__main__":
    main()
