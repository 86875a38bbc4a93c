#!/usr/bin/env bash
# Installs what is missing, builds, and runs every test: the Release build with all tests (C++ and Python), one
# clang ASan+UBSan build for both the C++ tests (the slow data sweeps excluded) and the libFuzzer targets (each run
# for a bounded time), the linters of the deployment files, the Slurm runner on a single-node Slurm
# (scripts/test-slurm.sh) and the container image built and run (scripts/test-docker.sh).
# Exit status non-zero on any failure.
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD
jobs=$(getconf _NPROCESSORS_ONLN)   # not nproc: it follows OMP_NUM_THREADS
export OPENBLAS_NUM_THREADS=1 OMP_NUM_THREADS=1   # tests run in parallel: no nested threading
fuzz_seconds=${WISH_FUZZ_SECONDS:-30}

step() { printf '\n==== %s (%s)\n' "$1" "$(date -u +%H:%M:%S)"; }
# Ninja for a new build folder (see scripts/serve.sh); a folder configured before keeps its generator.
generator() { sed -n 's/^CMAKE_GENERATOR:INTERNAL=//p' "$1/CMakeCache.txt" 2>/dev/null | grep . || echo Ninja; }

step "dependencies"
bash scripts/install-deps.sh --test

# The container images in the background from here on: the base image and the image's dependency stage
# (debootstrap's and apt's downloads, minutes of network wait) overlap the host's Release build; the image itself
# follows that build, its compile taking the host's objects from the compiler cache .ccache/ (sent in the build
# context; docker/Dockerfile) instead of compiling the libraries a fourth time. The last step re-runs the build from
# docker's cache.
mkdir -p build
rm -f build/release-build.done
step "container images: building in the background (build/docker-prebuild.log)"
bash scripts/test-docker.sh --prebuild-after build/release-build.done >build/docker-prebuild.log 2>&1 &
docker_prebuild_pid=$!
# On an early failure, stop it (its children first: bash runs its EXIT trap, which stops its dockerd, only after
# the foreground docker client is gone).
trap 'if kill -0 "$docker_prebuild_pid" 2>/dev/null; then pkill -TERM -P "$docker_prebuild_pid"; kill -TERM "$docker_prebuild_pid"; wait "$docker_prebuild_pid" 2>/dev/null; fi' EXIT

step "release build"
# Through ccache into .ccache/ (the image's build reuses it): paths relative to the checkout, and the sloppiness the
# precompiled header needs (without it ccache caches nothing here: every file includes the precompiled header).
# ccache hashes the locale variables too: the build runs in the locale of the image's build stage (LANG=C.UTF-8).
export CCACHE_DIR="$root/.ccache" CCACHE_BASEDIR="$root" CCACHE_SLOPPINESS=pch_defines,time_macros CCACHE_MAXSIZE=2G
image_locale=(env -u LC_ALL -u LC_CTYPE -u LC_MESSAGES LANG=C.UTF-8)
"${image_locale[@]}" cmake -G "$(generator build/release)" -S . -B build/release -DCMAKE_BUILD_TYPE=Release \
      -DWISH_SANITIZE=OFF -DWISH_BUILD_TESTS=ON -DWISH_BUILD_BENCH=ON -DCMAKE_CXX_COMPILER_LAUNCHER=ccache >/dev/null
"${image_locale[@]}" cmake --build build/release -j "$jobs"

touch build/release-build.done   # the background job builds the image now

step "sanitizer build (ASan + UBSan, clang) with the libFuzzer targets"
# One clang tree for both: the C++ tests under ASan+UBSan and the fuzzers (until session 12 a gcc tree for the tests
# and a second, clang tree for the fuzzers compiled the libraries twice under the sanitizers; docs/benchmarks.md,
# "Third pass"). Only the readers and the validation, the libraries the fuzzers exercise, carry libFuzzer's coverage
# counters (-fsanitize=fuzzer-no-link, tests/fuzz/CMakeLists.txt; CMAKE_CXX_FLAGS empty so that an older tree's cached
# global flag goes); the test programs do not link libFuzzer. -O1, as libFuzzer's documentation builds its targets;
# line tables only (-gline-tables-only), all a sanitizer report's stack needs (file:line of every frame); asserts on
# (Debug). No programs for the slow sweeps, which this tree's run skips (WISH_SLOW_TESTS=OFF: 11 programs, about 80
# CPU s of this build measured 2026-12-07).
CC=clang CXX=clang++ cmake -G "$(generator build/sanitize)" -S . -B build/sanitize -DCMAKE_BUILD_TYPE=Debug \
      -DCMAKE_CXX_FLAGS_DEBUG="-O1 -gline-tables-only" -DCMAKE_CXX_FLAGS="" \
      -DWISH_SANITIZE=ON -DWISH_FUZZ=ON -DWISH_BUILD_BENCH=OFF -DWISH_BUILD_APPS=OFF -DWISH_SLOW_TESTS=OFF >/dev/null
