"""What the container tests share: the docker CLI, free loopback ports, waiting for conditions, the image under test.

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
