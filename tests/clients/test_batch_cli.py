"""`wish-client classify` against a fake server: folders, parallelism, output formats, retries, resume, summary."""

from __future__ import annotations

import contextlib
import csv
import io
import json
import os
import subprocess
import sys
import tempfile
import unittest
from pathlib import Path

from fake_wish_server import FakeWishServer, fake_mesh

from wish_client.batch import expand_paths, read_records
from wish_client.cli import EXIT_FAILED, EXIT_OK, EXIT_UNREACHABLE, EXIT_USAGE, main
from wish_client.errors import WishInputError

FAST = ["--retries", "4", "--max-delay", "0.05", "--timeout", "10", "--no-progress"]


def run_cli(*argv: str) -> tuple[int, str, str]:
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main(list(argv))
    return code, out.getvalue(), err.getvalue()


def make_folder(root: Path, labels: dict[str, str]) -> None:
    """Writes one fake mesh per ``relative path -> label`` (label "!code" makes a mesh the server refuses)."""
    for rel, label in labels.items():
        p = root / rel
        p.parent.mkdir(parents=True, exist_ok=True)
        if label.startswith("!"):
            p.write_bytes(fake_mesh(error=label[1:]))
        else:
            p.write_bytes(fake_mesh(label, fmt="off" if rel.endswith(".off") else "obj"))


class ExpandTest(unittest.TestCase):
    def test_folders_recursive_sorted_filtered(self) -> None:
        with tempfile.TemporaryDirectory() as d:
            root = Path(d)
            for rel in ["b/2.obj", "b/1.PLY", "a.off", "notes.txt", ".hidden/x.obj", "b/.y.obj", "c/d/e.stl"]:
                (root / rel).parent.mkdir(parents=True, exist_ok=True)
                (root / rel).write_text("x")
            got = [os.path.relpath(p, d) for p in expand_paths([d])]
            self.assertEqual(got, ["a.off", "b/1.PLY", "b/2.obj", "c/d/e.stl"])
            # explicit files are kept whatever their extension; duplicates dropped
            self.assertEqual(expand_paths([root / "notes.txt", root / "a.off", str(root / "a.off")]),
                             [str(root / "notes.txt"), str(root / "a.off")])
            with self.assertRaises(WishInputError):
                expand_paths([root / "missing"])


