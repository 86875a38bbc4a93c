"""Batch classification: many files, parallel requests, retries, resumable output, a summary.

The output (``.csv`` or ``.json``) has one record per mesh file, and one per object of a label volume
(``.nii``, ``.nii.gz``, ``.tif``, ``.tiff``: every object classified in one request, keyed by its label id):

=============== ====================================================================================
file            the mesh or volume path as expanded from the command line (the resume key)
label_id        the object's label id in a label volume ("" for a mesh, and for a volume that failed whole)
voxel_count     the object's voxel count (volumes)
truncated       ``true`` when the object touches the volume border (volumes)
status          ``ok`` or ``error``
label           predicted class (ok)
confidence      probability of ``label``
margin          decision margin of the winner against the runner-up
novel           ``true``: none of the types the model knows (its novelty threshold); empty: not computed
novelty_p_value how typical of the training set (small: unlike every training sample)
novelty_nearest_class  why: the class the sample is most like relative to that class's spread (the predicted
                class for a model with the predicted_class rule); empty: not reported
novelty_distance_ratio its distance in units of that class's calibration spread (novel above 1)
model           the model that answered
prob_<class>    probability per class (CSV); ``probabilities`` object (JSON)
error_code      the server's error code, ``connection_error`` or ``read_error`` (error)
error_message   the server's sentence (error)
request_id      the server's request id, to find the request in its logs
=============== ====================================================================================

Resuming: files whose records in the output all have ``status == ok`` are skipped; failed files are tried again
(a volume as a whole: its records are replaced by the new run's). While a run
is in progress every finished record is appended (and flushed) to ``<out>.partial`` (JSON Lines); the output is
rewritten atomically at the end and the journal removed, so an interrupted run (Ctrl-C, crash, power loss) loses at
most the requests in flight.
"""

from __future__ import annotations

import csv
import io
import json
import os
import sys
import threading
import time
from collections import Counter
from collections.abc import Callable, Iterable, Sequence
from concurrent.futures import FIRST_COMPLETED, Future, ThreadPoolExecutor, wait
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, TextIO

from .client import VOLUME_EXTENSIONS, VOLUME_PARAMETERS, ClassifyResult, WishClient, is_volume_name, is_zarr_store
from .errors import WishClientError, WishConnectionError, WishInputError, WishServerError

#: File extensions taken when a folder is expanded (case-insensitive). Files named explicitly are always taken.
MESH_EXTENSIONS = (".obj", ".ply", ".off", ".stl")
INPUT_EXTENSIONS = MESH_EXTENSIONS + VOLUME_EXTENSIONS

BASE_COLUMNS = ["file", "label_id", "status", "label", "confidence", "margin", "novel", "novelty_p_value", "novelty_nearest_class",
                "novelty_distance_ratio", "model", "voxel_count", "truncated",
                "error_code", "error_message", "request_id"]


def expand_paths(paths: Iterable[str | os.PathLike], extensions: Sequence[str] = INPUT_EXTENSIONS) -> list[str]:
    """Expands folders (recursively, sorted, hidden entries skipped) to the mesh files in them.

    Files given explicitly are kept whatever their extension; duplicates are dropped, first occurrence wins.

    Raises:
        WishInputError: a path that does not exist.
    """
    exts = tuple(e.lower() for e in extensions)
    out: list[str] = []
    seen: set[str] = set()

    def add(p: str) -> None:
        key = os.path.normpath(p)
        if key not in seen:
            seen.add(key)
            out.append(key)

    for raw in paths:
        p = Path(raw)
        if is_zarr_store(p):  # an OME-Zarr store is one volume, not a folder of inputs
            add(str(p))
        elif p.is_dir():
            for root, dirs, files in os.walk(p):
                for d in sorted(d for d in dirs if is_zarr_store(os.path.join(root, d))):
                    add(os.path.join(root, d))
                dirs[:] = sorted(d for d in dirs if not d.startswith(".") and not is_zarr_store(os.path.join(root, d)))
                for name in sorted(files):
                    if not name.startswith(".") and name.lower().endswith(exts):
                        add(os.path.join(root, name))
        elif p.is_file():
            add(str(p))
        else:
            raise WishInputError(f"no such file or folder: {raw}")
    return out


