"""The service image, run as it is deployed (read-only root, no capabilities, host network on 127.0.0.1):

* it classifies the bundled mesh over HTTP with the baked-in default model,
* Docker's HEALTHCHECK (the image's own command) reports it healthy,
* the server process runs as the image's non-root user and cannot write its root file system,
* a mounted models volume replaces the default model, and SIGHUP loads a model added to it later,
* SIGTERM with a request in flight: the request is answered and the container exits 0.

Run by scripts/test-docker.sh (engine + image); skipped without them.
"""

from __future__ import annotations

import json
import os
import re
import shutil
import tempfile
import threading
import unittest
from pathlib import Path

from docker_harness import (SOURCE, container_name, docker, http_ok, logs, metric, remove, run_service,
                            skip_reason, wait_for, IMAGE)
from loopback import free_ports
from wish_client import WishClient

MESHES = SOURCE / "data" / "meshes"
DEFAULT_MODEL_NAME = "wish-default-synthetic"   # data/models/default.json, baked into the image
WISH_UID = "10001"                               # the image's `wish` user (docker/Dockerfile)
DRAIN_PARTS = 48                                 # meshes in the request that is in flight at SIGTERM


def model_name(label: str | None) -> str:
    """The model's name from the client's ``name@version`` label."""
    return (label or "").split("@", 1)[0]


def train_model(into: Path, name: str) -> Path:
    """A real model named ``name``, trained by the image's own `wish train` on the bundled demo descriptors."""
    out = into / f"{name}.json"
    docker("run", "--rm", "--network", "none", "--entrypoint", "wish", "--user", f"{os.getuid()}:{os.getgid()}",
           "-v", f"{SOURCE / 'data' / 'models'}:/in:ro", "-v", f"{into}:/out", IMAGE,
           "train", "/in/demo-descriptors.csv", "--name", name, "--out", f"/out/{name}.json.tmp",
           "--nested-repeats", "0", "--grid-splits", "2", "--no-compare", "--quiet", "--jobs", "1", timeout=300)
    # Renamed into place only when complete: the server never sees a half-written file.
    os.replace(into / f"{name}.json.tmp", out)
    return out


@unittest.skipIf(skip_reason(), skip_reason() or "")
class DefaultContainerTest(unittest.TestCase):
    """One container on the image's defaults."""

    @classmethod
    def setUpClass(cls) -> None:
        cls.port = free_ports(1)[0]
        cls.name = container_name()
        # The image's HEALTHCHECK command, checked every 2 s instead of 15 s so the test need not wait.
        run_service(cls.name, cls.port, "--health-interval", "2s", "--health-start-period", "1s",
                    env={"WISH_WORKERS": "1"})
        cls.url = f"http://127.0.0.1:{cls.port}"
        try:
            wait_for(lambda: http_ok(cls.url + "/readyz"), "the container's /readyz")
        except Exception:
            print(logs(cls.name))
            remove(cls.name)
            raise

    @classmethod
    def tearDownClass(cls) -> None:
        remove(cls.name)

    def test_classifies_the_bundled_mesh(self) -> None:
        r = WishClient(self.url, timeout=120).classify(MESHES / "sphere.off")
        self.assertEqual(model_name(r.model), DEFAULT_MODEL_NAME)
        self.assertIn(r.label, r.probabilities)
        self.assertAlmostEqual(sum(r.probabilities.values()), 1.0, places=6)
        # Not asserted: label == the class of highest probability. The label is libsvm's one-against-one vote
        # winner and the probabilities its pairwise coupling (Wu, Lin, Weng 2004); on an ambiguous input such as this
        # perfect sphere (no class of the synthetic model) the two can differ (proto/openapi.json Prediction.label).
        self.assertGreater(r.probabilities[r.label], 0.0)

    def test_healthcheck_reports_healthy(self) -> None:
        def health() -> dict:
            return json.loads(docker("inspect", "-f", "{{json .State.Health}}", self.name).stdout)
        wait_for(lambda: health()["Status"] == "healthy", "Docker's health status", timeout=60)
        last = health()["Log"][-1]
        self.assertEqual(last["ExitCode"], 0, last)

    def test_runs_as_non_root_on_a_read_only_root(self) -> None:
        self.assertEqual(docker("inspect", "-f", "{{.HostConfig.ReadonlyRootfs}}", self.name).stdout.strip(), "true")
        # PID 1 is the service itself: the entrypoint execs `wish serve`, which execs `wish-server` (the service
        # executable beside it, cli/cmd_serve.cpp) — same pid, with the wish user's real and effective uid.
        status = docker("exec", self.name, "cat", "/proc/1/status").stdout
        fields = dict(line.split(":", 1) for line in status.splitlines() if ":" in line)
        self.assertEqual(fields["Name"].strip(), "wish-server")
        self.assertEqual(fields["Uid"].split()[:2], [WISH_UID, WISH_UID])
        self.assertEqual(docker("exec", self.name, "id", "-u").stdout.strip(), WISH_UID)  # the image's USER
        for target in ("/usr/local/bin/new-file", "/opt/wish/models/default.json", "/etc/passwd", "/new-file"):
            # Not even root may write: the file system itself refuses (not merely the file's permissions).
            r = docker("exec", "--user", "0", self.name, "sh", "-c", f"echo x >> {target}", check=False)
            self.assertNotEqual(r.returncode, 0, target)
            self.assertIn("Read-only file system", r.stderr, target)
        # /tmp is the one writable place (a tmpfs, as in the Kubernetes manifest).
        self.assertEqual(docker("exec", self.name, "sh", "-c", "echo x > /tmp/probe && cat /tmp/probe").stdout, "x\n")


