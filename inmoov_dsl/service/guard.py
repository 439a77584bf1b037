"""Who may ask the service (pure): a machine that moves is not for other web sites.

- Listening on anything but a loopback address needs a token, asked of every request
  (``Authorization: Bearer TOKEN``, or ``?token=TOKEN`` where a browser cannot set a
  header: the page's address and its WebSocket).
- Without a token, the ``Host`` a request names must be this loopback service itself:
  a page on another site that rebinds its DNS name to 127.0.0.1 is refused.
- A request that carries an ``Origin`` must come from the service's own page; no CORS
  preflight is answered.
"""

from __future__ import annotations

import hmac
import ipaddress
from collections.abc import Mapping

LOOPBACK_NAMES = ("localhost",)


def is_loopback(host: str) -> bool:
    """Is ``host`` (an address or ``localhost``) on this computer only?"""
    if host in LOOPBACK_NAMES:
        return True
    try:
        return ipaddress.ip_address(host.strip("[]")).is_loopback
    except ValueError:
        return False


def own_hosts(host: str, port: int) -> set[str]:
    """The ``Host`` values a loopback service at ``host``:``port`` answers to."""
    names = {host, "localhost", "127.0.0.1", "[::1]"} if is_loopback(host) else {host}
    return {f"{n}:{port}" for n in names} | ({*names} if port == 80 else set())


class Guard:
    """The checks of one service: its address, its port and its token (None: none)."""

    def __init__(self, host: str, port: int, token: str | None):
        self.host, self.token = host, token
        self.bind(port)

    def bind(self, port: int) -> None:
        """The service listens on ``port`` (known once it listens, when 0 was asked)."""
        self.hosts = own_hosts(self.host, port)

    def refuse(self, method: str, headers: Mapping[str, str], query: Mapping[str, str]
               ) -> tuple[int, str] | None:
        """(HTTP status, why) when the request may not be answered, else None."""
        host = headers.get("Host", "")
        origin = headers.get("Origin")
        if method == "OPTIONS":
            return 403, "no cross-origin requests: the service answers its own page only"
        if origin is not None and origin != f"http://{host}":
            return 403, f"a request from another site ({origin}) is refused"
        if self.token is None:
            if host not in self.hosts:
                return 403, f"unknown Host '{host}': use http://127.0.0.1 or localhost"
            return None
        given = headers.get("Authorization", "")
        given = given[7:] if given.startswith("Bearer ") else query.get("token", "")
        if not hmac.compare_digest(given.encode(), self.token.encode()):
            return 401, "a token is needed: Authorization: Bearer TOKEN"
        return None
