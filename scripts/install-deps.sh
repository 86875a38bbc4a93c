#!/usr/bin/env bash
# Installs the Debian 12 packages WISH needs, skipping those already present.
# The one list of packages: used by the README's commands, .ci/run and docker/Dockerfile.
#   scripts/install-deps.sh            build and run the service (scripts/serve.sh): nothing else
#   scripts/install-deps.sh --image    that, plus what docker/Dockerfile's build stage compiles with (ccache)
#   scripts/install-deps.sh --test     everything: also what the tests, fuzzers, linters and browser tests need
# A fresh machine's set-up time is mostly these packages (docs/benchmarks.md, "A bare machine to a served page"):
# the service's list is kept to what its build and its web page use, and --no-install-recommends throughout.
set -euo pipefail

mode=serve
case "${1:-}" in
  "") ;;
  --image) mode=image ;;
  --test) mode=test ;;
  *) echo "usage: scripts/install-deps.sh [--image|--test]" >&2; exit 2 ;;
esac

# The service: compiler and build tools (g++ and Ninja: no make, no dpkg-dev), the libraries it links, Debian's
# three.js for its web page (served from /usr/share/javascript/three: no build step, no Node.js), curl for the
# example request serve.sh prints. OpenMesh: the runtime library here; its headers below.
serve=(
  g++ cmake ninja-build pkg-config curl
  libeigen3-dev libsuitesparse-dev libopenblas-dev libopenblas0-pthread
  libcpp-httplib-dev nlohmann-json3-dev libspdlog-dev libcli11-dev libsvm-dev
  zlib1g-dev libtiff-dev libopenmesh1
  libzip-dev libzstd-dev libblosc-dev   # OME-Zarr label images: zip stores, zstd and blosc chunks
  libhdf5-dev                          # the per-object table of a classified volume as AnnData (.h5ad)
  libjs-three
)
image_extra=(
  libopenmesh-dev   # the headers where the host's --test build has them, so that ccache finds the host's objects
  ccache            # docker/Dockerfile compiles through it: the image reuses the objects scripts/test.sh compiled
)
test_extra=(
  build-essential git ca-certificates python3 libopenmesh-dev
  libgtest-dev libgmock-dev libbenchmark-dev ccache
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

want=("${serve[@]}")
case $mode in
  image) want+=("${image_extra[@]}") ;;
  test) want+=("${test_extra[@]}") ;;
esac

# Node.js and npm run the browser tests only (playwright-core below). A machine that already has them (e.g. a newer
# Node.js whose package bundles npm) keeps them: Debian's `npm` package would conflict with such a `nodejs`.
if [[ $mode == test ]] && { ! command -v node >/dev/null || ! command -v npm >/dev/null; }; then want+=(nodejs npm); fi

installed() { dpkg-query -W -f='${Status}' "$1" 2>/dev/null | grep -q "install ok installed"; }
missing=()
for p in "${want[@]}"; do
  installed "$p" || missing+=("$p")
done

SUDO=""; [[ $(id -u) -ne 0 ]] && SUDO="sudo"
export DEBIAN_FRONTEND=noninteractive
updated=false
if ((${#missing[@]})); then
  echo "install-deps: installing ${missing[*]}"
  $SUDO apt-get update -qq
  updated=true
  $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
else
  echo "install-deps: all ${#want[@]} packages present"
fi

# OpenMesh's headers and CMake files without Debian's libopenmesh-dev package when the service alone is set up:
# that package depends on libopenscenegraph-dev, which brings in 153 more packages (GDAL, Mesa, LLVM, X11, ...;
# 105 MB to download, 400 MB installed) for OpenSceneGraph adaptor headers WISH never includes (OpenMesh/Tools/
# Kernel_OSG). So its files are unpacked from the same Debian package into build/debian-dev/ (apt-get download and
# dpkg-deb: Debian's own tools, nothing from elsewhere) and linked against the installed libopenmesh1;
# cmake/WishDependencies.cmake looks there when libopenmesh-dev is not installed. --image and --test install it.
root=$(cd "$(dirname "$0")/.." && pwd)
openmesh_dev="$root/build/debian-dev/libopenmesh-dev"
if ! installed libopenmesh-dev; then
  version=$(dpkg-query -W -f='${Version}' libopenmesh1)
  if [[ "$(cat "$openmesh_dev/VERSION" 2>/dev/null)" != "$version" ]]; then
    echo "install-deps: unpacking libopenmesh-dev $version into build/debian-dev/ (its headers, without its dependencies)"
    $updated || $SUDO apt-get update -qq
    work=$(mktemp -d) && chmod 755 "$work"   # apt's download user (_apt) writes there
    (cd "$work" && apt-get download -qq "libopenmesh-dev=$version")
    rm -rf "$openmesh_dev" && mkdir -p "$openmesh_dev"
    dpkg-deb -x "$work"/libopenmesh-dev_*.deb "$openmesh_dev"
    rm -rf "$work"
    # The package's .so links point at the shared libraries beside them, which are libopenmesh1's (installed).
    for lib in "$openmesh_dev"/usr/lib/*/libOpenMesh*.so; do
      real=$(readlink "$lib")
      ln -sfn "/usr/lib/$(basename "$(dirname "$lib")")/$real" "$(dirname "$lib")/$real"
    done
    echo "$version" >"$openmesh_dev/VERSION"
  fi
fi

# CHOLMOD's supernodal factorisation runs on BLAS: make OpenBLAS the system BLAS/LAPACK
# (Debian's default libblas3 is the slow reference implementation).
for alt in libblas.so.3-x86_64-linux-gnu liblapack.so.3-x86_64-linux-gnu; do
  target=$(update-alternatives --list "$alt" 2>/dev/null | grep -m1 openblas-pthread || true)
  if [[ -n "$target" ]]; then $SUDO update-alternatives --quiet --set "$alt" "$target"; fi
done

# The browser tests' npm package (playwright-core, driving Debian's chromium: it never downloads a browser), exactly
# as web/package-lock.json pins it. Skipped when node_modules matches the lock. The page itself needs no npm package.
if [[ $mode == test && -f "$root/web/package-lock.json" ]] &&
   [[ ! -f "$root/web/node_modules/.package-lock.json" ||
      "$root/web/package-lock.json" -nt "$root/web/node_modules/.package-lock.json" ]]; then
  echo "install-deps: npm ci in web/"
  (cd "$root/web" && PLAYWRIGHT_SKIP_BROWSER_DOWNLOAD=1 npm ci --no-audit --no-fund --loglevel=error)
fi
