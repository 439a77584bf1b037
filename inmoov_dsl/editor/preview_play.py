"""The preview page's "Play on the robot": the gesture sent to a running ``gestplay
serve`` (docs/service.md) in one ``POST /api/play``: the text its plan was made from
and its name (``"text"``, ``"gesture"``), which the service plans again from where the
robot is, checks and plays as ``gestplay`` would play the file, ``through``, ``stagger``
and ``say`` as written.

A request reads no file of the service's computer: the file's ``use`` lines are left
blank (so its lines keep their numbers: a refusal points at the line it is about) and
the files they name, but the library's, follow its text, their own ``robot`` and
``use`` lines blank (pure: ``request``). ``Player`` is the edge: it sends it (urllib),
only when the page's button is clicked.
"""

from __future__ import annotations

import json
import os
import re
import urllib.error
import urllib.request
from pathlib import Path
from typing import Any

from ..language.library import library_dirs
from ..views.timeline import View

TIMEOUT = 5.0  #: s for the service to answer a request
USE = re.compile(r"[ \t]*use\b")  #: a use line
ROBOT = re.compile(r"[ \t]*robot\b")  #: a robot line
ROBOT_FILE = re.compile(r'[ \t]*robot[ \t]+"')  #: one that names a profile's file


def request(view: View) -> tuple[dict[str, Any] | None, str]:
    """The body that plays ``view``'s gesture, or None and why it cannot be sent."""
    program = view.program
    if view.plan is None or program is None or view.gesture is None:
        return None, "the gesture does not compile"
    root = program.texts[program.root]
    rows = ["" if USE.match(row) or ROBOT_FILE.match(row) else row  # (the service's own)
            for row in root.split("\n")]
    library = [os.path.realpath(d) + os.sep for d in library_dirs()]
    for file, text in program.texts.items():
        if file != program.root and not os.path.realpath(file).startswith(tuple(library)):
            rows += ["", f"# {Path(file).name}"]
            rows += ["" if USE.match(row) or ROBOT.match(row) else row
                     for row in text.split("\n")]
    return {"text": "\n".join(rows), "gesture": view.gesture, "when": "now"}, ""


class Player:
    """Plays a view's gesture on the ``gestplay serve`` at ``url`` (``token``: the
    secret it asks for, if any): a ``LivePage.on_play``."""

    def __init__(self, url: str, token: str | None = None, timeout: float = TIMEOUT):
        self.url = url.rstrip("/")
        self.token = token
        self.timeout = timeout
        self.hint = f"plays the gesture on gestplay serve at {self.url}"

    def __call__(self, view: View) -> str:
        """Send it; what happened, in a line."""
        body, why = request(view)
        if body is None:
            return why
        status, answer = self._post(body)
        if status != 202:
            said = answer.get("text") or answer.get("error") or f"status {status}"
            return f"'{view.gesture}' was refused ({status}): {said}"
        warned = len(answer.get("warnings") or ())
        return (f"'{view.gesture}' sent to {self.url} (id {answer.get('id', '?')})"
                + (f", {warned} warning{'s' * (warned != 1)}" if warned else ""))

    def _post(self, body: dict[str, Any]) -> tuple[int, dict[str, Any]]:
        """POST /api/play: the status and the JSON answer (a refusal's too; a service
        that cannot be reached is status 0)."""
        headers = {"Content-Type": "application/json"}
        if self.token:
            headers["Authorization"] = f"Bearer {self.token}"
        request = urllib.request.Request(f"{self.url}/api/play", json.dumps(body).encode(),
                                         headers, method="POST")
        try:
            with urllib.request.urlopen(request, timeout=self.timeout) as answer:
                return answer.status, json.loads(answer.read() or b"{}")
        except urllib.error.HTTPError as exc:
            try:
                return exc.code, json.loads(exc.read() or b"{}")
            except ValueError:
                return exc.code, {}
        except (urllib.error.URLError, OSError, ValueError) as exc:
            return 0, {"error": f"cannot reach {self.url}: {getattr(exc, 'reason', exc)}"}
