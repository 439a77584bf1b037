"""Which pairs of a profile's parts are never checked against each other (data), and
the file that keeps them beside the profile (``NAME.collisions.json``).

As MoveIt's setup assistant decides: pairs joined by a joint (``adjacent``: a part and
the nearest part with a shape above it), pairs with no moving joint between them
(``rigid``), and pairs closer than the clearance in every pose of a broad random sample
(``always``: the upper arm and the forearm about the elbow, the jaw under the neck).
The parts of one hand (``hand``: its palm and fingers) are not checked against each
other either: a fist closes the fingers on the palm and the thumb over them by design,
the tendons give, and the model's cylinders are not the printed phalanges (its thumb
would go through the fingers). Every other pair is checked: a hand against the other
hand, the head, the body. ``allowed_pairs`` makes them; ``save`` and ``load`` keep them
(JSON: a profile's directory holds TOML profiles only).
"""

from __future__ import annotations

import contextlib
import hashlib
import json
import os
import tempfile
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from ..hardware import Profile
from ..resources import private_cache_dir, private_file, read_regular
from .kinematics import Chain
from .shapes import Bodies
from .urdf import body

SAMPLES = 10_000  #: random poses the "always" pairs are found in (MoveIt's default)
SEED = 43
SUFFIX = ".collisions.json"
PALM = "_palm"  #: a hand's root link: it and the fingers below it are one hand
REASONS = ("adjacent", "rigid", "hand", "always")
CACHE = "collisions"  #: the folder of the private cache the pairs made are kept in
MOST = 1_000_000  #: bytes of a kept file read; a larger one is not ours
KEPT = 32  #: models whose pairs the cache keeps, the newest

Pair = tuple[str, str]


@dataclass(frozen=True)
class Allowed:
    """The pairs never checked (link names, in the model's order), each with why
    (``adjacent``, ``rigid``, ``hand``, ``always``); how they were found; ``model``: a digest of
    what they were made from (a profile whose model changed needs them made again)."""

    profile: str
    model: str
    clearance_mm: float
    samples: int
    seed: int
    pairs: dict[Pair, str]

    def __contains__(self, pair: Pair) -> bool:
        return pair in self.pairs or pair[::-1] in self.pairs


def digest(profile: Profile) -> str:
    """What the allowed pairs depend on: the model's parts that carry a shape, or a link
    that does, and each servo's travel (a frame with nothing under it, a hand's point or
    the gaze, changes no pair)."""
    parts = body(profile)
    bearing = {p.link for p in parts if p.shape is not None}
    for p in reversed(parts):  # each part comes after its parent
        if p.link in bearing:
            bearing.add(p.parent)
    text = repr([p for p in parts if p.link in bearing]) + repr(
        [(s.joint, s.rest, s.lo, s.hi, s.calibration) for s in profile.servos])
    return hashlib.sha256(text.encode()).hexdigest()[:16]


def joined(chain: Chain) -> dict[tuple[int, int], str]:
    """Pairs of links (indices, the parent's first) joined by a joint, with no moving
    joint between them, or in one hand; links without a shape are passed through."""
    shaped = [s is not None for s in chain.shapes]
    group = list(range(len(chain.links)))  # the rigid group: its topmost link
    above = [-1] * len(chain.links)  # the nearest link above with a shape
    hand = [-1] * len(chain.links)  # the palm the link is in or below
    for i, p in enumerate(chain.parent):  # parents come first
        hand[i] = i if chain.links[i].endswith(PALM) else hand[p] if p >= 0 else -1
        if p >= 0:
            group[i] = i if chain.moving[i] else group[p]
            above[i] = p if shaped[p] else above[p]
    out = {(above[i], i): "adjacent" for i in range(len(chain.links))
           if shaped[i] and above[i] >= 0}
    for i in range(len(chain.links)):
        for j in range(i):
            if not (shaped[i] and shaped[j]) or (j, i) in out:
                continue
            if group[i] == group[j]:
                out[(j, i)] = "rigid"
            elif hand[i] == hand[j] >= 0:
                out[(j, i)] = "hand"
    return out


def allowed_pairs(profile: Profile, samples: int = SAMPLES, seed: int = SEED,
                  clearance_mm: float | None = None) -> Allowed:
    """The profile's allowed pairs: joined ones, then those closer than ``clearance_mm``
    (the profile's clearance unless given) in each of ``samples`` random poses (each
    servo anywhere in its range)."""
    if clearance_mm is None:
        clearance_mm = profile.clearance_mm
    chain = Chain(profile)
    bodies = Bodies(chain)
    where = {link: k for k, link in enumerate(bodies.links)}
    pairs = {(where[i], where[j]): why for (i, j), why in joined(chain).items()}
    n = len(bodies.links)
    rest = [(i, j) for j in range(n) for i in range(j) if (i, j) not in pairs]
    a, b = (np.array(x, dtype=int) for x in zip(*rest, strict=True)) if rest else (
        np.zeros(0, int), np.zeros(0, int))
    rng = np.random.default_rng(seed)
    low = np.array([s.lo for s in profile.servos], dtype=float)
    high = np.array([s.hi for s in profile.servos], dtype=float)
    for _ in range(samples):
        if not len(a):
            break
        transforms = chain.transforms(rng.uniform(low, high))
        near = bodies.near(transforms, a, b, clearance_mm)
        a, b = a[near], b[near]
        touching = bodies.gaps(transforms, a, b) < clearance_mm
        a, b = a[touching], b[touching]
    pairs.update({(i, j): "always" for i, j in zip(a.tolist(), b.tolist(), strict=True)})
    named = {(bodies.names[i], bodies.names[j]): why for (i, j), why in sorted(pairs.items())}
    return Allowed(profile.name, digest(profile), clearance_mm, samples, seed, named)


