"""Exceptions raised by :mod:`wish_client`.

Every failure the server reports arrives as one JSON body (proto/: ``{"error": {"code", "message", "details"},
"request_id"}``); :class:`WishServerError` carries all of it, so callers can branch on the stable, machine-readable
``code`` (``"genus_nonzero"``, ``"parse_error"``, ``"model_not_found"``, ...) rather than on message text.
"""

from __future__ import annotations

from typing import Any


class WishClientError(Exception):
    """Base class of every exception this package raises."""


class WishConnectionError(WishClientError):
    """The server could not be reached (refused, reset, DNS, timeout) — after any retries."""


class WishServerError(WishClientError):
    """The server answered with an HTTP error status.

    Attributes:
        status: HTTP status code (400, 413, 415, 422, 503, ...).
        code: the server's machine-readable error code, e.g. ``"genus_nonzero"``; ``"http_<status>"`` when the
            body was not the documented error JSON (e.g. a proxy's HTML page).
        message: the server's human-readable sentence.
        details: structured details (numbers that matter), possibly empty.
        request_id: the server's request id (also sent as the ``X-Request-Id`` header), for its logs.
        retry_after: seconds the server asked us to wait (``Retry-After`` on 503), or ``None``.
        document: the whole JSON body of the answer when it was JSON (a multipart answer whose parts all failed
            alike is a 4xx with one entry per part in ``document["results"]``; a label volume whose objects all
            failed alike, one per object in ``document["objects"]``), else ``None``.
    """

    def __init__(self, status: int, code: str, message: str, details: dict[str, Any] | None = None,
                 request_id: str | None = None, retry_after: float | None = None,
                 document: dict[str, Any] | None = None) -> None:
        self.status = status
        self.document = document
        self.code = code
        self.message = message
        self.details = dict(details or {})
        self.request_id = request_id
        self.retry_after = retry_after
        rid = f", request_id={request_id}" if request_id else ""
        super().__init__(f"HTTP {status} {code}: {message}{rid}")

    @property
    def retryable(self) -> bool:
        """True when retrying later may succeed: overloaded / shutting down / bad gateway / rate limited.
        Never for a refusal of the input (400, 413, 415, 422): the same upload fails the same way.

        A 504 is retried only when a proxy produced it (no service error JSON): the service's own 504 means the
        mesh exceeded its time limit, and sending it again would only burn the same time again.
        """
        if self.status == 504:
            return self.code.startswith("http_")
        return self.status in RETRYABLE_STATUSES


#: HTTP statuses a client should retry with back-off. 503 is the service's "queue full / shutting down";
#: 502 and 504 come from a reverse proxy whose upstream died or stalled; 429 from a rate-limiting proxy.
RETRYABLE_STATUSES = frozenset({429, 502, 503, 504})


class WishInputError(WishClientError, ValueError):
    """A local input problem found before anything was sent (missing file, unknown output format, ...)."""
