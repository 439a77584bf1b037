"""The mouth's track fitted to a sound known in advance (pure): a linear program, solved
by scipy's HiGHS (the ``voice`` extra).

The track is a uniform cubic B-spline with a knot every ``speech.HOP``. Its velocity,
acceleration and jerk are B-splines whose control points are the differences of its
own, divided by HOP, HOP² and HOP³; a B-spline stays within its control points, so
bounding those differences holds the servo's limits at every instant, not only at the
knots. The program minimises the distance between the track and the target at every
knot (the sum of their absolute differences).

Where the mouth must be closed and still, three control points in a row are fixed; the
free runs between are separate programs. A run longer than CHUNK knots is solved CHUNK
at a time, each looking OVERLAP further, so time and memory grow with the sound's
length, not faster. Where the jaw cannot follow at full size (the track's shape
correlates less than FAITHFUL with the target's, over up to CHUNK knots), the target is
fitted again smaller (SCALES): quick speech opens the mouth less, but in its rhythm.
"""

from __future__ import annotations

import numpy as np

from ..hardware import Servo

SCALES = (1.0, 0.8, 0.65, 0.5, 0.4, 0.3)  #: of the opening, tried in turn
FAITHFUL = 0.9  #: the correlation a run's track must reach with its target
CHUNK = 1500  #: knots solved at once in a long run (15 s)...
OVERLAP = 300  #: ...looking this many knots further
MARGIN = 1 - 1e-6  #: of each limit: floating point keeps to the inside


NEEDS_SCIPY = "planning the mouth for 'say' needs scipy, which is not installed"


class MouthError(ValueError):
    """The mouth's track cannot be planned (scipy missing, or the solver failing)."""


def solvable() -> bool:
    """Is the solver (scipy) there?"""
    import importlib.util

    return importlib.util.find_spec("scipy") is not None


def runs(mask: np.ndarray) -> list[tuple[int, int]]:
    """The runs ``[a, b)`` where ``mask`` is true."""
    edges = np.diff(np.concatenate(([0], np.asarray(mask, dtype=np.int8), [0])))
    return list(zip(np.flatnonzero(edges == 1).tolist(),
                    np.flatnonzero(edges == -1).tolist(), strict=True))


def fit(target: np.ndarray, fixed: np.ndarray, servo: Servo, hop: float,
        span: tuple[float, float], closed: float, judged: np.ndarray) -> np.ndarray:
    """The control points (``len(target) + 2``) of the track whose value at each knot k
    is nearest ``target[k]``, or a smaller opening (from ``closed``) of the same shape
    (the shape judged at the knots ``judged`` marks); ``fixed[j]`` (not NaN) fixes
    control point j. The track stays within ``span`` and the servo's limits."""
    c = fixed.astype(float).copy()
    for parts in _windows(np.isnan(c)):
        best, best_r = None, -2.0
        for scale in SCALES:
            tried = c.copy()
            aim = closed + scale * (target - closed)
            for first, stop, look in parts:
                lo = first - 3
                tried[first:stop] = _solve(tried[lo:look + 3], lo, aim, servo, hop,
                                           span)[3:3 + stop - first]
            knots = np.arange(parts[0][0] - 2, min(len(target), parts[-1][1]))
            values = (tried[knots] + 4 * tried[knots + 1] + tried[knots + 2]) / 6
            known = np.isfinite(values) & judged[knots]  # (a long run's next part is
            # not solved yet)
            r = _correlation(values[known], target[knots][known])
            if best is None or r > best_r:
                best, best_r = tried, r
            if r >= FAITHFUL:
                break
        c = best
    return c


def _windows(free: np.ndarray) -> list[list[tuple[int, int, int]]]:
    """The free control points in parts ``(first, stop, look)``: each solves
    ``first..look-1`` and keeps ``first..stop-1``. A run longer than CHUNK is cut into
    parts, each its own window; shorter runs share a window up to CHUNK long. Every run
    has three fixed points on each side."""
    windows: list[list[tuple[int, int, int]]] = []
    group: list[tuple[int, int, int]] = []  # short runs sharing a window
    for a, b in runs(free):
        if group and b - group[0][0] > CHUNK:
            windows.append(group)
            group = []
        if b - a <= CHUNK:
            group.append((a, b, b))
            continue
        windows += [[(k, min(b, k + CHUNK), min(b, k + CHUNK + OVERLAP))]
                    for k in range(a, b, CHUNK)]
    return windows + [group] * bool(group)


def _correlation(a: np.ndarray, b: np.ndarray) -> float:
    """Pearson's r; 1 where both are flat and equal, 0 where either is flat."""
    if len(a) < 2 or np.ptp(a) < 1e-6 or np.ptp(b) < 1e-6:
        return 1.0 if np.allclose(a, b) else 0.0
    return float(np.corrcoef(a, b)[0, 1])


def _solve(window: np.ndarray, offset: int, aim: np.ndarray, servo: Servo,
           hop: float, span: tuple[float, float]) -> np.ndarray:
    """The linear program over the control points ``offset..`` (``window``; fixed
    where not NaN) and an error e per knot they place: minimise the sum of e with
    -e <= value - aim <= e, and each difference of the points within its limit."""
    try:
        from scipy import sparse
        from scipy.optimize import linprog
    except ImportError:
        raise MouthError(NEEDS_SCIPY) from None
    knots = np.arange(offset, min(len(aim), offset + len(window) - 2))
    (lo, hi), m, n, aim = span, len(window), len(knots), aim[knots]
    knots = knots - offset
    value = sparse.csr_matrix(
        (np.tile([1 / 6, 4 / 6, 1 / 6], n),
         (np.repeat(np.arange(n), 3), (knots[:, None] + np.arange(3)).ravel())), (n, m))
    eye = sparse.identity(n, format="csr")
    rows, bounds_ub = [sparse.hstack([value, -eye]), sparse.hstack([-value, -eye])], [aim, -aim]
    limits = (servo.max_velocity * hop, servo.max_acceleration * hop ** 2,
              servo.max_jerk * hop ** 3)
    d = sparse.identity(m, format="csr")
    for limit in limits:
        d = d[1:] - d[:-1]
        pad = sparse.csr_matrix((d.shape[0], n))
        rows += [sparse.hstack([d, pad]), sparse.hstack([-d, pad])]
        bounds_ub += [np.full(d.shape[0], limit * MARGIN)] * 2
    bounds = [(v, v) if np.isfinite(v) else (lo, hi) for v in window.tolist()]
    bounds += [(0.0, None)] * n
    cost = np.concatenate((np.zeros(m), np.ones(n)))
    done = linprog(cost, A_ub=sparse.vstack(rows, format="csc"),
                   b_ub=np.concatenate(bounds_ub), bounds=bounds, method="highs")
    if done.status != 0:
        raise MouthError(f"the mouth's track cannot be planned ({done.message})")
    return np.clip(done.x[:m], lo, hi)
