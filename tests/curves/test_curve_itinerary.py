"""Two-parameter curves of orbits with several constraints (issue 25, item 4): the NS
curve of the 3-mass chain's two-stop orbit in (omega, stop[2].gap), its gradient from the
exact jets of flights between the two stops' sections."""
import numpy as np
import pytest

from symvi.continuation import continue_orbits
from symvi.curves import continue_curve
from tests.continuation.test_itinerary_normal_forms import chain


@pytest.fixture(scope="module")
def ns_curve():
    m = chain(0.6, -0.3)
    brs = continue_orbits(m, "omega", 1.0, 2.0, start_omega=1.5)
    sp = next(s for b in brs for s in b.special if s.kind == "ns")
    return m, sp, continue_curve(m, "ns", ("omega", "stop[2].gap"), sp, max_points=25)


def test_ns_curve_points_have_a_pair_on_the_unit_circle(ns_curve):
    m, sp, c = ns_curve
    assert len(c.points) > 20 and c.as_dict()["signature"] == sp.orbit.signature_names
    gaps = [pt.params["stop[2].gap"] for pt in c.points]
    assert max(gaps) - min(gaps) > 1e-3              # the curve moves in the second gap
    for pt in c.points:
        mu = np.array(pt.orbit.multipliers)
        pair = [z for z in mu if abs(z.imag) > 1e-6]
        assert min(abs(abs(z) - 1) for z in pair) < 1e-9


def test_ns_curve_point_is_the_branch_s_ns_point(ns_curve):
    """Independent check: at a curve point's gap, a branch in omega from the curve's orbit
    locates its NS point at the curve's omega."""
    m, sp, c = ns_curve
    pt = c.points[-1]
    g, w = pt.params["stop[2].gap"], pt.params["omega"]
    at = m.with_(**{"stop[2].gap": g})
    brs = continue_orbits(at, "omega", w - 0.02, w + 0.02, start_omega=w + 0.01)
    ns = [s for b in brs for s in b.special if s.kind == "ns"]
    assert ns and min(abs(s.value - w) for s in ns) < 1e-8