# ---- records and the output file ---------------------------------------------------------------------------------

@dataclass
class Record:
    """One line of the output: the outcome for one mesh file."""

    file: str
    status: str                       # "ok" | "error"
    label: str = ""
    confidence: float | None = None
    margin: float | None = None
    novel: bool | None = None         # None: the model computed no novelty
    novelty_p_value: float | None = None
    novelty_nearest_class: str = ""   # "": not reported
    novelty_distance_ratio: float | None = None
    model: str = ""
    probabilities: dict[str, float] = field(default_factory=dict)
    error_code: str = ""
    error_message: str = ""
    request_id: str = ""
    label_id: str = ""                # volumes: the object's label id
    voxel_count: int | None = None    # volumes
    truncated: bool | None = None     # volumes

    @property
    def key(self) -> tuple[str, str]:
        return (self.file, self.label_id)

    @classmethod
    def from_result(cls, file: str, r: ClassifyResult, label_id: str = "") -> Record:
        return cls(file=file, status="ok", label=r.label, confidence=r.confidence, margin=r.margin,
                   novel=r.novel, novelty_p_value=r.novelty_p_value,
                   novelty_nearest_class=r.novelty_nearest_class or "", novelty_distance_ratio=r.novelty_distance_ratio, model=r.model or "", probabilities=dict(r.probabilities), request_id=r.request_id or "",
                   label_id=label_id)

    @classmethod
    def from_error(cls, file: str, e: Exception, label_id: str = "") -> Record:
        if isinstance(e, WishServerError):
            return cls(file=file, status="error", error_code=e.code, error_message=e.message,
                       request_id=e.request_id or "", label_id=label_id)
        code = "connection_error" if isinstance(e, WishConnectionError) else (
            "read_error" if isinstance(e, WishInputError) else type(e).__name__)
        return cls(file=file, status="error", error_code=code, error_message=str(e), label_id=label_id)

    def to_json(self) -> dict[str, Any]:
        return {"file": self.file, "label_id": self.label_id, "status": self.status, "label": self.label,
                "confidence": self.confidence, "margin": self.margin, "novel": self.novel,
                "novelty_p_value": self.novelty_p_value, "novelty_nearest_class": self.novelty_nearest_class,
                "novelty_distance_ratio": self.novelty_distance_ratio, "model": self.model,
                "probabilities": self.probabilities, "voxel_count": self.voxel_count, "truncated": self.truncated,
                "error_code": self.error_code, "error_message": self.error_message, "request_id": self.request_id}

    @classmethod
    def from_json(cls, d: dict[str, Any]) -> Record:
        truncated = d.get("truncated")
        if isinstance(truncated, str):
            truncated = {"true": True, "false": False}.get(truncated.lower())
        voxels = d.get("voxel_count")
        novel = d.get("novel")
        if isinstance(novel, str):
            novel = {"true": True, "false": False}.get(novel.lower())
        return cls(novel=novel if isinstance(novel, bool) else None,
                   novelty_p_value=_opt_float(d.get("novelty_p_value")),
                   novelty_nearest_class=d.get("novelty_nearest_class") or "",
                   novelty_distance_ratio=_opt_float(d.get("novelty_distance_ratio")),
                   file=str(d["file"]), status=str(d.get("status", "ok")), label=d.get("label") or "",
                   confidence=_opt_float(d.get("confidence")), margin=_opt_float(d.get("margin")),
                   model=d.get("model") or "", probabilities={k: float(v) for k, v in
                                                               (d.get("probabilities") or {}).items()},
                   error_code=d.get("error_code") or "", error_message=d.get("error_message") or "",
                   request_id=d.get("request_id") or "", label_id=str(d.get("label_id") or ""),
                   voxel_count=int(voxels) if voxels not in (None, "") else None, truncated=truncated)


def _opt_float(v: Any) -> float | None:
    if v is None or v == "":
        return None
    return float(v)


