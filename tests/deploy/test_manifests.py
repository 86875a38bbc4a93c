"""The deployment files agree with each other and with the service (no engine needed; the container tests then run
what these files describe):

* compose's `wish` service and the Kubernetes `wish` container set the same environment, probe the same paths and
  run as the image's user on a read-only root;
* the nginx configuration's body limit equals the service's default upload limit, and its read timeout outlasts the
  service's time limit (so the service answers 504 itself rather than nginx cutting the request);
* the Kubernetes nginx ConfigMap provides exactly the files the image's nginx.conf includes.
"""

from __future__ import annotations

import os
import re
import subprocess
import unittest
from pathlib import Path

import yaml

SOURCE = Path(os.environ.get("WISH_SOURCE_DIR", Path(__file__).resolve().parents[2]))
DOCKER = SOURCE / "docker"
WISH_BIN = os.environ.get("WISH_BIN", "")


def k8s_docs() -> list[dict]:
    return [d for p in sorted((DOCKER / "k8s").glob("*.yaml")) for d in yaml.safe_load_all(p.read_text()) if d]


def k8s_container(deployment: str, container: str) -> tuple[dict, dict]:
    d = next(d for d in k8s_docs() if d["kind"] == "Deployment" and d["metadata"]["name"] == deployment)
    pod = d["spec"]["template"]["spec"]
    return pod, next(c for c in pod["containers"] if c["name"] == container)


def nginx_directive(name: str) -> str:
    m = re.search(rf"^\s*{name}\s+([^;]+);", (DOCKER / "nginx" / "nginx.conf").read_text(), re.M)
    assert m, f"nginx.conf has no {name}"
    return m.group(1).strip()


def serve_default(option: str) -> str:
    """The default `wish serve --help` shows for an option."""
    text = subprocess.run([WISH_BIN, "serve", "--help"], capture_output=True, text=True, timeout=30).stdout
    m = re.search(rf"{re.escape(option)}\s+[A-Z]+(?:=|\s+\[)([^\s\]]+)", text)   # `UINT=64` or `UINT [64]`
    assert m, f"no default of {option} in `wish serve --help`"
    return m.group(1)


class ComposeMatchesKubernetesTest(unittest.TestCase):
    def setUp(self) -> None:
        self.compose = yaml.safe_load((DOCKER / "compose.yaml").read_text())["services"]
        self.pod, self.wish = k8s_container("wish", "wish")

    def test_same_environment(self) -> None:
        k8s_env = {e["name"]: e["value"] for e in self.wish["env"]}
        self.assertEqual(self.compose["wish"]["environment"], k8s_env)

    def test_same_health_path_and_hardening(self) -> None:
        health = self.compose["wish"]["healthcheck"]["test"][-1]
        self.assertEqual(health.rsplit(":8080", 1)[1], self.wish["livenessProbe"]["httpGet"]["path"])
        self.assertTrue(self.compose["wish"]["read_only"])
        self.assertTrue(self.wish["securityContext"]["readOnlyRootFilesystem"])
        self.assertEqual(self.compose["wish"]["cap_drop"], self.wish["securityContext"]["capabilities"]["drop"])
        self.assertIn("/tmp", self.compose["wish"]["tmpfs"])
        self.assertIn("/tmp", [m["mountPath"] for m in self.wish["volumeMounts"]])

    def test_pod_user_is_the_image_user(self) -> None:
        dockerfile = (DOCKER / "Dockerfile").read_text()
        uid = re.search(r"useradd [^\n]*--uid (\d+)", dockerfile).group(1)
        self.assertIn("USER wish:wish", dockerfile)
        self.assertEqual(str(self.pod["securityContext"]["runAsUser"]), uid)

    def test_shutdown_grace_fits_the_termination_grace(self) -> None:
        grace = int(self.compose["wish"]["stop_grace_period"].rstrip("s"))
        self.assertEqual(grace, self.pod["terminationGracePeriodSeconds"])


class NginxConfigTest(unittest.TestCase):
    def test_includes_are_what_compose_and_kubernetes_provide(self) -> None:
        includes = set(re.findall(r"^\s*include\s+/etc/nginx/([^;]+);", (DOCKER / "nginx" / "nginx.conf").read_text(),
                                  re.M))
        self.assertEqual(includes, {"wish-upstream.conf", "wish-listen.conf"})
        for name in includes:   # the image's defaults (compose)
            self.assertTrue((DOCKER / "nginx" / name).exists(), name)
        cm = next(d for d in k8s_docs() if d["kind"] == "ConfigMap" and d["metadata"]["name"] == "wish-nginx")
        self.assertEqual(set(cm["data"]), includes)
        _, nginx = k8s_container("wish-nginx", "nginx")
        self.assertEqual({m["subPath"] for m in nginx["volumeMounts"] if "subPath" in m}, includes)

    @unittest.skipUnless(WISH_BIN and Path(WISH_BIN).exists(), "WISH_BIN is not set")
    def test_limits_agree_with_the_service(self) -> None:
        body = nginx_directive("client_max_body_size")
        self.assertRegex(body, r"^\d+m$")
        self.assertEqual(int(body[:-1]) << 20, int(serve_default("--max-upload-bytes")))
        read_timeout = float(nginx_directive("proxy_read_timeout").rstrip("s"))
        self.assertGreater(read_timeout, float(serve_default("--time-limit")))


if __name__ == "__main__":
    unittest.main()
