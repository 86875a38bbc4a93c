"""The WISH REST client library: paths or bytes in, parsed results out.

    >>> from wish_client import WishClient
    >>> client = WishClient("http://127.0.0.1:8080")
    >>> result = client.classify("nucleus.obj")          # one mesh -> ClassifyResult
    >>> result.label, result.probabilities["neuron"]
    >>> [r.label for r in client.classify(["a.obj", "b.ply"])]  # several meshes, one request -> list

The wire contract is proto/openapi.json; this module depends on nothing else of the project. Errors the server
reports raise :class:`~wish_client.errors.WishServerError` (with the server's ``code``, HTTP ``status`` and
``request_id``); an unreachable server raises :class:`~wish_client.errors.WishConnectionError`. Transient failures
(503 with ``Retry-After``, a proxy's 502, refused/reset connections) are retried per :class:`RetryPolicy`.
"""

from __future__ import annotations

import base64
import email.utils
import http.client
import io
import json
import os
import random
import socket
import time
import urllib.error
import urllib.parse
import urllib.request
import zipfile
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Union

from . import __version__
from .errors import WishConnectionError, WishInputError, WishServerError
from .multipart import encode_multipart

#: A mesh given to the client: a file path, raw bytes (named "mesh"), or an explicit ``(name, bytes)`` pair.
#: The server recognises the format from the file name's extension and the content (OBJ, PLY, OFF, STL).
MeshInput = Union[str, os.PathLike, bytes, tuple[str, bytes]]

_FORMATS = ("obj", "ply", "off", "stl")  # the `format` hint of a raw body (proto: components/parameters/format)

#: Label volume files (NIfTI-1, TIFF stacks, OME-Zarr stores as a directory or their zip); the server detects them
#: from the content. Volume options (proto: components/parameters spacing, unit, objects, min_voxels, fragment_gap,
#: max_repair_share, drop_truncated, labels, threshold, label_image, level) mirror ``wish mesh-labels``.
VOLUME_EXTENSIONS = (".nii", ".nii.gz", ".tif", ".tiff", ".zarr.zip")
VOLUME_PARAMETERS = ("spacing", "unit", "objects", "min_voxels", "fragment_gap", "max_repair_share", "drop_truncated",
                     "labels", "threshold", "label_image", "level")
_ZARR_METADATA = (".zgroup", ".zattrs", ".zarray")


def is_zarr_store(path: str | os.PathLike) -> bool:
    """True for a directory holding zarr metadata (.zgroup, .zattrs or .zarray): a zarr v2 store on disk."""
    p = Path(path)
    return p.is_dir() and any((p / m).is_file() for m in _ZARR_METADATA)


def is_volume_name(name: str | os.PathLike) -> bool:
    """True for names ending .nii, .nii.gz, .tif, .tiff, .zarr.zip (case-insensitive) and for zarr store directories."""
    return str(name).lower().endswith(VOLUME_EXTENSIONS) or is_zarr_store(name)


def zip_zarr_store(path: str | os.PathLike) -> bytes:
    """The zip of a zarr store directory as the server reads it (zarr's ZipStore layout: the store's keys are the
    entry names, stored uncompressed — the chunks are compressed already). For an image with a ``labels/`` group only
    the metadata and ``labels/`` go in: the image's own arrays are not needed to read its labels."""
    root = Path(path)
    has_labels = (root / "labels" / ".zattrs").is_file()
    buffer = io.BytesIO()
    with zipfile.ZipFile(buffer, "w", compression=zipfile.ZIP_STORED) as z:
        for dirpath, dirnames, filenames in os.walk(root):
            dirnames.sort()
            rel_dir = Path(dirpath).relative_to(root)
            for name in sorted(filenames):
                key = (rel_dir / name).as_posix()
                if has_labels and rel_dir.parts and rel_dir.parts[0] != "labels":
                    continue  # the image's own arrays
                if has_labels and not rel_dir.parts and name not in _ZARR_METADATA:
                    continue
                z.write(os.path.join(dirpath, name), key)
    return buffer.getvalue()


