#!/usr/bin/env bash
# Lints the deployment files (no Docker engine runs here): YAML manifests with yamllint, the Dockerfile
# with scripts/lint-dockerfile.py (our own checks of the rules that matter for this image).
set -euo pipefail
cd "$(dirname "$0")/.."
shopt -s nullglob globstar
yaml=(docker/**/*.yaml docker/**/*.yml)
if ((${#yaml[@]})); then yamllint -s -d '{extends: default, rules: {line-length: {max: 120}, document-start: disable}}' "${yaml[@]}"; fi
if [[ -f docker/Dockerfile && -f scripts/lint-dockerfile.py ]]; then /usr/bin/python3 scripts/lint-dockerfile.py docker/Dockerfile; fi
echo "lint-deploy: ok"
