#!/usr/bin/env bash
# The container image, built and run for real (part of scripts/test.sh, so CI runs it):
#   1. a Docker engine: the running one, or Debian's dockerd started here (and stopped again, by its pid);
#   2. the base image made from Debian's repository when missing (no registry is needed: scripts/docker-engine.sh);
#   3. docker/Dockerfile built (--network host, the legacy builder: nothing is fetched from a registry), its build time
#      and image size printed;
#   4. the end-to-end tests against running containers, all on 127.0.0.1 with --network host:
#      tests/deploy/test_container.py (classify, healthcheck, non-root on a read-only root, models volume + reload,
#      SIGTERM drain), tests/deploy/test_nginx_cap.py (nginx's connection cap answered 503 at once) and
#      tests/deploy/test_scale_out_containers.py (N containers behind nginx, one killed and one restarted under load
#      from the batch client).
# When no engine can start, it says why and fails. Containers and images it made carry the names wish-test-*.
#   WISH_DOCKER_TESTS="test_container"   run only these test modules
#   WISH_IMAGE=wish:test                 the tag built and tested
#   --build-only                         steps 1-3 only (the later full run then finds every layer in the build cache)
#   --prebuild-after FILE                steps 1-3 for scripts/test.sh, in the background from its start: the base image,
#                                        the image's dependency stage (`--target deps`: apt's downloads) and the nginx
#                                        image at once, overlapping the host builds; the image itself once FILE exists
#                                        (test.sh makes it when its Release build has filled .ccache/, which the image's
#                                        compile reuses: docker/Dockerfile)
set -euo pipefail
mode=all
case "${1:-}" in
  --build-only) mode=build ;;
  --prebuild-after) mode=prebuild; marker=${2:?--prebuild-after needs a file} ;;
esac
cd "$(dirname "$0")/.."
root=$PWD
export OPENBLAS_NUM_THREADS=1 OMP_NUM_THREADS=1
image=${WISH_IMAGE:-wish:test}
# shellcheck source=scripts/docker-engine.sh
source scripts/docker-engine.sh

trap 'docker_engine_down' EXIT
if ! docker_engine_up; then
  echo "test-docker: FAILED: no container engine could be started on this machine" >&2
  exit 1
fi
docker_base_image

build_nginx_image() {
  DOCKER_BUILDKIT=0 docker build --network host --build-arg "DEBIAN=$WISH_BASE_IMAGE" -f docker/nginx/Dockerfile \
    -t "$nginx_image" docker/nginx >"${TMPDIR:-/tmp}/wish-docker-build-nginx.log" 2>&1 || {
    echo "test-docker: FAILED: docker build of docker/nginx; the end of the log:" >&2
    tail -n 20 "${TMPDIR:-/tmp}/wish-docker-build-nginx.log" >&2
    exit 1
  }
  echo "test-docker: image $nginx_image built; size $(docker image inspect -f '{{.Size}}' "$nginx_image" |
    awk '{printf "%.1f MB", $1 / 1e6}')"
}
nginx_image=${WISH_NGINX_IMAGE:-wish-nginx:test}

if [[ $mode == prebuild ]]; then
  # The stage copies scripts/install-deps.sh only: a context of that one file (the checkout's .ccache/ is being
  # written by the host build meanwhile); the full build later finds the layer by the file's content.
  t0=$SECONDS
  context=$(mktemp -d "${TMPDIR:-/tmp}/wish-deps-context.XXXXXX")
  mkdir "$context/scripts" && cp -p scripts/install-deps.sh "$context/scripts/"   # same mode: same layer
  DOCKER_BUILDKIT=0 docker build --network host --build-arg "DEBIAN=$WISH_BASE_IMAGE" --target deps \
    -f docker/Dockerfile "$context" >"${TMPDIR:-/tmp}/wish-docker-build-deps.log" 2>&1 || {
    rm -rf "$context"
    echo "test-docker: FAILED: docker build --target deps; the end of the log:" >&2
    tail -n 40 "${TMPDIR:-/tmp}/wish-docker-build-deps.log" >&2
    exit 1
  }
  rm -rf "$context"
  echo "test-docker: the dependency stage of docker/Dockerfile built in $((SECONDS - t0)) s"
  build_nginx_image
  while [[ ! -e "$marker" ]]; do sleep 5; done
  mode=build
fi

t0=$SECONDS
echo "test-docker: building $image from docker/Dockerfile (base $WISH_BASE_IMAGE)"
DOCKER_BUILDKIT=0 docker build --network host --build-arg "DEBIAN=$WISH_BASE_IMAGE" --build-arg JOBS=2 \
  -f docker/Dockerfile -t "$image" . >"${TMPDIR:-/tmp}/wish-docker-build.log" 2>&1 || {
  echo "test-docker: FAILED: docker build; the end of the log:" >&2
  tail -n 40 "${TMPDIR:-/tmp}/wish-docker-build.log" >&2
  exit 1
}
build_seconds=$((SECONDS - t0))
grep -m1 '^ccache:' "${TMPDIR:-/tmp}/wish-docker-build.log" | sed 's/^/test-docker: the compile in the image: /' || true
size=$(docker image inspect -f '{{.Size}}' "$image")
echo "test-docker: image $image built in ${build_seconds} s; size $(awk -v s="$size" 'BEGIN {printf "%.1f MB", s / 1e6}')" \
     "(${size} bytes; base $(docker image inspect -f '{{.Size}}' "$WISH_BASE_IMAGE" | awk '{printf "%.1f MB", $1 / 1e6}'))"
build_nginx_image

if [[ $mode == build ]]; then exit 0; fi

modules=${WISH_DOCKER_TESTS:-"test_container test_nginx_cap test_scale_out_containers"}
cd tests/deploy
# shellcheck disable=SC2086
WISH_IMAGE="$image" WISH_NGINX_IMAGE="$nginx_image" WISH_SOURCE_DIR="$root" PYTHONPATH="$root/clients/python:$root/tests/testing${PYTHONPATH:+:$PYTHONPATH}" \
  /usr/bin/python3 -m unittest -v $modules
