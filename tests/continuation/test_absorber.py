"""The 2-DOF impact Duffing absorber of PWS-DDE-cont's demo (issue 28): a primary mass
with a small absorber mass (mu = 0.05) on a cubic spring, impacts between the two with
the two-body law at x2 - x1 = 1 and x1 - x2 = 1 (``docs/gallery/absorber.toml``).

Its symmetric 1-2 orbit at omega = 1.5 (one impact on each side per forcing period) is
continued over omega in [1, 5]; the special points are checked against things computed
here without symvi's shooting system:

* the model file is the demo's equations and impact law: the orbit's point, integrated
  with scipy's DOP853 on the demo's own right-hand side and two-body law, comes back to
  itself after one period (and the grazing orbit touches |x2 - x1| = 1 without impact);
* det DP = r^4 exp(-tr(M^-1 C) T) along every branch (the cubic springs are conservative);
* the stable stretches are the attractors of brute-force sweeps, the unstable ones not;
* the fold at omega = 3.159 is a jump (runs past it end with no impact);
* the symmetry-breaking pitchfork is supercritical: below it runs settle on the switched
  branch's asymmetric orbit, whose asymmetry grows as sqrt(distance);
* the supercritical NS point's l1 predicts the simulated circle; the subcritical one's
  predicts the unstable circle that separates what returns to the orbit from what leaves.

The regression values of the special points (``SPECIAL``) were computed by this branch;
the checks above confirm each independently.  PWS-DDE-cont's demo publishes no numbers
(its script draws the branch only), so none is compared here.
"""
import math
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import symvi
from symvi.continuation import continue_orbits
from symvi.orbits.periodic import detect_period, periodic_orbit

MODEL = symvi.load_model(Path(__file__).resolve().parents[2] / "docs/gallery/absorber.toml")
#: the demo's parameters
ZETA, XI, PHI, MU, ETA1, ETA2, R = 0.02, 0.127, 0.952, 0.05, 0.1, 0.1, 0.9
#: the special points of the 1-2 branch from omega = 1.5, as this test's branch locates
#: them (kind, omega); each is confirmed by a check below against simulation or scipy
SPECIAL = [("fold", 1.2989631938), ("symmetry-breaking", 1.4390800002),
           ("grazing", 1.6247087657), ("ns", 1.9765518613), ("ns", 2.0949537364),
           ("fold", 3.1593133866)]


@pytest.fixture(scope="module")
def branches():
    """(down, up, asymmetric): the 1-2 orbit at omega = 1.5 continued down (it turns at a
    fold and comes back), up (to a fold and back down to grazing), and the asymmetric
    branch switched at the symmetry-breaking pitchfork."""
    run = symvi.simulate(MODEL, 1.5, n_impacts=40, transient=1000)
    assert detect_period(run) == (1, 2)
    down, up, asym = continue_orbits(MODEL, "omega", 1.0, 5.0, simulation=run, switch=True)
    return down, up, asym


def special(brs, kind, near):
    """The special point of that kind within 1e-3 of ``near`` (the first of a grazing's
    two events: both impacts of the symmetric orbit graze at once)."""
    return [s for b in brs for s in b.special if s.kind == kind and abs(s.value - near) < 1e-3][0]


def orbit_at(branch, w):
    """The orbit at omega = w on the branch's first leg (up to its first turn), by Newton
    from the leg's nearest point."""
    v = np.asarray(branch.values)
    turn = np.flatnonzero(np.diff(np.sign(np.diff(v))) != 0)
    leg = branch.points[:turn[0] + 2] if len(turn) else branch.points
    near = min(leg, key=lambda p: abs(p.value - w))
    return periodic_orbit(MODEL, n=near.orbit.n, p=near.orbit.p, guess=near.orbit, omega=w)


def distance(run, orbit):
    """The largest distance of the run's last 2p section points from the orbit's point on
    the same stop (tau mod 2 pi)."""
    sec, hits = np.asarray(run.section), np.asarray(run.hits)
    worst = 0.0
    for y, k in zip(orbit.points, orbit.signature):
        rows = sec[hits == k][-2:]
        if not len(rows):
            return math.inf
        d = rows - np.asarray(y)
        d[:, -1] = (d[:, -1] + math.pi) % (2 * math.pi) - math.pi
        worst = max(worst, float(np.min(np.max(np.abs(d), axis=1))))
    return worst


