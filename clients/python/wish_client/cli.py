"""The ``wish-client`` command line.

    wish-client classify PATHS... --server URL [--jobs N] --out results.csv|results.json
    wish-client models  --server URL
    wish-client health  --server URL
    wish-client plot tsne|spectrum|confusion ...      (see ``wish-client plot --help``)

Exit status: 0 everything succeeded; 1 some meshes failed (their reasons are in the output and the summary) or the
server refused a request; 2 bad command line or local input; 3 the server could not be reached.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
from collections.abc import Sequence
from typing import Any

from . import __version__
from .batch import Progress, classify_batch, expand_paths, output_format
from .client import RetryPolicy, WishClient, volume_query
from .errors import WishConnectionError, WishInputError, WishServerError

EXIT_OK, EXIT_FAILED, EXIT_USAGE, EXIT_UNREACHABLE = 0, 1, 2, 3
DEFAULT_SERVER = os.environ.get("WISH_SERVER", "http://127.0.0.1:8080")


def _key_value(text: str) -> tuple[str, str]:
    if "=" not in text:
        raise argparse.ArgumentTypeError(f"expected KEY=VALUE, got {text!r}")
    k, v = text.split("=", 1)
    return k, v


def _spacing(text: str) -> list[float]:
    try:
        values = [float(v) for v in text.split(",")]
    except ValueError:
        values = []
    if len(values) != 3 or not all(v > 0 for v in values):
        raise argparse.ArgumentTypeError(f"expected three positive voxel sizes X,Y,Z, not {text!r}")
    return values


def _label_ids(text: str) -> list[int]:
    try:
        ids = [int(v) for v in text.split(",")]
    except ValueError:
        ids = []
    if not ids or not all(i > 0 for i in ids):
        raise argparse.ArgumentTypeError(f"expected label ids 1,2,..., not {text!r}")
    return ids


def _volume_params(args: argparse.Namespace) -> dict[str, Any]:
    return volume_query(spacing=args.spacing, unit=args.unit, objects=args.objects, min_voxels=args.min_voxels,
                        drop_truncated=True if args.drop_truncated else None, labels=args.labels,
                        threshold=args.threshold, label_image=args.label_image, level=args.level,
                        fragment_gap=args.fragment_gap, max_repair_share=args.max_repair_share)


def _add_server_args(p: argparse.ArgumentParser) -> None:
    p.add_argument("--server", default=DEFAULT_SERVER,
                   help="base URL of the service or its load balancer (default: $WISH_SERVER or %(default)s)")
    p.add_argument("--timeout", type=float, default=300.0, help="seconds per attempt (default: %(default)s)")
    p.add_argument("--retries", type=int, default=5,
                   help="retries of a request after 503 / connection errors, with exponential back-off "
                        "honouring Retry-After (default: %(default)s)")
    p.add_argument("--max-delay", type=float, default=30.0, help="longest wait between retries, s (default: 30)")
    p.add_argument("--token", default=None, help="bearer token when the server requires one "
                   "(default: $WISH_AUTH_TOKEN)")


def _client(args: argparse.Namespace) -> WishClient:
    return WishClient(args.server, timeout=args.timeout, token=args.token,
                      retry=RetryPolicy(max_attempts=max(1, args.retries + 1), max_delay=args.max_delay))


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="wish-client", description="Client of the WISH nucleus classification "
                                     "service: batch classification and plots.")
    parser.add_argument("--version", action="version", version=f"wish-client {__version__}")
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")

    c = sub.add_parser("classify", help="classify mesh files, label volumes and folders in parallel into a CSV/JSON file",
                       description="Classify meshes and every object of label volumes (folders are expanded "
                       "recursively to *.obj/*.ply/*.off/*.stl/*.nii/*.nii.gz/*.tif/*.tiff; a volume gives one row per "
                       "object, keyed by label_id). Resumable: files already classified in --out are skipped; failed "
                       "ones are tried again.")
    c.add_argument("paths", nargs="+", metavar="PATH", help="mesh files, label volumes or folders")
    _add_server_args(c)
    c.add_argument("--jobs", "-j", type=int, default=4, help="requests in flight (default: %(default)s); match "
                   "the server's worker count (times the number of instances behind a balancer)")
    c.add_argument("--out", "-o", required=True, help="results file, .csv or .json")
    c.add_argument("--model", help="model name (default: the server's default model)")
    c.add_argument("--param", action="append", type=_key_value, default=[], metavar="KEY=VALUE",
                   help="extra query parameter of POST /v1/classify (repeatable)")
    v = c.add_argument_group("label volumes (as `wish mesh-labels`; sent with volumes only)")
    v.add_argument("--spacing", type=_spacing, metavar="X,Y,Z", help="voxel size, overriding the file's")
    v.add_argument("--unit", help="unit of the voxel size (e.g. nm, um)")
    v.add_argument("--objects", help="object rule, one of the server's ObjectMode names (server default: auto)")
    v.add_argument("--min-voxels", type=int, help="drop objects with fewer voxels (server default: drop specks)")
    v.add_argument("--fragment-gap", type=int, metavar="N",
                   help="masks: pieces within N voxels of a dominant object are its fragments (server default 3; -1 never)")
    v.add_argument("--max-repair-share", type=float, metavar="S",
                   help="remove handles when that changes at most this share of an object's voxels (server default 0.1)")
    v.add_argument("--threshold", type=float,
                   help="mask with soft edges / probability map: foreground is value >= T (server default: half its maximum)")
    v.add_argument("--drop-truncated", action="store_true", help="drop objects touching the volume border")
    v.add_argument("--labels", type=_label_ids, metavar="ID,ID,...", help="only these label ids")
    v.add_argument("--label-image", metavar="NAME", help="OME-Zarr: label image labels/NAME (default: first)")
    v.add_argument("--level", type=int, metavar="N", help="OME-Zarr stores: multiscale level (default 0)")
    c.add_argument("--no-progress", action="store_true", help="no progress bar on stderr")
    c.add_argument("--summary-json", action="store_true", help="print the summary as JSON instead of text")

    m = sub.add_parser("models", help="list the server's models (JSON)")
    _add_server_args(m)
    m.add_argument("name", nargs="?", help="show this model's metadata")

    h = sub.add_parser("health", help="check liveness and readiness")
    _add_server_args(h)

    from .plots import add_plot_parser  # matplotlib is imported only when a plot is drawn
    add_plot_parser(sub)
    return parser


def _cmd_classify(args: argparse.Namespace) -> int:
    output_format(args.out)
    files = expand_paths(args.paths)
    if not files:
        raise WishInputError("no mesh files found in " + " ".join(args.paths))
    client = _client(args)
    progress = Progress(len(files), enabled=not args.no_progress)
    report = classify_batch(client, files, args.out, jobs=args.jobs, model=args.model, params=dict(args.param),
                            volume_params=_volume_params(args), progress=progress)
    if args.summary_json:
        print(json.dumps(report.summary(), indent=1))
    else:
        print(report.format_summary())
    print(f"results: {args.out}", file=sys.stderr)
    return EXIT_FAILED if report.failures else EXIT_OK


def _cmd_models(args: argparse.Namespace) -> int:
    client = _client(args)
    doc: Any = client.model(args.name) if args.name else client.models()
    print(json.dumps(doc, indent=1))
    return EXIT_OK


def _cmd_health(args: argparse.Namespace) -> int:
    client = _client(args)
    live = client.health()
    ready = client.ready()
    print(json.dumps({"server": client.server, "healthz": live, "ready": ready}, indent=1))
    return EXIT_OK if ready else EXIT_FAILED


def main(argv: Sequence[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    handlers = {"classify": _cmd_classify, "models": _cmd_models, "health": _cmd_health}
    try:
        if args.command == "plot":
            from .plots import run_plot
            return run_plot(args)
        return handlers[args.command](args)
    except WishInputError as e:
        print(f"wish-client: {e}", file=sys.stderr)
        return EXIT_USAGE
    except WishConnectionError as e:
        print(f"wish-client: server unreachable: {e}", file=sys.stderr)
        return EXIT_UNREACHABLE
    except WishServerError as e:
        print(f"wish-client: {e}", file=sys.stderr)
        return EXIT_FAILED
    except KeyboardInterrupt:
        print("\nwish-client: interrupted; run the same command again to resume", file=sys.stderr)
        return 130


if __name__ == "__main__":
    sys.exit(main())
