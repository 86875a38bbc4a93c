"""Scale-out with the real images: N service containers behind the nginx container (docker/nginx, the configuration
docker/compose.yaml runs), all on the host network at distinct 127.0.0.1 ports. The batch client (`wish-client
classify`, its own retries) classifies a folder through nginx while one container is killed (SIGKILL) and another
restarted (SIGTERM drain, then a fresh start). Every mesh must come back exactly once with the result a single
instance gives (no lost, no duplicated rows), and every instance must have taken load.

Run by scripts/test-docker.sh (engine + images WISH_IMAGE, WISH_NGINX_IMAGE); skipped without them.
"""

from __future__ import annotations

import csv
import json
import shutil
import subprocess
import sys
import tempfile
import threading
import unittest
from pathlib import Path

from docker_harness import (SOURCE, container_name, docker, http_ok, logs, metric, nginx_skip_reason, remove,
                            run_nginx, run_service, wait_for)
from loopback import free_ports

N_INSTANCES = 3
N_MESHES = 240
# The two largest closed genus-0 bundled meshes (~0.1 s each): enough work for the run to outlast a restart.
SOURCES = ["celegans_cell.obj", "cube-meshed.off"]


def classify_cli(server: str, folder: Path, out: Path, jobs: int) -> subprocess.Popen:
    """The batch client as a user runs it, with enough retries to outlast an instance's restart."""
    return subprocess.Popen(
        [sys.executable, "-m", "wish_client", "classify", str(folder), "--server", server, "--out", str(out),
         "--jobs", str(jobs), "--retries", "10", "--max-delay", "2", "--timeout", "120", "--no-progress",
         "--summary-json"], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)


def read_rows(path: Path) -> list[dict[str, str]]:
    with path.open(newline="", encoding="utf-8") as f:
        return list(csv.DictReader(f))


def comparable(row: dict[str, str]) -> dict[str, str]:
    """A result row without what legitimately differs between runs (the request id) and with the file's own name."""
    return {k: v for k, v in row.items() if k != "request_id"} | {"file": Path(row["file"]).name}


