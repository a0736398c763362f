"""Neimark–Sacker points of the paper's examples and of a set of our own, (H1)–(H3), events.

Reference values marked "chain B" come from ``symvi.mpcheck`` chain B: Newton
on the numeric map P and finite differences of P at 80 digits, with no
derivation or generated code (``python -m symvi hopf ... --digits 50`` prints
them; ``test_mpcheck.py`` re-runs that chain).
"""
import numpy as np
import pytest

from symvi import Params, period1_orbits
from symvi.paper.hopf import hopf_points   # the paper's view: eq. (60)'s f1 too
from symvi.errors import ParameterError, SingularCaseError

EX1, EX2 = Params(2, 5, 0, 1.5, 0.8), Params(4, 2, 0, 1.8, 0.8)
OWN = Params(1.5, 3.0, 0.3, 0.9, 0.7)     # f2 != 0: the pair goes out and comes back in

# chain B, 50 digits (see module docstring); float64 must agree to the stated tolerance
REF = {
    "ex1": (0.73687692209059288146931069861462348177282038333809,
            2.3555388215687949927294703397754617651891957453438,
            -0.097200709117769724249893935548912318349565909956412),
    "ex2": (0.49051951702623259894172421615887333693475333432735,
            2.5555571472517326992847291520492826975796918429011,
            -0.020062248269107043973086507638367764208423604963124),
    "own1": (0.71759189291177360436800665792553862996847969889034,
             4.6020593858993245082244929536209357187702547571566,
             -0.52986663689749615284227489625271510449654052425609),
    "own2": (0.75545201427534108779144205841492648706214619565192,
             -1.4703100559980248180635923385078625310376989850708,
             0.00051304246945523199293486230667801314936698124086371),
}


@pytest.fixture(scope="module")
def ex1():
    return hopf_points(EX1, 0.70, 0.76)


@pytest.fixture(scope="module")
def ex2():
    return hopf_points(EX2, 0.44, 0.52)


@pytest.fixture(scope="module")
def own():
    return hopf_points(OWN, 0.70, 0.78)


def _check(pt, ref, rtol_l1=1e-9):
    wc, dmod, l1 = ref
    assert abs(pt.omega_c - wc) < 1e-12
    assert pt.dmod_domega == pytest.approx(dmod, rel=1e-9)
    assert pt.l1 == pytest.approx(l1, rel=rtol_l1)
    assert pt.f1_wan == pytest.approx(-pt.l1 / 4, rel=1e-12)
    assert abs(abs(pt.multiplier) - 1) < 1e-12


def test_example1(ex1):
    """Paper, Sec. 4, example 1: v_c = 0.7368, d|lambda|/dv = 3.0701, f1(0) = 1.361, supercritical.

    v_c and the kind are reproduced.  d|lambda|/dv = 2.35554 here, from eqs. (A1)–(A3),
    from |lambda1| along the branch, and from chain B; f1(0) depends on the eigenvector
    normalisation (the paper does not state it) and eq. (60) as printed is wrong, so
    only its sign is comparable: f1 > 0 (attracting) in every form.
    """
    assert len(ex1.points) == 1
    pt = ex1.points[0]
    _check(pt, REF["ex1"])
    assert round(pt.omega_c, 4) == 0.7369 and abs(pt.omega_c - 0.7368) < 1e-4
    assert pt.branch == "+" and pt.h1 and pt.h2 and pt.h3
    assert pt.kind == "supercritical" and pt.f1_paper > 0 and pt.f1_wan > 0
    assert pt.circle.side == 1 and pt.circle.stable
    # the paper: on [0.7219, 0.7368) all multipliers inside; below, a flip at 0.71332
    kinds = [(e.kind, e.branch) for e in ex1.events]
    assert kinds == [("multiplier-1", "+")]
    assert 0.70 < ex1.events[0].omega < 0.7219


def test_example2(ex2):
    """Paper, Sec. 4, example 2: v_c = 0.4906, d|lambda|/dv = 0.641, f1(0) = 1.096, supercritical.

    v_c and the kind are reproduced; d|lambda|/dv = 2.55556 here (three independent
    ways), not 0.641."""
    assert len(ex2.points) == 1
    pt = ex2.points[0]
    _check(pt, REF["ex2"], rtol_l1=1e-8)
    assert abs(pt.omega_c - 0.4906) < 1e-4
    assert pt.kind == "supercritical" and pt.h1 and pt.h2 and pt.h3
    # the + branch starts grazing below omega = 0.45767 (the paper scans from 0.458)
    ev = [e for e in ex2.events if e.kind == "becomes-admissible"]
    assert len(ev) == 1 and 0.457 < ev[0].omega < 0.458 and "grazing" in ev[0].detail


def test_own_two_crossings(own):
    """Our own set (f2 = 0.3): the pair leaves the unit circle at 0.71759 (supercritical)
    and comes back at 0.75545, where (H3) fails (d|lambda|/dv < 0) and l1 > 0."""
    assert len(own.points) == 2
    a, b = own.points
    _check(a, REF["own1"])
    _check(b, REF["own2"], rtol_l1=1e-8)
    assert a.h3 and a.kind == "supercritical" and a.circle.side == 1
    assert not b.h3 and b.kind == "subcritical" and b.circle.side == 1 and not b.circle.stable


