"""Canonical JSON as nlohmann::json writes it, so Python can seal a WISH model file the way the C++ loader checks it.

The model file (core/classify/model_file.cpp) is ``{"format", "format_version", "payload", "payload_sha256"}`` where
``payload_sha256`` is the SHA-256 of ``payload.dump()`` in nlohmann::json: compact, keys sorted by bytes, strings in
UTF-8 with only control characters escaped, and doubles printed by Grisu2 in nlohmann's layout (fixed notation for
decimal exponents in (-4, 15], otherwise ``d.ddde±XX``; integral doubles get ``.0``).

Grisu2 prints the shortest decimal that lies in a slightly *narrowed* rounding interval of the double. Python's
``repr`` prints the shortest decimal in the full interval, exactly rounded. The two can differ when that decimal
sits within a hair of the interval's edge or when several 16/17-digit strings qualify; :func:`grisu_safe` rounds a
double to 15 significant digits, nudged away from the edges (a ~1e-15 relative change, far below anything a
classifier can notice), so that both print the same digits. Every float written through :func:`dumps` is made safe first,
so the file's text, parsed by nlohmann and dumped again, gives exactly the bytes hashed here.
"""

from __future__ import annotations

import hashlib
import json
import math
from decimal import Decimal
from fractions import Fraction
from typing import Any

#: How far (in ulps of the double) the shortest decimal must stay from the rounding interval's edges. Grisu2's
#: narrowing is about 2^-10 ulp (one unit of a 64-bit significand, plus the cached power's error); 2^-5 is ample.
_EDGE_MARGIN = Fraction(1, 32)
_MIN_EXP, _MAX_EXP = -4, 15  # nlohmann::detail::to_chars: kMinExp, kMaxExp = digits10


def _shortest_digits(v: float) -> tuple[str, int]:
    """``(digits, n)`` with ``|v| = 0.digits × 10^n``, digits the shortest round-trip string (Python repr)."""
    sign, digits, exp = Decimal(repr(abs(v))).as_tuple()
    ds = "".join(map(str, digits)).rstrip("0")
    exp += len(digits) - len(ds)
    return ds or "0", len(ds) + exp


def _is_safe(v: float) -> bool:
    """True when repr(v)'s digits are safely inside v's rounding interval (see module doc)."""
    if v == 0 or not math.isfinite(v):
        return True
    a = abs(v)
    prev, nxt = math.nextafter(a, 0.0), math.nextafter(a, math.inf)
    if not math.isfinite(nxt) or prev == 0:
        return True
    x, lo_gap, hi_gap = Fraction(a), Fraction(a) - Fraction(prev), Fraction(nxt) - Fraction(a)
    d = Fraction(Decimal(repr(a)))
    low, high = x - lo_gap / 2, x + hi_gap / 2
    return d - low >= _EDGE_MARGIN * lo_gap and high - d >= _EDGE_MARGIN * hi_gap


def grisu_safe(v: float) -> float:
    """A double within ~1e-13 (relative) of ``v`` that Grisu2 (nlohmann) and Python print with the same digits.

    Two conditions make the printed digits unique: at most 15 significant digits (a 15-digit decimal is the only one
    of its length inside a double's rounding interval, so "shortest" cannot pick between candidates, where Grisu2's
    approximate rounding may differ from Python's exact one), and that decimal away from the interval's edges
    (where Grisu2's narrowed interval would miss it).
    """
    if v == 0 or not math.isfinite(v) or (_is_safe(v) and len(_shortest_digits(v)[0]) <= 15):
        return v
    # Neighbouring 15-digit decimals can sit at nearly the same spot of their doubles' intervals (1e-15 is close
    # to a multiple of the ulp), so fewer digits are tried too: the worst change stays around 1e-13, relative.
    for digits in (15, 14, 13, 12):
        base = Decimal(f"{v:.{digits}g}")
        unit = Decimal(1).scaleb(base.adjusted() - digits + 1)
        for step in (0, 1, -1, 2, -2, 3, -3):
            candidate = float(base + step * unit)
            if len(_shortest_digits(candidate)[0]) <= 15 and _is_safe(candidate):
                return candidate
    raise ValueError(f"cannot find a Grisu-safe neighbour of {v!r}")  # not seen in 10^6 random doubles


def format_double(v: float) -> str:
    """``v`` as nlohmann::json prints a double (callers pass :func:`grisu_safe` values)."""
    if not math.isfinite(v):
        raise ValueError(f"JSON cannot hold {v!r}")
    if v == 0:
        return "-0.0" if math.copysign(1.0, v) < 0 else "0.0"
    sign = "-" if v < 0 else ""
    ds, n = _shortest_digits(v)
    k = len(ds)
    if k <= n <= _MAX_EXP:
        body = ds + "0" * (n - k) + ".0"
    elif 0 < n <= _MAX_EXP:
        body = ds[:n] + "." + ds[n:]
    elif _MIN_EXP < n <= 0:
        body = "0." + "0" * (-n) + ds
    else:
        e = n - 1
        mant = ds if k == 1 else ds[0] + "." + ds[1:]
        body = f"{mant}e{'-' if e < 0 else '+'}{abs(e):02d}"
    return sign + body


def _canon(obj: Any) -> Any:
    """Makes every float Grisu-safe (recursively); rejects what JSON cannot hold."""
    if isinstance(obj, bool) or obj is None or isinstance(obj, str):
        return obj
    if isinstance(obj, int):
        return int(obj)
    if isinstance(obj, float):
        return grisu_safe(obj)
    if isinstance(obj, dict):
        return {str(k): _canon(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_canon(v) for v in obj]
    if hasattr(obj, "tolist"):  # numpy scalars and arrays
        return _canon(obj.tolist())
    raise TypeError(f"cannot write {type(obj).__name__} to JSON")


def dumps(obj: Any, indent: int | None = None, _level: int = 0) -> str:
    """JSON text with nlohmann's number and string formatting; keys sorted. ``indent=None`` is ``dump()``."""
    obj = _canon(obj) if _level == 0 else obj
    nl = "" if indent is None else "\n"
    pad = "" if indent is None else " " * (indent * (_level + 1))
    end = "" if indent is None else " " * (indent * _level)
    colon = ":" if indent is None else ": "
    if isinstance(obj, dict):
        if not obj:
            return "{}"
        items = [f"{pad}{json.dumps(k, ensure_ascii=False)}{colon}{dumps(obj[k], indent, _level + 1)}"
                 for k in sorted(obj, key=lambda s: s.encode("utf-8"))]
        return "{" + nl + ("," + nl).join(items) + nl + end + "}"
    if isinstance(obj, list):
        if not obj:
            return "[]"
        items = [f"{pad}{dumps(v, indent, _level + 1)}" for v in obj]
        return "[" + nl + ("," + nl).join(items) + nl + end + "]"
    if isinstance(obj, bool):
        return "true" if obj else "false"
    if obj is None:
        return "null"
    if isinstance(obj, int):
        return str(obj)
    if isinstance(obj, float):
        return format_double(obj)
    return json.dumps(obj, ensure_ascii=False)


def seal(payload: dict[str, Any]) -> str:
    """``payload_sha256`` of a model payload: SHA-256 (hex) of its canonical compact dump."""
    return hashlib.sha256(dumps(payload).encode("utf-8")).hexdigest()
