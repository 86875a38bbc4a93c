"""Start the real `wish serve` binary on a free port and talk HTTP to it (stdlib only + python3-jsonschema).

Environment (set by ctest, see tests/CMakeLists.txt): WISH_BIN (the wish executable), WISH_SOURCE_DIR (repository),
WISH_SHARED_DATA (../shared/data). Every server listens on 127.0.0.1 with --port 0; the port is read from the
"listening on http://127.0.0.1:PORT" log line, so there is no race for a pre-chosen port.
"""
import http.client
import json
import os
import re
import shutil
import signal
import subprocess
import tempfile
import time
import uuid

import jsonschema

SOURCE_DIR = os.environ.get("WISH_SOURCE_DIR", os.path.abspath(os.path.join(os.path.dirname(__file__), "..", "..")))
SHARED_DATA = os.environ.get("WISH_SHARED_DATA", os.path.join(SOURCE_DIR, "..", "shared", "data"))
WISH_BIN = os.environ.get("WISH_BIN", os.path.join(SOURCE_DIR, "build", "server", "cli", "wish"))
CGAL = os.path.join(SHARED_DATA, "cgal")
DEFAULT_MODEL = os.path.join(SOURCE_DIR, "data", "models", "default.json")


def wait_for(predicate, timeout=30, interval=0.02):
    """Polls predicate until it is true (returns True) or timeout seconds pass (returns False): tests wait for a
    condition, never for a moment."""
    end = time.time() + timeout
    while time.time() < end:
        if predicate():
            return True
        time.sleep(interval)
    return False


def shared(*parts):
    return os.path.join(CGAL, *parts)


def read_bytes(path):
    with open(path, "rb") as f:
        return f.read()


def off_to_obj(off_bytes):
    """Same mesh as OBJ text (to exercise the OBJ reader without another data file)."""
    tokens = [line.split("#")[0] for line in off_bytes.decode().splitlines()]
    words = " ".join(tokens).split()
    assert words[0] == "OFF"
    nv, nf = int(words[1]), int(words[2])
    pos = 4
    out = []
    for _ in range(nv):
        out.append("v %s %s %s" % tuple(words[pos:pos + 3]))
        pos += 3
    for _ in range(nf):
        k = int(words[pos])
        idx = [str(int(w) + 1) for w in words[pos + 1:pos + 1 + k]]
        out.append("f " + " ".join(idx))
        pos += 1 + k
    return ("\n".join(out) + "\n").encode()


# ---------------------------------------------------------------- schemas
with open(os.path.join(SOURCE_DIR, "proto", "openapi.json")) as f:
    OPENAPI = json.load(f)
_RESOLVER = jsonschema.RefResolver.from_schema(OPENAPI)


def validate(schema_name, instance):
    """Validates `instance` against components/schemas/<schema_name> of proto/openapi.json."""
    validator = jsonschema.Draft202012Validator({"$ref": "#/components/schemas/" + schema_name}, resolver=_RESOLVER)
    errors = sorted(validator.iter_errors(instance), key=lambda e: list(e.path))
    if errors:
        raise AssertionError("%s does not match schema %s: %s" % (
            json.dumps(instance)[:600], schema_name, "; ".join("%s at %s" % (e.message[:200], list(e.path)) for e in errors[:5])))


# ---------------------------------------------------------------- multipart
def multipart(files, fields=None):
    """files: list of (field, filename, bytes); fields: dict. Returns (body, content_type)."""
    boundary = "wishboundary" + uuid.uuid4().hex
    parts = []
    for name, value in (fields or {}).items():
        parts.append(("--%s\r\nContent-Disposition: form-data; name=\"%s\"\r\n\r\n%s\r\n" % (boundary, name, value)).encode())
    for field, filename, data in files:
        head = "--%s\r\nContent-Disposition: form-data; name=\"%s\"" % (boundary, field)
        if filename is not None:
            head += "; filename=\"%s\"" % filename
        head += "\r\nContent-Type: application/octet-stream\r\n\r\n"
        parts.append(head.encode() + data + b"\r\n")
    body = b"".join(parts) + ("--%s--\r\n" % boundary).encode()
    return body, "multipart/form-data; boundary=" + boundary


class Response:
    def __init__(self, status, headers, body):
        self.status, self.headers, self.body = status, headers, body

    def json(self):
        return json.loads(self.body)

    def header(self, name):
        for k, v in self.headers:
            if k.lower() == name.lower():
                return v
        return None


