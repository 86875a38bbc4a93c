"""wish_client — Python client of the WISH cell-nucleus classification service.

Library:  :class:`WishClient` (classify, describe, classify_volume, describe_volume, models, health, ready, metrics),
          :class:`RetryPolicy`,
          result types :class:`ClassifyResult` / :class:`DescribeResult`, and the exceptions in
          :mod:`wish_client.errors` (:class:`WishServerError` carries the server's error code, status and request id).
Command line: ``wish-client classify PATHS... --server URL --jobs N --out results.csv`` and ``wish-client plot ...``
(see ``wish-client --help``).

Only the standard library is needed for the client; ``plot`` needs matplotlib and scikit-learn (Debian
python3-matplotlib, python3-sklearn).
"""

__version__ = "0.1.0"

from .client import (  # noqa: E402
    NO_RETRY,
    ClassifyResult,
    DescribeResult,
    RetryPolicy,
    VolumeObjectResult,
    VolumeResult,
    WishClient,
)
from .errors import (  # noqa: E402
    WishClientError,
    WishConnectionError,
    WishInputError,
    WishServerError,
)

__all__ = [
    "WishClient", "RetryPolicy", "NO_RETRY", "ClassifyResult", "DescribeResult", "VolumeResult", "VolumeObjectResult",
    "WishClientError", "WishConnectionError", "WishInputError", "WishServerError", "__version__",
]
