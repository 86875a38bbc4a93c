"""Free TCP ports on 127.0.0.1 for the Python tests (all test traffic stays on loopback).

Binding to port 0 lets the kernel pick an unused port; the sockets are held until all n are chosen, so the n ports
are distinct. A port can in principle be taken by another process between this call and the caller's bind; servers
that can report their own port (`wish serve --port 0`) should be preferred where possible.
"""

from __future__ import annotations

import socket


def free_ports(n: int) -> list[int]:
    socks = [socket.socket() for _ in range(n)]
    try:
        for s in socks:
            s.bind(("127.0.0.1", 0))
        return [s.getsockname()[1] for s in socks]
    finally:
        for s in socks:
            s.close()


def free_port() -> int:
    return free_ports(1)[0]