class Server:
    """A running `wish serve`; use as a context manager. Logs go to a file (never a pipe that could fill up)."""

    def __init__(self, models_dir=None, args=(), env=None, start_timeout=30):
        self.tmp = tempfile.mkdtemp(prefix="wish-server-test-")
        if models_dir is None:  # an empty models directory; False: no --models at all (the bundled default model)
            models_dir = os.path.join(self.tmp, "models")
            os.makedirs(models_dir)
        self.models_dir = models_dir
        self.log_path = os.path.join(self.tmp, "server.log")
        models_args = [] if models_dir is False else ["--models", models_dir]
        cmd = [WISH_BIN, "serve"] + models_args + ["--host", "127.0.0.1", "--port", "0"] + list(args)
        full_env = dict(os.environ)
        full_env.update(env or {})
        self.log = open(self.log_path, "wb")
        self.proc = subprocess.Popen(cmd, stdout=self.log, stderr=subprocess.STDOUT, env=full_env)
        self.port = None
        deadline = time.time() + start_timeout
        while time.time() < deadline:
            m = re.search(r"listening on http://127\.0\.0\.1:(\d+)", self.log_text())
            if m:
                self.port = int(m.group(1))
                break
            if self.proc.poll() is not None:
                break
            time.sleep(0.05)
        if self.port is None:
            self.kill()
            raise RuntimeError("server did not start: %s" % self.log_text()[-3000:])

    def log_text(self):
        with open(self.log_path, "rb") as f:
            return f.read().decode(errors="replace")

    def complete_log_lines(self):
        """The log's whole lines (a line being written has no newline yet)."""
        text = self.log_text()
        return [l for l in text[:text.rfind("\n") + 1].splitlines() if l.strip()]

    def wait_for_log_lines(self, marker, timeout=30):
        """The whole log lines containing marker, once there is one (the access line is written after the response
        is sent, so a test reading the log right after its answer must wait for it); [] after timeout."""
        found = []

        def seen():
            found[:] = [l for l in self.complete_log_lines() if marker in l]
            return bool(found)

        wait_for(seen, timeout=timeout)
        return found

    def request(self, method, path, body=None, headers=None, timeout=120):
        conn = http.client.HTTPConnection("127.0.0.1", self.port, timeout=timeout)
        try:
            conn.request(method, path, body=body, headers=headers or {})
            r = conn.getresponse()
            return Response(r.status, r.getheaders(), r.read())
        finally:
            conn.close()

    def post_mesh(self, path, data, content_type="application/octet-stream", headers=None, timeout=120):
        h = {"Content-Type": content_type}
        h.update(headers or {})
        return self.request("POST", path, body=data, headers=h, timeout=timeout)

    def post_multipart(self, path, files, fields=None, timeout=120):
        body, ctype = multipart(files, fields)
        return self.request("POST", path, body=body, headers={"Content-Type": ctype}, timeout=timeout)

    def metric(self, name, labels=None):
        """Value of one sample of /metrics (labels: dict that must match exactly), or None."""
        text = self.request("GET", "/metrics").body.decode()
        for line in text.splitlines():
            if line.startswith("#"):
                continue
            m = re.match(r"^([a-z_]+)(\{[^}]*\})? (\S+)$", line)
            if not m or m.group(1) != name:
                continue
            got = dict(re.findall(r'(\w+)="([^"]*)"', m.group(2) or ""))
            if labels is None or got == labels:
                return float(m.group(3))
        return None

    def signal(self, sig):
        self.proc.send_signal(sig)

    def stop(self, timeout=60):
        """SIGTERM and wait; returns the exit code."""
        if self.proc.poll() is None:
            self.proc.send_signal(signal.SIGTERM)
            try:
                self.proc.wait(timeout=timeout)
            except subprocess.TimeoutExpired:
                self.kill()
        return self.proc.returncode

    def kill(self):
        if self.proc.poll() is None:
            self.proc.kill()
            self.proc.wait(timeout=30)

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.stop()
        self.log.close()
        shutil.rmtree(self.tmp, ignore_errors=True)


def models_dir_with_default(tmpdir):
    """A temporary models directory holding a copy of data/models/default.json, or None when it does not exist."""
    if not os.path.exists(DEFAULT_MODEL):
        return None
    d = os.path.join(tmpdir, "models")
    os.makedirs(d, exist_ok=True)
    shutil.copy(DEFAULT_MODEL, os.path.join(d, "default.json"))
    return d


def skip_reason_binary():
    if not os.path.exists(WISH_BIN):
        return "wish binary not found at %s (set WISH_BIN)" % WISH_BIN
    if not os.path.isdir(CGAL):
        return "shared test meshes not found at %s (set WISH_SHARED_DATA)" % CGAL
    return None