def mirror(orbit):
    """The mirror image of an orbit under x -> -x, t -> t + pi / omega: each point on the
    other stop, every coordinate but tau negated (what distance() reads)."""
    pts = tuple((-y[0], -y[1], -y[2], (y[3] + math.pi) % (2 * math.pi)) for y in orbit.points)
    return SimpleNamespace(points=pts, signature=tuple(1 - k for k in orbit.signature))


# -- the model is the demo's -------------------------------------------------------------

def _demo_field(w, tau):
    """The demo's right-hand side (its problem file's equations, forced by sin(w t + tau))."""
    def f(t, z):
        x1, x2, v1, v2 = z
        d, dv = x1 - x2, v1 - v2
        a1 = (math.sin(w * t + tau) - 2 * ZETA * v1 - 2 * XI * MU * dv - x1 - ETA1 * x1 ** 3
              - PHI ** 2 * MU * d - ETA2 * MU * d ** 3)
        return [v1, v2, a1, 2 * XI * dv + PHI ** 2 * d + ETA2 * d ** 3]
    return f


def _state(y, stop):
    """Masses' state (x1, x2, v1, v2) of a section point (v2 - v1, x1, v1, tau) of a stop."""
    x1, v1 = y[1], y[2]
    return np.array([x1, x1 + (1.0, -1.0)[stop], v1, v1 + y[0]])


def demo_run(w, y, stop, t_end):
    """(state at t_end, [(stop, t, relative speed)] of each impact, (min, max) of x2 - x1):
    DOP853 on the demo's equations with its two-body law, vs = (v1 + mu v2)/(1 + mu),
    v+ = (1 + r) vs - r v."""
    f, z, t = _demo_field(w, y[-1]), _state(y, stop), 0.0
    hits, lo, hi = [], math.inf, -math.inf

    def upper(t, z):
        return z[1] - z[0] - 1.0

    def lower(t, z):
        return z[1] - z[0] + 1.0
    upper.terminal = lower.terminal = True
    upper.direction, lower.direction = 1, -1
    while True:
        s = solve_ivp(f, (t, t_end), z, method="DOP853", rtol=1e-13, atol=1e-13,
                      events=(upper, lower), dense_output=True)
        tt = np.linspace(t, s.t[-1], 20001)            # the extremes to 1e-7
        gap = s.sol(tt)[1] - s.sol(tt)[0]
        lo, hi = min(lo, float(gap.min())), max(hi, float(gap.max()))
        if s.status == 0:
            return s.y[:, -1], hits, (lo, hi)
        k = 0 if s.t_events[0].size else 1
        t, z = float(s.t_events[k][0]), s.y_events[k][0].copy()
        vs = (z[2] + MU * z[3]) / (1 + MU)
        z[2], z[3] = (1 + R) * vs - R * z[2], (1 + R) * vs - R * z[3]
        hits.append((k, t, abs(z[3] - z[2])))
        t += 1e-12                                     # off the guard, moving away


def test_the_model_file_is_the_demos_system():
    """M, C and K of the file are the demo's in symvi's form (its second equation times mu)."""
    assert np.allclose(MODEL.mass, np.diag([1.0, MU]), atol=1e-15)
    c, k = 2 * XI * MU, PHI ** 2 * MU
    assert np.allclose(MODEL.damping, [[2 * ZETA + c, -c], [-c, c]], atol=1e-15)
    assert np.allclose(MODEL.stiffness, [[1 + k, -k], [-k, k]], atol=1e-15)
    assert (MODEL.value("eta1"), MODEL.value("eta2")) == (ETA1, ETA2)