def volume_query(spacing: Sequence[float] | str | None = None, unit: str | None = None, objects: str | None = None,
                 min_voxels: int | None = None, drop_truncated: bool | str | None = None,
                 labels: Sequence[int] | str | None = None, threshold: float | str | None = None,
                 label_image: str | None = None,
                 level: int | None = None, fragment_gap: int | None = None,
                 max_repair_share: float | None = None) -> dict[str, Any]:
    """The query parameters of a volume upload (``None``: the server's default). ``spacing`` and ``labels`` may
    also be given already encoded ("1,1,2", "3,7"). ``label_image`` and ``level`` choose an OME-Zarr store's label
    image (labels/NAME; default the first listed) and multiscale level (default 0). ``min_voxels`` replaces the
    server's speck rule; ``fragment_gap`` (-1: never) and ``max_repair_share`` (0: never) bound the merging of mask
    fragments and the removal of handles."""
    q: dict[str, Any] = {}
    if isinstance(spacing, str):
        q["spacing"] = spacing
    elif spacing is not None:
        if len(spacing) != 3:
            raise WishInputError(f"spacing needs three voxel sizes x,y,z, not {list(spacing)}")
        q["spacing"] = ",".join(repr(float(v)) for v in spacing)
    if unit is not None:
        q["unit"] = unit
    if objects is not None:
        q["objects"] = objects
    if min_voxels is not None:
        q["min_voxels"] = int(min_voxels)
    if isinstance(drop_truncated, str):
        q["drop_truncated"] = drop_truncated
    elif drop_truncated is not None:
        q["drop_truncated"] = "true" if drop_truncated else "false"
    if isinstance(labels, str):
        q["labels"] = labels
    elif labels:
        q["labels"] = ",".join(str(int(v)) for v in labels)
    if threshold is not None:
        q["threshold"] = threshold if isinstance(threshold, str) else repr(float(threshold))
    if label_image is not None:
        q["label_image"] = label_image
    if level is not None:
        q["level"] = int(level)
    if fragment_gap is not None:
        q["fragment_gap"] = int(fragment_gap)
    if max_repair_share is not None:
        q["max_repair_share"] = repr(float(max_repair_share))
    return q


@dataclass(frozen=True)
class RetryPolicy:
    """When and how long to retry a request that failed transiently.

    Retried: connection errors (refused, reset, timed out) and the statuses for which
    :attr:`WishServerError.retryable` holds (503 / 502 / 429, a proxy's 504). The wait before attempt ``k`` (1-based
    retry count) is ``min(max_delay, base_delay * 2**(k-1))`` with ±25 % jitter — unless the server sent
    ``Retry-After``, which is honoured as given (capped at ``max_delay``).
    """

    max_attempts: int = 6          # total attempts, including the first; 1 disables retrying
    base_delay: float = 0.5        # seconds before the first retry
    max_delay: float = 30.0        # cap of one wait, seconds
    jitter: float = 0.25           # relative random spread of a computed wait (not of Retry-After)

    def delay(self, retry: int, retry_after: float | None = None) -> float:
        """Seconds to wait before retry number ``retry`` (1-based)."""
        if retry_after is not None:
            return max(0.0, min(self.max_delay, retry_after))
        base = min(self.max_delay, self.base_delay * 2 ** (retry - 1))
        return max(0.0, base * (1 + random.uniform(-self.jitter, self.jitter)))


NO_RETRY = RetryPolicy(max_attempts=1)


