"""wish_client library against a fake server speaking the wire contract: parsing, errors, retries."""

from __future__ import annotations

import email.utils
import tempfile
import time
import unittest
from pathlib import Path

from fake_wish_server import FakeWishServer, fake_mesh

from wish_client import (NO_RETRY, ClassifyResult, DescribeResult, RetryPolicy, WishClient, WishConnectionError,
                         WishInputError, WishServerError)
from wish_client.client import _parse_retry_after
from loopback import free_port

FAST = RetryPolicy(max_attempts=4, base_delay=0.01, max_delay=0.05)


class LibraryTest(unittest.TestCase):
    def setUp(self) -> None:
        self.server = FakeWishServer().__enter__()
        self.addCleanup(self.server.__exit__)
        self.client = WishClient(self.server.url, retry=FAST, timeout=10)
        self.tmp = Path(tempfile.mkdtemp(prefix="wish-client-lib-"))

    def test_classify_path_sends_raw_body_with_format_hint(self) -> None:
        p = self.tmp / "cell.off"
        p.write_bytes(fake_mesh("astrocyte", fmt="off"))
        r = self.client.classify(p)
        self.assertIsInstance(r, ClassifyResult)
        self.assertEqual(r.label, "astrocyte")
        self.assertEqual(r.name, "cell.off")
        self.assertAlmostEqual(r.confidence, 0.75)
        self.assertAlmostEqual(sum(r.probabilities.values()), 1.0)
        self.assertEqual(r.model, "default@1")
        self.assertEqual(r.margin, 0.8)
        self.assertTrue(r.request_id.startswith("fake-"))
        req = self.server.compute_requests()[-1]
        self.assertEqual(req["query"].get("format"), "off")
        self.assertEqual(req["headers"]["Content-Type"], "application/octet-stream")

    def test_classify_reports_novelty(self) -> None:
        known = self.client.classify(fake_mesh("astrocyte"))
        self.assertIs(known.novel, False)
        self.assertEqual(known.novelty_p_value, 0.5)
        novel = self.client.classify(fake_mesh("astrocyte", novel=True))
        self.assertIs(novel.novel, True)
        self.assertEqual(novel.novelty_p_value, 0.004)
        # Why (issue 38 item 3): the nearest class and the distance in units of its spread.
        self.assertEqual((known.novelty_nearest_class, known.novelty_distance_ratio), ("astrocyte", 0.333))
        self.assertEqual((novel.novelty_nearest_class, novel.novelty_distance_ratio), ("astrocyte", 3.0))
        self.assertEqual(novel.label, "astrocyte")  # the label is still given beside the flag

    def test_classify_bytes_and_named_bytes(self) -> None:
        self.assertEqual(self.client.classify(fake_mesh("pericyte")).label, "pericyte")
        r = self.client.classify(("x.obj", fake_mesh("microglia")))
        self.assertEqual((r.name, r.label), ("x.obj", "microglia"))

    def test_classify_list_is_multipart_with_per_part_errors(self) -> None:
        out = self.client.classify([("a.obj", fake_mesh("neuron")), ("torus.obj", fake_mesh(error="genus_nonzero")),
                                    ("c.obj", fake_mesh("pericyte"))])
        self.assertEqual(len(out), 3)
        self.assertEqual((out[0].name, out[0].label), ("a.obj", "neuron"))
        self.assertIsInstance(out[1], WishServerError)
        self.assertEqual((out[1].status, out[1].code), (422, "genus_nonzero"))
        self.assertEqual(out[2].label, "pericyte")
        self.assertEqual(self.server.compute_requests()[-1]["names"], ["a.obj", "torus.obj", "c.obj"])
        self.assertEqual(self.server.batch_statuses, [207])  # the parts differ: Multi-Status, read as usual

    def test_multipart_whose_parts_all_fail_is_read_per_part_and_not_retried(self) -> None:
        # Every part refused alike: the answer is that part status (422), with one entry per part; the client
        # gives each part's error instead of raising, and does not send a refusal of the input again.
        out = self.client.classify([("t1.obj", fake_mesh(error="genus_nonzero")),
                                    ("t2.obj", fake_mesh(error="genus_nonzero"))])
        self.assertEqual(self.server.batch_statuses, [422])
        self.assertEqual([(e.status, e.code) for e in out], [(422, "genus_nonzero")] * 2)  # type: ignore[union-attr]
        self.assertEqual(len(self.server.compute_requests()), 1)
        one = self.client.describe([("t3.obj", fake_mesh(error="not_closed"))])
        self.assertEqual(self.server.batch_statuses, [422, 422])
        self.assertIsInstance(one[0], WishServerError)
        self.assertEqual(one[0].code, "not_closed")  # type: ignore[union-attr]
        self.assertEqual(len(self.server.compute_requests()), 2)

    def test_multipart_all_good_is_200(self) -> None:
        out = self.client.classify([("a.obj", fake_mesh("neuron")), ("b.obj", fake_mesh("neuron"))])
        self.assertEqual([r.label for r in out], ["neuron", "neuron"])  # type: ignore[union-attr]
        self.assertEqual(self.server.batch_statuses, [200])

    def test_request_level_error_of_a_multipart_upload_raises(self) -> None:
        with self.assertRaises(WishServerError) as cm:  # no `results`: the request itself was refused
            self.client.classify([("a.obj", fake_mesh("neuron"))], model="nope")
        self.assertEqual((cm.exception.status, cm.exception.code), (404, "model_not_found"))

    def test_describe(self) -> None:
        d = self.client.describe(fake_mesh(), lmax=5)
        self.assertIsInstance(d, DescribeResult)
        self.assertEqual(d.lmax, 5)
        self.assertEqual(len(d.invariants), 6)
        self.assertEqual(self.server.compute_requests()[-1]["query"]["lmax"], "5")

    def test_models_health_ready_metrics(self) -> None:
        models = self.client.models()
        self.assertEqual(models[0]["name"], "default")
        self.assertIn("neuron", self.client.model("default")["classes"])
        self.assertEqual(self.client.health(), {"status": "ok"})
        self.assertTrue(self.client.ready())
        self.assertIn("wish_http_requests_total", self.client.metrics())

    def test_not_ready_is_false_not_an_exception(self) -> None:
        self.server.busy_next(1)
        self.assertFalse(WishClient(self.server.url, retry=NO_RETRY).ready())

    def test_server_error_carries_code_status_details_request_id(self) -> None:
        with self.assertRaises(WishServerError) as cm:
            self.client.model("nope")
        e = cm.exception
        self.assertEqual((e.status, e.code), (404, "model_not_found"))
        self.assertEqual(e.details, {"name": "nope"})
        self.assertTrue(e.request_id.startswith("fake-"))
        self.assertIn("model_not_found", str(e))

    def test_client_errors_are_not_retried(self) -> None:
        with self.assertRaises(WishServerError) as cm:
            self.client.classify(fake_mesh(error="not_closed"))
        self.assertEqual((cm.exception.status, cm.exception.code), (422, "not_closed"))
        self.assertEqual(len(self.server.compute_requests()), 1)

    def test_503_is_retried_and_retry_after_honoured(self) -> None:
        # A computed back-off would be 5 s per retry; Retry-After: 0 must win, so this returns at once.
        waits: list[float] = []
        client = WishClient(self.server.url, retry=RetryPolicy(max_attempts=5, base_delay=5, max_delay=5),
                            on_retry=lambda attempt, delay, err: waits.append(delay))
        self.server.busy_next(3, retry_after="0")
        t0 = time.monotonic()
        self.assertEqual(client.classify(fake_mesh("neuron")).label, "neuron")
        self.assertLess(time.monotonic() - t0, 3)
        self.assertEqual(waits, [0.0, 0.0, 0.0])
        self.assertEqual(len(self.server.compute_requests()), 4)

    def test_503_after_last_attempt_raises_with_retry_after(self) -> None:
        self.server.busy_next(10, retry_after="0")
        with self.assertRaises(WishServerError) as cm:
            self.client.classify(fake_mesh())
        self.assertEqual((cm.exception.status, cm.exception.code), (503, "queue_full"))
        self.assertEqual(cm.exception.retry_after, 0.0)
        self.assertEqual(len(self.server.compute_requests()), FAST.max_attempts)

    def test_dropped_connection_and_proxy_502_are_retried(self) -> None:
        self.server.drop_next(2)
        self.assertEqual(self.client.classify(fake_mesh("neuron")).label, "neuron")
        self.server.proxy_error_next(2)
        self.assertEqual(self.client.classify(fake_mesh("pericyte")).label, "pericyte")

    def test_non_json_error_page(self) -> None:
        self.server.proxy_error_next(10)
        with self.assertRaises(WishServerError) as cm:
            WishClient(self.server.url, retry=NO_RETRY).classify(fake_mesh())
        self.assertEqual((cm.exception.status, cm.exception.code), (502, "http_502"))
        self.assertIn("Bad Gateway", cm.exception.message)

    def test_unreachable_server(self) -> None:
        calls: list[int] = []
        client = WishClient(f"127.0.0.1:{free_port()}", retry=FAST, on_retry=lambda a, d, e: calls.append(a))
        with self.assertRaises(WishConnectionError):
            client.health()
        self.assertEqual(calls, [1, 2, 3])

    def test_missing_file_is_an_input_error(self) -> None:
        with self.assertRaises(WishInputError):
            self.client.classify(self.tmp / "missing.obj")

    def test_bearer_token(self) -> None:
        self.server.require_token = "s3cret"
        with self.assertRaises(WishServerError) as cm:
            self.client.models()
        self.assertEqual((cm.exception.status, cm.exception.code), (401, "unauthorized"))
        ok = WishClient(self.server.url, token="s3cret", retry=FAST)
        self.assertEqual(ok.models()[0]["name"], "default")


