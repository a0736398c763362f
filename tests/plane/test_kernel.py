"""The one attractor classifier (:mod:`symvi.simulations.classifier`, the planes') on
the paper's examples: period-k orbits against direct simulation and the orbits'
multipliers, the circle born at the NS point, the torus doubling, chaos, stopped runs;
follow mode and determinism."""
import math

import numpy as np
import pytest

import symvi
from symvi.flow import compiled as cf
from symvi.orbits import admissible_orbits
from symvi.simulations.classifier import ATTRACTORS, FIELDS, Classified, label
from symvi.simulations.classifier import classify_runs as classify
from symvi.simulations import simulation
from tests.zoo import PAPER_EX1, PAPER_EX2

KEEP, TRANSIENT = 2000, 2000


def _one(model, omega, n_keep=KEEP, transient=TRANSIENT, y0=None):
    if y0 is None:
        y0 = simulation.start_point(model, omega)[0]
    return classify(cf.constants(model, omega)[None], np.array(y0, dtype=float)[None],
                    n_keep, transient)


def _bound(J):
    """log of the condition number of the real basis (Re q, Im q) of J's leading
    complex eigenvector: the finite-time Lyapunov mean over n steps is within that / n
    of log |multiplier| (|DP^n v| / |v| = |multiplier|^n |E a_n| / |E a_0|, |a_n| = |a_0|)."""
    ev, V = np.linalg.eig(J)
    q = V[:, np.argmax(np.abs(ev))]
    s = np.linalg.svd(np.column_stack([q.real, q.imag]), compute_uv=False)
    return math.log(s[0] / s[1])


def test_period1_lyapunov():
    """omega = 0.72 (example 1, below the NS point): period-1, one impact per period;
    the Lyapunov exponent is log |largest multiplier| of the period-1 orbit within the
    finite-time bound (7e-7 at 2e5 impacts), rotation undefined (q = 1).  (Paper's
    0.70 lies in a flip window, 0.698 - 0.713, where the period-1 orbit has a
    multiplier -1.086: the attractor there is period-2, see below.)"""
    n = 200_000
    r = _one(PAPER_EX1, 0.72, n_keep=n)
    assert r.labels()[0] == "period-1" and r.impacts[0] == 1 and r.period[0] == 1
    assert abs(r.impacts_per_period[0] - 1) < 1e-9
    assert np.isnan(r.rotation[0])
    orbit = admissible_orbits(PAPER_EX1, 0.72)[0]
    want = math.log(max(abs(complex(z)) for z in orbit.multipliers))
    assert np.allclose(r.y_end[0], orbit.y, atol=1e-12)
    bound = _bound(cf.jacobian_tangent(cf.constants(PAPER_EX1, 0.72), r.y_end[0])) / n
    assert bound < 1e-6
    assert abs(r.lyapunov[0] - want) <= bound + 1e-10


def test_period2_against_simulation():
    """omega = 0.70 (example 1, flip window): period-2, two impacts; the section points
    repeat every 2 impacts in a direct simulation; lyapunov = log |largest multiplier of
    P^2| / 2.  Example 2 at 0.68: 4 impacts in 2 forcing periods (q != k)."""
    r = _one(PAPER_EX1, 0.70)
    assert r.labels()[0] == "period-2" and r.impacts[0] == 2 and r.period[0] == 2
    assert abs(r.impacts_per_period[0] - 1) < 1e-9 and np.isnan(r.rotation[0])
    c = cf.constants(PAPER_EX1, 0.70)
    y1 = r.y_end[0]
    J2 = cf.jacobian_tangent(c, cf.step(c, y1)[2]) @ cf.jacobian_tangent(c, y1)
    want = 0.5 * math.log(np.abs(np.linalg.eigvals(J2)).max())
    assert abs(r.lyapunov[0] - want) < 1e-3

    r = _one(PAPER_EX2, 0.68)
    assert r.labels()[0] == "period-2" and r.impacts[0] == 4 and r.period[0] == 2
    assert abs(r.impacts_per_period[0] - 2) < 1e-9
    sim = simulation.simulate(PAPER_EX2, 0.68, simulation.start_point(PAPER_EX2, 0.68)[0],
                              n_impacts=12, transient=KEEP + TRANSIENT - 12)
    sec, t = np.array(sim.section), np.array(sim.t)
    gaps = [np.abs(sec[q:] - sec[:-q]).max() for q in range(1, 5)]
    assert min(gaps[:3]) > 0.1 and gaps[3] < 1e-9
    assert np.allclose((t[4:] - t[:-4]) * 0.68 / (2 * math.pi), 2, atol=1e-9)
    assert np.array_equal(sec[-1], r.y_end[0])       # the same run, bit for bit


