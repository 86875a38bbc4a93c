#!/usr/bin/python3
"""Run time of two builds of the service, paired: does a change of how the service is compiled (optimisation level,
precompiled headers, unity batches) change what it computes or how fast?

Starts `A` and `B` (two wish-server executables) on 127.0.0.1 with one worker each and OPENBLAS_NUM_THREADS=1, sends
one warm-up request to each, then N rounds of POST /v1/classify of MESH, alternating which server goes first. Prints
the median server CPU seconds per request (utime + stime of the process from /proc, across the request) and wall
seconds of each, the ratio B / A, and whether the two servers' last responses agree once the fields that are
timings or request ids are removed. Bounded: N rounds, each request with a 600 s timeout.

    /usr/bin/python3 bench/server_build_ab.py A/cli/wish-server B/cli/wish-server MESH [--rounds 10] [--models DIR]
"""
import argparse
import json
import os
import statistics
import subprocess
import sys
import time
import urllib.request
import uuid

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from server_load import cpu_seconds  # noqa: E402 (utime + stime of the server process, as the load bench reads it)


def classify(port, path):
    with open(path, "rb") as f:
        data = f.read()
    boundary = uuid.uuid4().hex
    body = (("--%s\r\nContent-Disposition: form-data; name=\"mesh\"; filename=\"%s\"\r\n"
             "Content-Type: application/octet-stream\r\n\r\n") % (boundary, os.path.basename(path))).encode()
    body += data + ("\r\n--%s--\r\n" % boundary).encode()
    request = urllib.request.Request("http://127.0.0.1:%d/v1/classify" % port, data=body,
                                     headers={"Content-Type": "multipart/form-data; boundary=" + boundary})
    with urllib.request.urlopen(request, timeout=600) as response:
        return response.status, response.read()


def start(executable, port, models):
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1", OMP_NUM_THREADS="1")
    process = subprocess.Popen([executable, "--models", models, "--port", str(port), "--workers", "1"],
                               stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, env=env)
    for _ in range(300):
        try:
            urllib.request.urlopen("http://127.0.0.1:%d/healthz" % port, timeout=1)
            return process
        except OSError:
            if process.poll() is not None:
                raise SystemExit("%s exited with %d" % (executable, process.returncode))
            time.sleep(0.1)
    process.terminate()
    raise SystemExit("%s did not answer /healthz within 30 s" % executable)


def without_timings(value):
    """The response with every timing field and request id removed (they differ between any two requests)."""
    if isinstance(value, dict):
        return {k: without_timings(v) for k, v in value.items()
                if "second" not in k and k not in ("request_id", "timings", "profile")}
    if isinstance(value, list):
        return [without_timings(v) for v in value]
    return value


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("a")
    parser.add_argument("b")
    parser.add_argument("mesh")
    parser.add_argument("--rounds", type=int, default=10)
    parser.add_argument("--models", default=os.path.join(HERE, "..", "data", "models"))
    parser.add_argument("--ports", type=int, nargs=2, default=[18601, 18602])
    args = parser.parse_args()
    servers = {"A": (start(args.a, args.ports[0], args.models), args.ports[0]),
               "B": (start(args.b, args.ports[1], args.models), args.ports[1])}
    samples = {"A": [], "B": []}
    last = {}
    try:
        for name, (_, port) in servers.items():
            classify(port, args.mesh)
        for i in range(args.rounds):
            for name in ("A", "B") if i % 2 == 0 else ("B", "A"):
                process, port = servers[name]
                cpu0, t0 = cpu_seconds(process.pid), time.monotonic()
                status, body = classify(port, args.mesh)
                if status != 200:
                    raise SystemExit("%s answered %d" % (name, status))
                samples[name].append((cpu_seconds(process.pid) - cpu0, time.monotonic() - t0))
                last[name] = json.loads(body)
    finally:
        for process, _ in servers.values():
            process.terminate()
            process.wait()
    same = without_timings(last["A"]) == without_timings(last["B"])
    print("mesh %s, %d rounds" % (args.mesh, args.rounds))
    print("%-4s %14s %12s" % ("", "CPU s/request", "wall s"))
    for name in "AB":
        print("%-4s %14.3f %12.3f" % (name, statistics.median(s[0] for s in samples[name]),
                                      statistics.median(s[1] for s in samples[name])))
    print("B/A CPU ratio %.3f; responses without timings identical: %s" % (
        statistics.median(s[0] for s in samples["B"]) / statistics.median(s[0] for s in samples["A"]),
        "yes" if same else "NO"))
    return 0 if same else 1


if __name__ == "__main__":
    raise SystemExit(main())
