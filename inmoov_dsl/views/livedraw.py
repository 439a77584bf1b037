"""What the live preview page draws, as HTML and SVG text (pure): the timeline of a
``timeline.View`` (a row of steps, a row of marks, a row per sound, a row per servo with
its limits, its planned curve and the values its board receives), and the small parts
that change as the page plays: the time, the pose, the playhead and the highlighted
steps.

The timeline is drawn once per view; what moves in it (the playhead, the highlight on
the steps under the cursor) is a ``<style>`` of a few bytes (``state``) that places two
rectangles and colours a step, so playing sends no curve again.
"""

from __future__ import annotations

import base64
import functools
import html
import io
import math
import wave
from collections.abc import Sequence

import numpy as np

from ..model import joints
from .timeline import Series, Sound, View

WIDTH, LEFT, RIGHT = 600.0, 72.0, 8.0  #: the drawing's units: about a pixel each
STEPS, MARKS, SOUND, SERVO, AXIS = 24.0, 14.0, 40.0, 42.0, 18.0  #: row heights
PAD = '<div style="padding:0 0.75rem">'  #: as viser's own rows stand from the edge
RATE = 16_000  #: samples a second of a sound sent to the page, at most
COLOURS = {"plan": "#1f77b4", "sent": "#d62728", "limit": "#9a9a9a", "stretched": "#f08c00",
           "full link": "#c92a2a", "contact": "#862e9c", "sound": "#2ca02c",
           "cursor": "#ffd43b", "span": "#e9ecef", "hold": "#f8f9fa"}
STYLE = (".gl-tl text{{font:11px sans-serif;fill:#333}}.gl-tl .gl-n{{font-size:10px}}"
         ".gl-tl .gl-span rect{{fill:{span};stroke:#adb5bd;stroke-width:.5}}"
         ".gl-tl .gl-hold rect{{fill:{hold}}}.gl-tl .gl-hl{{fill:{cursor};opacity:.28}}"
         ".gl-tl .gl-ph{{fill:#111}}".format(**COLOURS))


def span_x(view: View, t: float) -> float:
    """Where time ``t`` is across the drawing."""
    end = view.duration or 1.0
    return LEFT + (WIDTH - LEFT - RIGHT) * min(max(t / end, 0.0), 1.0)


def timeline(view: View) -> str:
    """The view's timeline as an SVG (its width the page's); empty without a plan."""
    if view.plan is None or view.motion is None:
        return ""
    motion, out, y = view.motion, [], 0.0
    out.append(_steps(view))
    y += STEPS
    out.append(_marks(view, y))
    y += MARKS
    for sound in motion.sounds:
        out.append(_sound(view, sound, y))
        y += SOUND
    for series in motion.series:
        out.append(_servo(view, series, y))
        y += SERVO
    out.append(_axis(view, y))
    height = y + AXIS
    out.append(f'<rect class="gl-hl" x="0" y="0" width="0" height="{height:.0f}"/>'
               f'<rect class="gl-ph" x="{LEFT:.0f}" y="0" width="1.5" height="{height:.0f}"/>')
    return (f'<svg class="gl-tl" viewBox="0 0 {WIDTH:.0f} {height:.0f}" width="100%" '
            f'xmlns="http://www.w3.org/2000/svg"><style>{STYLE}</style>{"".join(out)}</svg>')


def _steps(view: View) -> str:
    """The steps as labelled spans: their number, their code in a tooltip."""
    parts = ['<text x="4" y="15">steps</text>']
    for k, s in enumerate(view.spans):
        x0, x1 = span_x(view, s.start), span_x(view, s.end)
        kind = " gl-hold" if s.kind == "hold" else ""
        fits = int((x1 - x0 - 4) / 5.5)  # characters of 10 px text
        said = f"{s.number} {s.label}" if fits >= len(str(s.number)) + 6 else str(s.number)
        said = said if len(said) <= fits else said[:max(fits - 1, 0)] + "…"
        number = (f'<text class="gl-n" x="{(x0 + x1) / 2:.1f}" y="15" text-anchor="middle">'
                  f'{html.escape(said)}</text>') if fits >= len(str(s.number)) else ""
        parts.append(f'<g class="gl-span gl-s{k}{kind}"><title>{s.number}. '
                     f'{html.escape(s.label)} ({s.start:.2f}–{s.end:.2f} s)</title>'
                     f'<rect x="{x0:.1f}" y="3" width="{max(x1 - x0, 0.8):.1f}" height="17"/>'
                     f'{number}</g>')
    return "".join(parts)


