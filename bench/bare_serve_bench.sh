#!/usr/bin/env bash
# A bare machine to a served page (issue 40 item 1): the README's serve command, `bash scripts/serve.sh`, in a fresh
# container of the debootstrap base image (scripts/docker-engine.sh: Debian 12 minbase, nothing else installed), a
# fresh clone of COMMIT mounted at /src, timed from `docker run` until `/healthz` answers on 127.0.0.1, with the wall
# seconds of each step read from serve.sh's own trace (every traced line time-stamped as it arrives). Prints one
# column per run; with several commits the runs alternate (A B A B ...), so that a pair shares the host's speed.
#   bash bench/bare_serve_bench.sh [--runs N] [--port P] COMMIT [COMMIT ...]
# Needs root (dockerd, as the docker tests) and the network to Debian's mirror (the container's apt-get). The
# container uses the host's network (--network host): the service listens on 127.0.0.1:P and only that is polled.
# Leaves nothing behind: each container is removed, each clone deleted, a dockerd it started is stopped.
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD
runs=1 port=18495 commits=()
while (($#)); do
  case $1 in
    --runs) runs=$2; shift 2 ;;
    --port) port=$2; shift 2 ;;
    -h|--help) sed -n '2,10p' "$0"; exit 0 ;;
    *) commits+=("$(git rev-parse --short "$1")"); shift ;;
  esac
done
((${#commits[@]})) || { echo "usage: $0 [--runs N] [--port P] COMMIT [COMMIT ...]" >&2; exit 2; }
if curl -sf "http://127.0.0.1:$port/healthz" >/dev/null 2>&1; then
  echo "port $port already answers /healthz: choose another (--port)" >&2; exit 2
fi

source scripts/docker-engine.sh
docker_engine_up
work=$(mktemp -d /tmp/wish-bare-serve.XXXXXX)
container=""
cleanup() {
  [[ -n $container ]] && docker rm -f "$container" >/dev/null 2>&1
  rm -rf "$work"
  docker_engine_down
}
trap cleanup EXIT
docker_base_image

# One run: prints "name seconds" lines (the steps, then total and the checks) into $work/<run>.steps.
one_run() {
  local run=$1 commit=$2 clone=$work/$1/src out=$work/$1/out
  mkdir -p "$out"
  git clone -q "$root" "$clone" && git -C "$clone" checkout -q "$commit"
  container=wish-bare-serve-$$-${run//#/-}
  local t0=$EPOCHREALTIME
  docker run -d --name "$container" --network host -e PORT="$port" -v "$clone":/src -v "$out":/out -w /src \
    "$WISH_BASE_IMAGE" bash -c 'env SHELLOPTS=xtrace bash scripts/serve.sh \
      2> >(while IFS= read -r l; do echo "$EPOCHREALTIME $l"; done >/out/trace.log)' >/dev/null
  local status=ok
  until curl -sf "http://127.0.0.1:$port/healthz" >/dev/null 2>&1; do
    sleep 0.25
    if [[ -z $(docker ps -q -f "name=^$container\$") ]]; then status="container exited"; break; fi
    if (( ${EPOCHREALTIME%.*} - ${t0%.*} > 1800 )); then status="no /healthz in 1800 s"; break; fi
  done
  local t1=$EPOCHREALTIME
  if [[ $status != ok ]]; then
    echo "run $run ($commit): $status; the end of its log:" >&2; docker logs "$container" 2>&1 | tail -n 20 >&2
    return 1
  fi
  {
    python3 - "$out/trace.log" "$t0" "$t1" <<'PY'
import re, sys
# serve.sh's steps, in order, by the first traced command of each (install-deps.sh's apt-get calls, serve.sh's cmake
# calls and its exec); the time of a step runs until the next step's first command.
path, t0, t1 = sys.argv[1], float(sys.argv[2]), float(sys.argv[3])
steps = [("apt-get update", "apt-get update"), ("apt-get install", "apt-get install"),
         ("apt-get download", "libopenmesh-dev's headers"), ("cmake -G", "configure"), ("cmake -S", "configure"),
         ("cmake --build", "compile wish-server"), ("exec build", "start to /healthz")]
marks = []
for line in open(path, errors="replace"):
    m = re.match(r"^(\d+\.\d+) \++ (.*)", line)
    if not m:
        continue
    for prefix, name in steps:
        if m.group(2).startswith(prefix) and (not marks or marks[-1][1] != name):
            marks.append((float(m.group(1)), name))
            break
bounds = [(t0, "docker run, bash")] + marks + [(t1, None)]
for (start, name), (end, _) in zip(bounds, bounds[1:]):
    print("%s\t%.1f" % (name, end - start))
print("docker run to /healthz\t%.1f" % (t1 - t0))
PY
    printf 'GET / / three.js\t%s / %s\n' \
      "$(curl -s -o /dev/null -w '%{http_code}' "http://127.0.0.1:$port/")" \
      "$(curl -s -o /dev/null -w '%{http_code}' "http://127.0.0.1:$port/vendor/three/build/three.module.js")"
    printf 'packages in the container\t%s\n' "$(docker exec "$container" bash -c 'dpkg -l | grep -c ^ii')"
    printf 'load average at the start\t%s\n' "$(cut -d' ' -f1 "$work/$run.load")"
  } >"$work/$run.steps"
  docker rm -f "$container" >/dev/null; container=""
  rm -rf "$clone"
}

names=()
for ((r = 1; r <= runs; r++)); do
  for commit in "${commits[@]}"; do
    run="$commit#$r"; names+=("$run")
    cut -d' ' -f1 /proc/loadavg >"$work/$run.load"
    echo "run $run: $(date -u +%H:%M:%S) UTC" >&2
    one_run "$run" "$commit"
  done
done

# The table: one row per step (in the order first seen), one column per run, wall seconds.
python3 - "$work" "${names[@]}" <<'PY'
import sys
work, names = sys.argv[1], sys.argv[2:]
cols, order = [], []
for name in names:
    rows = dict(line.rstrip("\n").split("\t") for line in open("%s/%s.steps" % (work, name)))
    cols.append(rows)
    order += [k for k in rows if k not in order]
print("| step | " + " | ".join(names) + " |")
print("|---|" + "---:|" * len(names))
for k in order:
    print("| %s | %s |" % (k, " | ".join(c.get(k, "-") for c in cols)))
PY
