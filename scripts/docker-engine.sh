# Sourced by the container tests (scripts/test-docker.sh): a Docker engine to talk to, and the Debian base image.
#
#   docker_engine_up      uses the engine `docker info` reaches; else starts Debian's dockerd (docker.io) with its own
#                         socket, data root and pid file, no bridge and no iptables rules (every container runs with
#                         --network host, so all test traffic stays on 127.0.0.1). Exports DOCKER_HOST.
#   docker_engine_down    stops the dockerd this script started (by its pid), nothing else.
#   docker_base_image     makes wish-debian:bookworm when missing: `debootstrap --variant=minbase bookworm` from
#                         Debian's repository, trimmed like debian:bookworm-slim, `docker import`ed (no registry).
# Environment: WISH_DOCKER_ROOT (data root of a started engine, default /var/lib/wish-docker: kept between runs so the
# base image and the build cache survive), WISH_DEBIAN_MIRROR (default http://deb.debian.org/debian).

WISH_BASE_IMAGE=${WISH_BASE_IMAGE:-wish-debian:bookworm}
_wish_dockerd_pid=""

docker_engine_up() {
  if ! command -v docker >/dev/null; then
    echo "docker-engine: no docker client: install docker.io (scripts/install-deps.sh --test)" >&2; return 1
  fi
  if docker info >/dev/null 2>&1; then
    echo "docker-engine: using the running engine ($(docker version -f '{{.Server.Version}}' 2>/dev/null))"; return 0
  fi
  local run=/run/wish-docker root=${WISH_DOCKER_ROOT:-/var/lib/wish-docker}
  export DOCKER_HOST="unix://$run/docker.sock"
  if docker info >/dev/null 2>&1; then   # one started earlier by this script and left running: use it, never stop it
    echo "docker-engine: using the engine on $DOCKER_HOST"; return 0
  fi
  if ! command -v dockerd >/dev/null; then
    echo "docker-engine: FAILED: no engine is running and dockerd is not installed (Debian docker.io)" >&2; return 1
  fi
  if [[ $(id -u) -ne 0 ]]; then
    echo "docker-engine: FAILED: no engine is running and starting dockerd needs root" >&2; return 1
  fi
  mkdir -p "$run" "$root"
  dockerd --bridge=none --iptables=false --ip6tables=false --data-root "$root" --exec-root "$run/exec" \
          --pidfile "$run/dockerd.pid" --host "$DOCKER_HOST" >"$run/dockerd.log" 2>&1 &
  _wish_dockerd_pid=$!
  local i
  for ((i = 0; i < 120; i++)); do   # up to 60 s
    if docker info >/dev/null 2>&1; then
      echo "docker-engine: started dockerd (pid $_wish_dockerd_pid, data root $root)"; return 0
    fi
    if ! kill -0 "$_wish_dockerd_pid" 2>/dev/null; then break; fi
    sleep 0.5
  done
  echo "docker-engine: FAILED: dockerd did not start; the end of $run/dockerd.log:" >&2
  tail -n 15 "$run/dockerd.log" >&2
  docker_engine_down
  return 1
}

docker_engine_down() {
  [[ -n "$_wish_dockerd_pid" ]] || return 0
  if kill -0 "$_wish_dockerd_pid" 2>/dev/null; then
    kill -TERM "$_wish_dockerd_pid"
    local i
    for ((i = 0; i < 60 && $(kill -0 "$_wish_dockerd_pid" 2>/dev/null && echo 1 || echo 0); i++)); do sleep 0.5; done
    kill -0 "$_wish_dockerd_pid" 2>/dev/null && kill -KILL "$_wish_dockerd_pid"
    wait "$_wish_dockerd_pid" 2>/dev/null || true
    echo "docker-engine: stopped dockerd (pid $_wish_dockerd_pid)"
  fi
  _wish_dockerd_pid=""
}

docker_base_image() {
  if docker image inspect "$WISH_BASE_IMAGE" >/dev/null 2>&1; then
    echo "docker-engine: base image $WISH_BASE_IMAGE present"; return 0
  fi
  command -v debootstrap >/dev/null || { echo "docker-engine: FAILED: debootstrap is not installed" >&2; return 1; }
  local dir t0=$SECONDS
  dir=$(mktemp -d /tmp/wish-rootfs.XXXXXX)
  echo "docker-engine: making $WISH_BASE_IMAGE with debootstrap (a few minutes)"
  if ! debootstrap --variant=minbase bookworm "$dir" "${WISH_DEBIAN_MIRROR:-http://deb.debian.org/debian}" \
       >"$dir.log" 2>&1; then
    echo "docker-engine: FAILED: debootstrap; the end of $dir.log:" >&2; tail -n 15 "$dir.log" >&2
    rm -rf "$dir"; return 1
  fi
  # As debian:bookworm-slim: no documentation or man pages in images built on it, no package caches.
  cat >"$dir/etc/dpkg/dpkg.cfg.d/docker-slim" <<'EOF'
path-exclude /usr/share/doc/*
path-include /usr/share/doc/*/copyright
path-exclude /usr/share/man/*
path-exclude /usr/share/info/*
path-exclude /usr/share/locale/*
path-include /usr/share/locale/locale.alias
EOF
  printf 'APT::Install-Recommends "false";\n' >"$dir/etc/apt/apt.conf.d/docker-no-recommends"
  rm -rf "$dir"/var/cache/apt/archives/*.deb "$dir"/var/lib/apt/lists/* "$dir"/usr/share/man/* "$dir"/usr/share/info/*
  find "$dir/usr/share/doc" -mindepth 2 ! -name copyright -delete 2>/dev/null || true
  tar -C "$dir" --numeric-owner -c . | docker import -c 'CMD ["/bin/bash"]' - "$WISH_BASE_IMAGE" >/dev/null
  rm -rf "$dir" "$dir.log"
  echo "docker-engine: made $WISH_BASE_IMAGE in $((SECONDS - t0)) s ($(docker image inspect -f '{{.Size}}' \
    "$WISH_BASE_IMAGE" | awk '{printf "%.0f MB", $1 / 1e6}'))"
}
