#!/usr/bin/python3
"""Checks of the Kubernetes manifests that matter for WISH (kubeconform is not available here).

    /usr/bin/python3 scripts/lint-k8s.py docker/k8s/*.yaml

Every document needs apiVersion, kind, metadata.name. A Deployment: selector matching its template labels; each
container with an image, cpu+memory requests and limits, httpGet readiness and liveness probes, runAsNonRoot; the
container named `wish`: a readinessProbe on /readyz, a livenessProbe on /healthz and WISH_WORKERS equal to the cpu
request (one compute worker per requested core). A Service must select
a Deployment's pods; an HPA must target an existing Deployment with minReplicas <= maxReplicas. Exit 1 on failure.
"""

from __future__ import annotations

import sys
from pathlib import Path
from typing import Any

import yaml


def cpu_cores(value: Any) -> float:
    text = str(value)
    return float(text[:-1]) / 1000 if text.endswith("m") else float(text)


def check(docs: list[tuple[str, dict[str, Any]]]) -> list[str]:
    errors: list[str] = []
    deployments: dict[str, dict[str, Any]] = {}
    for where, d in docs:
        for key in ("apiVersion", "kind"):
            if not d.get(key):
                errors.append(f"{where}: missing {key}")
        if d.get("kind") != "Kustomization" and not (d.get("metadata") or {}).get("name"):
            errors.append(f"{where}: missing metadata.name")
        if d.get("kind") == "Deployment":
            deployments[d["metadata"]["name"]] = d
            spec = d.get("spec", {})
            sel = (spec.get("selector") or {}).get("matchLabels") or {}
            labels = ((spec.get("template") or {}).get("metadata") or {}).get("labels") or {}
            if not sel or any(labels.get(k) != v for k, v in sel.items()):
                errors.append(f"{where}: spec.selector.matchLabels does not match the pod template labels")
            pod = (spec.get("template") or {}).get("spec") or {}
            non_root = (pod.get("securityContext") or {}).get("runAsNonRoot")
            for c in pod.get("containers") or []:
                name = f"{where}: container {c.get('name')}"
                if not c.get("image"):
                    errors.append(f"{name}: no image")
                res = c.get("resources") or {}
                for part in ("requests", "limits"):
                    for r in ("cpu", "memory"):
                        if r not in (res.get(part) or {}):
                            errors.append(f"{name}: resources.{part}.{r} missing")
                is_wish = c.get("name") == "wish"   # the service itself; others (nginx) need probes of their own
                for probe, path in (("readinessProbe", "/readyz"), ("livenessProbe", "/healthz")):
                    got = ((c.get(probe) or {}).get("httpGet") or {}).get("path")
                    if (got != path) if is_wish else not got:
                        errors.append(f"{name}: {probe} must be an httpGet of {path if is_wish else 'a path'} "
                                      f"(got {got})")
                if not (non_root or (c.get("securityContext") or {}).get("runAsNonRoot")):
                    errors.append(f"{name}: runAsNonRoot is not set")
                env = {e.get("name"): e.get("value") for e in c.get("env") or []}
                cpu = (res.get("requests") or {}).get("cpu")
                if not is_wish:
                    continue
                if "WISH_WORKERS" not in env:
                    errors.append(f"{name}: WISH_WORKERS is not set (default = all cores of the node)")
                elif cpu is not None and abs(cpu_cores(cpu) - float(env["WISH_WORKERS"])) > 1e-9:
                    errors.append(f"{name}: WISH_WORKERS={env['WISH_WORKERS']} but requests.cpu={cpu}: "
                                  "one worker per requested core")
    pod_labels = [((d["spec"].get("template") or {}).get("metadata") or {}).get("labels") or {}
                  for d in deployments.values()]
    for where, d in docs:
        if d.get("kind") == "Service":
            sel = (d.get("spec") or {}).get("selector") or {}
            if not sel or not any(all(lbl.get(k) == v for k, v in sel.items()) for lbl in pod_labels):
                errors.append(f"{where}: Service selector {sel} matches no Deployment's pods")
        if d.get("kind") == "HorizontalPodAutoscaler":
            spec = d.get("spec") or {}
            ref = spec.get("scaleTargetRef") or {}
            if ref.get("kind") != "Deployment" or ref.get("name") not in deployments:
                errors.append(f"{where}: scaleTargetRef {ref} is not a Deployment in these manifests")
            if int(spec.get("minReplicas", 1)) > int(spec.get("maxReplicas", 0)):
                errors.append(f"{where}: minReplicas > maxReplicas")
    return errors


def main(argv: list[str]) -> int:
    docs = []
    for p in argv:
        for i, d in enumerate(yaml.safe_load_all(Path(p).read_text(encoding="utf-8"))):
            if d:
                docs.append((f"{p}#{i}", d))
    errors = check(docs)
    for e in errors:
        print(e, file=sys.stderr)
    if not errors:
        print(f"lint-k8s: {len(docs)} documents ok")
    return 1 if errors else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