@dataclass
class ClassifyResult:
    """The classification of one mesh.

    Attributes:
        name: the mesh's name as sent (file name).
        label: the predicted class.
        probabilities: class -> Platt probability, in the model's class order.
        margin: decision value of the winner against the runner-up (libsvm one-vs-one); larger = more confident.
        novel: True when the sample is none of the types the model knows (its novelty score is above the model's
            threshold, proto ``Prediction.novel``); None when the model has no novelty calibration.
        novelty_p_value: how typical the sample is of the training set (conformal p-value; small = unlike it).
        novelty_nearest_class: why (issue 38): the class the novelty figures are given for — the class the sample is
            most like relative to that class's own spread (or the predicted class, for a model with the
            predicted_class novelty rule); None when not computed or the model has no classes in its novelty block.
        novelty_distance_ratio: the sample's distance in units of that class's calibration spread (1 = at the
            class's threshold quantile; novel above 1); None when not reported (or infinite).
        model: name of the model that answered (``name@version`` when the server reports a version).
        request_id: the server's id of the request that produced this result.
        raw: the result object exactly as received (descriptor, timings, warnings, ...).
    """

    name: str
    label: str
    probabilities: dict[str, float] = field(default_factory=dict)
    margin: float | None = None
    model: str | None = None
    request_id: str | None = None
    raw: dict[str, Any] = field(default_factory=dict)
    novel: bool | None = None
    novelty_p_value: float | None = None
    novelty_nearest_class: str | None = None
    novelty_distance_ratio: float | None = None

    @property
    def confidence(self) -> float | None:
        """Probability of the predicted label, when reported."""
        return self.probabilities.get(self.label)


@dataclass
class DescribeResult:
    """Rotation-invariant descriptor of one mesh.

    Attributes:
        name: the mesh's name as sent.
        invariants: ξ(0..Lmax), the SH energies summed over x, y, z (paper Eq. 14).
        lmax: the SH degree used.
        raw: the result object as received (coefficients, fit error, map diagnostics, ...).
    """

    name: str
    invariants: list[float]
    lmax: int | None = None
    request_id: str | None = None
    raw: dict[str, Any] = field(default_factory=dict)


@dataclass
class VolumeObjectResult:
    """One object of a label volume: its label id, the voxel object, and its result or the error of that object.

    Attributes:
        label_id: the label value (components mode: the component number).
        status: the HTTP status this object alone would have had (200 when described).
        object: voxel count, centroid (physical units), bounding box, ``truncated``, genus, surface figures.
        result: a :class:`ClassifyResult` (classify) or :class:`DescribeResult` (describe) when ``status == 200``.
        error: the object's :class:`WishServerError` otherwise (e.g. code ``genus_nonzero``).
    """

    label_id: int
    status: int
    object: dict[str, Any] = field(default_factory=dict)
    result: ClassifyResult | DescribeResult | None = None
    error: WishServerError | None = None

    @property
    def ok(self) -> bool:
        return self.result is not None


@dataclass
class VolumeResult:
    """A label volume upload (proto: VolumeResult): one entry per kept object, in label-id order."""

    name: str
    objects: list[VolumeObjectResult]
    # format, dims, spacing, unit, objects found / dropped, input (kind: labels / mask / soft_mask /
    # probability_map, threshold, why, warnings)
    volume: dict[str, Any] = field(default_factory=dict)
    request_id: str | None = None
    raw: dict[str, Any] = field(default_factory=dict)

    def by_label(self) -> dict[int, VolumeObjectResult]:
        return {o.label_id: o for o in self.objects}

    @property
    def class_map(self) -> dict[str, Any] | None:
        """With ``output="labels"`` (:meth:`WishClient.classify_volume`): the class map's name, format, file name and
        legend (``values``: value, class name, rgb), without its data; ``None`` otherwise."""
        cm = self.raw.get("class_map")
        return {k: v for k, v in cm.items() if k != "data"} if isinstance(cm, dict) else None

    def save_class_map(self, path: str | os.PathLike | None = None) -> Path:
        """Writes the class map the server returned (``output="labels"``) to ``path`` — by default its own file name
        (``<upload stem>_<model>.nii.gz`` | ``.tif`` | ``.ome.zarr.zip``) in the current directory — and returns the
        path. An OME-Zarr class map is the zip of a store holding ``labels/<model>``: unzip it into the input store
        to see it beside the input's labels."""
        cm = self.raw.get("class_map")
        if not isinstance(cm, dict) or "data" not in cm:
            raise WishInputError("the answer has no class map: classify with output=\"labels\"")
        data = base64.b64decode(cm["data"])
        if len(data) != int(cm.get("bytes", len(data))):
            raise WishInputError(f"the class map holds {len(data)} bytes, the answer says {cm.get('bytes')}")
        target = Path(path) if path is not None else Path(cm["filename"])
        target.write_bytes(data)
        return target


