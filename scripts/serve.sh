#!/usr/bin/env bash
# Installs what is missing, builds the service executable `wish-server` (what `wish serve` runs), and starts the
# HTTP service on the bundled default model (data/models/default.json — trained on a SYNTHETIC demo set, see
# data/models/README.md).
#   PORT=8080 WISH_MODELS=data/models bash scripts/serve.sh [extra `wish serve` flags]
# Only the service is built: the command line tool's own files (cli/, about a quarter of the compile;
# docs/benchmarks.md, "Third pass") and the training library it alone links (core/training/,
# wire/training_report_json.cpp) wait for `cmake --build build/release --target wish`.
set -euo pipefail
cd "$(dirname "$0")/.."
port=${PORT:-8080}
models=${WISH_MODELS:-data/models}

bash scripts/install-deps.sh
# A new build folder: Ninja, which compiles the objects of every library at once (Make waits for each library's
# dependencies) and keeps both cores busy with the few large unity batches (cmake/WishBuildSpeed.cmake); no tests
# or benchmarks, whose packages the service's set-up does not install (scripts/test.sh turns them on). One unity
# batch per library (WISH_UNITY_BATCH=0) for this one-off build: the Eigen and JSON templates a library's files share
# are instantiated once instead of once per batch of 8 (docs/benchmarks.md, "A bare machine to a served page").
new_folder=(); [[ -f build/release/CMakeCache.txt ]] || new_folder=(-G Ninja -DWISH_BUILD_TESTS=OFF -DWISH_BUILD_BENCH=OFF -DWISH_UNITY_BATCH=0)
cmake "${new_folder[@]}" -S . -B build/release -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build/release -j "$(getconf _NPROCESSORS_ONLN)" --target wish-server

example=data/meshes/celegans_cell.obj

cat <<MSG

WISH is starting on http://127.0.0.1:${port} with the models in ${models}/.
Classify a bundled example mesh from another terminal:

  curl -s -F mesh=@${PWD}/${example} http://127.0.0.1:${port}/v1/classify

MSG
# What `wish serve` does (cli/cmd_serve.cpp: exec of the wish-server beside it, every argument passed on).
exec build/release/cli/wish-server --models "$models" --port "$port" "$@"
