"""clients/curl: the batch script (curl + xargs -P) and the README examples script, against the fake server."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import tempfile
import unittest
from pathlib import Path

from fake_wish_server import FakeWishServer, fake_mesh

SOURCE = Path(os.environ.get("WISH_SOURCE_DIR", Path(__file__).resolve().parents[2]))
BATCH = SOURCE / "clients" / "curl" / "wish-batch.sh"
EXAMPLES = SOURCE / "clients" / "curl" / "examples.sh"


@unittest.skipUnless(shutil.which("curl") and shutil.which("xargs"), "needs curl and xargs")
class CurlScriptsTest(unittest.TestCase):
    def setUp(self) -> None:
        self.server = FakeWishServer(delay=0.02).__enter__()
        self.addCleanup(self.server.__exit__)
        self.tmp = Path(tempfile.mkdtemp(prefix="wish-curl-"))
        self.meshes = self.tmp / "meshes"
        self.labels = {f"a/m{i}.obj": ["neuron", "pericyte", "microglia"][i % 3] for i in range(9)}
        for rel, label in self.labels.items():
            (self.meshes / rel).parent.mkdir(parents=True, exist_ok=True)
            (self.meshes / rel).write_bytes(fake_mesh(label))

    def batch(self, *paths: str, jobs: int = 3) -> subprocess.CompletedProcess[str]:
        return subprocess.run(["bash", str(BATCH), "-s", self.server.url, "-j", str(jobs), "-o",
                               str(self.tmp / "out"), *paths], capture_output=True, text=True, timeout=120)

    def test_batch_classifies_in_parallel_and_resumes(self) -> None:
        self.server.busy_next(3, retry_after="0")  # curl --retry honours Retry-After
        r = self.batch(str(self.meshes))
        self.assertEqual(r.returncode, 0, r.stderr + r.stdout)
        lines = [line.split("\t") for line in r.stdout.strip().splitlines()]
        got = {os.path.relpath(f, self.meshes): (code, label) for f, code, label in lines}
        self.assertEqual(got, {k: ("200", v) for k, v in self.labels.items()})
        self.assertEqual(len(list((self.tmp / "out").glob("*.json"))), 9)
        saved = json.loads(next((self.tmp / "out").glob("*m0.obj.json")).read_text())
        self.assertEqual(saved["prediction"]["label"], "neuron")
        self.assertGreater(self.server.max_in_flight, 1)
        before = len(self.server.compute_requests())
        self.assertEqual(before, 9 + 3)
        r = self.batch(str(self.meshes))  # resume: nothing left to do
        self.assertEqual((r.returncode, r.stdout), (0, ""))
        self.assertEqual(len(self.server.compute_requests()), before)

    def test_batch_reports_refusals_and_fails(self) -> None:
        (self.meshes / "torus.obj").write_bytes(fake_mesh(error="genus_nonzero"))
        r = self.batch(str(self.meshes))
        self.assertEqual(r.returncode, 1)
        self.assertIn("torus.obj\t422\tgenus_nonzero", r.stdout)
        self.assertTrue(list((self.tmp / "out").glob("*torus.obj.error.json")))

    def test_examples_script(self) -> None:
        mesh = self.tmp / "example.obj"
        mesh.write_bytes(fake_mesh("astrocyte"))
        bad = self.tmp / "open.obj"
        bad.write_bytes(fake_mesh(error="not_closed"))
        r = subprocess.run(["bash", str(EXAMPLES), self.server.url, str(mesh), str(bad)], capture_output=True,
                           text=True, timeout=60)
        self.assertEqual(r.returncode, 0, r.stderr + r.stdout)
        self.assertIn('"label": "astrocyte"', r.stdout)
        self.assertEqual(r.stdout.count("exit 22, HTTP 422"), 2)  # multipart and raw body: curl -f fails
        self.assertIn("HTTP 207", r.stdout)
        self.assertEqual(self.server.batch_statuses, [200, 422, 207, 200])  # good batch, bad alone, mixed, describe
        self.assertIn("model_not_found", r.stdout)
        self.assertIn("wish_http_requests_total", r.stdout)


if __name__ == "__main__":
    unittest.main()