def test_circle_past_ns():
    """omega = 0.7369, just past the NS point (paper, Sec. 4: 0.7368): an invariant
    circle still growing from the start near the fixed point (|multiplier| = 1.00005);
    its rotation is the argument of the period-1 orbit's critical multipliers / 2 pi
    within 1e-3, lyapunov ~ 0."""
    r = _one(PAPER_EX1, 0.7369)
    assert r.labels()[0] == "circle"
    lam = max(admissible_orbits(PAPER_EX1, 0.7369)[0].multipliers, key=abs)
    assert abs(r.rotation[0] - abs(np.angle(complex(lam))) / (2 * math.pi)) < 1e-3
    assert abs(r.lyapunov[0]) < 1e-3 and abs(r.impacts_per_period[0] - 1) < 1e-6


@pytest.mark.parametrize("omega, name", [(0.743, "circle"), (0.744, "doubled-torus")])
def test_torus_doubling(omega, name):
    """Paper, Sec. 4: a torus doubling at omega = 0.744; the circle at 0.743 becomes a
    closed curve winding twice at 0.744."""
    r = _one(PAPER_EX1, omega)
    assert r.labels()[0] == name
    assert abs(r.lyapunov[0]) < 1e-3 and 0.3 < r.rotation[0] < 0.4


def test_chaos():
    """omega = 0.76 (example 1): chaotic over the first 4000 impacts, lyapunov ~ 0.03 per
    impact (a transient: after ~4e4 impacts the run settles on a circle)."""
    r = _one(PAPER_EX1, 0.76)
    assert r.labels()[0] == "chaos"
    assert 0.02 < r.lyapunov[0] < 0.045 and 0 <= r.rotation[0] <= 0.5
    assert r.max_velocity[0] > 0


def test_no_impact():
    """b = 50: the first impacts lose energy until the mass no longer reaches the stop."""
    model = symvi.Model.luo_xie(mu_m=2, mu_k=5, f2=0, b=50, r=0.8)
    r = _one(model, 0.76, y0=[-1.0, 0.0, 0.0, 0.0])
    assert r.labels()[0] == "no-impact" and r.stop[0] == cf.STOP_NO_IMPACT
    assert r.period[0] == 0 and r.impacts[0] == 0
    assert np.isnan(r.lyapunov[0]) and np.isnan(r.rotation[0])
    assert np.isnan(r.max_velocity[0])                   # stopped during the transient
    assert np.all(np.isfinite(r.y_end[0]))               # the last section point reached


def _row_inputs():
    """Two rows of three points each: a stopped point in the first row (its successor
    starts from its own Y0), bounded attractors otherwise."""
    far = symvi.Model.luo_xie(mu_m=2, mu_k=5, f2=0, b=50, r=0.8)
    pts = [(PAPER_EX1, 0.7369), (far, 0.76), (PAPER_EX1, 0.743), (PAPER_EX1, 0.72), (PAPER_EX1, 0.744), (PAPER_EX1, 0.76)]
    C = np.array([cf.constants(m, w) for m, w in pts])
    Y0 = np.array([[-1.0, 0, 0, 0] if m is far else simulation.start_point(m, w)[0]
                   for m, w in pts])
    return C, Y0


