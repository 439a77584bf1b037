"""The preview page's "Play on the robot": a gesture's plan sent to a running
``gestplay serve`` (docs/service.md), a ``POST /api/play`` per step.

The service plays one line of the language per request and reaches only the library
and the profile, not the file being edited; so each planned step is sent as what it
does (pure: ``requests``): the values its servos end on, ``over`` the time it was
planned to take (``wait`` for a hold, ``say`` for spoken text), the first taking over
from where the robot is (and bringing every servo the gesture names to the plan's
values), the others queued after it (``"when": "after"``). Each is
planned again by the service from rest to rest: a step that flows ``through`` its
keyframe stops there, a ``stagger`` is not kept, a ``say`` of a file is left out.
``Player`` is the edge: it sends them (urllib), only when the page's button is clicked.
"""

from __future__ import annotations

import json
import math
import urllib.error
import urllib.request
from typing import Any

from ..model.timeline import View

TIMEOUT = 5.0  #: s for the service to answer a request


def requests(view: View) -> tuple[list[dict[str, Any]], list[str]]:
    """The bodies of the requests that play ``view``'s gesture, in order, and what
    could not be sent (a line each)."""
    plan, bodies, left = view.plan, [], []
    if plan is None:
        return [], ["the gesture does not compile"]
    names = [s.name for s in plan.profile.servos]
    sounds = list(plan.sounds)
    for span in view.spans:
        length = f"{math.ceil((span.end - span.start) * 1000 - 1e-6) / 1000:g}s"
        if span.kind == "say":
            speech = next((s for t, s in sounds if span.start <= t <= span.end + 1e-9), None)
            if speech is None or speech.sound.path or '"' in speech.sound.source:
                left.append(f"step {span.number}: a say of a file is not sent")
                continue
            line = f'say "{speech.sound.source}"'
        else:  # the first brings every servo the gesture names where the plan has it
            servos = sorted(set(span.servos) | (plan.named if not bodies else set()))
            if span.kind == "hold" or not servos:
                line = f"wait {length}"
            else:
                line = ", ".join(f"{names[i]} {round(float(plan.tracks[i].position(span.end)))}"
                                 for i in servos) + f" over {length}"
        bodies.append({"steps": line, "when": "after" if bodies else "now"})
    return bodies, left


class Player:
    """Plays a view's gesture on the ``gestplay serve`` at ``url`` (``token``: the
    secret it asks for, if any): a ``LivePage.on_play``."""

    def __init__(self, url: str, token: str | None = None, timeout: float = TIMEOUT):
        self.url = url.rstrip("/")
        self.token = token
        self.timeout = timeout
        self.hint = f"plays the gesture on gestplay serve at {self.url}"

    def __call__(self, view: View) -> str:
        """Send the requests; what happened, in a line."""
        bodies, left = requests(view)
        ids = []
        for k, body in enumerate(bodies):
            status, answer = self._post(body)
            if status != 202:
                said = answer.get("text") or answer.get("error") or f"status {status}"
                return (f"step {k + 1} of {len(bodies)} ({body['steps']}) was refused "
                        f"({status}): {said}" + (f"; {k} sent before it" if k else ""))
            ids.append(answer.get("id", "?"))
        return " ".join([f"sent {len(bodies)} step{'s' * (len(bodies) != 1)} to {self.url}"
                         f" (first id {ids[0]})" if ids else "nothing to send", *left])

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
