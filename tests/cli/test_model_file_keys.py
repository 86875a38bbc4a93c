"""`wish predict --model` refuses a model file with a key it does not know (issue 27), naming the key, its path in
the file and the file, instead of computing the descriptor with its own value of a setting the file states.

The bad file is the bundled default model with one unknown key added and the seal recomputed
(tests/testing/model_file_edit.py), so the unknown key is the only thing wrong with it. Environment (set by ctest):
WISH_BIN, the wish executable; WISH_SHARED_DATA for a mesh (skipped without).
"""
import os
import shutil
import subprocess
import tempfile
import unittest

import model_file_edit

SOURCE_DIR = os.environ.get("WISH_SOURCE_DIR", os.path.abspath(os.path.join(os.path.dirname(__file__), "..", "..")))
WISH_BIN = os.environ.get("WISH_BIN", os.path.join(SOURCE_DIR, "build", "release", "cli", "wish"))
DEFAULT_MODEL = os.path.join(SOURCE_DIR, "data", "models", "default.json")
SHARED = os.environ.get("WISH_SHARED_DATA", os.path.join(SOURCE_DIR, "..", "shared", "data"))
MESH = os.path.join(SHARED, "cgal", "genus0_closed", "sphere.off")
ENV = dict(os.environ, OPENBLAS_NUM_THREADS="1", OMP_NUM_THREADS="1")

SKIP = ("wish binary not found at %s (set WISH_BIN)" % WISH_BIN if not os.path.exists(WISH_BIN) else
        "no bundled default model" if not os.path.exists(DEFAULT_MODEL) else
        "shared test mesh %s not found (set WISH_SHARED_DATA)" % MESH if not os.path.exists(MESH) else None)


def predict(model):
    return subprocess.run([WISH_BIN, "predict", "--model", model, MESH], capture_output=True, text=True, env=ENV,
                          timeout=300)


@unittest.skipIf(SKIP, SKIP or "")
class ModelFileKeysTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.mkdtemp(prefix="wish-model-keys-")

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.tmp, ignore_errors=True)

    def test_the_bundled_model_predicts(self):
        r = predict(DEFAULT_MODEL)
        self.assertEqual(r.returncode, 0, r.stderr)

    def test_unknown_key_is_refused_with_its_path_and_the_file(self):
        for anchor, where in (('"map": {', "payload.recipe.map"), ('"cmcf": {', "payload.recipe.map.cmcf"),
                              ('"svm": {', "payload.svm")):
            bad = os.path.join(self.tmp, "bad-%s.json" % where.replace(".", "-"))
            model_file_edit.with_unknown_key(DEFAULT_MODEL, bad, anchor=anchor)
            r = predict(bad)
            self.assertNotEqual(r.returncode, 0, (where, r.stdout[-2000:]))
            out = r.stderr + r.stdout
            self.assertIn("unknown key %s.%s" % (where, model_file_edit.UNKNOWN_KEY), out)
            self.assertIn(bad, out)
            self.assertIn("model_version", out)
            self.assertNotIn("Traceback", out)

    def test_the_helpers_seal_is_the_loaders(self):
        # So the refusal above is the unknown key's, not the seal's: the helper computes the bundled model's seal.
        with open(DEFAULT_MODEL, encoding="utf-8") as f:
            text = f.read()
        self.assertIn('"payload_sha256": "%s"' % model_file_edit.payload_seal(text), text)

if __name__ == "__main__":
    unittest.main()
