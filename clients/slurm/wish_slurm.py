#!/usr/bin/env python3
"""Describe many meshes on a Slurm cluster: shards in an `sbatch --array` job, one merged CSV, resumable.

    wish_slurm.py submit MANIFEST --workdir DIR --shards K [--wish PATH] [--lmax L] [--label-image NAME --level N]
                         [--sbatch-arg=ARG ...] [--wait]
    wish_slurm.py status DIR
    wish_slurm.py merge DIR          (what the merge job runs)

MANIFEST: one mesh path per line (relative paths are relative to the manifest's folder; blank lines and `#` comments
are skipped). It is cut into K contiguous shards of near-equal size (DIR/shards/NNNN.txt), so concatenating the shard
outputs in shard order gives the manifest order. Array task i runs `wish describe --csv` on shard i and keeps its
output only when every mesh of the shard succeeded (DIR/out/NNNN.csv, written under a temporary name and renamed);
a failed shard leaves its reasons in DIR/logs/shard-NNNN.err. A second job, dependent on the array (afterany: it runs
even when shards failed), merges DIR/merged.csv in manifest order, or lists the missing shards and exits 1.

Re-running `submit` with the same DIR (and the same manifest) submits only the shards without an output: failed or
never-run ones. A different manifest in an existing DIR is refused. Standard library only; needs sbatch and wish on
the nodes (DIR on a file system they share).
"""

from __future__ import annotations

import argparse
import csv
import hashlib
import json
import os
import shlex
import shutil
import subprocess
import sys
from pathlib import Path

STATE = "state.json"


def read_manifest(path: Path) -> list[str]:
    """Absolute mesh paths in manifest order; an error naming the line for a mesh that does not exist."""
    out = []
    for number, raw in enumerate(path.read_text(encoding="utf-8").splitlines(), start=1):
        line = raw.strip()
        if not line or line.startswith("#"):
            continue
        p = Path(line) if Path(line).is_absolute() else (path.parent / line)
        out.append(str(p.resolve()))
    if not out:
        raise SystemExit(f"wish_slurm: {path}: no meshes in the manifest")
    return out