@pytest.mark.parametrize("which", ["ex1", "ex2", "own"])
def test_crossings_bracketed_directly(which, request):
    """Each omega_c is within 2e-12 of a sign change of |lambda1| - 1 (plain orbit calls)."""
    res = request.getfixturevalue(which)
    for pt in res.points:
        side = []
        for w in (pt.omega_c - 2e-12, pt.omega_c + 2e-12):
            o = {x.branch: x for x in period1_orbits(res.params, w)}[pt.branch]
            z = min((complex(x) for x in o.multipliers), key=lambda x: abs(x - pt.multiplier))
            side.append(abs(z) > 1)
        assert side[0] != side[1]
        assert side[1] == (pt.dmod_domega > 0)


@pytest.mark.parametrize("which", ["ex1", "ex2", "own"])
def test_two_dmod_agree(which, request):
    """(H3) two ways: F11 by eqs. (A1)–(A3) and |lambda1| differentiated along the branch."""
    for pt in request.getfixturevalue(which).points:
        assert pt.dmod_domega_branch == pytest.approx(pt.dmod_domega, rel=1e-8)


@pytest.mark.slow
def test_dense_scan_finds_nothing_more(own):
    """A brute-force uniform scan (4001 samples) sees exactly the crossings hopf_points found."""
    ws = np.linspace(0.70, 0.78, 4001)
    prev, found = None, []
    for w in ws:
        o = {x.branch: x for x in period1_orbits(OWN, w)}.get("+")
        m = max(abs(complex(z)) for z in o.multipliers if abs(complex(z).imag) > 1e-9)
        if prev is not None and (prev > 1) != (m > 1):
            found.append(w)
        prev = m
    assert len(found) == len(own.points)
    for w, pt in zip(found, own.points):
        assert abs(w - pt.omega_c) < 0.08 / 4000


def test_json_shape(ex1):
    d = ex1.as_dict()
    assert set(d) >= {"params", "points", "events"}
    p = d["points"][0]
    need = {"omega_c", "multiplier", "theta_over_2pi", "dmod_domega", "dmod_domega_branch", "l1",
            "f1_paper", "f1_wan", "kind", "h1", "h2", "nearest_resonance", "orbit", "circle"}
    assert need <= set(p)
    assert p["kind"] in ("supercritical", "subcritical")
    assert p["circle"]["half_width_coefficients"]["x20"] > 0
    import json
    json.dumps(d, allow_nan=False)


def test_circle_api(ex1):
    """The object the simulation side calls: point.circle.half_widths(mu)."""
    c = ex1.points[0].circle
    hw = c.half_widths(1e-4)
    assert hw.shape == (4,) and np.all(hw > 0)
    assert hw == pytest.approx(2 * c.radius(1e-4) * np.array(c.q_abs))
    with pytest.raises(ParameterError, match="mu"):
        c.half_widths(-1e-4)


def test_singular_frequency_reported():
    """omega_1 / 2 = 0.44024 and omega_2 / 4 = 0.44894 lie in [0.42, 0.46] (example 1):
    eq. (15) is singular there; the scan reports both and goes on around them.  The
    crossing it finds has another multiplier outside the circle: (H1) is False."""
    res = hopf_points(EX1, 0.42, 0.46)
    ev = [e.omega for e in res.events if e.kind == "singular"]
    assert ev == pytest.approx([0.8804857344718374 / 2, 1.795757464523422 / 4], abs=1e-12)
    assert len(res.points) == 1 and not res.points[0].h1


@pytest.mark.parametrize("a,b,word", [(0.76, 0.70, "omega_max"), (float("nan"), 0.7, "omega_min"),
                                      (-1, 0.7, "omega_min"), (0.7, float("inf"), "omega_max"),
                                      ("x", 0.7, "omega_min")])
def test_bad_interval(a, b, word):
    with pytest.raises(ParameterError, match=word):
        hopf_points(EX1, a, b)


def test_natural_frequency_at_an_end_refused():
    """omega_1 = 0.88048573 as an end is refused (inside, the scan is cut there instead)."""
    with pytest.raises(SingularCaseError, match="omega_1"):
        hopf_points(EX1, 0.8, 0.8804857344718374)


def test_crossing_on_a_sample_of_the_scan_is_located():
    """A crossing on a sample of the initial grid lies at the end of a bracket, where the
    bialternate product is zero to rounding and may keep its sign across the bracket: it
    is still found, once.  The inputs are example 1's Chenciner point as symvi's NS curve
    in (omega, r) locates it (tests/curves): the interval is centred on its omega."""
    r, w = 0.2761921526561491, 0.7852013525248023
    res = hopf_points(Params(2, 5, 0, 1.5, r), w - 2e-3, w + 2e-3)
    assert len(res.points) == 1
    assert abs(res.points[0].omega_c - w) < 1e-9
    assert abs(abs(res.points[0].multiplier) - 1) < 1e-12


def test_flip_events_carry_the_period_doubling_coefficient(ex1):
    """Located by the continuation's locator, with its coefficient c (||q|| = 1, <p,q> = 1):
    the paper's flip at 0.71332 is supercritical (c > 0) and has a multiplier -1."""
    (e,) = [e for e in ex1.events if e.kind == "multiplier-1"]
    assert e.coefficients["c"] > 0 and "supercritical" in e.detail
    assert abs(e.coefficients["multiplier"] + 1) < 1e-9
    assert e.as_dict()["coefficients"]["c"] == e.coefficients["c"]
