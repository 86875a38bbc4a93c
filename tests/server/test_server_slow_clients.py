"""Hostile and slow clients: many idle half-open connections must not starve /healthz or a classify; a silent
connection is dropped after the read timeout while a slow upload that keeps sending is served. All traffic to
127.0.0.1; connection counts and every wait are bounded. Prints the measured figures (seconds)."""
import concurrent.futures
import os
import shutil
import socket
import sys
import tempfile
import time
import unittest

import wish_server_harness as h

SKIP = None if os.path.exists(h.WISH_BIN) else "wish binary not found at %s (set WISH_BIN)" % h.WISH_BIN
HALF_OPEN = int(os.environ.get("WISH_TEST_HALF_OPEN", "500"))
SPHERE_OFF = os.path.join(h.SOURCE_DIR, "data", "meshes", "sphere.off")


def half_open(port, n):
    """n connections that each send half a request (headers never finished), then wait. Opened from 8 threads
    (a busy machine schedules the server's accept loop late; one connection at a time took ~0.1 s each)."""
    def one(i):
        s = socket.create_connection(("127.0.0.1", port), timeout=10)
        s.sendall(b"POST /v1/classify HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Length: 100000\r\nX-Slow: %d\r\n" % i)
        return s
    with concurrent.futures.ThreadPoolExecutor(max_workers=8) as pool:
        return list(pool.map(one, range(n)))


def timed(fn):
    t = time.monotonic()
    out = fn()
    return out, time.monotonic() - t


@unittest.skipIf(SKIP, SKIP or "")
class SlowClientTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.mkdtemp(prefix="wish-slow-")
        cls.models = h.models_dir_with_default(cls.tmp)
        with open(SPHERE_OFF, "rb") as f:
            cls.sphere = f.read()

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.tmp, ignore_errors=True)

    def test_half_open_connections_do_not_starve_health_or_classify(self):
        read_timeout = 30
        with h.Server(models_dir=self.models, args=["--workers", "2", "--read-timeout", str(read_timeout)]) as s:
            socks, open_s = timed(lambda: half_open(s.port, HALF_OPEN))
            try:
                r, health_s = timed(lambda: s.request("GET", "/healthz", timeout=10))
                self.assertEqual(r.status, 200)
                r, metrics_s = timed(lambda: s.request("GET", "/metrics", timeout=10))
                self.assertEqual(r.status, 200)
                path = "/v1/classify" if self.models else "/v1/describe"
                r, classify_s = timed(lambda: s.post_mesh(path, self.sphere, timeout=60))
                self.assertEqual(r.status, 200, r.body[:300])
                sys.stderr.write("\n%d half-open connections (opened in %.1f s): /healthz %.3f s, /metrics %.3f s, "
                                 "%s %.3f s\n" % (HALF_OPEN, open_s, health_s, metrics_s, path, classify_s))
                # Starved, they would wait for a half-open connection's read timeout; answered, they take
                # milliseconds (printed above). The bound is that mechanism's, not a speed: 1 s failed with both
                # cores busy (1.28 s), a tenth of the read timeout does not.
                self.assertLess(health_s, read_timeout / 10)
                self.assertLess(metrics_s, read_timeout / 10)
            finally:
                for c in socks:
                    c.close()

    def test_silent_connection_is_dropped_slow_upload_is_served(self):
        with h.Server(args=["--workers", "1", "--read-timeout", "1"]) as s:
            silent = half_open(s.port, 1)[0]
            silent.settimeout(10)
            t = time.monotonic()
            try:
                data = silent.recv(4096)  # the server closes it (b"") or answers an error before closing
            except (ConnectionResetError, socket.timeout):
                data = None
            waited = time.monotonic() - t
            silent.close()
            self.assertIsNotNone(data, "the silent connection was not dropped within 10 s")
            self.assertLess(waited, 5.0)
            self.assertGreaterEqual(waited, 0.5)
            # A slow upload: the body in 6 pieces, 0.5 s apart (3 s in all, past the 1 s read timeout per read).
            body = self.sphere
            c = socket.create_connection(("127.0.0.1", s.port), timeout=30)
            c.sendall(b"POST /v1/describe?lmax=4 HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Type: application/octet-stream"
                      b"\r\nConnection: close\r\nContent-Length: %d\r\n\r\n" % len(body))
            step = (len(body) + 5) // 6
            for i in range(0, len(body), step):
                time.sleep(0.5)
                c.sendall(body[i:i + step])
            reply = b""
            while True:
                chunk = c.recv(65536)
                if not chunk:
                    break
                reply += chunk
            c.close()
            self.assertTrue(reply.startswith(b"HTTP/1.1 200"), reply[:200])


    def test_a_client_that_shuts_its_sending_side_after_the_request_is_answered(self):
        # A client may half-close once its request is sent (nc -N, some scripts): it can still read the answer.
        # httplib's own stream refuses to write once the client's EOF is pending, leaving it without an answer.
        with h.Server(args=["--workers", "1"]) as s:
            body = self.sphere
            c = socket.create_connection(("127.0.0.1", s.port), timeout=30)
            c.sendall(b"POST /v1/describe?lmax=4 HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Type: application/octet-stream"
                      b"\r\nConnection: close\r\nContent-Length: %d\r\n\r\n" % len(body) + body)
            c.shutdown(socket.SHUT_WR)
            reply = b""
            while True:
                chunk = c.recv(65536)
                if not chunk:
                    break
                reply += chunk
            c.close()
            self.assertTrue(reply.startswith(b"HTTP/1.1 200"), reply[:200])

if __name__ == "__main__":
    unittest.main()