def _parse_retry_after(value: str | None) -> float | None:
    """Parses ``Retry-After`` (delta-seconds or an HTTP-date, RFC 9110 §10.2.3) to seconds from now."""
    if not value:
        return None
    value = value.strip()
    try:
        return max(0.0, float(value))
    except ValueError:
        pass
    try:
        when = email.utils.parsedate_to_datetime(value)
    except (TypeError, ValueError):
        return None
    return max(0.0, when.timestamp() - time.time())


def _error_from_response(status: int, headers: Any, body: bytes) -> WishServerError:
    """Builds the exception for an error response, from the documented JSON body when there is one."""
    retry_after = _parse_retry_after(headers.get("Retry-After") if headers else None)
    header_rid = headers.get("X-Request-Id") if headers else None
    try:
        doc = json.loads(body.decode("utf-8"))
        err = doc["error"]
        return WishServerError(status, str(err.get("code") or f"http_{status}"), str(err.get("message", "")),
                               err.get("details") or {}, doc.get("request_id") or header_rid, retry_after,
                               document=doc if isinstance(doc, dict) else None)
    except (ValueError, KeyError, TypeError, AttributeError, UnicodeDecodeError):
        text = body.decode("utf-8", "replace").strip().replace("\n", " ")
        return WishServerError(status, f"http_{status}", text[:300] or http.client.responses.get(status, ""),
                               {}, header_rid, retry_after)


def _mesh_name_and_bytes(mesh: MeshInput) -> tuple[str, bytes]:
    """Reads a :data:`MeshInput` into ``(name, content)``; raises :class:`WishInputError` for a missing file."""
    if isinstance(mesh, (bytes, bytearray, memoryview)):
        return "mesh", bytes(mesh)
    if isinstance(mesh, tuple):
        name, content = mesh
        return str(name), bytes(content)
    path = Path(mesh)
    if is_zarr_store(path):  # an OME-Zarr store directory travels as its zip
        return path.name, zip_zarr_store(path)
    try:
        return path.name, path.read_bytes()
    except OSError as e:
        raise WishInputError(f"cannot read mesh {path}: {e.strerror or e}") from e


def _as_float_map(value: Any) -> dict[str, float]:
    """Accepts ``{"cls": p}`` or ``[{"class"|"label": cls, "probability": p}, ...]`` and returns ``{cls: p}``."""
    if isinstance(value, dict):
        return {str(k): float(v) for k, v in value.items()}
    out: dict[str, float] = {}
    for item in value or []:
        if isinstance(item, dict):
            key = item.get("class", item.get("label", item.get("name")))
            out[str(key)] = float(item.get("probability", item.get("p", 0.0)))
        elif isinstance(item, (list, tuple)) and len(item) == 2:
            out[str(item[0])] = float(item[1])
    return out


def _model_label(model: Any) -> str | None:
    if isinstance(model, dict):
        name, version = model.get("name"), model.get("version")
        return f"{name}@{version}" if name and version else (name or None)
    return None if model is None else str(model)


