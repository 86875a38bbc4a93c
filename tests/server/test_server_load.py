"""Concurrency, back-pressure and lifecycle of the real server: N concurrent clients get correct answers, a full
queue answers 503 quickly and before the request's body is read, a burst past what the time limit allows is refused
503 at admission rather than answered 504 after waiting, SIGHUP / admin reloads under load lose no request, SIGTERM
during load loses no accepted request and exits 0."""
import os
import shutil
import signal
import socket
import tempfile
import threading
import time
import unittest

import wish_server_harness as h

SKIP = h.skip_reason_binary()


def run_parallel(fn, n):
    results = [None] * n
    def work(i):
        try:
            results[i] = fn(i)
        except Exception as e:  # connection-level failures are results too
            results[i] = e
    threads = [threading.Thread(target=work, args=(i,)) for i in range(n)]
    for t in threads:
        t.start()
    for t in threads:
        t.join(timeout=300)
    return results


def raw_request_head(path, content_length, extra=""):
    return ("POST %s HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Type: application/octet-stream\r\n"
            "Content-Length: %d\r\n%s\r\n" % (path, content_length, extra)).encode()


def read_head(sock, timeout):
    """The status line and headers of the next response on a raw socket: (status, {lower name: value}); raises
    socket.timeout when none arrives within timeout seconds."""
    sock.settimeout(timeout)
    data = b""
    while b"\r\n\r\n" not in data:
        chunk = sock.recv(65536)
        if not chunk:
            raise ConnectionError("closed before a response: %r" % data[:200])
        data += chunk
    head, _, rest = data.partition(b"\r\n\r\n")
    lines = head.decode().split("\r\n")
    headers = dict((k.strip().lower(), v.strip()) for k, _, v in (l.partition(":") for l in lines[1:]))
    return int(lines[0].split()[1]), headers, rest


def closes_within(sock, seconds):
    """True when the server closes the connection (EOF) within `seconds`, whatever else it sends."""
    sock.settimeout(seconds)
    try:
        while sock.recv(65536):
            pass
        return True
    except socket.timeout:
        return False



