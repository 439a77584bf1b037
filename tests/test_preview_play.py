"""The live preview's "Play on the robot" (issue 44): the one request it makes of a
running ``gestplay serve`` (the gesture's name and the text its plan was made from, its
``use`` lines blank and the user's own files it uses after it, the library's not), that
request played by the service on sim:// (the robot ends where the plan does), the
token shown, a refusal and a service that is not there each said in a line."""

from __future__ import annotations

from test_service import serving, still, until, values

from inmoov_dsl.editor.analysis import analyse
from inmoov_dsl.editor.preview_play import Player, request
from inmoov_dsl.editor.preview_view import view_of

TOKEN = "s3cret-token-of-16"
BEARER = {"Authorization": f"Bearer {TOKEN}"}
MINE = "robot rhand\nopen: fingers 0 over 0.5s\n"
WAVE = """robot rhand
use "mine.gest"
use "peace.gest"

wave:
    open
    wrist 180, index 120 over 0.4s through
    wrist 30 over 0.4s stagger 0.1s
    peace
    index 90 over 0.3s
"""


def wave_view(tmp_path, text: str = WAVE):
    (tmp_path / "mine.gest").write_text(MINE)
    path = tmp_path / "wave.gest"
    path.write_text(text)
    return view_of(analyse(text, str(path)), 6)


def test_what_play_on_the_robot_sends(tmp_path):
    view = wave_view(tmp_path)
    body, why = request(view)
    assert why == "" and set(body) == {"text", "gesture", "when"}
    assert (body["gesture"], body["when"]) == ("wave", "now")
    rows = body["text"].split("\n")
    assert rows[:5] == ["robot rhand", "", "", "", "wave:"]  # the lines keep their numbers
    assert rows[5:10] == WAVE.split("\n")[5:10]  # through, stagger: as written
    mine = rows.index("# mine.gest")  # the user's own file follows, its robot line blank
    assert rows[mine + 1:mine + 3] == ["", "open: fingers 0 over 0.5s"]
    assert "# peace.gest" not in rows  # the library's: the service has it
    stale = view_of(analyse(WAVE.replace("wrist 30", "wrist"), view.path), 6, previous=view)
    assert stale.stale and request(stale)[0] == body  # what compiled, not what is typed
    none = view_of(analyse("wave: indx 9\n", view.path))
    assert request(none) == (None, "the gesture does not compile")


def test_the_player_plays_the_gesture_on_a_running_service(tmp_path):
    view = wave_view(tmp_path)
    final = {view.profile.servos[i].name: v for i, v in enumerate(view.plan.final)}
    with serving("--token", TOKEN) as service, service.events(BEARER) as ws:
        said = Player(service.url, TOKEN)(view)
        assert said.startswith(f"'wave' sent to {service.url} (id "), said
        told = until(ws, "done", said.split("(id ")[1].rstrip(")"), 60)
        events = [e["event"] for e in told if e["event"] != "pose"]
        assert (events[0], set(events[1:-1]), events[-1]) == ("started", {"warning"}, "done")
        warned = {(d["line"], d["source"], d["message"].split(":")[0]) for e in told
                  if e["event"] == "warning" for d in e["diagnostics"]}
        assert (10, "    index 90 over 0.3s", "move stretched") in warned  # the file's line
        assert values(still(service, 60, BEARER)) == final  # the whole gesture: its end
        refused = Player(service.url)(view)  # no token
        assert refused.startswith("'wave' was refused (401): "), refused
        body = view_of(analyse("robot inmoov\nnod: rothead 120 over 1s\n", view.path))
        said = Player(service.url, TOKEN)(body)  # the service drives a hand
        assert said.startswith("'nod' was refused (422): <request>:1:7: error: this file is "
                               "for robot 'inmoov', and profile 'rhand' has no "), said
    gone = Player(service.url, TOKEN, timeout=2)(view)
    assert gone.startswith(f"'wave' was refused (0): cannot reach {service.url}"), gone
