"""Deployment files: the real Dockerfile/manifests pass our linters; each rule catches what it is for."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import tempfile
import unittest
from pathlib import Path

SOURCE = Path(os.environ.get("WISH_SOURCE_DIR", Path(__file__).resolve().parents[2]))
sys.path.insert(0, str(SOURCE / "scripts"))
LINT_DF = SOURCE / "scripts" / "lint-dockerfile.py"


def lint_dockerfile(text: str) -> str:
    with tempfile.NamedTemporaryFile("w", suffix=".Dockerfile", delete=False) as f:
        f.write(text)
    r = subprocess.run([sys.executable, str(LINT_DF), f.name], capture_output=True, text=True, timeout=30)
    os.unlink(f.name)
    return r.stderr if r.returncode else ""


class DockerfileLintTest(unittest.TestCase):
    def setUp(self) -> None:
        self.good = (SOURCE / "docker" / "Dockerfile").read_text()

    def test_project_dockerfile_passes(self) -> None:
        self.assertEqual(lint_dockerfile(self.good), "")

    def test_rules(self) -> None:
        cases = {
            "DF001": self.good.replace("ARG DEBIAN=debian:bookworm-slim", "ARG DEBIAN=ubuntu:latest"),
            "DF002": self.good.replace("USER wish:wish", "USER root"),
            "DF003": self.good.replace("HEALTHCHECK", "# HEALTHCHECK").replace("  CMD curl", "#  CMD curl"),
            "DF004": self.good.replace("RUN bash scripts/install-deps.sh",
                                       "RUN curl -fsSL https://example.org/x.sh | sh && bash scripts/install-deps.sh"),
            "DF005": self.good.replace(" && rm -rf /var/lib/apt/lists/* /tmp/runtime-packages.txt", ""),
            "DF006": self.good.replace("RUN bash scripts/install-deps.sh --image && rm -rf /var/lib/apt/lists/*",
                                       "RUN apt-get update && apt-get install -y --no-install-recommends cmake "
                                       "&& rm -rf /var/lib/apt/lists/*"),
            "DF007": self.good.replace("--no-install-recommends ca-certificates", "ca-certificates"),
        }
        for rule, text in cases.items():
            self.assertNotEqual(text, self.good, f"{rule}: the test's edit did not apply")
            self.assertIn(rule, lint_dockerfile(text), rule)


@unittest.skipUnless(shutil.which("yamllint"), "yamllint is not installed")
class DeployLintTest(unittest.TestCase):
    def test_lint_deploy_script_passes(self) -> None:
        r = subprocess.run(["bash", str(SOURCE / "scripts" / "lint-deploy.sh")], capture_output=True, text=True,
                           timeout=120)
        self.assertEqual(r.returncode, 0, r.stdout + r.stderr)
        self.assertIn("lint-k8s", r.stdout)

    def test_k8s_rules(self) -> None:
        import importlib.util

        import yaml
        spec = importlib.util.spec_from_file_location("lint_k8s", SOURCE / "scripts" / "lint-k8s.py")
        mod = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(mod)
        docs = [(p.name, d) for p in sorted((SOURCE / "docker" / "k8s").glob("*.yaml"))
                for d in yaml.safe_load_all(p.read_text()) if d]
        self.assertEqual(mod.check(docs), [])
        dep = next(d for _, d in docs if d["kind"] == "Deployment")
        c = dep["spec"]["template"]["spec"]["containers"][0]
        c["resources"]["requests"]["cpu"] = "4"
        c["readinessProbe"]["httpGet"]["path"] = "/healthz"
        hpa = next(d for _, d in docs if d["kind"] == "HorizontalPodAutoscaler")
        hpa["spec"]["scaleTargetRef"]["name"] = "other"
        errors = "\n".join(mod.check(docs))
        self.assertIn("one worker per requested core", errors)
        self.assertIn("readinessProbe must be an httpGet of /readyz", errors)
        self.assertIn("scaleTargetRef", errors)


if __name__ == "__main__":
    unittest.main()