def output_format(path: str | os.PathLike) -> str:
    """``"csv"`` or ``"json"`` from the output's extension; raises :class:`WishInputError` otherwise."""
    suffix = Path(path).suffix.lower()
    if suffix in (".csv", ".json"):
        return suffix[1:]
    raise WishInputError(f"--out must end in .csv or .json, not {str(path)!r}")


def read_records(path: str | os.PathLike) -> list[Record]:
    """Reads an output file (CSV or JSON) and its ``.partial`` journal, if present. Later records win."""
    records: dict[tuple[str, str], Record] = {}
    p = Path(path)
    if p.exists() and p.stat().st_size > 0:
        if output_format(p) == "csv":
            with p.open(newline="", encoding="utf-8") as f:
                for row in csv.DictReader(f):
                    probs = {k[5:]: float(v) for k, v in row.items() if k and k.startswith("prob_") and v}
                    rec = Record.from_json({**row, "probabilities": probs})
                    records[rec.key] = rec
        else:
            doc = json.loads(p.read_text(encoding="utf-8"))
            for d in (doc.get("results", []) if isinstance(doc, dict) else doc):
                rec = Record.from_json(d)
                records[rec.key] = rec
    journal = Path(str(p) + ".partial")
    if journal.exists():
        with journal.open(encoding="utf-8") as f:
            for line in f:
                line = line.strip()
                if not line:
                    continue
                try:
                    rec = Record.from_json(json.loads(line))
                except (ValueError, KeyError):
                    continue  # a line torn by a crash mid-write: that file is simply done again
                records[rec.key] = rec
    return list(records.values())


def write_records(path: str | os.PathLike, records: Sequence[Record], summary: dict[str, Any] | None = None) -> None:
    """Writes the output atomically (temporary file + rename). CSV gets one ``prob_<class>`` column per class."""
    p = Path(path)
    fmt = output_format(p)
    buf = io.StringIO()
    if fmt == "csv":
        classes: list[str] = []
        for r in records:
            classes.extend(c for c in r.probabilities if c not in classes)
        w = csv.writer(buf, lineterminator="\n")
        w.writerow(BASE_COLUMNS + [f"prob_{c}" for c in classes])
        for r in records:
            d = r.to_json()
            w.writerow([_csv_cell(d[c]) for c in BASE_COLUMNS] +
                       [_csv_cell(r.probabilities.get(c)) for c in classes])
    else:
        doc: dict[str, Any] = {"results": [r.to_json() for r in records]}
        if summary is not None:
            doc["summary"] = summary
        buf.write(json.dumps(doc, indent=1) + "\n")
    tmp = p.with_name(p.name + ".tmp")
    tmp.write_text(buf.getvalue(), encoding="utf-8")
    os.replace(tmp, p)


def _csv_cell(v: Any) -> str:
    if v is None:
        return ""
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, float):
        return repr(v)
    return str(v)


# ---- progress ------------------------------------------------------------------------------------------------------

class Progress:
    """A one-line progress bar on a terminal; on a pipe/file, a plain line every ``interval`` seconds."""

    def __init__(self, total: int, stream: TextIO | None = None, enabled: bool = True, interval: float = 5.0) -> None:
        self.total = total
        self.stream = stream or sys.stderr
        self.enabled = enabled and total > 0
        self.tty = self.enabled and hasattr(self.stream, "isatty") and self.stream.isatty()
        self.interval = interval
        self.done = self.failed = self.retries = 0
        self.start = time.monotonic()
        self._last = 0.0
        self._lock = threading.Lock()

    def update(self, ok: bool) -> None:
        with self._lock:
            self.done += 1
            self.failed += 0 if ok else 1
            self._draw()

    def retry(self) -> None:
        with self._lock:
            self.retries += 1
            self._draw()

    def _draw(self, final: bool = False) -> None:
        if not self.enabled:
            return
        now = time.monotonic()
        if not self.tty and not final and now - self._last < self.interval and self.done < self.total:
            return
        self._last = now
        elapsed = now - self.start
        rate = self.done / elapsed if elapsed > 0 else 0.0
        eta = (self.total - self.done) / rate if rate > 0 else float("nan")
        width = 30
        filled = int(width * self.done / self.total)
        bar = "#" * filled + "." * (width - filled)
        eta_text = f"{eta:5.0f}s" if eta == eta else "    ?s"
        line = (f"[{bar}] {self.done}/{self.total}  failed {self.failed}  retries {self.retries}  "
                f"{rate:5.2f}/s  eta {eta_text}")
        self.stream.write(("\r" + line) if self.tty else (line + "\n"))
        self.stream.flush()

    def close(self) -> None:
        with self._lock:
            if self.enabled:
                self._draw(final=True)
                if self.tty:
                    self.stream.write("\n")
                self.stream.flush()