def _marks(view: View, y: float) -> str:
    """Stretched moves, full links and contacts, each with what it is in a tooltip."""
    parts = [f'<text x="4" y="{y + 11:.0f}">marks</text>']
    for m in view.marks:
        x0, x1 = span_x(view, m.start), span_x(view, m.end)
        colour = COLOURS[m.kind]
        title = f"<title>{html.escape(m.kind)} at {m.start:.2f} s: {html.escape(m.text)}</title>"
        if m.kind == "contact":
            parts.append(f'<g>{title}<path d="M{x0:.1f} {y + 1:.0f}l5 6-5 6-5-6z" '
                         f'fill="{colour}"/></g>')
        else:
            parts.append(f'<g>{title}<rect x="{x0:.1f}" y="{y + 3:.0f}" '
                         f'width="{max(x1 - x0, 1.5):.1f}" height="8" fill="{colour}" '
                         f'opacity=".8"/></g>')
    return "".join(parts)


def _sound(view: View, sound: Sound, y: float) -> str:
    """A ``say``'s waveform and its loudness."""
    mid, half = y + SOUND / 2, SOUND / 2 - 3
    step = sound.duration / max(len(sound.low), 1)
    xs = [span_x(view, sound.start + (k + 0.5) * step) for k in range(len(sound.low))]
    wave = " ".join(f"{x:.1f},{mid - half * v:.1f}" for x, v in zip(xs, sound.high,
                                                                      strict=True))
    back = " ".join(f"{x:.1f},{mid - half * v:.1f}" for x, v in zip(xs[::-1], sound.low[::-1],
                                                                      strict=True))
    every = max(1, math.ceil(len(sound.levels) / 400))  # a level a unit apart, at most
    level = " ".join(f"{span_x(view, sound.start + k * every * sound.hop):.1f},"
                     f"{y + SOUND - 3 - (SOUND - 6) * v:.1f}"
                     for k, v in enumerate(sound.levels[::every].tolist()))
    return (f'<g><title>say "{html.escape(sound.source)}" at {sound.start:.2f} s, '
            f'{sound.duration:.2f} s</title><text x="4" y="{mid + 4:.0f}">say</text>'
            f'<polygon points="{wave} {back}" fill="#adb5bd"/><polyline points="{level}" '
            f'fill="none" stroke="{COLOURS["sound"]}" stroke-width="1.2"/></g>')


def _servo(view: View, s: Series, y: float) -> str:
    """A servo's row: its limits, its planned curve, the values its board receives."""
    def at(v: float) -> float:
        return y + SERVO - 4 - (SERVO - 8) * v / 180

    xs = [span_x(view, t) for t in s.times.tolist()]
    curve = " ".join(f"{px:.1f},{py:.1f}" for px, py in _bends(
        xs, [at(v) for v in s.planned.tolist()]))
    start = view.plan.start[s.servo] if view.plan is not None else s.lo
    held = [(LEFT, start)]  # (x, value) where the board's value changes, a half unit apart
    for t, v in zip(s.sent_times.tolist(), s.sent.tolist(), strict=True):
        x = round(span_x(view, t) * 2) / 2
        if v != held[-1][1]:
            held[-1:] = [(x, v)] if x == held[-1][0] and len(held) > 1 else [held[-1], (x, v)]
    path = f"M{LEFT:.1f} {at(start):.1f}" + "".join(f"H{x:.1f}V{at(v):.1f}"
                                                     for x, v in held[1:])
    path += f"H{WIDTH - RIGHT:.1f}"
    grey = COLOURS["limit"]
    return (f'<g><text x="4" y="{y + SERVO / 2 + 4:.0f}">{html.escape(s.name)}</text>'
            f'<title>{html.escape(s.name)}: range {s.lo}..{s.hi}</title>'
            f'<path d="M{LEFT:.0f} {at(s.lo):.1f}H{WIDTH - RIGHT:.0f}M{LEFT:.0f} {at(s.hi):.1f}'
            f'H{WIDTH - RIGHT:.0f}" stroke="{grey}" stroke-dasharray="4 3" stroke-width=".8"/>'
            f'<polyline points="{curve}" fill="none" stroke="{COLOURS["plan"]}" '
            f'stroke-width="2.2" opacity=".6"/><path d="{path}" fill="none" '
            f'stroke="{COLOURS["sent"]}" stroke-width=".9"/></g>')


def _bends(xs: list[float], ys: list[float]) -> list[tuple[float, float]]:
    """The points of a curve where it is not flat (as drawn, to a tenth of a unit): a
    still servo's row is two points, not hundreds."""
    keep = [(x, y) for k, (x, y) in enumerate(zip(xs, ys, strict=True))
            if k in (0, len(ys) - 1) or round(ys[k - 1], 1) != round(y, 1)
            or round(ys[k + 1], 1) != round(y, 1)]
    return keep


def _axis(view: View, y: float) -> str:
    """Seconds along the bottom."""
    end = view.duration or 1.0
    tick = next(t for t in (0.1, 0.2, 0.5, 1, 2, 5, 10, 20, 30, 60, 120, 300, 600, 1800,
                            3600) if end / t <= 10)
    parts = [f'<path d="M{LEFT:.0f} {y + 2:.0f}H{WIDTH - RIGHT:.0f}" stroke="#888"/>']
    for k in range(int(end / tick + 1e-9) + 1):
        x = span_x(view, k * tick)
        parts.append(f'<text x="{x:.1f}" y="{y + 14:.0f}" text-anchor="middle">'
                     f'{k * tick:g}</text>')
    return "".join(parts) + f'<text x="4" y="{y + 14:.0f}">s</text>'