class WishClient:
    """A client of one WISH server (or of a load balancer in front of several).

    Thread-safe: every call opens its own connection, so one client may be shared by a thread pool.

    Args:
        server: base URL, e.g. ``http://127.0.0.1:8080`` (a trailing ``/`` is ignored).
        timeout: socket timeout of one attempt, seconds. Classifying a large mesh takes seconds; keep it generous.
        retry: transient-failure policy; :data:`NO_RETRY` disables retrying.
        on_retry: called ``(attempt, delay_seconds, exception)`` before each wait — for logging / progress.
        token: bearer token, when the server runs with ``--auth-token`` (default: ``$WISH_AUTH_TOKEN``).
    """

    def __init__(self, server: str, *, timeout: float = 300.0, retry: RetryPolicy | None = None,
                 on_retry: Callable[[int, float, Exception], None] | None = None,
                 token: str | None = None) -> None:
        if not server.startswith(("http://", "https://")):
            server = "http://" + server
        self.server = server.rstrip("/")
        self.timeout = timeout
        self.retry = retry or RetryPolicy()
        self.on_retry = on_retry
        self.user_agent = f"wish-client/{__version__}"
        self.token = token if token is not None else os.environ.get("WISH_AUTH_TOKEN") or None

    # ---- transport ---------------------------------------------------------------------------------------------

    def request(self, method: str, path: str, body: bytes | None = None, content_type: str | None = None,
                query: dict[str, Any] | None = None, accept: str = "application/json") -> tuple[int, Any, bytes]:
        """Sends one request with retries; returns ``(status, headers, body)`` of a 2xx answer.

        Raises:
            WishServerError: a non-2xx answer that is not retryable, or still failing after the last attempt.
            WishConnectionError: the server stayed unreachable through every attempt.
        """
        url = self.server + path
        if query:
            pairs = {k: (str(v).lower() if isinstance(v, bool) else v) for k, v in query.items() if v is not None}
            if pairs:
                url += "?" + urllib.parse.urlencode(pairs)
        headers = {"User-Agent": self.user_agent, "Accept": accept}
        if content_type:
            headers["Content-Type"] = content_type
        if self.token:
            headers["Authorization"] = f"Bearer {self.token}"
        attempt = 0
        while True:
            attempt += 1
            try:
                req = urllib.request.Request(url, data=body, method=method, headers=headers)
                with urllib.request.urlopen(req, timeout=self.timeout) as resp:
                    return resp.status, resp.headers, resp.read()
            except urllib.error.HTTPError as e:
                err: Exception = _error_from_response(e.code, e.headers, e.read() if e.fp else b"")
                retryable = err.retryable  # type: ignore[attr-defined]
                retry_after = err.retry_after  # type: ignore[attr-defined]
            except (urllib.error.URLError, http.client.HTTPException, ConnectionError, socket.timeout,
                    TimeoutError) as e:
                reason = getattr(e, "reason", e)
                err = WishConnectionError(f"{method} {url}: {reason}")
                retryable, retry_after = True, None
            if not retryable or attempt >= self.retry.max_attempts:
                raise err
            delay = self.retry.delay(attempt, retry_after)
            if self.on_retry:
                self.on_retry(attempt, delay, err)
            time.sleep(delay)

    def _json(self, method: str, path: str, **kwargs: Any) -> Any:
        _, _, data = self.request(method, path, **kwargs)
        try:
            return json.loads(data.decode("utf-8"))
        except (ValueError, UnicodeDecodeError) as e:
            raise WishServerError(200, "bad_response", f"{method} {path}: the answer is not JSON ({e})") from e

    def _post_meshes(self, path: str, meshes: MeshInput | Sequence[MeshInput], params: dict[str, Any]
                     ) -> tuple[bool, list[tuple[str, dict[str, Any] | WishServerError]]]:
        """Sends one mesh as the raw body, or several as multipart parts.

        Returns ``(single, [(name, result_object | per-part error), ...])``.
        """
        single = not isinstance(meshes, list | tuple) or _is_named_bytes(meshes)
        items: list[MeshInput] = [meshes] if single else list(meshes)  # type: ignore[list-item]
        parts = [_mesh_name_and_bytes(m) for m in items]
        if not parts:
            raise WishInputError("no mesh given")
        if single:
            name, content = parts[0]
            fmt = Path(name).suffix.lower().lstrip(".")
            query = {**params, "format": params.get("format") or (fmt if fmt in _FORMATS else None)}
            doc = self._json("POST", path, body=content, content_type="application/octet-stream", query=query)
            return True, [(name, doc)]
        body, ctype = encode_multipart([("mesh", name, content) for name, content in parts])
        # The answer's status follows its parts' (proto: BatchResponse): 200 all good, 207 Multi-Status when they
        # differ, and the parts' common 4xx/5xx when every part failed alike — that one still carries one entry per
        # part, read here like the others. A request-level error (no `results`: bad parameter, unknown model,
        # queue full after the retries) raises.
        try:
            doc = self._json("POST", path, body=body, content_type=ctype, query=params)
        except WishServerError as e:
            if not (isinstance(e.document, dict) and isinstance(e.document.get("results"), list)):
                raise
            doc = e.document
        out: list[tuple[str, dict[str, Any] | WishServerError]] = []
        for (name, _), item in zip(parts, doc.get("results", [])):
            if isinstance(item.get("result"), dict) and "objects" in item["result"]:
                # A label-volume part: its VolumeResult lists every object with its own result or error, also when
                # the part's status is the common 4xx of objects all refused alike.
                out.append((item.get("filename", name), item["result"]))
            elif "error" in item:
                err = item["error"]
                out.append((name, WishServerError(int(item.get("status", 422)), str(err.get("code", "error")),
                                                  str(err.get("message", "")), err.get("details") or {},
                                                  doc.get("request_id"))))
            else:
                out.append((item.get("filename", name), item.get("result", {})))
        return False, out

    # ---- endpoints ---------------------------------------------------------------------------------------------

    def classify(self, meshes: MeshInput | Sequence[MeshInput], *, model: str | None = None, **params: Any
                 ) -> ClassifyResult | VolumeResult | list[ClassifyResult | VolumeResult | WishServerError]:
        """Classifies one mesh, or several in one multipart request.

        Args:
            meshes: a path / bytes / ``(name, bytes)`` — sent as the raw body, returns a :class:`ClassifyResult`
                (an error raises :class:`WishServerError`) — or a list of them — sent as multipart parts, returns
                one entry per mesh, in order: a :class:`ClassifyResult`, or the :class:`WishServerError` of that
                part alone (one bad file does not fail the others).
            model: model name (``GET /v1/models``); the server's default model when ``None``.
            params: further query parameters of ``POST /v1/classify`` (``include``, ...; proto/openapi.json).

        A label volume (``.nii``, ``.nii.gz``, ``.tif``, ``.tiff``), alone or as one of the parts, comes back as a
        :class:`VolumeResult` with one entry per object, as from :meth:`classify_volume`.
        """
        if _is_single_volume(meshes):
            return self.classify_volume(meshes, model=model, **params)  # type: ignore[arg-type]
        single, items = self._post_meshes("/v1/classify", meshes, {"model": model, **params})
        results = [_parse_item(name, r, classify=True) for name, r in items]
        return results[0] if single else results  # type: ignore[return-value]

    def describe(self, meshes: MeshInput | Sequence[MeshInput], **params: Any
                 ) -> DescribeResult | VolumeResult | list[DescribeResult | VolumeResult | WishServerError]:
        """Spherical map + SH descriptor ξ(0..Lmax) of one mesh or several (``POST /v1/describe``).

        Same calling convention as :meth:`classify` (label volumes included); ``params`` e.g. ``lmax=15,
        method="willmore", steps=10``.
        """
        if _is_single_volume(meshes):
            return self.describe_volume(meshes, **params)  # type: ignore[arg-type]
        single, items = self._post_meshes("/v1/describe", meshes, params)
        results = [_parse_item(name, r, classify=False) for name, r in items]
        return results[0] if single else results  # type: ignore[return-value]

    def classify_volume(self, volume: MeshInput, *, model: str | None = None, spacing: Sequence[float] | None = None,
                        unit: str | None = None, objects: str | None = None, min_voxels: int | None = None,
                        drop_truncated: bool | None = None, labels: Sequence[int] | None = None,
                        threshold: float | None = None, label_image: str | None = None, level: int | None = None,
                        output: str | None = None, **params: Any
                        ) -> VolumeResult:
        """Classifies every object of a label volume (NIfTI-1 .nii / .nii.gz, TIFF stack, OME-Zarr store directory
        or its zip) in one request.

        The volume options mirror ``wish mesh-labels``: ``spacing`` (x, y, z voxel size, overriding the file's),
        ``unit``, ``objects`` (``labels`` / ``components`` / ``auto``), ``min_voxels``, ``drop_truncated``,
        ``labels`` (a subset of label ids), ``threshold`` (a mask with soft edges or a probability map: foreground
        is value >= threshold; default half its maximum; ``volume["input"]`` says what was decided), ``label_image`` and
        ``level`` (an OME-Zarr store: labels/NAME, multiscale level). An object that cannot be classified carries its
        own error, whatever
        the answer's status (200 all classified, 207 some refused, the common 4xx when all were: proto
        VolumeResult); a volume that fails as a whole raises :class:`WishServerError` — unreadable, past the time
        limit, or with no object left after the filters (422 ``no_objects``, its counts in ``details``).
        ``output="labels"`` also returns the class map in the upload's format (:meth:`VolumeResult.save_class_map`).
        """
        query = {"model": model, **volume_query(spacing, unit, objects, min_voxels, drop_truncated, labels, threshold,
                                                label_image, level), **params}
        if output is not None:
            query["output"] = output
        return self._post_volume("/v1/classify", volume, query, classify=True)

    def describe_volume(self, volume: MeshInput, *, spacing: Sequence[float] | None = None, unit: str | None = None,
                        objects: str | None = None, min_voxels: int | None = None,
                        drop_truncated: bool | None = None, labels: Sequence[int] | None = None,
                        threshold: float | None = None, label_image: str | None = None, level: int | None = None,
                        **params: Any
                        ) -> VolumeResult:
        """SH descriptor of every object of a label volume; same options as :meth:`classify_volume`."""
        query = {**volume_query(spacing, unit, objects, min_voxels, drop_truncated, labels, threshold, label_image,
                                level), **params}
        return self._post_volume("/v1/describe", volume, query, classify=False)

    def _post_volume(self, path: str, volume: MeshInput, query: dict[str, Any], classify: bool) -> VolumeResult:
        name, content = _mesh_name_and_bytes(volume)
        # Like a batch (_post_meshes): a volume whose objects were all refused alike is a 4xx that still lists
        # every object; read it like a 200 or a 207. An error without `objects` failed the whole volume.
        try:
            doc = self._json("POST", path, body=content, content_type="application/octet-stream", query=query)
        except WishServerError as e:
            if not (isinstance(e.document, dict) and isinstance(e.document.get("objects"), list)):
                raise
            doc = e.document
        if not isinstance(doc, dict) or "objects" not in doc:
            raise WishServerError(200, "bad_response", "the answer is not a VolumeResult (no `objects`): was the "
                                  "file a label volume?", {}, doc.get("request_id") if isinstance(doc, dict) else None)
        return _parse_volume(name, doc, classify)

    def models(self) -> list[dict[str, Any]]:
        """The loaded models (``GET /v1/models``), each a dict with at least ``name``."""
        doc = self._json("GET", "/v1/models")
        return list(doc.get("models", doc) if isinstance(doc, dict) else doc)

    def model(self, name: str) -> dict[str, Any]:
        """One model's metadata: classes, descriptor settings, training summary (``GET /v1/models/{name}``)."""
        return self._json("GET", "/v1/models/" + urllib.parse.quote(name, safe=""))

    def health(self) -> dict[str, Any]:
        """Liveness (``GET /healthz``); raises when the process does not answer."""
        return self._json("GET", "/healthz")

    def ready(self) -> bool:
        """Readiness (``GET /readyz``): True when the server accepts work; False on 503 (loading / draining)."""
        try:
            self.request("GET", "/readyz")
            return True
        except WishServerError as e:
            if e.status == 503:
                return False
            raise

    def metrics(self) -> str:
        """The Prometheus text exposition (``GET /metrics``)."""
        return self.request("GET", "/metrics", accept="text/plain")[2].decode("utf-8")

    def openapi(self) -> dict[str, Any]:
        """The server's OpenAPI document (``GET /openapi.json``)."""
        return self._json("GET", "/openapi.json")