@unittest.skipIf(SKIP, SKIP or "")
class ServerLoadTest(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.mkdtemp(prefix="wish-load-")
        self.sphere = h.read_bytes(h.shared("genus0_closed", "sphere.off"))
        # Times of a default describe (the training recipe's map: cMCF chain + canonical relaxation), measured alone.
        self.blobby = h.read_bytes(h.shared("genus0_closed", "blobby.off"))   # ~0.4 s
        self.bear = h.read_bytes(h.shared("genus0_closed", "bear.off"))       # ~2 s
        # The job that keeps the only worker busy while a refusal is checked: long enough that the refusal (answered
        # from the request's headers, in milliseconds) comes back first, short enough not to dominate the run (the
        # diplodocus, ~4 s when chosen, costs ~19 s since the canonical relaxation).
        self.cow = h.read_bytes(h.shared("genus0_closed", "cow.off"))         # ~5 s

    def tearDown(self):
        shutil.rmtree(self.tmp, ignore_errors=True)

    def test_concurrent_clients_get_correct_answers(self):
        with h.Server(args=["--workers", "2", "--queue-size", "16"]) as s:
            ref = {}
            for name, data in (("sphere", self.sphere), ("blobby", self.blobby)):
                r = s.post_mesh("/v1/describe?lmax=8", data)
                self.assertEqual(r.status, 200)
                ref[name] = r.json()["descriptor"]["invariants"]
            meshes = [("sphere", self.sphere), ("blobby", self.blobby)] * 4

            def one(i):
                name, data = meshes[i]
                r = s.post_mesh("/v1/describe?lmax=8", data, headers={"X-Request-Id": "conc-%d" % i})
                return name, r
            for i, (name, r) in enumerate(run_parallel(one, len(meshes))):
                self.assertEqual(r.status, 200, r.body[:300])
                body = r.json()
                h.validate("DescribeResult", body)
                self.assertEqual(body["request_id"], "conc-%d" % i)  # answers are not mixed up between clients
                for a, b in zip(body["descriptor"]["invariants"], ref[name]):
                    self.assertAlmostEqual(a, b, delta=1e-9 * max(1.0, abs(b)))

    def test_full_queue_gives_503_quickly(self):
        with h.Server(args=["--workers", "1", "--queue-size", "1", "--retry-after", "2"]) as s:
            def one(i):
                r = s.post_mesh("/v1/describe", self.bear, timeout=120)
                return r, time.monotonic()
            results = run_parallel(one, 6)
            statuses = sorted(r.status for r, _ in results)
            self.assertEqual(statuses.count(200), 2, statuses)  # one running + one queued
            self.assertEqual(statuses.count(503), 4, statuses)
            # Refused at once, not after waiting for a worker: every refusal is answered before the running job
            # ends (an order of events, so it holds however slow a busy machine makes both).
            first_done = min(done for r, done in results if r.status == 200)
            for r, done in results:
                if r.status == 503:
                    h.validate("Error", r.json())
                    self.assertEqual(r.json()["error"]["code"], "queue_full")
                    self.assertEqual(r.header("Retry-After"), "2")
                    self.assertLess(done, first_done)
            self.assertEqual(s.metric("wish_rejected_requests_total", {"reason": "queue_full"}), 4)

    def busy_server_with_no_place(self, extra_args=()):
        """A server with one worker running a cow describe (~5 s) and no queue place: (server, thread, result)."""
        s = h.Server(args=["--workers", "1", "--queue-size", "0", "--retry-after", "3"] + list(extra_args))
        result = {}
        t = threading.Thread(target=lambda: result.setdefault("r", s.post_mesh("/v1/describe", self.cow)))
        t.start()
        if not h.wait_for(lambda: s.metric("wish_workers_busy") == 1):
            s.kill()
            t.join(timeout=120)
            self.fail("the worker never took the cow")
        return s, t, result

    def test_full_queue_answers_before_reading_the_body(self):
        # The request announces 48 MB and sends 64 KB of it; the 503 comes back while the rest is still unsent: the
        # server answered from the headers, it neither waited for nor kept the body. It then closes the connection.
        s, t, result = self.busy_server_with_no_place()
        with s:
            sock = socket.create_connection(("127.0.0.1", s.port))
            sock.sendall(raw_request_head("/v1/describe", 48 << 20) + b"\0" * 65536)
            status, headers, _ = read_head(sock, timeout=30)
            self.assertNotIn("r", result, "answered only after the running job ended")
            self.assertEqual(status, 503)
            self.assertEqual(headers.get("retry-after"), "3")
            self.assertEqual(headers.get("connection"), "close")
            self.assertTrue(closes_within(sock, 10), "the connection was left open")
            sock.close()
            self.assertEqual(s.metric("wish_rejected_requests_total", {"reason": "queue_full"}), 1)
            t.join(timeout=120)
            self.assertEqual(result["r"].status, 200)

    def test_refusal_from_the_headers_reaches_a_client_that_sends_its_whole_body_first(self):
        # Python's http.client (like most clients) sends the whole body before reading: the server drops what it
        # reads after its answer instead of resetting the connection under it, so the client still gets its 503.
        s, t, _ = self.busy_server_with_no_place()
        with s:
            r = s.post_mesh("/v1/describe", b"\0" * (8 << 20))
            self.assertEqual(r.status, 503, r.body[:200])
            self.assertEqual(r.json()["error"]["code"], "queue_full")
            self.assertEqual(r.header("Retry-After"), "3")
            t.join(timeout=120)

    def test_oversized_content_length_is_refused_before_the_body(self):
        with h.Server(args=["--max-upload-bytes", "1000000"]) as s:
            sock = socket.create_connection(("127.0.0.1", s.port))
            sock.sendall(raw_request_head("/v1/classify", 50_000_000) + b"\0" * 65536)
            status, headers, rest = read_head(sock, timeout=30)
            self.assertEqual(status, 413)
            self.assertEqual(headers.get("connection"), "close")
            body_len = int(headers["content-length"])
            while len(rest) < body_len:
                rest += sock.recv(65536)
            error = __import__("json").loads(rest[:body_len])["error"]
            self.assertEqual(error["code"], "payload_too_large")
            self.assertEqual(error["details"]["limit"], 1000000)
            self.assertTrue(closes_within(sock, 10))
            sock.close()

    def test_expect_100_continue_is_answered_from_the_headers(self):
        s, t, _ = self.busy_server_with_no_place()
        with s:
            # Refused: the final 503 instead of "100 Continue", so the client never sends its body.
            sock = socket.create_connection(("127.0.0.1", s.port))
            sock.sendall(raw_request_head("/v1/describe", len(self.sphere), "Expect: 100-continue\r\n"))
            status, headers, _ = read_head(sock, timeout=30)
            self.assertEqual(status, 503)
            self.assertEqual(headers.get("retry-after"), "3")
            sock.close()
            t.join(timeout=120)
            # Admitted (the worker is free now): 100 Continue, then the answer to the body.
            self.assertTrue(h.wait_for(lambda: s.metric("wish_workers_busy") == 0))
            sock = socket.create_connection(("127.0.0.1", s.port))
            sock.sendall(raw_request_head("/v1/describe", len(self.sphere), "Expect: 100-continue\r\n"))
            status, _, _ = read_head(sock, timeout=30)
            self.assertEqual(status, 100)
            sock.sendall(self.sphere)
            status, _, _ = read_head(sock, timeout=120)
            self.assertEqual(status, 200)
            sock.close()

    def test_burst_past_the_time_limit_is_refused_at_admission_not_timed_out(self):
        # One worker, a queue of 64, a 4 s limit: a burst of 24 describes of ~0.4 s each is about 10 s of work, so
        # queued by count alone the tail would wait past the limit and be answered 504. Admission by predicted time
        # (--admit-fraction 0.5: a request is admitted when it is predicted to end within 2 s of its arrival)
        # refuses the tail at once with 503 + Retry-After, and every request it admitted finishes.
        with h.Server(args=["--workers", "1", "--queue-size", "64", "--time-limit", "4", "--admit-fraction", "0.5"]) as s:
            for _ in range(2):  # the server learns what this mesh costs
                self.assertEqual(s.post_mesh("/v1/describe", self.blobby).status, 200)

            def one(i):
                return s.post_mesh("/v1/describe", self.blobby, timeout=120)
            results = run_parallel(one, 24)
            statuses = [r.status for r in results]
            self.assertNotIn(504, statuses)
            self.assertEqual(set(statuses) - {200, 503}, set(), statuses)
            self.assertGreater(statuses.count(200), 0, statuses)
            self.assertGreater(statuses.count(503), 0, statuses)  # the burst is past what 2 s allows
            for r in results:
                if r.status == 503:
                    self.assertEqual(r.json()["error"]["code"], "queue_full")
                    self.assertGreaterEqual(int(r.header("Retry-After")), 1)
                    self.assertIn("predicted_wait_seconds", r.json()["error"]["details"])
            self.assertEqual(s.metric("wish_rejected_requests_total", {"reason": "queue_time"}), statuses.count(503))

    def test_readyz_reflects_full_queue(self):
        with h.Server(args=["--workers", "1", "--queue-size", "0"]) as s:
            t = threading.Thread(target=lambda: s.post_mesh("/v1/describe", self.bear))
            t.start()
            self.assertTrue(h.wait_for(lambda: s.metric("wish_workers_busy") == 1))
            r = s.request("GET", "/readyz")
            self.assertEqual(r.status, 503)
            self.assertIn(r.json()["error"]["code"], {"not_ready"})
            t.join(timeout=120)

    def test_reload_under_load_loses_no_request(self):
        models = h.models_dir_with_default(self.tmp) or os.path.join(self.tmp, "empty-models")
        os.makedirs(models, exist_ok=True)
        have_model = os.path.exists(os.path.join(models, "default.json"))
        route = "/v1/classify" if have_model else "/v1/describe"
        with h.Server(models_dir=models, args=["--workers", "2", "--queue-size", "64"]) as s:
            stop = threading.Event()
            outcomes = []
            lock = threading.Lock()

            def client(i):
                while not stop.is_set():
                    r = s.post_mesh(route, self.sphere if i % 2 else self.blobby)
                    with lock:
                        outcomes.append(r.status)
            threads = [threading.Thread(target=client, args=(i,)) for i in range(4)]
            for t in threads:
                t.start()
            with open(os.path.join(models, "broken.json"), "w") as f:
                f.write('{"format_version": 1, "truncated": ')
            for k in range(6):
                time.sleep(0.25)
                if k % 2:
                    s.signal(signal.SIGHUP)
                else:
                    report = s.request("POST", "/v1/admin/reload")
                    self.assertEqual(report.status, 200)
                    h.validate("ReloadReport", report.json())
                    self.assertIn("broken.json", [x["file"] for x in report.json()["refused"]])
            if have_model:
                # A bad new version of a loaded model is refused and the previous version stays.
                with open(os.path.join(models, "default.json"), "w") as f:
                    f.write("not a model")
                report = s.request("POST", "/v1/admin/reload").json()
                refused = [x for x in report["refused"] if x["file"] == "default.json"]
                self.assertTrue(refused and refused[0]["kept_previous"], report)
                time.sleep(0.5)
            stop.set()
            for t in threads:
                t.join(timeout=120)
            self.assertGreater(len(outcomes), 8)
            self.assertEqual(set(outcomes), {200}, outcomes)
            if have_model:
                self.assertEqual(s.post_mesh("/v1/classify", self.sphere).status, 200)
            self.assertIn("refused broken.json", s.log_text())

    def test_sigterm_during_load_loses_no_accepted_request(self):
        with h.Server(args=["--workers", "2", "--queue-size", "16", "--shutdown-grace", "60"]) as s:
            n = 4  # 2 running + 2 queued, long enough (~4 s each) that all are in flight when the signal comes
            results = [None] * n

            def one(i):
                results[i] = s.post_mesh("/v1/describe", self.bear)
            threads = [threading.Thread(target=one, args=(i,)) for i in range(n)]
            for t in threads:
                t.start()
            # All n running or queued before the signal (test_server_shutdown.py signals at the other moments).
            self.assertTrue(h.wait_for(lambda: (s.metric("wish_workers_busy") or 0) + (s.metric("wish_queue_depth") or 0)
                                     == n, timeout=30), "requests were not accepted")
            s.signal(signal.SIGTERM)
            for t in threads:
                t.join(timeout=120)
            self.assertEqual([r.status for r in results], [200] * n)
            s.proc.wait(timeout=60)
            self.assertEqual(s.proc.returncode, 0)
            self.assertIn("draining", s.log_text())

    def test_sigterm_grace_period_cancels_and_exits_0(self):
        with h.Server(args=["--workers", "1", "--queue-size", "4", "--shutdown-grace", "0.3"]) as s:
            results = [None] * 2

            def one(i):
                results[i] = s.post_mesh("/v1/describe", self.bear)
            threads = [threading.Thread(target=one, args=(i,)) for i in range(2)]
            for t in threads:
                t.start()
            # Both jobs accepted (one running, one queued) before SIGTERM, so the grace period cancels both.
            self.assertTrue(h.wait_for(lambda: (s.metric("wish_workers_busy") or 0) + (s.metric("wish_queue_depth") or 0) == 2))
            t0 = time.time()
            s.signal(signal.SIGTERM)
            for t in threads:
                t.join(timeout=120)
            s.proc.wait(timeout=60)
            self.assertEqual(s.proc.returncode, 0)
            self.assertLess(time.time() - t0, 3.5)  # bounded by the grace period, not by the 2 x 4 s of work
            for r in results:
                self.assertEqual(r.status, 503, r.body[:200])
                h.validate("Error", r.json())
                self.assertEqual(r.json()["error"]["code"], "cancelled")


if __name__ == "__main__":
    unittest.main()
