"""The bad-input corpus: each case gives the documented 4xx with the right code and the one JSON error body."""
import shutil
import tempfile
import unittest

import wish_server_harness as h

SKIP = h.skip_reason_binary()
VALIDATION_CODES = {"genus_nonzero", "not_closed", "multiple_components", "non_manifold_edge", "non_manifold_vertex",
                    "inconsistent_orientation", "degenerate_faces", "too_small"}


@unittest.skipIf(SKIP, SKIP or "")
class ServerErrorTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.mkdtemp(prefix="wish-errors-")
        cls.models = h.models_dir_with_default(cls.tmp)
        cls.server = h.Server(models_dir=cls.models, args=["--workers", "1", "--max-vertices", "5000",
                                                           "--max-parts", "3", "--max-lmax", "20"],
                              env={"WISH_MAX_UPLOAD_BYTES": "2000000"})  # an environment variable sets a limit
        cls.sphere = h.read_bytes(h.shared("genus0_closed", "sphere.off"))

    @classmethod
    def tearDownClass(cls):
        cls.server.__exit__(None, None, None)
        shutil.rmtree(cls.tmp, ignore_errors=True)

    def expect(self, r, status, codes):
        self.assertEqual(r.status, status, r.body[:400])
        body = r.json()
        h.validate("Error", body)
        if isinstance(codes, str):
            codes = {codes}
        self.assertIn(body["error"]["code"], codes, body)
        self.assertEqual(body["request_id"], r.header("X-Request-Id"))
        return body

    def describe(self, data, query="", content_type="application/octet-stream"):
        return self.server.post_mesh("/v1/describe" + query, data, content_type)

    # ---- broken files -> 400 / 415
    def test_garbage_is_unsupported_format(self):
        self.expect(self.describe(bytes(range(256)) * 8), 415, "unsupported_format")

    def test_truncated_off_is_parse_error(self):
        body = self.expect(self.describe(b"OFF\n8 12 0\n0 0 0\n1 0 0\n"), 400, "parse_error")
        self.assertIn("line", body["error"]["details"])

    def test_index_out_of_range(self):
        off = b"OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 1 2\n3 0 1 3\n3 0 2 3\n3 1 2 99\n"
        self.expect(self.describe(off), 400, "index_out_of_range")

    def test_non_finite_vertex(self):
        off = b"OFF\n4 4 0\n0 0 0\n1 0 nan\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n"
        self.expect(self.describe(off), 400, {"non_finite_vertex", "parse_error"})

    def test_empty_body(self):
        self.expect(self.describe(b""), 400, "no_mesh")

    # ---- not mappable -> 422
    def test_genus_nonzero(self):
        body = self.expect(self.describe(h.read_bytes(h.shared("negative", "anchor.off"))), 422, "genus_nonzero")
        self.assertEqual(body["error"]["details"].get("genus"), 4)

    def test_open_mesh(self):
        self.expect(self.describe(h.read_bytes(h.shared("negative", "cylinder.off"))), 422, VALIDATION_CODES)

    def test_multi_component(self):
        self.expect(self.describe(h.read_bytes(h.shared("negative", "blobby_3cc.off"))), 422, VALIDATION_CODES)

    def test_bones_many_components(self):
        self.expect(self.describe(h.read_bytes(h.shared("negative", "bones.off"))), 422, "multiple_components")

    # ---- too large -> 413
    def test_too_many_vertices(self):
        body = self.expect(self.describe(h.read_bytes(h.shared("genus0_closed", "bear.off"))), 413, "limit_exceeded")
        self.assertEqual(body["error"]["details"].get("allowed"), 5000)

    def test_upload_too_large_from_environment(self):
        self.expect(self.describe(b"x" * 2_100_000), 413, "payload_too_large")

    def test_lmax_above_limit(self):
        self.expect(self.describe(self.sphere, "?lmax=21"), 413, "limit_exceeded")

    def test_too_many_parts(self):
        r = self.server.post_multipart("/v1/describe", [("mesh", "s%d.off" % i, self.sphere) for i in range(4)])
        self.expect(r, 413, "too_many_parts")

    # ---- wrong type -> 415
    def test_form_urlencoded_refused(self):
        self.expect(self.describe(self.sphere, content_type="application/x-www-form-urlencoded"), 415,
                    "unsupported_media_type")

    def test_json_refused(self):
        self.expect(self.describe(b'{"mesh": 1}', content_type="application/json"), 415, "unsupported_media_type")

    # ---- bad parameters -> 400
    def test_invalid_parameters(self):
        for query, code in [("?lmax=abc", "invalid_parameter"), ("?lmax=0", "invalid_parameter"), ("?method=ricci", "invalid_parameter"),
                            ("?steps=-3", "invalid_parameter"), ("?include=everything", "invalid_parameter"),
                            ("?lamx=5", "invalid_parameter"), ("?model=default", "invalid_parameter"),
                            ("?lmax=5&lmax=6", "invalid_parameter"), ("?format=3ds", "invalid_parameter"),
                            ("?reconstruction_level=9", "invalid_parameter")]:
            with self.subTest(query=query):
                self.expect(self.describe(self.sphere, query), 400, code)

    def test_multipart_without_mesh(self):
        r = self.server.post_multipart("/v1/describe", [], fields={"lmax": "5"})
        self.expect(r, 400, "no_mesh")

    def test_parameter_in_query_and_form(self):
        r = self.server.post_multipart("/v1/describe?lmax=5", [("mesh", "s.off", self.sphere)], fields={"lmax": "6"})
        self.expect(r, 400, "invalid_parameter")

    # ---- unknown model -> 404
    def test_unknown_model(self):
        body = self.expect(self.server.post_mesh("/v1/classify?model=nope", self.sphere), 404, "model_not_found")
        self.assertEqual(body["error"]["details"]["model"], "nope")

    def test_classify_without_any_model(self):
        if self.models is not None:
            self.skipTest("a default model exists")
        self.expect(self.server.post_mesh("/v1/classify", self.sphere), 503, "no_model_loaded")