def state(view: View, t: float, cursor: Sequence[int]) -> str:
    """What moves on the timeline: the playhead at ``t``, the spans ``cursor``
    highlighted (a ``<style>``)."""
    rules = [f".gl-tl .gl-ph{{x:{span_x(view, t) - 0.75:.1f}px}}"]
    if cursor and view.spans:
        first, last = view.spans[cursor[0]], view.spans[cursor[-1]]
        x0, x1 = span_x(view, first.start), span_x(view, last.end)
        rules.append(f".gl-tl .gl-hl{{x:{x0:.1f}px;width:{max(x1 - x0, 1.5):.1f}px}}")
        rules += [f".gl-tl .gl-s{k} rect{{fill:{COLOURS['cursor']}}}" for k in cursor]
    return f"<style>{''.join(rules)}</style>"


def clock(view: View, t: float) -> str:
    """The time and the step playing at ``t`` (``id``s for a program reading the
    page)."""
    k = view.span_at(t)
    step = view.spans[k] if k is not None else None
    said = (f'step <span id="gl-step">{step.number}</span>: {html.escape(step.label)}'
            if step else 'step <span id="gl-step">-</span>')
    return (f'{PAD}<div style="font-size:13px">t = <b><span id="gl-time">{t:.3f}</span></b> s of '
            f'{view.duration:.3f} s &middot; {said}</div></div>')


def pose(view: View, values: Sequence[float]) -> str:
    """Each servo the gesture moves: its planned value and its joint's angle (a row
    each, ``data-servo`` and ``data-value`` for a program reading the page)."""
    rows = []
    for s in view.motion.series if view.motion else ():
        servo = view.profile.servos[s.servo]
        angle = math.degrees(joints.position(servo, values[s.servo]))
        rows.append(f'<tr data-servo="{html.escape(s.name)}" data-value="{values[s.servo]:.3f}">'
                    f'<td>{html.escape(s.name)}</td><td align="right">'
                    f'{values[s.servo]:.1f}</td><td align="right">{angle:.1f}°</td></tr>')
    if not rows:
        return ""
    return (f'{PAD}<table style="font-size:12px;border-spacing:8px 0"><tr><th align="left">'
            'servo</th><th>value</th><th>joint</th></tr>' + "".join(rows) + "</table></div>")


def contacts_note(view: View, unchecked: bool) -> str:
    """What the page says of the view's contacts (``unchecked``: they cannot be looked
    for)."""
    if view.contacts is None:
        return "Contacts: looking."
    if view.contacts:
        return f"Contacts: {len(view.contacts)} (marked on the timeline)."
    if unchecked:
        return "Contacts: not looked for (needs python-fcl and parts that can meet)."
    return "Contacts: none."


def diagnostics(view: View, most: int = 12) -> str:
    """The file's errors (and warnings), a line each; what is shown when it has
    errors."""
    if not view.diagnostics:
        return ""
    rows = []
    for d in view.diagnostics[:most]:
        where = f"{d.pos.line}:{d.pos.column}: " if d.pos is not None else ""
        colour = "#c92a2a" if d.severity == "error" else "#e67700"
        rows.append(f'<li style="color:{colour}">{where}{html.escape(d.severity)}: '
                    f"{html.escape(d.message)}</li>")
    more = len(view.diagnostics) - most
    if more > 0:
        rows.append(f"<li>and {more} more</li>")
    head = ("the text has errors: this is the last plan that compiled" if view.stale
            else "errors" if view.errors else "warnings")
    return (f'{PAD}<div id="gl-diagnostics" style="font-size:12px"><b>{head}</b>'
            f'<ul style="margin:2px 0;padding-left:16px">{"".join(rows)}</ul></div></div>')


def audio(sound: Sound, offset: float) -> str:
    """An ``<audio>`` element that plays ``sound`` from ``offset`` s as it is put on the
    page (a browser lets a page that was clicked play sound)."""
    return (f'<audio autoplay src="{_wav_url(sound)}#t={max(offset, 0.0):.3f}">'
            "</audio>")


@functools.lru_cache(maxsize=8)
def _wav_url(sound: Sound) -> str:
    """The sound as a WAV in a ``data:`` URL: 16-bit, at most RATE samples a second
    (each few samples' mean)."""
    k = max(1, math.ceil(sound.rate / RATE))
    samples = np.asarray(sound.samples, dtype=float)
    samples = np.resize(samples, len(samples) // k * k).reshape(-1, k).mean(axis=1)
    data = io.BytesIO()
    with wave.open(data, "wb") as w:
        w.setnchannels(1)
        w.setsampwidth(2)
        w.setframerate(round(sound.rate / k))
        w.writeframes((np.clip(samples, -1, 1) * 32767).astype("<i2").tobytes())
    return "data:audio/wav;base64," + base64.b64encode(data.getvalue()).decode()