def _is_named_bytes(value: Any) -> bool:
    return isinstance(value, tuple) and len(value) == 2 and isinstance(value[1], (bytes, bytearray))


def _parse_classify(name: str, doc: dict[str, Any]) -> ClassifyResult:
    """A ClassifyResult (proto: DescribeResult with ``prediction``) to the library's dataclass."""
    pred = doc.get("prediction")
    if not isinstance(pred, dict):
        raise WishServerError(200, "bad_response", "the answer has no `prediction` block", {},
                              doc.get("request_id"))
    return ClassifyResult(
        name=str(doc.get("mesh", {}).get("filename") or name),
        label=str(pred.get("label", "")),
        probabilities=_as_float_map(pred.get("probabilities", [])),
        margin=float(pred["margin"]) if pred.get("margin") is not None else None,
        model=_model_label(pred.get("model")),
        request_id=doc.get("request_id"),
        raw=doc,
        novel=pred["novel"] if isinstance(pred.get("novel"), bool) else None,
        novelty_p_value=_novelty_p_value(pred.get("novelty")),
        novelty_nearest_class=_novelty_field(pred.get("novelty"), "nearest_class", str),
        novelty_distance_ratio=_novelty_field(pred.get("novelty"), "distance_ratio", float),
    )


def _novelty_field(novelty: Any, key: str, kind: type) -> Any:
    """proto Novelty's `key` when novelty was computed and the field is present (not null), else None."""
    if isinstance(novelty, dict) and novelty.get("computed") and novelty.get(key) is not None:
        return kind(novelty[key])
    return None


