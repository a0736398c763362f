"""The one pseudo-arclength engine on a problem with a known answer: the circle
x^2 + lam^2 = 1, continued in lam through its folds at lam = +-1 (where x = 0), with the
test function x located as an event; Newton and chord correctors, the box landing."""
import math
from dataclasses import dataclass

import numpy as np
import pytest

from symvi.continuation import engine


class Circle:
    """F(x; lam) = x^2 + lam^2 - 1: one equation, one unknown, one parameter."""

    size = 1

    def at(self, lam, check=True):
        return None

    def evaluate(self, v, lam, jac=True, dparam=False, check=True):
        x = v[0]
        F = np.array([x * x + lam * lam - 1.0])
        if not jac:
            return F, None, None
        return F, np.array([[2 * x]]), (np.array([2 * lam]) if dparam else None)


@dataclass(frozen=True)
class Pt:
    x: float
    lam: float
    admissible: bool = True


class Run(engine.Client):
    names = ("lam",)

    def point(self, X, prev, Gu):
        return Pt(float(X[0]), float(X[1]))


class XTracker(engine.Tracker):
    """The event: x through 0 (the folds of the circle in lam)."""

    def tests(self, X, t, pt):
        return {"x": float(X[0])}

    def brackets(self, pa, pb, pta, ptb):
        return [("fold", {})] if engine.sign_change(pa["x"], pb["x"]) else []

    def locate_event(self, kind, Xa, ta, Xb, index):
        X, t, _ = self.root(lambda X, t, Gu: X[0], Xa, ta, Xb)
        return (kind, float(X[1]), index)

    def unlocated(self, kind, Xa, Xb, index, exc):
        return ("unlocated", None, index)


@pytest.mark.parametrize("chord", [False, True])
def test_circle_turns_at_both_folds_and_lands_on_the_bound(chord):
    system = Circle()
    X = np.array([1.0, 0.0])                         # (x, lam) on the circle
    F, DF, Fb = system.evaluate(X[:1], X[1], dparam=True)
    t = engine.tangent(DF, Fb, np.array([0.0, 1.0]))
    tracker = XTracker(system)
    # box lam in [-2, 2]: the run goes around the circle, never reaching the box
    # h_max large: the turning-angle limit is what bounds the step
    pts, states, end = engine.run(system, Run(), X, t, [-2.0], [2.0], h=0.6, h_max=1.0,
                                  max_points=200, tracker=tracker, chord_first=chord)
    S = np.array(states)
    assert np.max(np.abs(S[:, 0] ** 2 + S[:, 1] ** 2 - 1)) < 1e-10
    # consecutive tangents turn by at most arccos(MIN_COS) = theta: on the unit circle the
    # chord between the points is then at most 2 sin(theta / 2), and the limit binds
    chords = np.linalg.norm(np.diff(S, axis=0), axis=1)
    limit = 2 * math.sin(math.acos(engine.MIN_COS) / 2)
    assert np.max(chords) <= limit + 1e-12 and np.max(chords) > 0.5 * limit
    folds = [ev for ev in tracker.special if ev[0] == "fold"]
    assert len(folds) >= 2
    assert abs(abs(folds[0][1]) - 1) < 1e-12 and abs(abs(folds[1][1]) - 1) < 1e-12
    assert folds[0][1] * folds[1][1] < 0           # one fold at lam = +1, the other at -1
    # once round, the run passes through its first point in the same direction: it ends
    # there (a closed curve is followed once), having turned a full circle
    assert end.startswith("the curve closes on itself") and len(folds) == 2
    angles = np.unwrap(np.arctan2(S[:, 1], S[:, 0]))
    assert abs(abs(angles[-1] - angles[0]) - 2 * math.pi) < 0.5


def test_a_step_out_of_the_box_lands_on_the_bound():
    system = Circle()
    X = np.array([1.0, 0.0])
    F, DF, Fb = system.evaluate(X[:1], X[1], dparam=True)
    t = engine.tangent(DF, Fb, np.array([0.0, 1.0]))
    pts, states, end = engine.run(system, Run(), X, t, [-0.5], [0.5], h=0.07, h_max=0.2,
                                  max_points=100)
    assert end == "reached lam = 0.5"
    assert states[-1][1] == 0.5
    assert states[-1][0] == pytest.approx(math.sqrt(0.75), abs=1e-12)


def test_the_start_on_a_bound_leaving_the_box_ends_at_once():
    system = Circle()
    X = np.array([math.sqrt(0.75), 0.5])
    F, DF, Fb = system.evaluate(X[:1], X[1], dparam=True)
    t = engine.tangent(DF, Fb, np.array([0.0, 1.0]))
    pts, states, end = engine.run(system, Run(), X, t, [-0.5], [0.5], h=0.07, h_max=0.2,
                                  max_points=100)
    assert len(pts) == 1 and end == "reached lam = 0.5"
