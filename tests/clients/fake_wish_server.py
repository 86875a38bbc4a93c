"""A small in-process fake of `wish serve` speaking the wire contract (proto/openapi.json), for client tests.

The "classifier" reads the class from the mesh text itself: a line ``# label: <class>`` (OBJ/OFF comments), else
``neuron``. A mesh containing ``# error: <code>`` is refused with 422 and that code. Failure injection, all
thread-safe and counted:

* ``busy_next(n, retry_after)`` — the next ``n`` compute requests get 503 ``queue_full`` with ``Retry-After``.
* ``drop_next(n)`` — the next ``n`` compute requests have their connection closed without an answer.
* ``proxy_error_next(n)`` — the next ``n`` compute requests get a non-JSON 502 page, as nginx sends.
* ``require_token`` — /v1/* demand ``Authorization: Bearer <token>``.
"""

from __future__ import annotations

import email.parser
import email.policy
import itertools
import json
import re
import threading
import time
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer
from typing import Any
from urllib.parse import parse_qs, urlsplit

CLASSES = ["astrocyte", "endothelium", "microglia", "neuron", "oligodendrocyte", "pericyte"]


def label_of(content: bytes) -> tuple[str | None, str]:
    """``(error_code or None, label)`` of a fake mesh."""
    text = content.decode("utf-8", "replace")
    err = re.search(r"#\s*error:\s*(\w+)", text)
    lab = re.search(r"#\s*label:\s*(\w+)", text)
    return (err.group(1) if err else None), (lab.group(1) if lab else "neuron")


def fake_mesh(label: str = "neuron", error: str | None = None, fmt: str = "obj", novel: bool = False) -> bytes:
    """A tiny tetrahedron mesh text carrying the fake classifier's answer (``novel``: none of the known types)."""
    head = f"# label: {label}\n" + (f"# error: {error}\n" if error else "") + ("# novel: true\n" if novel else "")
    if fmt == "off":
        return (head + "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n").encode()
    return (head + "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n").encode()