# ---- the batch run -------------------------------------------------------------------------------------------------

@dataclass
class BatchReport:
    """What a batch run did."""

    total: int            # files after expansion
    skipped: int          # already done in the output (resume)
    records: list[Record]  # every record in the output, old and new
    new: list[Record]      # records produced by this run
    retries: int
    elapsed: float

    @property
    def failures(self) -> list[Record]:
        return [r for r in self.new if r.status != "ok"]

    def summary(self) -> dict[str, Any]:
        """Counts per class (over the whole output), failures of this run with reasons."""
        ok = [r for r in self.records if r.status == "ok"]
        return {
            "files": self.total, "skipped_already_done": self.skipped, "classified_now": len(self.new) -
            len(self.failures), "failed_now": len(self.failures), "retries": self.retries,
            "elapsed_seconds": round(self.elapsed, 3),
            "per_class": dict(sorted(Counter(r.label for r in ok).items())),
            "failures": [{"file": r.file, "error_code": r.error_code, "error_message": r.error_message}
                         for r in self.failures],
        }

    def format_summary(self) -> str:
        s = self.summary()
        lines = [f"{s['files']} files: {s['classified_now']} classified, {s['failed_now']} failed, "
                 f"{s['skipped_already_done']} already done (skipped); {s['retries']} retries; "
                 f"{s['elapsed_seconds']:.1f} s"]
        if s["per_class"]:
            lines.append("per class (whole output):")
            width = max(len(k) for k in s["per_class"])
            lines += [f"  {k:<{width}}  {v}" for k, v in s["per_class"].items()]
        if s["failures"]:
            lines.append("failures:")
            by_code = Counter(f["error_code"] for f in s["failures"])
            for code, n in by_code.most_common():
                lines.append(f"  {code}: {n}")
            for f in s["failures"]:
                lines.append(f"    {f['file']}: {f['error_message']}")
        return "\n".join(lines)


