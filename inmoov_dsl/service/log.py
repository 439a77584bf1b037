"""What the service logs of requests it cannot read (an edge: it writes to stderr): a
line each, ten a minute at most."""

from __future__ import annotations

import logging
import math
import sys
import time


class OneLine(logging.Handler):
    """What aiohttp says of a request it could not read or answer (a client's mistake:
    a malformed request line or header, a client gone mid-body): one line, with no
    traceback and none of the request's bytes, and at most LOUD lines a minute (then
    how many more there were), so that no local program can fill the log."""

    LOUD = 10  #: lines a minute

    def __init__(self, now=time.monotonic):
        super().__init__()
        self.now, self.since, self.said, self.more = now, -math.inf, 0, 0

    def emit(self, record: logging.LogRecord) -> None:
        """Say ``record`` in a line, unless LOUD were said this minute (then count it)."""
        t = self.now()
        if t - self.since >= 60:
            if self.more:
                print(f"gestplay serve: and {self.more:,} more requests it could not "
                      "read in that minute", file=sys.stderr)
            self.since, self.said, self.more = t, 0, 0
        if self.said >= self.LOUD:
            self.more += 1
            return
        self.said += 1
        exc = record.exc_info[1] if record.exc_info else None
        why = getattr(exc, "message", None) or (str(exc) if exc else "")
        why = " ".join(str(why).split("\n", 1)[0].split())[:80]
        named = type(exc).__name__ if exc else record.levelname.lower()
        print(f"gestplay serve: {record.getMessage()[:120]}: {named}"
              f"{': ' + why if why else ''}", file=sys.stderr)


def one_line(logger: logging.Logger) -> None:
    """``logger`` speaks through OneLine only."""
    logger.handlers[:] = [OneLine()]
    logger.propagate = False