class RetryPolicyTest(unittest.TestCase):
    def test_backoff_grows_and_is_capped(self) -> None:
        p = RetryPolicy(base_delay=1, max_delay=5, jitter=0)
        self.assertEqual([p.delay(k) for k in range(1, 6)], [1, 2, 4, 5, 5])

    def test_jitter_stays_in_band(self) -> None:
        p = RetryPolicy(base_delay=2, max_delay=100, jitter=0.25)
        for _ in range(100):
            self.assertTrue(1.5 <= p.delay(1) <= 2.5)

    def test_retry_after_wins_but_is_capped(self) -> None:
        p = RetryPolicy(base_delay=1, max_delay=10)
        self.assertEqual(p.delay(3, retry_after=2.0), 2.0)
        self.assertEqual(p.delay(1, retry_after=99.0), 10.0)

    def test_retry_after_parsing(self) -> None:
        self.assertEqual(_parse_retry_after("3"), 3.0)
        self.assertIsNone(_parse_retry_after(None))
        self.assertIsNone(_parse_retry_after("soon"))
        future = email.utils.formatdate(time.time() + 30, usegmt=True)
        self.assertTrue(25 <= _parse_retry_after(future) <= 31)
        self.assertEqual(_parse_retry_after(email.utils.formatdate(time.time() - 60, usegmt=True)), 0.0)

    def test_service_504_is_not_retryable_but_proxy_504_is(self) -> None:
        self.assertFalse(WishServerError(504, "timeout", "too slow").retryable)
        self.assertTrue(WishServerError(504, "http_504", "Gateway Time-out").retryable)
        self.assertTrue(WishServerError(503, "queue_full", "").retryable)
        self.assertFalse(WishServerError(422, "genus_nonzero", "").retryable)


if __name__ == "__main__":
    unittest.main()
