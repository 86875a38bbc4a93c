"""Scale-out on one machine: three real `wish serve` processes on loopback behind nginx (Debian nginx-light, run in
the foreground from a temp prefix, no system config). The batch client classifies a folder through nginx:

* every result is correct (equal to what one instance answers directly for the same mesh),
* the load reaches all three instances (their /metrics request counters),
* killing one instance mid-run loses no mesh (nginx moves on to the next upstream; the client retries the rest).

Skipped without the real binary (WISH_BIN with a `serve` subcommand), nginx, a model, or meshes.
"""

from __future__ import annotations

import contextlib
import json
import os
import re
import shutil
import signal
import subprocess
import tempfile
import time
import unittest
import urllib.request
from pathlib import Path

from wish_client import RetryPolicy, WishClient
from wish_client.batch import Progress, classify_batch, expand_paths, read_records
from loopback import free_ports

SOURCE = Path(os.environ.get("WISH_SOURCE_DIR", Path(__file__).resolve().parents[2]))
SHARED = Path(os.environ.get("WISH_SHARED_DATA", SOURCE.parent / "shared" / "data"))
WISH_BIN = os.environ.get("WISH_BIN", "")
NGINX = shutil.which("nginx") or ("/usr/sbin/nginx" if Path("/usr/sbin/nginx").exists() else None)


def _has_serve() -> str | None:
    """None when the real server can run here, else the reason to skip."""
    if not WISH_BIN or not Path(WISH_BIN).exists():
        return "WISH_BIN is not set or missing (build the `wish` target)"
    try:
        r = subprocess.run([WISH_BIN, "serve", "--help"], capture_output=True, text=True, timeout=30)
    except OSError as e:
        return f"cannot run {WISH_BIN}: {e}"
    if r.returncode != 0:
        return f"{WISH_BIN} has no `serve` subcommand yet"
    if not NGINX:
        return "nginx is not installed (Debian nginx-light)"
    return None


def wait_ready(url: str, proc: subprocess.Popen, timeout: float = 60) -> None:
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if proc.poll() is not None:
            raise RuntimeError(f"{proc.args[0]} exited with {proc.returncode} before becoming ready")
        with contextlib.suppress(OSError):
            with urllib.request.urlopen(url, timeout=2) as r:
                if r.status == 200:
                    return
        time.sleep(0.1)
    raise TimeoutError(f"{url} not ready after {timeout} s")


def requests_served(port: int) -> int:
    """Sum of wish_http_requests_total for the compute routes, from the instance's /metrics."""
    with urllib.request.urlopen(f"http://127.0.0.1:{port}/metrics", timeout=5) as r:
        text = r.read().decode()
    total = 0.0
    for line in text.splitlines():
        if line.startswith("wish_http_requests_total") and "/v1/classify" in line:
            total += float(line.rsplit(" ", 1)[1])
    return int(total)


def pick_meshes(dest: Path, count: int) -> list[Path]:
    """Small closed genus-0 meshes, copied (under distinct names) into ``dest``: fast to classify."""
    bundled = sorted((SOURCE / "data" / "meshes").glob("*.off")) + sorted((SOURCE / "data" / "meshes").glob("*.obj"))
    candidates = [p for p in bundled if p.name != "eight.off"]  # eight.off is the bundled genus-2 negative case
    candidates += [SHARED / "cgal" / "genus0_closed" / n for n in ("sphere.off", "ellipsoid.off", "geosphere.off",
                                                                    "blob-closed.off", "dragknob.off")]
    small = [p for p in candidates if p.exists() and p.stat().st_size < 150_000]
    out = []
    for i in range(count):
        src = small[i % len(small)]
        target = dest / f"{i:03d}_{src.name}"
        shutil.copyfile(src, target)
        out.append(target)
    return out


NGINX_CONF = """
{user}
worker_processes 1;
daemon off;
master_process on;
pid {prefix}/nginx.pid;
error_log {prefix}/error.log warn;
events {{ worker_connections 256; }}
http {{
  log_format upstreamlog '$request $status upstream=$upstream_addr upstream_status=$upstream_status';
  access_log {prefix}/access.log upstreamlog;
  client_body_temp_path {prefix}/body;
  proxy_temp_path {prefix}/proxy;
  fastcgi_temp_path {prefix}/fastcgi;
  uwsgi_temp_path {prefix}/uwsgi;
  scgi_temp_path {prefix}/scgi;
  client_max_body_size 64m;
  upstream wish {{
    least_conn;
{servers}
    keepalive 16;
  }}
  server {{
    listen 127.0.0.1:{port};
    location / {{
      proxy_pass http://wish;
      proxy_http_version 1.1;
      proxy_set_header Connection "";
      proxy_set_header X-Request-Id $request_id;
      # A dead or overloaded instance: try the next one (POST included: classify is idempotent).
      proxy_next_upstream error timeout http_502 http_503 non_idempotent;
      proxy_next_upstream_tries 3;
      proxy_connect_timeout 2s;
      proxy_read_timeout 120s;
    }}
  }}
}}
"""