class BatchCliTest(unittest.TestCase):
    def setUp(self) -> None:
        self.server = FakeWishServer(delay=0.02).__enter__()
        self.addCleanup(self.server.__exit__)
        self.tmp = Path(tempfile.mkdtemp(prefix="wish-client-batch-"))
        self.meshes = self.tmp / "meshes"
        self.labels = {f"set{i % 3}/cell{i:02d}.{'off' if i % 2 else 'obj'}": ["neuron", "astrocyte", "pericyte"][i % 3]
                       for i in range(18)}
        make_folder(self.meshes, self.labels)

    def expected(self) -> dict[str, str]:
        return {os.path.normpath(str(self.meshes / k)): v for k, v in self.labels.items()}

    def test_csv_output_summary_and_parallelism(self) -> None:
        out = self.tmp / "results.csv"
        code, stdout, _ = run_cli("classify", str(self.meshes), "--server", self.server.url, "--jobs", "4",
                                  "--out", str(out), *FAST)
        self.assertEqual(code, EXIT_OK)
        with out.open(newline="") as f:
            rows = list(csv.DictReader(f))
        self.assertEqual({r["file"]: r["label"] for r in rows}, self.expected())
        self.assertTrue(all(r["status"] == "ok" for r in rows))
        self.assertIn("prob_neuron", rows[0])
        self.assertAlmostEqual(float(rows[0][f"prob_{rows[0]['label']}"]), 0.75)
        # The novelty flag beside the label (the fake server calls none of these novel).
        self.assertEqual({r["novel"] for r in rows}, {"false"})
        self.assertEqual(float(rows[0]["novelty_p_value"]), 0.5)
        self.assertEqual({(r["novelty_nearest_class"], r["novelty_distance_ratio"]) for r in rows},
                         {(r["label"], "0.333") for r in rows})
        self.assertEqual([r["file"] for r in rows], sorted(self.expected()))  # output follows input order
        self.assertIn("18 classified, 0 failed", stdout)
        self.assertRegex(stdout, r"neuron\s+6")
        self.assertFalse(Path(str(out) + ".partial").exists())
        self.assertGreater(self.server.max_in_flight, 1)  # requests really were in parallel
        self.assertLessEqual(self.server.max_in_flight, 4)

    def test_json_output_failures_and_exit_status(self) -> None:
        make_folder(self.meshes, {"bad/torus.obj": "!genus_nonzero", "bad/open.obj": "!not_closed"})
        out = self.tmp / "results.json"
        code, stdout, _ = run_cli("classify", str(self.meshes), "--server", self.server.url, "-j", "3",
                                  "-o", str(out), *FAST)
        self.assertEqual(code, EXIT_FAILED)
        doc = json.loads(out.read_text())
        by_file = {r["file"]: r for r in doc["results"]}
        torus = by_file[os.path.normpath(str(self.meshes / "bad/torus.obj"))]
        self.assertEqual((torus["status"], torus["error_code"]), ("error", "genus_nonzero"))
        self.assertTrue(torus["request_id"])
        self.assertEqual(doc["summary"]["failed_now"], 2)
        self.assertEqual(doc["summary"]["per_class"], {"astrocyte": 6, "neuron": 6, "pericyte": 6})
        self.assertIn("genus_nonzero: 1", stdout)
        self.assertIn("torus.obj: refused: genus_nonzero", stdout)

    def test_retries_on_503_and_dropped_connections_lose_nothing(self) -> None:
        self.server.busy_next(5, retry_after="0")
        self.server.drop_next(2)
        out = self.tmp / "r.csv"
        code, _, _ = run_cli("classify", str(self.meshes), "--server", self.server.url, "-j", "4",
                             "-o", str(out), *FAST, "--summary-json")
        self.assertEqual(code, EXIT_OK)
        recs = {r.file: r.label for r in read_records(out)}
        self.assertEqual(recs, self.expected())
        self.assertEqual(len(self.server.compute_requests()), 18 + 7)

    def test_resume_skips_done_and_retries_failed(self) -> None:
        out = self.tmp / "r.csv"
        make_folder(self.meshes, {"late.obj": "!queue_full_forever"})
        code, _, _ = run_cli("classify", str(self.meshes), "--server", self.server.url, "-o", str(out), *FAST)
        self.assertEqual(code, EXIT_FAILED)
        first = len(self.server.compute_requests())
        self.assertEqual(first, 19)
        make_folder(self.meshes, {"late.obj": "oligodendrocyte", "new.obj": "microglia"})  # fixed + one new file
        code, stdout, _ = run_cli("classify", str(self.meshes), "--server", self.server.url, "-o", str(out), *FAST)
        self.assertEqual(code, EXIT_OK, stdout)
        self.assertEqual(len(self.server.compute_requests()) - first, 2)  # only late.obj and new.obj
        self.assertIn("18 already done (skipped)", stdout)
        recs = {r.file: (r.status, r.label) for r in read_records(out)}
        self.assertEqual(recs[os.path.normpath(str(self.meshes / "late.obj"))], ("ok", "oligodendrocyte"))
        self.assertEqual(len(recs), 20)

    def test_resume_from_journal_of_an_interrupted_run(self) -> None:
        out = self.tmp / "r.json"
        done = sorted(self.expected())[:5]
        with open(str(out) + ".partial", "w") as f:
            for file in done:
                f.write(json.dumps({"file": file, "status": "ok", "label": "neuron"}) + "\n")
            f.write('{"file": "torn')  # a line cut by the crash
        code, stdout, _ = run_cli("classify", str(self.meshes), "--server", self.server.url, "-o", str(out), *FAST)
        self.assertEqual(code, EXIT_OK)
        self.assertEqual(len(self.server.compute_requests()), 13)
        self.assertIn("5 already done", stdout)
        self.assertFalse(Path(str(out) + ".partial").exists())
        self.assertEqual(len(json.loads(out.read_text())["results"]), 18)

    def test_unreachable_server_records_connection_errors(self) -> None:
        self.server.__exit__()
        out = self.tmp / "r.csv"
        code, stdout, _ = run_cli("classify", str(self.meshes / "set0"), "--server", self.server.url, "-o",
                                  str(out), "--retries", "1", "--max-delay", "0.01", "--no-progress")
        self.assertEqual(code, EXIT_FAILED)
        self.assertTrue(all(r.error_code == "connection_error" for r in read_records(out)))
        self.assertIn("connection_error: 6", stdout)

    def test_usage_errors(self) -> None:
        self.assertEqual(run_cli("classify", str(self.meshes), "--out", str(self.tmp / "r.txt"))[0], EXIT_USAGE)
        self.assertEqual(run_cli("classify", str(self.tmp / "nope"), "--out", str(self.tmp / "r.csv"))[0],
                         EXIT_USAGE)

    def test_models_and_health_commands(self) -> None:
        code, stdout, _ = run_cli("models", "--server", self.server.url)
        self.assertEqual((code, json.loads(stdout)[0]["name"]), (EXIT_OK, "default"))
        code, stdout, _ = run_cli("health", "--server", self.server.url)
        self.assertEqual((code, json.loads(stdout)["ready"]), (EXIT_OK, True))
        code, _, err = run_cli("models", "missing", "--server", self.server.url)
        self.assertEqual(code, EXIT_FAILED)
        self.assertIn("model_not_found", err)

    def test_console_script_progress_on_stderr(self) -> None:
        """The real entry point, as a subprocess: progress lines on stderr, summary on stdout."""
        env = dict(os.environ, PYTHONPATH=os.pathsep.join(sys.path))
        proc = subprocess.run([sys.executable, "-m", "wish_client", "classify", str(self.meshes), "--server",
                               self.server.url, "-o", str(self.tmp / "r.csv")], capture_output=True, text=True,
                              env=env, timeout=60)
        self.assertEqual(proc.returncode, 0, proc.stderr)
        self.assertIn("18/18", proc.stderr)
        self.assertIn("per class", proc.stdout)
        proc = subprocess.run([sys.executable, "-m", "wish_client", "health", "--server",
                               "http://127.0.0.1:9", "--retries", "0"], capture_output=True, text=True, env=env,
                              timeout=60)
        self.assertEqual(proc.returncode, EXIT_UNREACHABLE, proc.stderr)


if __name__ == "__main__":
    unittest.main()
