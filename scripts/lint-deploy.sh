#!/usr/bin/env bash
# Lints the deployment files (no Docker engine runs here): YAML manifests with yamllint, the Dockerfile
# with scripts/lint-dockerfile.py (our own checks of the rules that matter for this image), the Kubernetes
# manifests with scripts/lint-k8s.py (required fields, probes, resources).
set -euo pipefail
cd "$(dirname "$0")/.."
shopt -s nullglob globstar
yaml=(docker/**/*.yaml docker/**/*.yml)
if ((${#yaml[@]})); then yamllint -s -d '{extends: default, rules: {line-length: {max: 120}, document-start: disable}}' "${yaml[@]}"; fi
if [[ -f docker/Dockerfile && -f scripts/lint-dockerfile.py ]]; then /usr/bin/python3 scripts/lint-dockerfile.py docker/Dockerfile; fi
# Kubernetes manifests: required fields, probes, resources matched to WISH_WORKERS (scripts/lint-k8s.py).
k8s=(docker/k8s/*.yaml)
if ((${#k8s[@]})) && [[ -f scripts/lint-k8s.py ]]; then /usr/bin/python3 scripts/lint-k8s.py "${k8s[@]}"; fi
echo "lint-deploy: ok"