def test_the_orbit_at_1_5_is_a_periodic_orbit_of_the_demos_equations(branches):
    """The 1-2 orbit symvi finds at omega = 1.5, integrated by scipy on the demo's own
    equations and impact law: the impacts at symvi's times on symvi's stops, and back to
    the start after one forcing period."""
    o = periodic_orbit(MODEL, n=1, p=2, guess=branches[1].points[0].orbit, omega=1.5)
    T = 2 * math.pi / 1.5
    z, hits, _ = demo_run(1.5, o.y, o.signature[0], T + 1e-9)
    assert [h[0] for h in hits] == [o.signature[1], o.signature[0]]
    assert np.allclose([h[1] for h in hits], np.cumsum(o.times), atol=1e-10, rtol=0)
    assert np.max(np.abs(z - _state(o.y, o.signature[0]))) < 1e-7
    assert o.symmetric and o.stable
    assert abs(o.impact_velocities[0] - o.impact_velocities[1]) < 1e-12


def test_the_grazing_orbit_touches_both_stops_without_impact(branches):
    """At the located grazing the orbit's flights reach |x2 - x1| = 1 with zero relative
    speed: scipy's run of the demo from its point comes back after a period, x2 - x1
    reaching the other stop to 1e-6, and any contact it counts is a touch."""
    sp = special(branches, "grazing", 1.6247)
    assert len([s for s in branches[1].special if s.kind == "grazing"]) == 2
    o = sp.orbit
    z, hits, (lo, hi) = demo_run(sp.value, o.y, o.signature[0], 2 * math.pi / sp.value - 1e-6)
    assert all(h[2] < 1e-3 for h in hits)      # a touch (speed ~ sqrt of the overshoot)
    assert abs(lo + 1) < 1e-6 and abs(hi - 1) < 1e-6
    assert np.max(np.abs(z - _state(o.y, o.signature[0]))) < 1e-5


# -- the branches ------------------------------------------------------------------------

def test_the_special_points(branches):
    down, up, asym = branches
    got = {(s.kind, round(s.value, 6)) for s in down.special + up.special}
    assert got == {(k, round(w, 6)) for k, w in SPECIAL}        # the grazing: both impacts
    for kind, w in SPECIAL:
        assert abs(special([down, up], kind, w).value - w) < 1e-8
    assert special([up], "ns", 1.9766).coefficients["l1"] > 0       # subcritical
    assert special([up], "ns", 2.0950).coefficients["l1"] < 0       # supercritical
    # the asymmetric branch leaves the pitchfork downwards and ends at a grazing
    assert max(asym.values) <= 1.43908 + 1e-6 and min(asym.values) < 1.37


@pytest.mark.parametrize("which", [0, 1, 2])
def test_determinant_identity_along_the_branches(branches, which):
    """det DP = r^(2p) exp(-tr(M^-1 C) T): the forces' divergence is the linear part's.
    Away from grazing (V > 0.1), where the multipliers lose accuracy as 1/V."""
    tr = 2 * ZETA + 2 * XI * MU + 2 * XI
    pts = [p for p in branches[which].points if min(p.orbit.impact_velocities) > 0.1]
    assert len(pts) > 50
    for pt in pts:
        det = np.prod(pt.multipliers).real
        want = R ** (2 * pt.orbit.p) * math.exp(-tr * 2 * math.pi * pt.orbit.n / pt.value)
        assert abs(det / want - 1) < 1e-9


# -- against simulation ------------------------------------------------------------------

def sweep(ws, y0=None):
    """Runs along ws, each from the previous run's last point on stop 1 (the first from
    y0, by default the default start): [(omega, run)]."""
    out = []
    for w in ws:
        run = symvi.simulate(MODEL, w, y0=y0, n_impacts=20, transient=3000)
        out.append((w, run))
        k = np.flatnonzero(np.asarray(run.hits) == 0)
        y0 = run.section[k[-1]] if run.stop == "completed" and len(k) else None
    return out