def classify_batch(client: WishClient, files: Sequence[str], out: str | os.PathLike, *, jobs: int = 4,
                   model: str | None = None, params: dict[str, Any] | None = None,
                   volume_params: dict[str, Any] | None = None, progress: Progress | None = None,
                   on_record: Callable[[Record], None] | None = None) -> BatchReport:
    """Classifies ``files`` with ``jobs`` requests in flight, appending to ``out`` (resumable, see module doc).

    One request per file, so one bad mesh fails alone and retries resend only what failed. A label volume is one
    request that classifies every object (``volume_params``: spacing, unit, objects, min_voxels, drop_truncated,
    labels — proto's volume parameters, sent with volumes only) and gives one record per object. The client's
    :class:`~wish_client.client.RetryPolicy` handles 503/connection errors; a file still failing after it is
    recorded as ``error`` with the reason, and the run goes on.
    """
    output_format(out)
    if jobs < 1:
        raise WishInputError("--jobs must be at least 1")
    started = time.monotonic()
    previous: dict[str, list[Record]] = {}
    for r in read_records(out):
        previous.setdefault(r.file, []).append(r)
    todo = [f for f in files if not previous.get(f) or any(r.status != "ok" for r in previous[f])]
    skipped = len(files) - len(todo)
    # The previous output stays untouched until the final atomic rewrite; new records go to the journal.
    journal_path = Path(str(out) + ".partial")
    journal_path.parent.mkdir(parents=True, exist_ok=True)
    journal = journal_path.open("a", encoding="utf-8")
    journal_lock = threading.Lock()
    new: list[Record] = []
    retries = 0
    retries_lock = threading.Lock()
    progress = progress or Progress(len(todo), enabled=False)
    progress.total = len(todo)
    progress.enabled = progress.enabled and len(todo) > 0

    user_on_retry = client.on_retry

    def on_retry(attempt: int, delay: float, err: Exception) -> None:
        nonlocal retries
        with retries_lock:
            retries += 1
        progress.retry()
        if user_on_retry:
            user_on_retry(attempt, delay, err)

    client.on_retry = on_retry
    extra = dict(params or {})
    volume_extra = dict(volume_params or {})
    unknown = sorted(set(volume_extra) - set(VOLUME_PARAMETERS))
    if unknown:
        raise WishInputError(f"not volume parameters: {', '.join(unknown)} (known: {', '.join(VOLUME_PARAMETERS)})")

    def volume_records(file: str) -> list[Record]:
        result = client.classify_volume(file, model=model, **{**extra, **volume_extra})
        out_records = []
        for o in result.objects:
            label_id = str(o.label_id)
            if o.result is not None:
                rec = Record.from_result(file, o.result, label_id)  # type: ignore[arg-type]
            else:
                rec = Record.from_error(file, o.error or WishServerError(o.status, "error", ""), label_id)
            rec.voxel_count = o.object.get("voxel_count")
            rec.truncated = o.object.get("truncated")
            out_records.append(rec)
        return out_records  # never empty: a volume with no object left is the server's 422 no_objects, raised

    def one(file: str) -> list[Record]:
        try:
            if is_volume_name(file):
                return volume_records(file)
            result = client.classify(file, model=model, **extra)  # one path -> raw body -> one ClassifyResult
            return [Record.from_result(file, result)]  # type: ignore[arg-type]
        except WishClientError as e:
            return [Record.from_error(file, e)]
        except Exception as e:  # noqa: BLE001 - a bug here must not lose the other files' results
            return [Record.from_error(file, e)]

    try:
        with ThreadPoolExecutor(max_workers=jobs, thread_name_prefix="wish-batch") as pool:
            pending: set[Future[list[Record]]] = set()
            queue = iter(todo)
            # Submit lazily (at most 2*jobs outstanding) so Ctrl-C does not leave thousands of queued futures.
            for file in queue:
                pending.add(pool.submit(one, file))
                if len(pending) >= 2 * jobs:
                    break
            while pending:
                done, pending = wait(pending, return_when=FIRST_COMPLETED)
                for fut in done:
                    recs = fut.result()
                    with journal_lock:
                        for rec in recs:
                            journal.write(json.dumps(rec.to_json()) + "\n")
                        journal.flush()
                    new.extend(recs)
                    progress.update(all(rec.status == "ok" for rec in recs))
                    if on_record:
                        for rec in recs:
                            on_record(rec)
                    nxt = next(queue, None)
                    if nxt is not None:
                        pending.add(pool.submit(one, nxt))
    finally:
        client.on_retry = user_on_retry
        journal.close()
        progress.close()

    # A file done again replaces all its previous records (a volume's objects may differ from a failed attempt's).
    redone = {r.file for r in new}
    merged = {r.key: r for recs in previous.values() for r in recs if r.file not in redone}
    for r in new:
        merged[r.key] = r
    order = {f: i for i, f in enumerate(files)}

    def sort_key(r: Record) -> tuple[int, str, int, str]:
        return (order.get(r.file, len(order)), r.file, int(r.label_id) if r.label_id.isdigit() else -1, r.label_id)

    records = sorted(merged.values(), key=sort_key)
    report = BatchReport(total=len(files), skipped=skipped, records=records, new=new, retries=retries,
                         elapsed=time.monotonic() - started)
    write_records(out, records, report.summary())
    journal_path.unlink(missing_ok=True)
    return report