def path_for(profile: Profile) -> Path | None:
    """Where the profile's allowed pairs are kept: beside its file (None: it has none)."""
    if not profile.path:
        return None
    path = Path(profile.path)
    return path.with_name(path.stem + SUFFIX)


def dumps(allowed: Allowed) -> str:
    """The file's text: one pair a line, so a change reads as a diff."""
    head = {"profile": allowed.profile, "model": allowed.model,
            "clearance_mm": allowed.clearance_mm, "samples": allowed.samples,
            "seed": allowed.seed}
    lines = [json.dumps([a, b, why]) for (a, b), why in allowed.pairs.items()]
    text = json.dumps(head, indent=1)[:-2]
    return text + ',\n "allowed": [\n  ' + ",\n  ".join(lines) + "\n ]\n}\n"


def save(allowed: Allowed, path: str | os.PathLike) -> None:
    """Write the allowed pairs to ``path``."""
    Path(path).write_text(dumps(allowed), encoding="utf-8")


def load(path: str | os.PathLike) -> Allowed:
    """The allowed pairs kept in ``path``; a ValueError (or OSError) when it holds none."""
    text = read_regular(path, MOST)
    if len(text) > MOST:
        raise ValueError(f"larger than {MOST:,} bytes")
    data = json.loads(text.decode("utf-8"))
    pairs = {}
    for entry in data["allowed"]:
        if not (isinstance(entry, list) and len(entry) == 3 and all(
                isinstance(x, str) for x in entry) and entry[2] in REASONS):
            raise ValueError(f"not an allowed pair: {entry!r:.60}")
        pairs[(entry[0], entry[1])] = entry[2]
    return Allowed(str(data["profile"]), str(data["model"]), float(data["clearance_mm"]),
                   int(data["samples"]), int(data["seed"]), pairs)


def allowed_for(profile: Profile) -> Allowed:
    """The profile's allowed pairs: its file's when it was made from this model at the
    profile's clearance, else the ones the user's cache keeps for this model, else made
    now (seconds) and kept there. A file that cannot be read, or was made from another
    model, is passed over: the pairs are made again."""
    model = digest(profile)
    cached = cache_path(model, profile.clearance_mm)
    for path, private in ((path_for(profile), False), (cached, True)):
        if path is not None and (kept := _kept(path, model, profile.clearance_mm, private)):
            if private:  # the newest used: the last the cache lets go (_prune)
                with contextlib.suppress(OSError):
                    os.utime(path)
            return replace(kept, profile=profile.name)
    made = allowed_pairs(profile)
    if cached is not None:
        _keep(made, cached)
    return made


def cache_path(model: str, clearance_mm: float) -> Path | None:
    """Where the user's private cache keeps the pairs made from ``model`` (a ``digest``)
    at ``clearance_mm``; None when there is no private cache."""
    folder = private_cache_dir()
    if folder is None:
        return None
    how = hashlib.sha256(repr((clearance_mm, SAMPLES, SEED)).encode()).hexdigest()[:8]
    return folder / CACHE / f"{model}-{how}{SUFFIX}"


def _kept(path: Path, model: str, clearance_mm: float, private: bool) -> Allowed | None:
    """The pairs ``path`` keeps, if it was made from ``model`` at ``clearance_mm`` (and,
    when ``private``, it is this user's file that no one else can write); None for
    anything else: missing, unreadable, corrupt, another model's or user's."""
    try:
        if not path.is_file() or private and not private_file(path):
            return None
        kept = load(path)
    except (OSError, ValueError, KeyError, TypeError, OverflowError, RecursionError):
        return None
    return kept if kept.model == model and kept.clearance_mm == clearance_mm else None


def _keep(allowed: Allowed, path: Path) -> None:
    """Write ``allowed`` to ``path`` whole or not at all (another process may be reading
    it, or writing it too); a cache that cannot be written is left as it is."""
    try:
        path.parent.mkdir(mode=0o700, exist_ok=True)
        fd, temporary = tempfile.mkstemp(dir=path.parent, suffix=".tmp")
    except OSError:
        return
    try:
        with os.fdopen(fd, "w", encoding="utf-8") as f:
            f.write(dumps(allowed))
        os.replace(temporary, path)
    except OSError:
        with contextlib.suppress(OSError):
            os.unlink(temporary)
    _prune(path.parent)


def _prune(folder: Path) -> None:
    """The KEPT newest files of the cache's ``folder`` kept, the older ones removed (a
    profile edited often makes a model a change)."""
    with contextlib.suppress(OSError):
        files = sorted(folder.glob("*" + SUFFIX), key=lambda f: f.stat().st_mtime_ns)
        for old in files[:-KEPT]:
            old.unlink()