def test_stable_stretches_are_the_sweeps_attractors(branches):
    """Sweeps down from omega = 2.35 to 1.95 and from 1.9 to 1.45 (each from the default
    start), and up from 2.4 to 3.15 (from the first run's attractor; from the default start
    the runs there settle on a motion without impacts): where the branch is stable the run sits on its
    orbit (to 1e-7); between the NS points, where it is unstable, the run is elsewhere (on
    the circle born at the supercritical one), and so it stays just below the subcritical
    one (the orbit is stable again, inside the unstable circle: hysteresis); past the upper
    fold there is no impacting orbit and the runs stop impacting."""
    up = branches[1]
    ns1, ns2 = special([up], "ns", 1.9766).value, special([up], "ns", 2.0950).value
    fold = special([up], "fold", 3.1593).value
    runs = sweep(np.arange(2.35, 1.949, -0.05)) + sweep(np.arange(1.9, 1.449, -0.05))
    first = runs[0][1]
    runs += sweep(np.arange(2.4, 3.151, 0.05), y0=first.section[np.flatnonzero(first.hits == 0)[-1]])
    on, off = 0, 0
    for w, run in runs:
        o = orbit_at(up, w)
        assert o.symmetric
        if ns1 - 0.03 < w < ns2 + 0.01:
            if ns2 < w:
                continue                          # slow convergence next to the NS point
            assert o.stable == (w < ns1) and distance(run, o) > 1e-3
            off += 1
        else:
            assert o.stable and run.stop == "completed"
            assert distance(run, o) < 1e-7, w
            on += 1
    assert on >= 25 and off == 3
    at = special([up], "fold", 3.1593).orbit
    y0 = at.points[at.signature.index(0)]             # a start on stop 1's section
    past = symvi.simulate(MODEL, fold + 0.01, y0=y0, n_impacts=5, transient=50)
    assert past.stop == "no-impact"
    before = orbit_at(up, fold - 0.01)
    run = symvi.simulate(MODEL, fold - 0.01, y0=y0, n_impacts=20, transient=3000)
    assert before.stable and distance(run, before) < 1e-7


def test_the_pitchfork_is_supercritical(branches):
    """Below the symmetry-breaking point the symmetric orbit is unstable and a run from it
    settles on the switched branch's asymmetric orbit (to 1e-7); its two impact velocities
    split as sqrt(distance) (ratio 2 for 4 times the distance, to 10 %); above it, a run
    from that asymmetric orbit returns to the symmetric one."""
    down, up, asym = branches
    sb = special([down], "symmetry-breaking", 1.4391).value
    split = []
    for dw in (0.002, 0.008):
        w = sb - dw
        sym = orbit_at(down, w)
        assert sym.symmetric and not sym.stable
        a = orbit_at(asym, w)
        assert a.stable and not a.symmetric
        y0 = np.array(sym.points[sym.signature.index(0)]) + 1e-4
        run = symvi.simulate(MODEL, w, y0=y0, n_impacts=20, transient=6000)
        assert distance(run, a) < 1e-7 or distance(run, mirror(a)) < 1e-7
        v = run.impact_velocity[-2:]
        split.append(abs(v[0] - v[1]))
        assert abs(split[-1] - abs(a.impact_velocities[0] - a.impact_velocities[1])) < 1e-7
    assert abs(split[1] / split[0] - 2) < 0.2
    w = sb + 0.005
    a = orbit_at(asym, sb - 0.002)
    run = symvi.simulate(MODEL, w, y0=a.points[a.signature.index(0)], n_impacts=20,
                         transient=6000)
    assert distance(run, orbit_at(up, w)) < 1e-7


def _ns_frame(sp):
    """(q, |q_k|) of an NS point: the critical eigenvector of its jet's Jacobian, ||q|| = 1."""
    A = sp.orbit.jet(2)[0]
    ev, V = np.linalg.eig(A)
    k = int(np.argmin(np.abs(ev - np.exp(1j * sp.coefficients["theta"]))))
    return V[:, k] / np.linalg.norm(V[:, k])