def cut(items: list[str], shards: int) -> list[list[str]]:
    """``shards`` contiguous slices whose sizes differ by at most one (fewer when there are fewer items)."""
    k = max(1, min(shards, len(items)))
    return [items[len(items) * i // k: len(items) * (i + 1) // k] for i in range(k)]


def lmax_args(state):
    """`wish describe --lmax` when the first run named one; otherwise describe's default (the training recipe's)."""
    return "" if state.get("lmax") is None else f" --lmax {int(state['lmax'])}"


def volume_args(state: dict) -> str:
    """`wish describe` options for OME-Zarr stores in the manifest (first run's; none when not given)."""
    out = ""
    if state.get("label_image"):
        out += " --label-image " + shlex.quote(str(state["label_image"]))
    if state.get("level"):
        out += " --level " + str(int(state["level"]))
    return out


def shard_name(i: int) -> str:
    return f"{i:04d}"


SHARD_SCRIPT = """#!/bin/bash
# Array task $SLURM_ARRAY_TASK_ID: `wish describe --csv` on one shard; the output is kept only if every mesh succeeded.
set -uo pipefail
cd {workdir}
id=$(printf %04d "$SLURM_ARRAY_TASK_ID")
mapfile -t meshes < "shards/$id.txt"
echo "$(date -u +%FT%TZ) job ${{SLURM_ARRAY_JOB_ID:-?}} task $SLURM_ARRAY_TASK_ID on $(hostname -s)" >> "attempts/$id"
export OPENBLAS_NUM_THREADS=1 OMP_NUM_THREADS=1
{wish} describe --csv{lmax_args}{volume_args} "${{meshes[@]}}" > "out/$id.csv.tmp" 2> "logs/shard-$id.err"
rc=$?
if [[ $rc -eq 0 ]]; then
  mv "out/$id.csv.tmp" "out/$id.csv"
else
  rm -f "out/$id.csv.tmp"
  echo "shard $id failed (wish describe exit $rc):" >&2; cat "logs/shard-$id.err" >&2
fi
exit $rc
"""


def submit(args: argparse.Namespace) -> int:
    workdir = Path(args.workdir).resolve()
    manifest = read_manifest(Path(args.manifest))
    digest = hashlib.sha256("\n".join(manifest).encode()).hexdigest()
    wish = shutil.which(args.wish) or args.wish
    state_path = workdir / STATE
    if state_path.exists():
        state = json.loads(state_path.read_text())
        if state["manifest_sha256"] != digest:
            raise SystemExit(f"wish_slurm: {workdir} holds a run of a different manifest; use another --workdir")
        shards = state["shards"]
    else:
        for sub in ("shards", "out", "logs", "attempts"):
            (workdir / sub).mkdir(parents=True, exist_ok=True)
        slices = cut(manifest, args.shards)
        for i, files in enumerate(slices):
            (workdir / "shards" / f"{shard_name(i)}.txt").write_text("".join(f + "\n" for f in files))
        (workdir / "manifest.txt").write_text("".join(f + "\n" for f in manifest))
        shards = len(slices)
        state = {"manifest_sha256": digest, "shards": shards, "meshes": len(manifest), "lmax": args.lmax,
                 "label_image": args.label_image, "level": args.level}
        state_path.write_text(json.dumps(state, indent=1) + "\n")
    (workdir / "shard.sh").write_text(SHARD_SCRIPT.format(workdir=shlex.quote(str(workdir)),
                                                          wish=shlex.quote(str(Path(wish).resolve())),
                                                          lmax_args=lmax_args(state),
                                                          volume_args=volume_args(state)))
    todo = [i for i in range(shards) if not (workdir / "out" / f"{shard_name(i)}.csv").exists()]
    if not todo:
        print(f"wish_slurm: all {shards} shards are done; merging")
    extra = [a for arg in args.sbatch_arg for a in shlex.split(arg)]
    dependency: list[str] = []
    if todo:
        array = subprocess.run(
            ["sbatch", "--parsable", f"--array={','.join(map(str, todo))}", "--job-name=wish-describe",
             f"--chdir={workdir}", f"--output={workdir}/logs/slurm-%A_%a.out", "--cpus-per-task=1", *extra,
             str(workdir / "shard.sh")], capture_output=True, text=True, check=False)
        if array.returncode != 0:
            raise SystemExit(f"wish_slurm: sbatch of the array failed: {array.stderr.strip()}")
        array_id = array.stdout.strip().split(";")[0]
        dependency = [f"--dependency=afterany:{array_id}"]
        print(f"wish_slurm: array job {array_id}: {len(todo)} of {shards} shards ({','.join(map(str, todo))})")
    merge_cmd = f"{shlex.quote(sys.executable)} {shlex.quote(str(Path(__file__).resolve()))} merge " \
                f"{shlex.quote(str(workdir))}"
    merge = subprocess.run(
        ["sbatch", "--parsable", *dependency, "--job-name=wish-merge", f"--chdir={workdir}",
         f"--output={workdir}/logs/merge-%j.out", *(["--wait"] if args.wait else []), *extra,
         f"--wrap={merge_cmd}"], capture_output=True, text=True, check=False)
    merge_id = merge.stdout.strip().split(";")[0]
    if not merge_id:
        raise SystemExit(f"wish_slurm: sbatch of the merge failed: {merge.stderr.strip()}")
    print(f"wish_slurm: merge job {merge_id}" + (f" finished with exit {merge.returncode}" if args.wait else ""))
    if args.wait:
        log = workdir / "logs" / f"merge-{merge_id}.out"
        if log.exists():
            sys.stdout.write(log.read_text())
        return merge.returncode
    return 0


def shard_status(workdir: Path, shards: int) -> dict[str, list[int]]:
    done, failed, pending = [], [], []
    for i in range(shards):
        name = shard_name(i)
        if (workdir / "out" / f"{name}.csv").exists():
            done.append(i)
        elif (workdir / "attempts" / name).exists():
            failed.append(i)
        else:
            pending.append(i)
    return {"done": done, "failed": failed, "pending": pending}


def status(args: argparse.Namespace) -> int:
    workdir = Path(args.workdir).resolve()
    state = json.loads((workdir / STATE).read_text())
    s = shard_status(workdir, state["shards"])
    print(json.dumps({"meshes": state["meshes"], "shards": state["shards"], **s}))
    return 0 if not s["failed"] and not s["pending"] else 1


def merge(args: argparse.Namespace) -> int:
    """DIR/merged.csv: the shard outputs in shard (= manifest) order, one header; checked against the manifest."""
    workdir = Path(args.workdir).resolve()
    state = json.loads((workdir / STATE).read_text())
    s = shard_status(workdir, state["shards"])
    if s["failed"] or s["pending"]:
        for i in s["failed"]:
            err = workdir / "logs" / f"shard-{shard_name(i)}.err"
            print(f"shard {i} failed: {err.read_text().strip() if err.exists() else '(no log)'}")
        print(f"merge: not merged: {len(s['failed'])} shard(s) failed {s['failed']}, "
              f"{len(s['pending'])} never ran {s['pending']}; re-run `submit` to redo only those")
        return 1
    manifest = (workdir / "manifest.txt").read_text().splitlines()
    header: list[str] | None = None
    rows: list[list[str]] = []
    for i in range(state["shards"]):
        with (workdir / "out" / f"{shard_name(i)}.csv").open(newline="") as f:
            reader = csv.reader(f)
            h = next(reader)
            if header is None:
                header = h
            elif h != header:
                print(f"merge: shard {i} has other columns than shard 0")
                return 1
            rows.extend(reader)
    files = [r[0] for r in rows]
    if files != manifest:
        print(f"merge: the rows ({len(files)}) are not the manifest ({len(manifest)}) in order")
        return 1
    tmp = workdir / "merged.csv.tmp"
    with tmp.open("w", newline="") as f:
        w = csv.writer(f, lineterminator="\n")
        w.writerow(header)
        w.writerows(rows)
    os.replace(tmp, workdir / "merged.csv")
    print(f"merge: {workdir / 'merged.csv'}: {len(rows)} meshes from {state['shards']} shards, manifest order")
    return 0


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    sub = p.add_subparsers(dest="command", required=True)
    s = sub.add_parser("submit", help="submit the shards still to do and the merge")
    s.add_argument("manifest")
    s.add_argument("--workdir", required=True, help="run folder, on a file system the nodes share")
    s.add_argument("--shards", type=int, default=10, help="array tasks (first run only; default 10)")
    s.add_argument("--wish", default="wish", help="the wish executable on the nodes (default: wish on PATH)")
    s.add_argument("--lmax", type=int, default=None,
                   help="wish describe --lmax (first run only; default: describe's own, the training recipe's)")
    s.add_argument("--label-image", default=None,
                   help="OME-Zarr stores in the manifest: the label image labels/NAME (first run only; default: first)")
    s.add_argument("--level", type=int, default=0, help="OME-Zarr stores: multiscale level (first run only; default 0)")
    s.add_argument("--sbatch-arg", action="append", default=[], help="extra sbatch options, e.g. --partition=x")
    s.add_argument("--wait", action="store_true", help="block until the merge job ends; exit with its status")
    s.set_defaults(run=submit)
    st = sub.add_parser("status", help="done / failed / pending shards (JSON)")
    st.add_argument("workdir")
    st.set_defaults(run=status)
    m = sub.add_parser("merge", help="merge the shard outputs (the merge job)")
    m.add_argument("workdir")
    m.set_defaults(run=merge)
    args = p.parse_args(argv)
    if getattr(args, "shards", 1) < 1:
        p.error("--shards must be at least 1")
    return args.run(args)


if __name__ == "__main__":
    sys.exit(main())