@unittest.skipIf(nginx_skip_reason(), nginx_skip_reason() or "")
class ScaleOutContainersTest(unittest.TestCase):
    def setUp(self) -> None:
        self.tmp = Path(tempfile.mkdtemp(prefix="wish-scale-docker-"))
        self.addCleanup(shutil.rmtree, self.tmp, True)
        self.meshes = self.tmp / "meshes"
        self.meshes.mkdir()
        for i in range(N_MESHES):
            src = SOURCE / "data" / "meshes" / SOURCES[i % len(SOURCES)]
            shutil.copyfile(src, self.meshes / f"{i:03d}_{src.name}")
        ports = free_ports(N_INSTANCES + 1)
        self.nginx_port, self.ports = ports[0], ports[1:]
        self.names = [container_name() for _ in self.ports]
        for name, port in zip(self.names, self.ports):
            # As the compose file runs them (one worker each here: three instances share the two cores).
            run_service(name, port, env={"WISH_WORKERS": "1", "WISH_QUEUE_SIZE": "4", "WISH_RETRY_AFTER": "1",
                                         "WISH_SHUTDOWN_GRACE": "60"})
            self.addCleanup(remove, name)
        self.nginx = run_nginx(self.tmp / "nginx", self.nginx_port, self.ports,
                               upstream_options="max_fails=1 fail_timeout=2s")
        self.addCleanup(remove, self.nginx)
        for name, port in zip(self.names, self.ports):
            wait_for(lambda: http_ok(f"http://127.0.0.1:{port}/readyz"), f"{name} /readyz ({logs(name)})")
        wait_for(lambda: http_ok(f"http://127.0.0.1:{self.nginx_port}/healthz"), f"nginx ({logs(self.nginx)})")

    def served(self, port: int) -> int:
        return int(metric(port, "wish_http_requests_total", 'route="/v1/classify"'))

    def test_batch_through_nginx_survives_a_kill_and_a_restart(self) -> None:
        # The single-instance run: the same folder against the first instance directly, before any chaos.
        ref_out = self.tmp / "single.csv"
        ref = classify_cli(f"http://127.0.0.1:{self.ports[0]}", self.meshes, ref_out, jobs=2)
        ref_stdout, ref_stderr = ref.communicate(timeout=600)
        self.assertEqual(ref.returncode, 0, ref_stderr)
        before = [self.served(p) for p in self.ports]

        out = self.tmp / "scaled.csv"
        journal = Path(str(out) + ".partial")
        run = classify_cli(f"http://127.0.0.1:{self.nginx_port}", self.meshes, out, jobs=4)
        events: list[str] = []
        served_by_victim: list[int] = []

        def done_so_far() -> int:
            if not journal.exists():
                return 0
            with journal.open() as f:
                return sum(1 for _ in f)

        def chaos() -> None:
            # Event-driven, not timed: kill once a quarter of the meshes are through, restart at a half.
            try:
                wait_for(lambda: done_so_far() >= N_MESHES // 4 or run.poll() is not None, "a quarter done", 600)
                if run.poll() is None:
                    served_by_victim.append(self.served(self.ports[2]) - before[2])
                    docker("kill", "-s", "KILL", self.names[2])
                    events.append(f"killed instance 3 after {done_so_far()} meshes")
                wait_for(lambda: done_so_far() >= N_MESHES // 2 or run.poll() is not None, "a half done", 600)
                if run.poll() is None:
                    at = done_so_far()
                    docker("restart", "-t", "60", self.names[1], timeout=180)
                    events.append(f"restarted instance 2 after {at} meshes (back after {done_so_far()})")
            except Exception as e:  # noqa: BLE001 - reported by the assertions below
                events.append(f"chaos failed: {e}")

        t = threading.Thread(target=chaos)
        t.start()
        stdout, stderr = run.communicate(timeout=900)
        t.join(timeout=300)
        summary = json.loads(stdout)
        print(f"\nscale-out: {N_MESHES} meshes over {N_INSTANCES} containers; {'; '.join(events)}; "
              f"client retries {summary['retries']}; {summary['elapsed_seconds']} s", file=sys.stderr)

        self.assertEqual([e.split(" ", 1)[0] for e in events], ["killed", "restarted"], events)
        self.assertEqual(run.returncode, 0, stderr)
        self.assertEqual(summary["failed_now"], 0, summary["failures"])
        self.assertGreater(served_by_victim[0], 0, "the killed instance never took load")
        wait_for(lambda: http_ok(f"http://127.0.0.1:{self.ports[1]}/readyz"), "the restarted instance ready again")
        print(f"scale-out: the restarted instance served {self.served(self.ports[1])} classify requests after its "
              f"restart", file=sys.stderr)

        rows, ref_rows = read_rows(out), read_rows(ref_out)
        files = [r["file"] for r in rows]
        self.assertEqual(len(files), len(set(files)), "duplicated rows")
        self.assertEqual(sorted(files), sorted(str(p) for p in self.meshes.iterdir()), "lost or unexpected rows")
        self.assertTrue(all(r["status"] == "ok" for r in rows))
        self.assertEqual(sorted((comparable(r) for r in rows), key=lambda r: r["file"]),
                         sorted((comparable(r) for r in ref_rows), key=lambda r: r["file"]))
        access = [line for line in docker("logs", self.nginx).stdout.splitlines() if "/v1/classify" in line]
        moved = sum(1 for line in access if "upstream=" in line and ", " in line.split("upstream=", 1)[1])
        print(f"scale-out: nginx: {len(access)} classify requests, {moved} moved to another instance; "
              f"lost 0, duplicated 0", file=sys.stderr)


if __name__ == "__main__":
    unittest.main()