def test_the_supercritical_ns_coefficient_predicts_the_simulated_circle(branches):
    """Below omega = 2.095 (l1 < 0, the orbit unstable there) the map settles on an
    invariant circle whose half-widths are 2 rho |q_k| to leading order, rho^2 = -(d|mu|/d
    omega) d omega / l1: within 1 % at d omega = -2e-3 and -4e-3 (0.13 % and 0.22 %
    measured), from a start outside the circle and one inside it alike."""
    sp = special([branches[1]], "ns", 2.0950)
    c, q = sp.coefficients, _ns_frame(sp)
    assert c["l1"] < 0 and c["dmod_dparam"] < 0
    k0 = sp.orbit.signature.index(0)
    for dw in (-2e-3, -4e-3):
        w = sp.value + dw
        rho = math.sqrt(-c["dmod_dparam"] * dw / c["l1"])
        fixed = periodic_orbit(MODEL, n=1, p=2, guess=sp.orbit, omega=w)
        assert not fixed.stable
        for f in (1.5, 0.5):
            # the run starts on stop 1's section at the orbit's point there (the mirror of
            # points[0]) moved to z = f rho on the mirror of y* + 2 Re(z q) (from next to
            # the orbit the growth would take ~1e5 impacts); the circle is measured where q
            # lives, on the section of points[0]
            y0 = np.array(fixed.points[k0]) + 2 * f * rho * (q * [-1, -1, -1, 1]).real
            run = symvi.simulate(MODEL, w, y0=y0, n_impacts=3000, transient=30000)
            assert run.stop == "completed"
            sec = np.asarray(run.section)[np.asarray(run.hits) == fixed.signature[0]]
            sec[:, -1] = (sec[:, -1] - fixed.points[0][-1] + math.pi) % (2 * math.pi) - math.pi
            half = (sec.max(axis=0) - sec.min(axis=0)) / 2
            assert abs(np.linalg.norm(half) / np.linalg.norm(2 * rho * np.abs(q)) - 1) < 0.01


def test_the_subcritical_ns_point_has_an_unstable_circle(branches):
    """Just above omega = 1.9766 (l1 > 0) the orbit is unstable and a run from next to it
    leaves; just below it is stable inside the unstable circle of radius rho^2 = -(d|mu|/d
    omega) d omega / l1: a start at |z| = rho / 2 (y* + 2 Re(z q), mirrored onto stop 1's
    section) returns to the orbit, one at 3 rho / 2 leaves it."""
    sp = special([branches[1]], "ns", 1.9766)
    c, q = sp.coefficients, _ns_frame(sp)
    assert c["l1"] > 0 and c["dmod_dparam"] > 0
    k0 = sp.orbit.signature.index(0)
    w = sp.value + 2e-3
    fixed = periodic_orbit(MODEL, n=1, p=2, guess=sp.orbit, omega=w)
    run = symvi.simulate(MODEL, w, y0=np.array(fixed.points[k0]) + 1e-4, n_impacts=20,
                         transient=30000)
    assert not fixed.stable and distance(run, fixed) > 1e-2
    dw = -2e-3
    w = sp.value + dw
    rho = math.sqrt(-c["dmod_dparam"] * dw / c["l1"])
    fixed = periodic_orbit(MODEL, n=1, p=2, guess=sp.orbit, omega=w)
    assert fixed.stable
    for f, back in ((0.5, True), (1.5, False)):
        y0 = np.array(fixed.points[k0]) + 2 * f * rho * (q * [-1, -1, -1, 1]).real
        run = symvi.simulate(MODEL, w, y0=y0, n_impacts=20, transient=30000)
        d = distance(run, fixed)
        assert d < 1e-3 if back else d > 1e-2, (f, d)


def test_dmod_is_the_derivative_at_the_ns_point(branches):
    """d|mu|/d omega of each NS point is the derivative there (a central difference of the
    critical modulus at +- 1e-5), not the secant over the bracketing step."""
    for near in (1.9766, 2.0950):
        sp = special([branches[1]], "ns", near)
        mods = [max(abs(z) for z in periodic_orbit(MODEL, n=1, p=2, guess=sp.orbit,
                                                   omega=sp.value + s).multipliers)
                for s in (-1e-5, 1e-5)]
        assert abs(sp.coefficients["dmod_dparam"] - (mods[1] - mods[0]) / 2e-5) < 1e-6