@unittest.skipIf(_has_serve(), _has_serve() or "")
class ScaleOutTest(unittest.TestCase):
    N_INSTANCES = 3
    N_MESHES = 24

    @classmethod
    def setUpClass(cls) -> None:
        cls.tmp = Path(tempfile.mkdtemp(prefix="wish-scale-"))
        models = SOURCE / "data" / "models"
        if not (models / "default.json").exists():
            raise unittest.SkipTest("data/models/default.json is missing (the default model)")
        cls.meshes = cls.tmp / "meshes"
        cls.meshes.mkdir()
        pick_meshes(cls.meshes, cls.N_MESHES)
        if not any(cls.meshes.iterdir()):
            raise unittest.SkipTest("no small meshes in data/meshes or the shared data")
        ports = free_ports(cls.N_INSTANCES + 1)
        cls.nginx_port, cls.ports = ports[0], ports[1:]
        cls.procs: list[subprocess.Popen] = []
        env = dict(os.environ, OPENBLAS_NUM_THREADS="1", OMP_NUM_THREADS="1")
        for i, port in enumerate(cls.ports):
            with open(cls.tmp / f"wish-{i}.log", "w") as log:  # the child keeps its own descriptor
                cls.procs.append(subprocess.Popen(
                    [WISH_BIN, "serve", "--models", str(models), "--host", "127.0.0.1", "--port", str(port),
                     "--workers", "1", "--queue-size", "4", "--retry-after", "1"],
                    stdout=log, stderr=subprocess.STDOUT, env=env))
        prefix = cls.tmp / "nginx"
        prefix.mkdir()
        servers = "\n".join(f"    server 127.0.0.1:{p} max_fails=1 fail_timeout=5s;" for p in cls.ports)
        # As root, nginx workers would drop to `nobody` and could not use the private temp prefix.
        user = "user root;" if os.geteuid() == 0 else ""
        (prefix / "nginx.conf").write_text(NGINX_CONF.format(prefix=prefix, servers=servers, port=cls.nginx_port,
                                                             user=user))
        cls.nginx = subprocess.Popen([NGINX, "-p", str(prefix), "-c", str(prefix / "nginx.conf"), "-e",
                                      str(prefix / "error.log")], stdout=subprocess.DEVNULL,
                                     stderr=subprocess.DEVNULL)
        try:
            for port, proc in zip(cls.ports, cls.procs):
                wait_ready(f"http://127.0.0.1:{port}/readyz", proc)
            wait_ready(f"http://127.0.0.1:{cls.nginx_port}/healthz", cls.nginx)
        except Exception:
            cls.tearDownClass()
            raise

    @classmethod
    def tearDownClass(cls) -> None:
        for p in [*cls.procs, getattr(cls, "nginx", None)]:
            if p is not None and p.poll() is None:
                p.send_signal(signal.SIGTERM if p is not getattr(cls, "nginx", None) else signal.SIGQUIT)
        for p in [*cls.procs, getattr(cls, "nginx", None)]:
            if p is not None:
                try:
                    p.wait(timeout=15)
                except subprocess.TimeoutExpired:
                    p.kill()

    def reference(self, files: list[str]) -> dict[str, str]:
        """Each mesh's label from one instance directly (the service is deterministic)."""
        direct = WishClient(f"http://127.0.0.1:{self.ports[0]}", retry=RetryPolicy(max_attempts=10, base_delay=0.2))
        out: dict[str, str] = {}
        for name in sorted({Path(f).name.split("_", 1)[1] for f in files}):
            src = next(f for f in files if Path(f).name.endswith("_" + name))
            out[name] = direct.classify(src).label
        return out

    def test_batch_through_nginx_survives_losing_an_instance(self) -> None:
        files = expand_paths([self.meshes])
        expected_by_source = self.reference(files)
        before = [requests_served(p) for p in self.ports]
        out = self.tmp / "results.csv"
        client = WishClient(f"http://127.0.0.1:{self.nginx_port}",
                            retry=RetryPolicy(max_attempts=8, base_delay=0.2, max_delay=2.0), timeout=120)
        victim = self.procs[2]
        killed_after: list[int] = []
        served_by_victim = 0
        count = 0

        def on_record(rec) -> None:
            # Kill one instance once a third of the meshes are through AND it has served at least one of them in
            # this run (its counter is read right here, just before it dies, so "it took load" is a fact, not a
            # race with a polling thread on a busy machine).
            nonlocal count, served_by_victim
            count += 1
            if killed_after or count < self.N_MESHES // 3 or victim.poll() is not None:
                return
            with contextlib.suppress(OSError):
                served_by_victim = requests_served(self.ports[2])
            if served_by_victim > before[2]:
                victim.kill()
                killed_after.append(count)

        report = classify_batch(client, files, out, jobs=4, progress=Progress(len(files), enabled=False),
                                on_record=on_record)

        self.assertTrue(killed_after, "the instance was never killed: the run was too short or the victim took no load")
        self.assertIsNotNone(victim.poll())
        self.assertEqual(report.failures, [], [f"{r.file}: {r.error_code} {r.error_message}" for r in report.failures])
        records = {r.file: r for r in read_records(out)}
        self.assertEqual(len(records), len(files))  # no mesh lost
        for f in files:
            self.assertEqual(records[f].status, "ok", f)
            self.assertEqual(records[f].label, expected_by_source[Path(f).name.split("_", 1)[1]], f)
        after = [requests_served(p) for p in self.ports[:2]]
        served = [a - b for a, b in zip(after, before[:2])] + [served_by_victim - before[2]]
        self.assertTrue(all(n > 0 for n in served), f"requests per instance {served}: not all took load")
        log = (self.tmp / "nginx" / "access.log").read_text()
        upstreams = set(re.findall(r"upstream=127\.0\.0\.1:(\d+)", log))
        self.assertEqual(upstreams, {str(p) for p in self.ports})
        print(f"\nscale-out: {len(files)} meshes, per instance {served}, killed after {killed_after[0]}, "
              f"client retries {report.retries}")


if __name__ == "__main__":
    unittest.main()