cmake --build build/sanitize -j "$jobs"

step "libFuzzer targets"
# A fuzzer runs on one core: $jobs of them at a time, each for the same bounded time; their reports in turn.
fuzz_one() {
  local fuzzer=$1 name; name=$(basename "$fuzzer")
  local corpus="build/sanitize/corpus/$name"; mkdir -p "$corpus"
  "$fuzzer" -max_total_time="$fuzz_seconds" -rss_limit_mb=2048 -timeout=10 -print_final_stats=0 \
            "$corpus" "tests/fuzz/corpus/${name#fuzz_}" >"build/sanitize/$name.log" 2>&1
}
fuzzers=(); for fuzzer in build/sanitize/tests/fuzz/fuzz_*; do [[ -x "$fuzzer" ]] && fuzzers+=("$fuzzer"); done
for ((i = 0; i < ${#fuzzers[@]}; i += jobs)); do
  pids=()
  for fuzzer in "${fuzzers[@]:i:jobs}"; do fuzz_one "$fuzzer" & pids+=("$!:$fuzzer"); done
  for entry in "${pids[@]}"; do
    pid=${entry%%:*} name=$(basename "${entry#*:}")
    status=0; wait "$pid" || status=$?
    echo "-- $name for ${fuzz_seconds}s"; tail -n 3 "build/sanitize/$name.log"
    if ((status)); then echo "fuzzer $name failed (exit $status): build/sanitize/$name.log" >&2; exit 1; fi
  done
done

step "deployment linters"
bash scripts/lint-deploy.sh

step "sanitizer tests"
# Besides the slow sweeps, three tests that repeat under the sanitizers what smaller ones there already cover, at 20-30x
# their Release time (measured 2026-12-06: 231 s and 95 s of the step's 345 s at -j2; 8 s and 4.5 s in Release, where
# both still run): a sample of every generated hard-mask family (its code paths: TopologyRepair.*, ObjectSurface.*,
# Volume/*) and the default chain on the shared meshes that need the progressive embedding (ProgressiveEmbedding.*);
# and (2026-12-07: 82 s here, 3.7 s in Release) the canonical relaxation's 131 steps from a progressive start on a
# real spine, whose code (the same Newton steps, damping and extrapolation) CanonicalMap.DoesNotDependOnTheStart... and
# CanonicalMap.EveryStepKeepsTheMapBijective run here.
sanitizer_skips="Sweep|Slow|HardMasks.ASampleOfEachFamily|ProgressiveEmbedding.EndsTheDefaultChainOnSharedMeshes"
sanitizer_skips+="|CanonicalMap.ReachesTheSameMapFromTheProgressiveEmbeddingOnARealSpine"
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1 \
  ctest --test-dir build/sanitize --output-on-failure -j "$jobs" -LE "slow|python" -E "$sanitizer_skips" --timeout 900

step "Slurm batch runner on a single-node Slurm (scripts/test-slurm.sh)"
WISH_BIN="$root/build/release/cli/wish" bash scripts/test-slurm.sh

step "container images: the background build (scripts/test-docker.sh --prebuild-after)"
if wait "$docker_prebuild_pid"; then tail -n 5 build/docker-prebuild.log
else echo "background image build failed (the next step builds again and reports):"; tail -n 20 build/docker-prebuild.log
fi

step "container image: build and end-to-end tests (scripts/test-docker.sh)"
bash scripts/test-docker.sh

step "release tests"
ctest --test-dir build/release --output-on-failure -j "$jobs" --timeout 1200
