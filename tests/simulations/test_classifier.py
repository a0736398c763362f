"""The one classifier (:mod:`symvi.simulations.classifier`) just past the Neimark-Sacker
point of example 1, where the plane and ``simulate --classify`` used to disagree."""
import math
import warnings

import numpy as np
import pytest

from symvi.flow import compiled as cf
from symvi.orbits import admissible_orbits
from symvi.simulations import classifier as cl
from symvi.simulations import diagnostics as dg
from symvi.simulations import simulation
from tests.conftest import EX1
from tests.zoo import PAPER_EX1

OMEGA = 0.738     # example 1 (b = 1.5, r = 0.8), omega_c ~ 0.7369 (paper, Sec. 4: 0.7368)


def _runs(n_keep, transient):
    y0 = simulation.start_point(PAPER_EX1, OMEGA)[0]
    return cl.classify_runs(cf.constants(PAPER_EX1, OMEGA)[None], np.array(y0)[None],
                            n_keep, transient)


@pytest.mark.parametrize("n_keep, transient", [(2000, 0), (2000, 2000), (5000, 0)])
def test_circle_past_ns_by_both_callers(n_keep, transient):
    """omega = 0.738: an invariant circle (evidence: test_long_run_settles_on_a_circle).
    From y* + 1e-4 the run spirals out of the unstable focus (|multiplier| = 1.00285)
    for ~2500 impacts at the exponent log 1.00285 = 2.85e-3 > 0: the old rule called
    that chaos (plane) or, still settling, a doubled torus (simulate --classify).
    Both callers now say circle, whether the record holds the spiral, the settling or
    both."""
    r = _runs(n_keep, transient)
    assert r.labels()[0] == "circle"
    sim = simulation.simulate(EX1, OMEGA, n_impacts=n_keep, transient=transient)
    c = dg.classify(sim)
    assert c.kind == "invariant circle" and c.label == "circle" and c.branches == 1
    # on the circle, not the spiral: rotation_number over the whole record of 5000 from
    # y* gives 0.261 (the spiral's angles about a centroid off the focus)
    assert abs(c.rotation - 0.3963) < 1e-3
    assert abs(c.rotation - r.rotation[0]) < 1e-9       # the same rule on the same points


@pytest.mark.slow
def test_long_run_settles_on_a_circle():
    """The evidence: 10^6 impacts kept after 10^5 dropped (3.7 s).  The largest exponent
    is 1.7e-8 (a chaotic set has > 1e-3, the spiral out of the focus 2.85e-3), its
    means over 100 blocks of 10^4 impacts within 6e-5 of 0; the points lie on one
    closed curve (loop ratio 1.000002 over the last 2e4, < 1.3), rotation 0.39635
    (arg(multiplier) / 2 pi = 0.39543 at the focus); the distance to the focus stays in
    [0.197, 0.260], its mean over the first and the last 10^5 kept impacts the same to
    1.2e-6 (it grew from 3e-4 to 0.22 over the first 3000 impacts): a settled invariant
    circle, not a transient, not chaos."""
    n, tr = 1_000_000, 100_000
    r = _runs(n, tr)
    assert r.labels()[0] == "circle" and r.stop[0] == cf.COMPLETED
    assert abs(r.lyapunov[0]) < 1e-6
    lam = max(admissible_orbits(PAPER_EX1, OMEGA)[0].multipliers, key=abs)
    assert abs(complex(lam)) > 1                       # the focus repels: no stable y*
    assert abs(r.rotation[0] - abs(np.angle(complex(lam))) / (2 * math.pi)) < 2e-3
    y0 = simulation.start_point(PAPER_EX1, OMEGA)[0]
    ys = np.array(simulation.fixed_point(PAPER_EX1, OMEGA))
    _, sec, _, _, _ = cf.run(cf.constants(PAPER_EX1, OMEGA), y0, n, tr)
    d = sec - ys
    d[:, -1] = (d[:, -1] + math.pi) % (2 * math.pi) - math.pi
    rad = np.linalg.norm(d, axis=1)
    assert abs(rad[:100_000].mean() / rad[-100_000:].mean() - 1) < 1e-5
    assert 0.15 < rad.min() and rad.max() < 0.3        # away from y*, bounded


def test_one_vocabulary():
    """simulate's spelling and the plane's label name the same codes."""
    assert len(cl.KINDS) == len(cl.ATTRACTORS)
    assert [cl.kind(c, 3) for c in range(8)][1:3] == ["invariant circle", "doubled torus"]
    assert cl.kind(cl.PERIOD, 3) == cl.label(cl.PERIOD, 3) == "period-3"
    assert all(cl.kind(c, 0) == cl.label(c, 0) for c in range(3, 8))


def test_period_detector_is_shared():
    """diagnostics.period_of is the classifier's detector (q impacts)."""
    base = np.array([[-1.0, 0.1, 0.2, 0.3], [-1.2, 0.0, 0.1, 6.2], [-0.9, 0.3, 0.0, 3.0]])
    sec = np.tile(base, (30, 1))
    assert dg.period_of(sec) == cl.period_of(sec) == 3
    t = np.arange(1, len(sec) + 1) * 2 * math.pi / 0.5      # one impact a forcing period
    assert cl.classify_section(sec, t, 0.5, np.zeros(0))[:3] == (cl.PERIOD, 3, 3)


def test_old_plane_kernel_path_warns():
    from symvi.plane import kernel
    with warnings.catch_warnings(record=True) as w:
        warnings.simplefilter("always")
        f = kernel.classify
    assert f is cl.classify_runs
    assert any(issubclass(x.category, DeprecationWarning)
               and "symvi.simulations.classifier" in str(x.message) for x in w)
