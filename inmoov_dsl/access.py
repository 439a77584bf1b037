"""Who may reach a page or a service of this computer (pure): any web site the user
visits can send requests to 127.0.0.1 and open a WebSocket there, and through DNS
rebinding read the answers. So a request is answered only when the ``Host`` it names is
this computer's own address for that port, and, when it carries an ``Origin`` (a
browser always does on a WebSocket), when that origin is the page's own.
The service, Blender's live listener (``Guard``: a token too, for any address but a
loopback one) and every page viser serves (``views/scene.py``) ask this one rule.

- Listening on anything but a loopback address needs a token, asked of every request
  (``Authorization: Bearer TOKEN``, or ``?token=TOKEN`` where a client cannot set a
  header: a browser's page and its WebSocket, Blender's add-on).
- Without a token, the ``Host`` a request names must be this loopback server itself:
  a page on another site that rebinds its DNS name to 127.0.0.1 is refused.
- A request that carries an ``Origin`` must come from the server's own page; no CORS
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
    """The ``Host`` values a loopback server at ``host``:``port`` answers to."""
    names = {host, "localhost", "127.0.0.1", "[::1]"} if is_loopback(host) else {host}
    return {f"{n}:{port}" for n in names} | ({*names} if port == 80 else set())


def foreign_origin(headers: Mapping[str, str]) -> str | None:
    """Why a request that names an ``Origin`` other than its own ``Host``'s page is
    refused (None: it names none, or its own)."""
    origin, host = headers.get("Origin"), headers.get("Host", "")
    if origin is not None and origin != f"http://{host}":
        return f"a request from another site ({_cut(origin)}) is refused"
    return None


def foreign_host(headers: Mapping[str, str], hosts: set[str]) -> str | None:
    """Why a request naming a ``Host`` not in ``hosts`` is refused (a page on another
    site whose name was rebound to 127.0.0.1), else None."""
    host = headers.get("Host", "")
    if host not in hosts:
        return f"unknown Host '{_cut(host)}': use http://127.0.0.1 or localhost"
    return None


def _cut(text: str, most: int = 80) -> str:
    return text if len(text) <= most else text[:most] + "..."


class Guard:
    """The checks of one server: its address, its port and its token (None: none)."""

    def __init__(self, host: str, port: int, token: str | None):
        self.host, self.token = host, token
        self.bind(port)

    def bind(self, port: int) -> None:
        """It listens on ``port`` (known once it listens, when 0 was asked)."""
        self.hosts = own_hosts(self.host, port)

    def refuse(self, method: str, headers: Mapping[str, str], query: Mapping[str, str]
               ) -> tuple[int, str] | None:
        """(HTTP status, why) when the request may not be answered, else None."""
        if method == "OPTIONS":
            return 403, "no cross-origin requests: this answers its own page only"
        why = foreign_origin(headers)
        if why:
            return 403, why
        if self.token is None:
            why = foreign_host(headers, self.hosts)
            return (403, why) if why else None
        given = headers.get("Authorization", "")
        given = given[7:] if given.startswith("Bearer ") else query.get("token", "")
        if not hmac.compare_digest(given.encode(), self.token.encode()):
            return 401, "a token is needed: Authorization: Bearer TOKEN"
        return None
