"""The status of a multipart answer follows its parts' (proto/openapi.json, BatchResponse; issue 15 "what a new user
expects"): a one-part upload answers with its part's own status, so `curl -f -F mesh=@bad.off` fails; every part
good is 200; every part failed alike is that status; parts that differ are 207 Multi-Status. The body is a
BatchResponse every time, and the Python client reads every part from each of these answers."""
import os
import shutil
import subprocess
import sys
import tempfile
import unittest

import wish_server_harness as h

SKIP = h.skip_reason_binary()
sys.path.insert(0, os.path.join(h.SOURCE_DIR, "clients", "python"))
from wish_client import RetryPolicy, WishClient, WishServerError  # noqa: E402


@unittest.skipIf(SKIP, SKIP or "")
class BatchStatusTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.mkdtemp(prefix="wish-batch-status-")
        cls.server = h.Server(args=["--workers", "2", "--max-vertices", "5000", "--max-parts", "4"])
        cls.good = h.read_bytes(h.shared("genus0_closed", "sphere.off"))           # 162 vertices, maps
        cls.genus4 = h.read_bytes(h.shared("negative", "anchor.off"))              # 422 genus_nonzero
        cls.large = h.read_bytes(h.shared("genus0_closed", "bear.off"))            # > 5000 vertices: 413
        cls.garbage = bytes(range(256)) * 8                                        # 415 unsupported_format
        cls.paths = {}
        for name, data in (("good.off", cls.good), ("bad.off", cls.genus4)):
            cls.paths[name] = os.path.join(cls.tmp, name)
            with open(cls.paths[name], "wb") as f:
                f.write(data)
        cls.contract = h.OPENAPI

    @classmethod
    def tearDownClass(cls):
        cls.server.__exit__(None, None, None)
        shutil.rmtree(cls.tmp, ignore_errors=True)

    def batch(self, *parts, op="describe"):
        # Parts are named by their content (the reader takes a hint from the extension): garbage is not an .off.
        files = [("mesh", ("garbage%d.bin" if data is self.garbage else "m%d.off") % i, data)
                 for i, data in enumerate(parts)]
        r = self.server.post_multipart("/v1/" + op, files, fields={"lmax": "4"} if op == "describe" else None)
        body = r.json()
        h.validate("BatchResponse", body)
        self.assertEqual(len(body["results"]), len(parts))
        # Every status the service answers is one the contract documents for the operation.
        self.assertIn(str(r.status), self.contract["paths"]["/v1/" + op]["post"]["responses"])
        return r, body

    def part_statuses(self, body):
        return [item["status"] for item in body["results"]]

    def test_one_bad_part_answers_its_status(self):
        for data, status, code in ((self.genus4, 422, "genus_nonzero"), (self.large, 413, "limit_exceeded"),
                                   (self.garbage, 415, "unsupported_format")):
            r, body = self.batch(data)
            self.assertEqual(r.status, status, r.body[:400])
            self.assertEqual(self.part_statuses(body), [status])
            self.assertEqual(body["results"][0]["error"]["code"], code)
            # Like every error answer, the top level names the error (the first failing part's).
            self.assertEqual(body["error"], body["results"][0]["error"])
            self.assertEqual(body["request_id"], r.header("X-Request-Id"))

    def test_one_good_part_is_200(self):
        r, body = self.batch(self.good)
        self.assertEqual(r.status, 200, r.body[:400])
        self.assertNotIn("error", body)
        self.assertEqual(body["results"][0]["result"]["descriptor"]["lmax"], 4)

    def test_all_good_is_200_and_all_alike_is_that_status(self):
        r, body = self.batch(self.good, self.good)
        self.assertEqual((r.status, self.part_statuses(body)), (200, [200, 200]))
        r, body = self.batch(self.genus4, self.genus4)
        self.assertEqual((r.status, self.part_statuses(body)), (422, [422, 422]))

    def test_parts_that_differ_are_207(self):
        r, body = self.batch(self.good, self.genus4, self.good)
        self.assertEqual((r.status, self.part_statuses(body)), (207, [200, 422, 200]), r.body[:400])
        self.assertNotIn("error", body)  # a 207 is not an error answer
        r, body = self.batch(self.genus4, self.large)  # two different errors
        self.assertEqual((r.status, self.part_statuses(body)), (207, [422, 413]))

    def test_request_level_errors_keep_the_error_body(self):
        r = self.server.post_multipart("/v1/describe", [("mesh", "s%d.off" % i, self.good) for i in range(5)])
        self.assertEqual(r.status, 413)
        h.validate("Error", r.json())  # no part was run: the plain error body
        self.assertEqual(r.json()["error"]["code"], "too_many_parts")

    def test_raw_body_is_unchanged(self):
        r = self.server.post_mesh("/v1/describe", self.genus4)
        self.assertEqual(r.status, 422)
        h.validate("Error", r.json())

    @unittest.skipUnless(shutil.which("curl"), "needs curl")
    def test_curl_fail_sees_a_refused_upload(self):
        url = "http://127.0.0.1:%d/v1/describe" % self.server.port

        def curl(*forms):
            args = ["curl", "-sS", "-f", "-o", os.devnull, "-w", "%{http_code}"]
            for p in forms:
                args += ["-F", "mesh=@" + p]
            done = subprocess.run(args + [url], capture_output=True, text=True, timeout=120)
            return done.returncode, done.stdout

        self.assertEqual(curl(self.paths["bad.off"]), (22, "422"))   # curl -f: exit 22 on HTTP >= 400
        self.assertEqual(curl(self.paths["good.off"]), (0, "200"))
        self.assertEqual(curl(self.paths["good.off"], self.paths["bad.off"]), (0, "207"))  # read the parts

    def test_python_client_reads_parts_of_every_answer_and_does_not_retry_refusals(self):
        retries = []
        client = WishClient("http://127.0.0.1:%d" % self.server.port, timeout=120,
                            retry=RetryPolicy(max_attempts=4, base_delay=0.01),
                            on_retry=lambda attempt, delay, err: retries.append(err))
        out = client.describe([("a.off", self.genus4), ("b.off", self.genus4)], lmax=4)    # HTTP 422
        self.assertEqual([(e.status, e.code) for e in out], [(422, "genus_nonzero")] * 2)
        out = client.describe([("a.off", self.good), ("b.off", self.genus4)], lmax=4)      # HTTP 207
        self.assertEqual(out[0].lmax, 4)
        self.assertIsInstance(out[1], WishServerError)
        self.assertEqual(out[1].code, "genus_nonzero")
        with self.assertRaises(WishServerError) as cm:                                      # raw body: 422 raises
            client.describe(("bad.off", self.genus4))
        self.assertEqual(cm.exception.code, "genus_nonzero")
        self.assertEqual(retries, [])  # a refusal of the input is never sent again


if __name__ == "__main__":
    unittest.main()
