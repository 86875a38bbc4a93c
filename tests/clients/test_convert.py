"""clients/convert: scikit-learn Pipeline -> WISH model file; predictions compared with scikit-learn itself, the
seal with nlohmann's number printing, and (when the binary is there) with the C++ `wish predict`."""

from __future__ import annotations

import csv
import json
import os
import pickle
import random
import shutil
import struct
import subprocess
import sys
import tempfile
import unittest
from pathlib import Path

import numpy as np

SOURCE = Path(os.environ.get("WISH_SOURCE_DIR", Path(__file__).resolve().parents[2]))
sys.path.insert(0, str(SOURCE / "clients" / "convert"))

import sklearn_to_wish as conv  # noqa: E402
import wish_model_json as mj  # noqa: E402
from sklearn.pipeline import Pipeline  # noqa: E402
from sklearn.preprocessing import StandardScaler  # noqa: E402
from sklearn.svm import SVC  # noqa: E402

CLASSES = ["astrocyte", "microglia", "neuron", "pericyte"]


def synthetic_spectra(n_per_class: int = 15, lmax: int = 6, seed: int = 7) -> tuple[np.ndarray, list[str]]:
    """ξ(0..lmax) rows: a class-specific decay and size, log-normal noise (energies are positive)."""
    rng = np.random.default_rng(seed)
    xi, y = [], []
    for c, name in enumerate(CLASSES):
        size = 10.0 * (1 + c)
        decay = 1.5 + 0.4 * c
        for _ in range(n_per_class):
            ls = np.arange(lmax + 1)
            row = size * np.exp(-decay * ls) * np.exp(rng.normal(0, 0.35, lmax + 1))
            row[0] = rng.uniform(0, 50)  # the position term, not used
            xi.append(row)
            y.append(name)
    return np.asarray(xi), y


def write_describe_csv(path: Path, xi: np.ndarray, labels: list[str] | None = None) -> None:
    lmax = xi.shape[1] - 1
    with path.open("w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["file", "n_vertices", "fit_error_mean", "fit_error_rms", "fit_error_max"] +
                   [f"xi_{l}" for l in range(lmax + 1)] + (["label"] if labels else []))
        for i, row in enumerate(xi):
            w.writerow([f"meshes/m{i:03d}.obj", 1000, 0.01, 0.01, 0.05] + [repr(float(v)) for v in row] +
                       ([labels[i]] if labels else []))


class ConvertTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls) -> None:
        cls.xi, cls.y = synthetic_spectra()
        cls.spec = conv.feature_spec(l_max=5, l_min=1, log=True)
        x = conv.apply_feature_spec(cls.xi, cls.spec)
        cls.pipe = Pipeline([("scale", StandardScaler()),
                             ("svm", SVC(kernel="rbf", C=10, gamma=0.1, probability=True, random_state=0))]).fit(x, cls.y)
        cls.doc = conv.pipeline_to_model(cls.pipe, cls.spec, lmax=6, name="test-model")
        cls.tmp = Path(tempfile.mkdtemp(prefix="wish-convert-"))

    def test_document_shape(self) -> None:
        p = self.doc["payload"]
        self.assertEqual((self.doc["format"], self.doc["format_version"]), ("wish-classifier", 2))
        self.assertEqual(p["classes"], CLASSES)
        self.assertEqual(p["recipe"]["features"]["names"], ["xi_1", "xi_2", "xi_3", "xi_4", "xi_5"])
        self.assertEqual(p["recipe"]["sh"]["lmax"], 6)
        # The version of the model the map/sh settings came from (the bundled one): it says which keys they hold.
        bundled = conv.read_model(conv.BUNDLED_MODEL, check_seal=False)["payload"]["recipe"]["recipe_version"]
        self.assertEqual(p["recipe"]["recipe_version"], bundled)
        self.assertIn(p["recipe"]["off_recipe"], ("refuse", "accept_flagged"))
        svm = p["svm"]
        self.assertEqual(sum(svm["n_sv"]), len(svm["support_vectors"]))
        self.assertEqual(len(svm["sv_coef"]), len(CLASSES) - 1)
        self.assertEqual(len(svm["rho"]), len(CLASSES) * (len(CLASSES) - 1) // 2)
        self.assertEqual(len(svm["prob_a"]), len(svm["rho"]))

    def test_predictions_match_sklearn(self) -> None:
        """Labels exactly; probabilities and pairwise decision values to libsvm's precision."""
        rng = np.random.default_rng(1)
        xi = np.vstack([self.xi, self.xi * np.exp(rng.normal(0, 0.3, self.xi.shape))])  # unseen points too
        x = conv.apply_feature_spec(xi, self.spec)
        ours = conv.predict_with_model(self.doc, xi)
        self.assertEqual([o["label"] for o in ours], list(self.pipe.predict(x)))
        proba = self.pipe.predict_proba(x)
        got = np.array([[o["probabilities"][c] for c in CLASSES] for o in ours])
        np.testing.assert_allclose(got, proba, atol=1e-5)
        svc = self.pipe.steps[1][1]
        svc.decision_function_shape = "ovo"  # libsvm's pairwise values, pair (i < j) in class order
        try:
            dec = svc.decision_function(self.pipe.steps[0][1].transform(x))
        finally:
            svc.decision_function_shape = "ovr"
        np.testing.assert_allclose(np.array([o["decision"] for o in ours]), dec, rtol=1e-9, atol=1e-9)

    def test_two_classes_sign_convention(self) -> None:
        keep = [i for i, c in enumerate(self.y) if c in ("astrocyte", "neuron")]
        xi, y = self.xi[keep], [self.y[i] for i in keep]
        x = conv.apply_feature_spec(xi, self.spec)
        pipe = Pipeline([("s", StandardScaler()), ("v", SVC(C=1, gamma=0.5, probability=True, random_state=0))])
        pipe.fit(x, y)
        doc = conv.pipeline_to_model(pipe, self.spec)
        ours = conv.predict_with_model(doc, xi)
        self.assertEqual([o["label"] for o in ours], list(pipe.predict(x)))
        np.testing.assert_allclose([o["probabilities"]["neuron"] for o in ours], pipe.predict_proba(x)[:, 1],
                                   atol=1e-5)

    def test_file_round_trip_and_seal(self) -> None:
        path = self.tmp / "model.json"
        conv.write_model(self.doc, path)
        again = conv.read_model(path)
        self.assertEqual(again["payload_sha256"], self.doc["payload_sha256"])
        text = path.read_text()
        path.write_text(text.replace('"notes": "', '"notes": "edited '))
        with self.assertRaisesRegex(ValueError, "payload_sha256"):
            conv.read_model(path)

    def test_rejects_what_the_service_cannot_run(self) -> None:
        x = conv.apply_feature_spec(self.xi, self.spec)
        with self.assertRaisesRegex(ValueError, "RBF"):
            conv.pipeline_to_model(Pipeline([("s", StandardScaler()), ("v", SVC(kernel="linear", probability=True))])
                                   .fit(x, self.y), self.spec)
        with self.assertRaisesRegex(ValueError, "probability=True"):
            conv.pipeline_to_model(Pipeline([("s", StandardScaler()), ("v", SVC())]).fit(x, self.y), self.spec)
        with self.assertRaises(TypeError):
            conv.pipeline_to_model(SVC(), self.spec)
        with self.assertRaisesRegex(ValueError, "features"):
            conv.pipeline_to_model(self.pipe, conv.feature_spec(l_max=3))

    def test_cli_train_convert_check(self) -> None:
        csv_path = self.tmp / "describe.csv"
        write_describe_csv(csv_path, self.xi, self.y)
        model = self.tmp / "trained.json"
        pick = self.tmp / "pipe.pickle"
        script = str(SOURCE / "clients" / "convert" / "sklearn_to_wish.py")
        run = lambda *a: subprocess.run([sys.executable, script, *a], capture_output=True, text=True, timeout=120)
        r = run("train", str(csv_path), "--C", "10", "--gamma", "0.1", "--log", "--l-max", "5", "--lmax", "6",
                "--out", str(model), "--save-pipeline", str(pick))
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn("4 classes", r.stdout)
        r = run("check", str(model), str(csv_path), "--pipeline", str(pick))
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn("60/60 labels agree", r.stderr)
        converted = self.tmp / "converted.json"
        r = run("convert", str(pick), "--log", "--lmax", "6", "--out", str(converted))
        self.assertEqual(r.returncode, 0, r.stderr)
        a, b = conv.read_model(model)["payload"], conv.read_model(converted)["payload"]
        self.assertEqual(a["svm"], b["svm"])
        self.assertEqual(a["recipe"]["features"], b["recipe"]["features"])


class CanonicalJsonTest(unittest.TestCase):
    def test_nlohmann_layout(self) -> None:
        cases = [(0.0, "0.0"), (-0.0, "-0.0"), (1.0, "1.0"), (0.1, "0.1"), (1e-4, "0.0001"), (1e-5, "1e-05"),
                 (123.5, "123.5"), (1e15, "1e+15"), (1e14, "100000000000000.0"), (2.5e-7, "2.5e-07"),
                 (-3.25e20, "-3.25e+20"), (1e100, "1e+100")]
        for v, text in cases:
            self.assertEqual(mj.format_double(v), text, v)
        self.assertEqual(mj.dumps({"b": [1, 2.0, True, None], "a": "é\n"}), '{"a":"é\\n","b":[1,2.0,true,null]}')

    def test_grisu_safe_is_close(self) -> None:
        rnd = random.Random(5)
        for _ in range(2000):
            v = struct.unpack("d", struct.pack("Q", rnd.getrandbits(64)))[0]
            if v != v or v in (float("inf"), float("-inf")) or v == 0:
                continue
            s = mj.grisu_safe(v)
            self.assertLess(abs(s - v) / abs(v), 1e-12)
            self.assertLessEqual(len(mj._shortest_digits(s)[0]), 15)

    @unittest.skipUnless(shutil.which("g++") and Path("/usr/include/nlohmann/json.hpp").exists(),
                         "needs g++ and nlohmann-json3-dev")
    def test_matches_nlohmann_dump(self) -> None:
        """The seal is only right if nlohmann prints every number as we do: check 20 000 random doubles."""
        tmp = Path(tempfile.mkdtemp(prefix="wish-nlohmann-"))
        (tmp / "t.cpp").write_text('#include <nlohmann/json.hpp>\n#include <iostream>\nint main(){std::string s;'
                                   'std::getline(std::cin,s);std::cout<<nlohmann::json::parse(s).dump();}\n')
        subprocess.run(["g++", "-O0", "-std=c++17", str(tmp / "t.cpp"), "-o", str(tmp / "t")], check=True,
                       timeout=120)
        rnd = random.Random(11)
        vals = []
        for i in range(20000):
            v = (rnd.uniform(-1, 1) if i % 3 == 0 else rnd.gauss(0, 1) * 10 ** rnd.randint(-30, 30) if i % 3 == 1
                 else struct.unpack("d", struct.pack("Q", rnd.getrandbits(64)))[0])
            if v == v and abs(v) != float("inf"):
                vals.append(v)
        payload = {"values": vals, "name": "x", "n": 3}
        text = mj.dumps(payload)
        out = subprocess.run([str(tmp / "t")], input=text, capture_output=True, text=True, timeout=60).stdout
        self.assertEqual(out, text)


@unittest.skipUnless(os.environ.get("WISH_BIN") and Path(os.environ.get("WISH_BIN", "")).exists(),
                     "WISH_BIN not set or missing: the C++ comparison needs the built `wish`")
class CppComparisonTest(unittest.TestCase):
    """The converted model, loaded by the C++ service code, predicts what scikit-learn predicts."""

    @classmethod
    def setUpClass(cls) -> None:
        # One scikit-learn model on ξ(1..5) of fits at Lmax 6, converted to a wish model file.
        cls.wish = os.environ["WISH_BIN"]
        cls.tmp = Path(tempfile.mkdtemp(prefix="wish-cpp-"))
        cls.xi, y = synthetic_spectra(lmax=6)
        spec = conv.feature_spec(l_max=5, log=True)
        cls.features = conv.apply_feature_spec(cls.xi, spec)
        cls.pipe = Pipeline([("s", StandardScaler()), ("v", SVC(C=10, gamma=0.1, probability=True, random_state=0))])
        cls.pipe.fit(cls.features, y)
        cls.model = cls.tmp / "model.json"
        conv.write_model(conv.pipeline_to_model(cls.pipe, spec, lmax=6), cls.model)

    def predict(self, xi: np.ndarray, *extra: str) -> subprocess.CompletedProcess:
        csv_path = self.tmp / f"describe-{xi.shape[1] - 1}.csv"
        write_describe_csv(csv_path, xi)
        return subprocess.run([self.wish, "predict", "--model", str(self.model), "--descriptors", str(csv_path),
                               *extra], capture_output=True, text=True, timeout=120)

    def test_wish_predict_agrees(self) -> None:
        r = self.predict(self.xi, "--json")
        self.assertEqual(r.returncode, 0, r.stderr)
        rows = json.loads(r.stdout)["predictions"]
        self.assertEqual([row["file"] for row in rows], [f"meshes/m{i:03d}.obj" for i in range(len(self.xi))])
        self.assertEqual([row["label"] for row in rows], list(self.pipe.predict(self.features)))
        # Probabilities too: libsvm's Platt scaling, replayed by the C++ engine, against scikit-learn's.
        for row, expected in zip(rows, self.pipe.predict_proba(self.features)):
            probabilities = {p["label"]: p["probability"] for p in row["probabilities"]}  # wire's list, as the service's
            got = [probabilities[c] for c in self.pipe.classes_]
            self.assertLess(max(abs(a - b) for a, b in zip(got, expected)), 1e-5)

    def test_wish_predict_refuses_a_table_of_another_lmax(self) -> None:
        r = self.predict(self.xi[:, :6])  # xi_0..xi_5: a fit at Lmax 5, not the model's 6
        self.assertNotEqual(r.returncode, 0)
        self.assertIn("descriptor_mismatch", r.stderr)
        self.assertIn("Lmax 6", r.stderr)


if __name__ == "__main__":
    unittest.main()
