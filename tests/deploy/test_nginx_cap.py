"""The connection cap of the nginx in front (docker/nginx: the image compose and the Kubernetes manifests run),
answered at once: with the cap's worth of requests in progress (each has sent its header and part of its body, so
nginx holds it while it buffers the upload), the next request gets 503 with Retry-After and the service's error body
at once, not a wait; nginx's own /nginx-healthz still answers; closing the holders frees the cap.

No service instance is needed: the upstream is a closed loopback port, so a request that passes the cap gets 502.
Run by scripts/test-docker.sh (engine + image WISH_NGINX_IMAGE); skipped without them.
"""

from __future__ import annotations

import json
import re
import resource
import shutil
import socket
import sys
import tempfile
import time
import unittest
import urllib.error
import urllib.request
from pathlib import Path

from docker_harness import SOURCE, http_ok, logs, nginx_skip_reason, remove, run_nginx, wait_for
from loopback import free_ports


def configured_cap() -> int:
    """The cap as the image's nginx.conf sets it (the test follows the configuration, not a copy of its number)."""
    m = re.search(r"^\s*limit_conn\s+wish_in_progress\s+(\d+);", (SOURCE / "docker" / "nginx" / "nginx.conf")
                  .read_text(), re.M)
    assert m, "nginx.conf has no limit_conn wish_in_progress"
    return int(m.group(1))


def post(url: str) -> tuple[int, dict[str, str], bytes]:
    req = urllib.request.Request(url, data=b"", method="POST", headers={"Content-Type": "application/octet-stream"})
    try:
        with urllib.request.urlopen(req, timeout=10) as r:
            return r.status, dict(r.headers), r.read()
    except urllib.error.HTTPError as e:
        return e.code, dict(e.headers), e.read()


@unittest.skipIf(nginx_skip_reason(), nginx_skip_reason() or "")
class NginxConnectionCapTest(unittest.TestCase):
    def setUp(self) -> None:
        self.cap = configured_cap()
        soft, hard = resource.getrlimit(resource.RLIMIT_NOFILE)
        if soft < self.cap + 64:
            resource.setrlimit(resource.RLIMIT_NOFILE, (min(hard, self.cap + 256), hard))
        self.tmp = Path(tempfile.mkdtemp(prefix="wish-nginx-cap-"))
        self.addCleanup(shutil.rmtree, self.tmp, True)
        self.port, closed_port = free_ports(2)
        self.nginx = run_nginx(self.tmp, self.port, [closed_port], "--read-only", "--tmpfs", "/tmp")
        self.addCleanup(remove, self.nginx)
        self.base = f"http://127.0.0.1:{self.port}"
        wait_for(lambda: http_ok(f"{self.base}/nginx-healthz"), f"nginx ({logs(self.nginx)})")
        self.holders: list[socket.socket] = []
        self.addCleanup(self.close_holders)

    def close_holders(self) -> None:
        for s in self.holders:
            s.close()
        self.holders.clear()

    def hold_requests(self, n: int) -> None:
        """n uploads that send their header and 1 of 1000 body bytes, then wait (nginx buffers, so each stays in
        progress until client_body_timeout)."""
        for _ in range(n):
            s = socket.create_connection(("127.0.0.1", self.port), timeout=10)
            s.sendall(b"POST /v1/classify HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Type: application/octet-stream\r\n"
                      b"Content-Length: 1000\r\n\r\nx")
            self.holders.append(s)

    def test_past_the_cap_a_request_is_answered_503_at_once(self) -> None:
        # Below the cap a request passes through to the (absent) instance: 502, not the cap's 503.
        self.hold_requests(self.cap - 1)
        status, _, _ = post(f"{self.base}/v1/classify")
        self.assertEqual(status, 502, "one below the cap, a request must reach the upstream")

        self.hold_requests(1)
        # nginx reads the holders' headers in its event loop; the cap holds once it has read the last one.
        answers: list[tuple[int, dict[str, str], bytes, float]] = []

        def capped() -> bool:
            t0 = time.monotonic()
            status, headers, body = post(f"{self.base}/v1/classify")
            answers.append((status, headers, body, time.monotonic() - t0))
            return status == 503

        wait_for(capped, "a request past the cap answered 503", timeout=20, poll=0.05)
        status, headers, body, seconds = answers[-1]
        # Printed, not asserted (timings belong in benchmarks): a 503 is the cap's answer, since nginx never queues a
        # request for an instance, and below the cap the same request got the upstream's 502.
        print(f"\nnginx cap {self.cap}: the request past it answered {status} in {seconds * 1000:.1f} ms "
              f"({len(answers)} probe(s))", file=sys.stderr)
        self.assertEqual(headers.get("Retry-After"), "1")
        error = json.loads(body)
        self.assertEqual(error["error"]["code"], "unavailable")
        self.assertEqual(error["error"]["details"]["cap"], self.cap)
        self.assertTrue(error["request_id"])
        self.assertTrue(http_ok(f"{self.base}/nginx-healthz"), "nginx's own health must not be capped")

        self.close_holders()
        wait_for(lambda: post(f"{self.base}/v1/classify")[0] == 502, "the cap freed once the holders closed",
                 timeout=20)


if __name__ == "__main__":
    unittest.main()
