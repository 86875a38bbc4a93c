"""GET /v1/models/{name}/report (issue 14, "Models"): the training report `wish train` wrote beside a model file,
served as written and validated against proto's TrainingReport; 404 model_not_found for an unknown model, 404
report_not_found for a model without one; read when asked for (a replaced report is served at once)."""
import json
import os
import shutil
import tempfile
import unittest

import model_file_edit
import wish_server_harness as h

SKIP = h.skip_reason_binary() or (None if os.path.exists(h.DEFAULT_MODEL) else "no bundled default model")
DEFAULT_REPORT = os.path.join(h.SOURCE_DIR, "data", "models", "default-report.json")


def renamed_model(path, name):
    """The text of the model file at `path` under another model name, resealed as the C++ writer seals (the number
    tokens kept as written: tests/testing/model_file_edit.py)."""
    with open(path, encoding="utf-8") as f:
        text = f.read()
    old = '"name": %s' % json.dumps(json.loads(text)["payload"]["name"])
    assert text.count(old) == 1, old
    text = text.replace(old, '"name": %s' % json.dumps(name))
    return text.replace(json.loads(text)["payload_sha256"], model_file_edit.payload_seal(text))


@unittest.skipIf(SKIP, SKIP or "")
class ModelReportTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.mkdtemp(prefix="wish-report-")
        cls.models = h.models_dir_with_default(cls.tmp)
        shutil.copy(DEFAULT_REPORT, os.path.join(cls.models, "default-report.json"))
        with open(os.path.join(cls.models, "bare.json"), "w", encoding="utf-8") as f:  # no report beside it
            f.write(renamed_model(h.DEFAULT_MODEL, "bare"))
        with open(DEFAULT_REPORT) as f:
            cls.report = json.load(f)
        with open(h.DEFAULT_MODEL) as f:
            cls.name = json.load(f)["payload"]["name"]  # the route takes the model's name, not its file's
        cls.server = h.Server(models_dir=cls.models, args=["--workers", "1", "--default-model", cls.name])

    @classmethod
    def tearDownClass(cls):
        cls.server.__exit__(None, None, None)
        shutil.rmtree(cls.tmp, ignore_errors=True)

    def test_report_is_served_as_written_and_matches_the_contract(self):
        r = self.server.request("GET", "/v1/models/%s/report" % self.name)
        self.assertEqual(r.status, 200, r.body[:400])
        self.assertTrue(r.header("Content-Type").startswith("application/json"))
        body = r.json()
        h.validate("TrainingReport", body)
        self.assertEqual(body, self.report)
        # What the page draws is in it: a C x gamma grid, a classes x classes confusion matrix, per-class scores.
        grid = body["grid"]
        self.assertEqual(len(grid["mean_accuracy"]), len(grid["C"]))
        self.assertTrue(all(len(row) == len(grid["gamma"]) for row in grid["mean_accuracy"]))
        n = len(body["classes"])
        self.assertEqual([len(row) for row in body["test"]["confusion_matrix"]], [n] * n)
        # The report and the model agree: the hold-out accuracy is the confusion matrix's trace over its total.
        cm = body["test"]["confusion_matrix"]
        self.assertAlmostEqual(sum(cm[i][i] for i in range(n)) / sum(map(sum, cm)), body["test"]["accuracy"])
        info = self.server.request("GET", "/v1/models/" + self.name).json()
        self.assertAlmostEqual(info["training_summary"]["test_accuracy"], body["test"]["accuracy"])

    def test_model_without_report_is_404_report_not_found(self):
        self.assertEqual(self.server.request("GET", "/v1/models/bare").status, 200)  # the model itself is loaded
        r = self.server.request("GET", "/v1/models/bare/report")
        self.assertEqual(r.status, 404, r.body[:400])
        h.validate("Error", r.json())
        self.assertEqual(r.json()["error"]["code"], "report_not_found")
        self.assertEqual(r.json()["error"]["details"], {"model": "bare", "file": "bare-report.json"})
        self.assertEqual(r.json()["request_id"], r.header("X-Request-Id"))

    def test_unknown_model_is_404_model_not_found(self):
        r = self.server.request("GET", "/v1/models/no-such-model/report")
        self.assertEqual(r.status, 404)
        h.validate("Error", r.json())
        self.assertEqual(r.json()["error"]["code"], "model_not_found")

    def test_other_methods_are_405_with_allow(self):
        r = self.server.request("POST", "/v1/models/%s/report" % self.name, body=b"")
        self.assertEqual(r.status, 405)
        self.assertEqual(r.header("Allow"), "GET, HEAD")
        self.assertEqual(r.json()["error"]["code"], "method_not_allowed")

    def test_report_is_read_when_asked_for(self):
        path = os.path.join(self.models, "bare-report.json")
        try:
            changed = dict(self.report, model_file="bare.json", samples=self.report["samples"] + 1)
            with open(path, "w") as f:
                json.dump(changed, f)
            r = self.server.request("GET", "/v1/models/bare/report")
            self.assertEqual(r.status, 200)
            self.assertEqual(r.json(), changed)
            with open(path, "w") as f:  # not a JSON object: no usable report, not a 500
                f.write("[1, 2")
            r = self.server.request("GET", "/v1/models/bare/report")
            self.assertEqual(r.status, 404)
            self.assertEqual(r.json()["error"]["code"], "report_not_found")
        finally:
            os.remove(path)

    def test_reports_are_not_models(self):
        # The report beside the model is skipped by the registry without an error line (issue 15).
        names = sorted(m["name"] for m in self.server.request("GET", "/v1/models").json()["models"])
        self.assertEqual(names, sorted(["bare", self.name]))
        self.assertNotIn("refused default-report.json", self.server.log_text())


if __name__ == "__main__":
    unittest.main()
