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
from collections.abc import Mapping

from ..access import foreign_host, foreign_origin, is_loopback, own_hosts

__all__ = ["Guard", "is_loopback"]


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
        if method == "OPTIONS":
            return 403, "no cross-origin requests: the service answers its own page only"
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
