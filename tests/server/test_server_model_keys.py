"""`wish serve --models DIR` refuses a model file with a key it does not know (issue 27): at start and on reload the
file is refused with the key, its path in the file and the file named in the log and in the reload report, the model
is not listed, and the good models beside it are served. The bad file is the bundled default model under another
name with one unknown key added and the seal recomputed (tests/testing/model_file_edit.py)."""
import json
import os
import shutil
import tempfile
import unittest

import model_file_edit
import wish_server_harness as h

SKIP = h.skip_reason_binary() or (None if os.path.exists(h.DEFAULT_MODEL) else "no bundled default model")


@unittest.skipIf(SKIP, SKIP or "")
class ServerModelKeysTest(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.mkdtemp(prefix="wish-server-model-keys-")
        self.models = h.models_dir_with_default(self.tmp)
        # Another name than the default model's, so that it would be a second model if it loaded.
        renamed = os.path.join(self.tmp, "renamed.json")
        with open(h.DEFAULT_MODEL, encoding="utf-8") as f:
            text = f.read()
        name = '"name": "wish-default-synthetic"'
        self.assertEqual(text.count(name), 1)
        text = text.replace(name, '"name": "with-unknown-key"')
        text = text.replace(json.loads(text)["payload_sha256"], model_file_edit.payload_seal(text))
        with open(renamed, "w", encoding="utf-8") as f:
            f.write(text)
        self.bad = os.path.join(self.models, "bad.json")
        model_file_edit.with_unknown_key(renamed, self.bad, anchor='"cmcf": {')

    def tearDown(self):
        shutil.rmtree(self.tmp, ignore_errors=True)

    def test_refused_at_start_and_on_reload_with_the_key_named(self):
        with h.Server(models_dir=self.models) as s:
            log = s.log_text()
            self.assertIn("refused bad.json", log)
            self.assertIn("unknown key payload.recipe.map.cmcf." + model_file_edit.UNKNOWN_KEY, log)
            self.assertIn(self.bad, log)
            listed = [m["name"] for m in s.request("GET", "/v1/models").json()["models"]]
            self.assertIn("wish-default-synthetic", listed)
            self.assertNotIn("with-unknown-key", listed)
            self.assertEqual(s.request("GET", "/v1/models/with-unknown-key").status, 404)
            report = s.request("POST", "/v1/admin/reload")
            self.assertEqual(report.status, 200)
            h.validate("ReloadReport", report.json())
            refused = [r for r in report.json()["refused"] if r["file"] == "bad.json"]
            self.assertEqual(len(refused), 1, report.json())
            self.assertIn("unknown key payload.recipe.map.cmcf." + model_file_edit.UNKNOWN_KEY, refused[0]["message"])
            self.assertEqual(s.post_mesh("/v1/classify", h.read_bytes(h.shared("genus0_closed", "sphere.off"))).status,
                             200)

    def test_the_same_file_without_the_key_loads(self):
        # Control: the renamed model, resealed by the same helper but with nothing unknown, is served — so the
        # refusal above is the unknown key's.
        os.remove(self.bad)
        shutil.copy(os.path.join(self.tmp, "renamed.json"), os.path.join(self.models, "renamed.json"))
        with h.Server(models_dir=self.models) as s:
            listed = [m["name"] for m in s.request("GET", "/v1/models").json()["models"]]
            self.assertIn("with-unknown-key", listed)


if __name__ == "__main__":
    unittest.main()