@unittest.skipIf(skip_reason(), skip_reason() or "")
class ModelsVolumeTest(unittest.TestCase):
    def setUp(self) -> None:
        self.models = Path(tempfile.mkdtemp(prefix="wish-models-"))
        self.addCleanup(shutil.rmtree, self.models, True)
        self.models.chmod(0o755)

    def test_mounted_models_replace_the_default_and_sighup_loads_a_new_one(self) -> None:
        train_model(self.models, "lab-a")
        port = free_ports(1)[0]
        name = container_name()
        run_service(name, port, "-v", f"{self.models}:/models:ro", env={"WISH_WORKERS": "1",
                                                                      "WISH_DEFAULT_MODEL": "lab-a"})
        self.addCleanup(remove, name)
        url = f"http://127.0.0.1:{port}"
        wait_for(lambda: http_ok(url + "/readyz"), f"/readyz ({logs(name)})")
        client = WishClient(url, timeout=120)
        self.assertEqual([m["name"] for m in client.models()], ["lab-a"])  # the baked-in default is not loaded
        self.assertEqual(model_name(client.classify(MESHES / "sphere.off").model), "lab-a")

        train_model(self.models, "lab-b")
        docker("kill", "-s", "HUP", name)
        wait_for(lambda: sorted(m["name"] for m in client.models()) == ["lab-a", "lab-b"], "lab-b after SIGHUP")
        r = client.classify(MESHES / "sphere.off", model="lab-b")
        self.assertEqual(model_name(r.model), "lab-b")
        self.assertIn(r.label, r.probabilities)
        self.assertEqual(metric(port, "wish_model_reloads_total", 'result="ok"'), 1)  # the SIGHUP (not the start)


@unittest.skipIf(skip_reason(), skip_reason() or "")
class SigtermDrainTest(unittest.TestCase):
    def test_sigterm_answers_the_request_in_flight_and_exits_0(self) -> None:
        port = free_ports(1)[0]
        name = container_name()
        run_service(name, port, env={"WISH_WORKERS": "1", "WISH_SHUTDOWN_GRACE": "60",
                                     "WISH_MAX_PARTS": str(DRAIN_PARTS),
                                     "WISH_QUEUE_SIZE": str(DRAIN_PARTS)})
        self.addCleanup(remove, name)
        url = f"http://127.0.0.1:{port}"
        wait_for(lambda: http_ok(url + "/readyz"), f"/readyz ({logs(name)})")
        # One multipart request of many copies of the largest bundled mesh on one worker: seconds of compute, so it
        # is still in flight when the signal arrives (the server's log below confirms it).
        meshes = [MESHES / "celegans_cell.obj"] * DRAIN_PARTS
        outcome: dict[str, object] = {}

        def request() -> None:
            try:
                outcome["result"] = WishClient(url, timeout=120).classify(meshes)
            except Exception as e:  # noqa: BLE001 - the assertion below reports it
                outcome["error"] = e

        t = threading.Thread(target=request)
        t.start()
        wait_for(lambda: metric(port, "wish_workers_busy") >= 1 or not t.is_alive(), "the request reaching a worker",
                 poll=0.02)
        self.assertTrue(t.is_alive(), f"the request ended before the signal: {outcome}")
        docker("kill", "-s", "TERM", name)
        t.join(timeout=120)
        self.assertFalse(t.is_alive())
        self.assertNotIn("error", outcome, outcome.get("error"))
        results = outcome["result"]
        self.assertEqual(len(results), DRAIN_PARTS)
        for r in results:   # every part answered, none cancelled by the shutdown
            self.assertEqual(model_name(getattr(r, "model", None)), DEFAULT_MODEL_NAME, r)
        exit_code = docker("wait", name, timeout=90).stdout.strip()
        self.assertEqual(exit_code, "0", logs(name))
        # The server's own account: the signal came while the request was in flight (server/run_server.cpp).
        drained = re.search(r"draining \((\d+) request", logs(name))
        self.assertIsNotNone(drained, logs(name))
        self.assertGreaterEqual(int(drained.group(1)), 1)


if __name__ == "__main__":
    unittest.main()