class FakeWishServer:
    """Start with ``with FakeWishServer() as srv: srv.url ...``."""

    def __init__(self, delay: float = 0.0, port: int = 0) -> None:
        self.delay = delay                      # seconds each compute request takes
        self.lock = threading.Lock()
        self.requests: list[dict[str, Any]] = []  # method, path, query, headers, names of compute requests
        self._busy = 0
        self._busy_retry_after = "0"
        self._drop = 0
        self._proxy = 0
        self.require_token: str | None = None
        self.in_flight = 0                      # compute requests being "computed" now
        self.max_in_flight = 0
        self.batch_statuses: list[int] = []     # HTTP status of each multipart answer sent
        self._ids = itertools.count(1)
        self.httpd = ThreadingHTTPServer(("127.0.0.1", port), self._handler())
        self.httpd.daemon_threads = True
        self.thread = threading.Thread(target=self.httpd.serve_forever, kwargs={"poll_interval": 0.05},
                                       daemon=True)

    @property
    def url(self) -> str:
        return f"http://127.0.0.1:{self.httpd.server_address[1]}"

    def __enter__(self) -> FakeWishServer:
        self.thread.start()
        return self

    def __exit__(self, *exc: Any) -> None:
        self.httpd.shutdown()
        self.httpd.server_close()

    def busy_next(self, n: int, retry_after: str = "0") -> None:
        with self.lock:
            self._busy, self._busy_retry_after = n, retry_after

    def drop_next(self, n: int) -> None:
        with self.lock:
            self._drop = n

    def proxy_error_next(self, n: int) -> None:
        with self.lock:
            self._proxy = n

    def compute_requests(self) -> list[dict[str, Any]]:
        with self.lock:
            return [r for r in self.requests if r["path"].startswith("/v1/classify") or
                    r["path"].startswith("/v1/describe")]

    # ---- the handler -----------------------------------------------------------------------------------------------

    def _handler(self) -> type[BaseHTTPRequestHandler]:
        srv = self

        class Handler(BaseHTTPRequestHandler):
            protocol_version = "HTTP/1.1"

            def log_message(self, *args: Any) -> None:  # quiet
                pass

            def _send(self, status: int, doc: Any, headers: dict[str, str] | None = None,
                      ctype: str = "application/json") -> None:
                body = (json.dumps(doc) if ctype == "application/json" else str(doc)).encode()
                self.send_response(status)
                self.send_header("Content-Type", ctype)
                self.send_header("Content-Length", str(len(body)))
                for k, v in (headers or {}).items():
                    self.send_header(k, v)
                self.end_headers()
                self.wfile.write(body)

            def _error(self, status: int, code: str, message: str, details: dict[str, Any] | None = None,
                       headers: dict[str, str] | None = None) -> None:
                rid = f"fake-{next(srv._ids)}"
                self._send(status, {"error": {"code": code, "message": message, "details": details or {}},
                                    "request_id": rid}, {"X-Request-Id": rid, **(headers or {})})

            def do_GET(self) -> None:  # noqa: N802
                path = urlsplit(self.path).path
                with srv.lock:
                    srv.requests.append({"method": "GET", "path": path, "headers": dict(self.headers)})
                if path.startswith("/v1/") and not self._authorised():
                    return
                model = {"name": "default", "version": "1", "file": "default.json", "loaded_at": "2024-01-01T00:00:00Z",
                         "is_default": True, "classes": CLASSES,
                         "descriptor_settings": {"lmax": 5, "method": "willmore", "steps": 10},
                         "feature_spec": {"family": "invariants", "l_min": 1, "l_max": 5, "scale": "none",
                                          "log_transform": True},
                         "training_summary": {"samples": 120, "test_accuracy": 0.83}}
                if path == "/healthz":
                    self._send(200, {"status": "ok"})
                elif path == "/readyz":
                    with srv.lock:
                        busy = srv._busy > 0
                    if busy:
                        self._error(503, "not_ready", "warming up", headers={"Retry-After": "1"})
                    else:
                        self._send(200, {"ready": True, "models": 1, "queue_depth": 0, "queue_capacity": 8,
                                         "workers": 2})
                elif path == "/metrics":
                    n = len(srv.compute_requests())
                    self._send(200, f'wish_http_requests_total{{route="/v1/classify",status="200"}} {n}\n',
                               ctype="text/plain; version=0.0.4")
                elif path == "/v1/models":
                    self._send(200, {"default": "default", "models": [model]})
                elif path == "/v1/models/default":
                    self._send(200, model)
                elif path.startswith("/v1/models/"):
                    self._error(404, "model_not_found", f"no model named {path[11:]!r}", {"name": path[11:]})
                else:
                    self._error(404, "not_found", f"no route {path}")

            def _authorised(self) -> bool:
                if srv.require_token and self.headers.get("Authorization") != f"Bearer {srv.require_token}":
                    self._error(401, "unauthorized", "missing or wrong bearer token")
                    return False
                return True

            def do_POST(self) -> None:  # noqa: N802
                url = urlsplit(self.path)
                query = {k: v[-1] for k, v in parse_qs(url.query).items()}
                length = int(self.headers.get("Content-Length") or 0)
                body = self.rfile.read(length)
                ctype = self.headers.get("Content-Type", "")
                parts = self._parts(ctype, body)
                with srv.lock:
                    srv.requests.append({"method": "POST", "path": url.path, "query": query,
                                         "headers": dict(self.headers), "names": [p[0] for p in parts]})
                    action = None
                    if srv._drop > 0:
                        srv._drop -= 1
                        action = "drop"
                    elif srv._proxy > 0:
                        srv._proxy -= 1
                        action = "proxy"
                    elif srv._busy > 0:
                        srv._busy -= 1
                        action = "busy"
                if action == "drop":
                    self.close_connection = True
                    self.connection.shutdown(2)  # reset-like: the client sees a connection error
                    return
                if action == "proxy":
                    self._send(502, "<html><body><h1>502 Bad Gateway</h1></body></html>", ctype="text/html")
                    return
                if action == "busy":
                    self._error(503, "queue_full", "the job queue is full (8 waiting)",
                                {"queue_capacity": 8}, {"Retry-After": srv._busy_retry_after})
                    return
                if not self._authorised():
                    return
                if url.path not in ("/v1/classify", "/v1/describe"):
                    self._error(404, "not_found", f"no route {url.path}")
                    return
                if ctype.startswith("application/x-www-form-urlencoded"):
                    self._error(415, "unsupported_media_type", "send the mesh as the raw body or multipart")
                    return
                if query.get("model", "default") != "default":
                    self._error(404, "model_not_found", f"no model named {query['model']!r}")
                    return
                if not parts:
                    self._error(400, "no_mesh", "the request has no mesh")
                    return
                with srv.lock:
                    srv.in_flight += 1
                    srv.max_in_flight = max(srv.max_in_flight, srv.in_flight)
                try:
                    if srv.delay:
                        time.sleep(srv.delay)
                finally:
                    with srv.lock:
                        srv.in_flight -= 1
                classify = url.path == "/v1/classify"
                rid = f"fake-{next(srv._ids)}"
                if not ctype.startswith("multipart/form-data"):
                    name, content = parts[0]
                    err, label = label_of(content)
                    if err:
                        self._error(422, err, f"refused: {err}", {"check": err})
                    else:
                        self._send(200, self._result(rid, None, content, label, classify), {"X-Request-Id": rid})
                    return
                items = []
                for name, content in parts:
                    err, label = label_of(content)
                    if err:
                        items.append({"part": "mesh", "filename": name, "status": 422,
                                      "error": {"code": err, "message": f"refused: {err}", "details": {}}})
                    else:
                        items.append({"part": "mesh", "filename": name, "status": 200,
                                      "result": self._result(rid, name, content, label, classify)})
                # proto BatchResponse: 200 all good, the common status when all failed alike (with the first
                # part's error at the top level), 207 Multi-Status when the parts differ.
                statuses = {item["status"] for item in items}
                status = statuses.pop() if len(statuses) == 1 else 207
                doc: dict[str, Any] = {"request_id": rid, "results": items}
                if status >= 400:
                    doc["error"] = items[0]["error"]
                srv.batch_statuses.append(status)
                self._send(status, doc, {"X-Request-Id": rid})

            @staticmethod
            def _parts(ctype: str, body: bytes) -> list[tuple[str, bytes]]:
                if not ctype.startswith("multipart/form-data"):
                    return [("", body)] if body else []
                msg = email.parser.BytesParser(policy=email.policy.HTTP).parsebytes(
                    b"Content-Type: " + ctype.encode() + b"\r\n\r\n" + body)
                return [(p.get_filename() or "", p.get_payload(decode=True) or b"")
                        for p in msg.iter_parts() if p.get_filename()]

            @staticmethod
            def _result(rid: str, name: str | None, content: bytes, label: str, classify: bool) -> dict[str, Any]:
                scale = 1.0 + len(content) % 7
                doc: dict[str, Any] = {
                    "request_id": rid,
                    "mesh": {"format": "obj", "bytes": len(content), "read_notes": [], "repairs": []},
                    "map": {"method": "willmore", "status": "ok", "seconds": 0.001},
                    "descriptor": {"lmax": 5, "settings": {"source": "model" if classify else "default", "lmax": 5,
                                                           "method": "willmore", "steps": 10},
                                   "invariants": [0.0] + [scale / (l * l) for l in range(1, 6)],
                                   "fit_error": {"mean": 0.01, "rms": 0.012, "max": 0.05}},
                    "timings": {"total": 0.001},
                }
                if name:
                    doc["mesh"]["filename"] = name
                if classify:
                    others = [c for c in CLASSES if c != label]
                    probs = [{"label": label, "probability": 0.75}] + [
                        {"label": c, "probability": 0.25 / len(others)} for c in others]
                    novel = b"# novel: true" in content
                    doc["prediction"] = {"label": label, "margin": 0.8, "probabilities": probs,
                                         "model": {"name": "default", "version": "1"}, "novel": novel,
                                         "novelty": {"computed": True, "score": 9.0 if novel else 1.0,
                                                     "p_value": 0.004 if novel else 0.5, "threshold": 3.0,
                                                     "quantile": 0.99, "nearest_class": label,
                                                     "distance_ratio": 3.0 if novel else 0.333}}
                return doc

        return Handler