def _same(a, b):
    for f in (*FIELDS, "stop", "y_end"):
        x, y = getattr(a, f), getattr(b, f)
        assert x.dtype == y.dtype and x.shape == y.shape, f
        assert np.array_equal(x.view(np.uint8), y.view(np.uint8)), f      # bit for bit


def _concat(parts, followed=None):
    f = np.zeros(sum(len(p.code) for p in parts), bool) if followed is None else followed
    return Classified(*(np.concatenate([getattr(p, f) for p in parts])
                        for f in (*FIELDS, "stop", "y_end")), np.asarray(f, bool))


def test_follow_equals_serial_emulation():
    """follow=True: within a row a point starts from the previous point's y_end when that
    run reached a bounded attractor, else from its own Y0; rows start from Y0."""
    C, Y0 = _row_inputs()
    got = classify(C, Y0, 500, 500, follow=True, row_len=3)
    parts, followed = [], []
    for i in range(len(C)):
        y = Y0[i]
        followed.append(bool(i % 3) and ATTRACTORS[parts[-1].code[0]] in (
            "period", "circle", "doubled-torus", "chaos"))
        if followed[-1]:
            y = parts[-1].y_end[0]
        parts.append(classify(C[i:i + 1], y[None], 500, 500))
    _same(got, _concat(parts))
    assert list(got.followed) == followed           # the kernel reports whom it followed
    assert got.labels()[1] == "no-impact"
    # the third point followed nobody, the fifth and sixth followed their left neighbour
    assert not np.array_equal(got.y_end, classify(C, Y0, 500, 500).y_end)


def test_deterministic_and_batch_independent():
    """Two calls give the same bits; a batch equals its points classified one by one."""
    C, Y0 = _row_inputs()
    a = classify(C, Y0, 500, 500)
    _same(a, classify(C, Y0, 500, 500))
    _same(a, _concat([classify(C[i:i + 1], Y0[i:i + 1], 500, 500) for i in range(len(C))]))
    assert a.code.dtype == np.int8 and a.period.dtype == np.int32 and a.stop.dtype == np.int8


def test_labels():
    assert label(0, 3) == "period-3" and label(1, 0) == "circle"
    assert [label(k, 0) for k in range(1, 8)] == list(ATTRACTORS[1:])
    C, Y0 = _row_inputs()
    r = classify(C[:2], Y0[:2], 500, 500)
    assert list(r.labels()) == [label(c, k) for c, k in zip(r.code, r.period)]


def test_bad_input():
    C, Y0 = _row_inputs()
    with pytest.raises(symvi.ParameterError):
        classify(C, Y0[:2], 500, 500)
    with pytest.raises(symvi.ParameterError):
        classify(C, Y0, 3, 500)


@pytest.mark.parametrize("omega,kind,want,transient", [
    (0.72, "period-1", "period-1", TRANSIENT), (0.7369, "circle", "invariant circle", TRANSIENT),
    (0.744, "doubled-torus", "doubled torus", 20_000)])
def test_agrees_with_the_python_diagnostics(omega, kind, want, transient):
    """The compiled classifier against :func:`symvi.diagnostics.classify` (QR Lyapunov
    exponents from the generated Jacobian, Otsu sheet count): same kind, same largest
    exponent to 2e-3 where both compute it, same rotation number on the circle.  At
    0.744 the doubling is still opening after 2000 impacts: the polygon test of the
    kernel sees the two strands already, the Otsu count only after ~2e4."""
    from symvi.simulations.diagnostics import classify as py_classify
    r = _one(PAPER_EX1, omega, transient=transient)
    sim = simulation.simulate(PAPER_EX1, omega, n_impacts=KEEP, transient=transient)
    py = py_classify(sim, max_period=64, lyap_points=KEEP)
    assert r.labels()[0] == kind and py.kind == want
    if py.lyapunov is not None:
        assert abs(py.lyapunov.largest - r.lyapunov[0]) < 2e-3
    if py.rotation is not None:
        assert abs(py.rotation - r.rotation[0]) < 1e-4
