#!/usr/bin/env bash
# Installs the Debian 12 packages WISH needs, skipping those already present.
# The one list of packages: used by the README's commands, .ci/run and docker/Dockerfile.
#   scripts/install-deps.sh            build + run the service
#   scripts/install-deps.sh --test     also what the tests, fuzzers and linters need
set -euo pipefail

runtime_build=(
  build-essential cmake ninja-build pkg-config git ca-certificates curl
  libeigen3-dev libsuitesparse-dev libopenblas-dev libopenblas0-pthread
  libcpp-httplib-dev nlohmann-json3-dev libspdlog-dev libcli11-dev libsvm-dev
  zlib1g-dev libtiff-dev libopenmesh-dev
  libzip-dev libzstd-dev libblosc-dev   # OME-Zarr label images: zip stores, zstd and blosc chunks
  libhdf5-dev                          # the per-object table of a classified volume as AnnData (.h5ad)
  libgtest-dev libgmock-dev libbenchmark-dev
  python3
  ccache   # docker/Dockerfile compiles through it: the image reuses the objects scripts/test.sh compiled on the host
)
test_extra=(
  clang libclang-rt-14-dev
  python3-jsonschema python3-numpy python3-scipy python3-sklearn python3-matplotlib
  python3-zarr                       # writes the OME-Zarr stores the reader's tests read (an independent writer)
  python3-nibabel python3-anndata python3-h5py  # independent readers of the class maps and the .h5ad table
  assimp-testmodels nginx-light wrk yamllint python3-yaml
  chromium
  docker.io debootstrap              # scripts/test-docker.sh: the image built and run, its base made from Debian
  python3-venv python3-setuptools    # tests/deploy/test_pip_install.py: the README's install line
  slurm-wlm munge                    # scripts/test-slurm.sh: the Slurm batch runner on a single-node Slurm
)

want=("${runtime_build[@]}")
if [[ "${1:-}" == "--test" ]]; then want+=("${test_extra[@]}"); fi

# Node.js and npm build the web page's assets. A machine that already has them (e.g. a newer Node.js whose package
# bundles npm) keeps them: Debian's `npm` package would conflict with such a `nodejs`.
if ! command -v node >/dev/null || ! command -v npm >/dev/null; then want+=(nodejs npm); fi

missing=()
for p in "${want[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if ((${#missing[@]})); then
  echo "install-deps: installing ${missing[*]}"
  SUDO=""; [[ $(id -u) -ne 0 ]] && SUDO="sudo"
  export DEBIAN_FRONTEND=noninteractive
  $SUDO apt-get update -qq
  $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
else
  echo "install-deps: all ${#want[@]} packages present"
fi

# CHOLMOD's supernodal factorisation runs on BLAS: make OpenBLAS the system BLAS/LAPACK
# (Debian's default libblas3 is the slow reference implementation).
for alt in libblas.so.3-x86_64-linux-gnu liblapack.so.3-x86_64-linux-gnu; do
  target=$(update-alternatives --list "$alt" 2>/dev/null | grep -m1 openblas-pthread || true)
  if [[ -n "$target" ]]; then ${SUDO:-} update-alternatives --quiet --set "$alt" "$target"; fi
done

# The web page's npm packages (three.js; playwright-core for the browser tests, driving Debian's chromium: it never
# downloads a browser), exactly as web/package-lock.json pins them. Skipped when node_modules matches the lock.
root=$(cd "$(dirname "$0")/.." && pwd)
if [[ -f "$root/web/package-lock.json" ]] && [[ ! -f "$root/web/node_modules/.package-lock.json" ||
      "$root/web/package-lock.json" -nt "$root/web/node_modules/.package-lock.json" ]]; then
  echo "install-deps: npm ci in web/"
  (cd "$root/web" && PLAYWRIGHT_SKIP_BROWSER_DOWNLOAD=1 npm ci --no-audit --no-fund --loglevel=error)
fi
