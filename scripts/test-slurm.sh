#!/usr/bin/env bash
# The Slurm batch runner (clients/slurm) on a real single-node Slurm: starts munged, slurmctld and slurmd with their
# configuration and state in a temporary folder (scripts/slurm-single-node.sh), runs tests/deploy/test_slurm_runner.py,
# stops exactly the daemons it started. Part of scripts/test.sh. If Slurm cannot be started, it says what failed.
#   WISH_BIN   the wish executable (default build/release/cli/wish)
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD
export OPENBLAS_NUM_THREADS=1 OMP_NUM_THREADS=1
wish=${WISH_BIN:-$root/build/release/cli/wish}
[[ -x "$wish" ]] || { echo "test-slurm: FAILED: no wish executable at $wish (build the wish target)" >&2; exit 1; }
# shellcheck source=scripts/slurm-single-node.sh
source scripts/slurm-single-node.sh
dir=$(mktemp -d /tmp/wish-slurm-cluster.XXXXXX)
cleanup() { slurm_down; rm -rf "$dir"; }
trap cleanup EXIT
slurm_up "$dir"
cd tests/deploy
WISH_BIN="$wish" WISH_SOURCE_DIR="$root" /usr/bin/python3 -m unittest -v test_slurm_runner