@unittest.skipIf(SKIP, SKIP or "")
class ServerAuthAndTimeoutTest(unittest.TestCase):
    def test_bearer_token(self):
        with h.Server(env={"WISH_AUTH_TOKEN": "s3cret"}) as s:
            r = s.request("GET", "/v1/models")
            self.assertEqual(r.status, 401)
            h.validate("Error", r.json())
            self.assertEqual(r.json()["error"]["code"], "unauthorized")
            self.assertEqual(r.header("WWW-Authenticate"), "Bearer")
            self.assertEqual(s.request("GET", "/v1/models", headers={"Authorization": "Bearer wrong"}).status, 401)
            self.assertEqual(s.request("GET", "/v1/models", headers={"Authorization": "Bearer s3cret"}).status, 200)
            self.assertEqual(s.request("GET", "/healthz").status, 200)  # operations stay open
            self.assertEqual(s.request("GET", "/metrics").status, 200)
            self.assertNotIn("s3cret", s.log_text())  # the token is never logged

    def test_time_limit_gives_504(self):
        mesh = h.read_bytes(h.shared("genus0_closed", "bunny00.off"))
        with h.Server(args=["--time-limit", "0.05", "--workers", "1"]) as s:
            r = s.post_mesh("/v1/describe", mesh)
            self.assertEqual(r.status, 504, r.body[:300])
            h.validate("Error", r.json())
            self.assertEqual(r.json()["error"]["code"], "timeout")

    def test_json_log(self):
        import json
        with h.Server(args=["--json-log"]) as s:
            s.request("GET", "/healthz", headers={"X-Request-Id": "json-log-check"})

            self.assertTrue(s.wait_for_log_lines("json-log-check"))
            parsed = [json.loads(l) for l in s.complete_log_lines()]  # every line is one JSON object
            access = [p for p in parsed if p.get("request_id") == "json-log-check"]
            self.assertEqual(access[0]["status"], 200)
            self.assertEqual(access[0]["route"], "/healthz")


if __name__ == "__main__":
    unittest.main()