def _novelty_p_value(novelty: Any) -> float | None:
    if isinstance(novelty, dict) and novelty.get("computed") and novelty.get("p_value") is not None:
        return float(novelty["p_value"])
    return None


def _parse_describe(name: str, doc: dict[str, Any]) -> DescribeResult:
    """A DescribeResult (proto) to the library's dataclass."""
    desc = doc.get("descriptor", {})
    return DescribeResult(
        name=str(doc.get("mesh", {}).get("filename") or name),
        invariants=[float(x) for x in desc.get("invariants", [])],
        lmax=desc.get("lmax"),
        request_id=doc.get("request_id"),
        raw=doc,
    )


def _is_single_volume(meshes: Any) -> bool:
    """One label volume given by a name that says so (a path, or ``(name, bytes)``): sent by the volume calls."""
    if isinstance(meshes, (str, os.PathLike)):
        return is_volume_name(meshes)
    return _is_named_bytes(meshes) and is_volume_name(meshes[0])


def _parse_item(name: str, item: dict[str, Any] | WishServerError, classify: bool
                ) -> ClassifyResult | DescribeResult | VolumeResult | WishServerError:
    """One entry of an answer: a per-part error, a label volume's VolumeResult (it has ``objects``), or one
    mesh's result."""
    if isinstance(item, WishServerError):
        return item
    if "objects" in item:
        return _parse_volume(name, item, classify)
    return _parse_classify(name, item) if classify else _parse_describe(name, item)


def _parse_volume(name: str, doc: dict[str, Any], classify: bool) -> VolumeResult:
    """A VolumeResult (proto) to the library's dataclasses."""
    objects: list[VolumeObjectResult] = []
    for entry in doc.get("objects", []):
        label = int(entry.get("label_id", 0))
        status = int(entry.get("status", 0))
        item = VolumeObjectResult(label_id=label, status=status, object=entry.get("object") or {})
        object_name = f"{name}#{label}"
        if "result" in entry:
            parse = _parse_classify if classify else _parse_describe
            item.result = parse(object_name, entry["result"])
            item.result.name = object_name
        else:
            err = entry.get("error") or {}
            item.error = WishServerError(status or 422, str(err.get("code", "error")), str(err.get("message", "")),
                                         err.get("details") or {}, doc.get("request_id"))
        objects.append(item)
    return VolumeResult(name=str(doc.get("volume", {}).get("filename") or name), objects=objects,
                        volume=doc.get("volume") or {}, request_id=doc.get("request_id"), raw=doc)
