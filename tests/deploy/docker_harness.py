"""What the container tests share: the docker CLI, free loopback ports, waiting for conditions, the images under test
(the service and nginx) and starting them.

Run by scripts/test-docker.sh, which provides the engine (DOCKER_HOST) and builds the image (WISH_IMAGE). Every
container runs with ``--network host`` and listens on a free 127.0.0.1 port picked here; containers are named
``wish-test-<pid>-<n>`` and removed by the test that made them.
"""

from __future__ import annotations

import contextlib
import itertools
import os
import shutil
import subprocess
import time
import urllib.request
from collections.abc import Callable
from pathlib import Path

SOURCE = Path(os.environ.get("WISH_SOURCE_DIR", Path(__file__).resolve().parents[2]))
IMAGE = os.environ.get("WISH_IMAGE", "")
NGINX_IMAGE = os.environ.get("WISH_NGINX_IMAGE", "")
_names = itertools.count()


def skip_reason() -> str | None:
    """None when the image can be run here, else why not (the tests are then skipped, not passed)."""
    if not IMAGE:
        return "WISH_IMAGE is not set: run scripts/test-docker.sh"
    if not shutil.which("docker"):
        return "no docker client"
    r = subprocess.run(["docker", "image", "inspect", IMAGE], capture_output=True, timeout=60)
    return None if r.returncode == 0 else f"image {IMAGE} is not built"


def docker(*args: str, check: bool = True, timeout: float = 120) -> subprocess.CompletedProcess:
    r = subprocess.run(["docker", *args], capture_output=True, text=True, timeout=timeout)
    if check and r.returncode != 0:
        raise RuntimeError(f"docker {' '.join(args)} failed ({r.returncode}): {r.stderr.strip()}")
    return r


def container_name() -> str:
    return f"wish-test-{os.getpid()}-{next(_names)}"


def wait_for(condition: Callable[[], bool], what: str, timeout: float = 90, poll: float = 0.2) -> None:
    """Polls ``condition`` until it holds; raises TimeoutError naming ``what`` after ``timeout`` seconds."""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        with contextlib.suppress(OSError, ValueError, RuntimeError):
            if condition():
                return
        time.sleep(poll)
    raise TimeoutError(f"{what}: not after {timeout} s")


def http_ok(url: str) -> bool:
    with urllib.request.urlopen(url, timeout=3) as r:
        return r.status == 200


def metric(port: int, name: str, label: str = "") -> float:
    """Sum of the samples of metric ``name`` on the instance's /metrics whose labels contain ``label``."""
    with urllib.request.urlopen(f"http://127.0.0.1:{port}/metrics", timeout=5) as r:
        text = r.read().decode()
    total = 0.0
    for line in text.splitlines():
        series, _, value = line.rpartition(" ")
        metric_name, _, labels = series.partition("{")
        if metric_name == name and label in labels:
            total += float(value)
    return total


def run_service(name: str, port: int, *extra: str, env: dict[str, str] | None = None) -> str:
    """Starts the image as the deployment does: read-only root, /tmp a tmpfs, host network on ``port``."""
    env_args = [a for k, v in {"PORT": str(port), "WISH_HOST": "127.0.0.1", **(env or {})}.items()
                for a in ("-e", f"{k}={v}")]
    docker("run", "-d", "--name", name, "--network", "host", "--read-only", "--tmpfs", "/tmp",
           "--cap-drop", "ALL", "--security-opt", "no-new-privileges", *env_args, *extra, IMAGE)
    return name


def remove(name: str) -> None:
    docker("rm", "-f", name, check=False)


def logs(name: str) -> str:
    r = docker("logs", "--tail", "40", name, check=False)
    return (r.stdout + r.stderr)[-4000:]


def nginx_skip_reason() -> str | None:
    """None when the service image and the nginx image (docker/nginx) can both be run here, else why not."""
    if reason := skip_reason():
        return reason
    if not NGINX_IMAGE:
        return "WISH_NGINX_IMAGE is not set: run scripts/test-docker.sh"
    return None


def run_nginx(conf_dir: Path, port: int, upstream_ports: list[int], *extra: str, upstream_options: str = "") -> str:
    """Starts the nginx image on 127.0.0.1:``port`` in front of ``upstream_ports``, through the two include files the
    image's nginx.conf reads (written into ``conf_dir`` and mounted, as compose and Kubernetes provide them)."""
    conf_dir.mkdir(parents=True, exist_ok=True)
    (conf_dir / "wish-listen.conf").write_text(f"listen 127.0.0.1:{port};\n")
    (conf_dir / "wish-upstream.conf").write_text(
        "".join(f"server 127.0.0.1:{p}{' ' + upstream_options if upstream_options else ''};\n" for p in upstream_ports))
    name = container_name()
    docker("run", "-d", "--name", name, "--network", "host", *extra,
           "-v", f"{conf_dir / 'wish-listen.conf'}:/etc/nginx/wish-listen.conf:ro",
           "-v", f"{conf_dir / 'wish-upstream.conf'}:/etc/nginx/wish-upstream.conf:ro", NGINX_IMAGE)
    return name
