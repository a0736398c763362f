"""Grazing curves in two parameters (issue 27, item 1, first kind: an impact velocity -> 0).

The reference is COCO's *Recipes for Continuation*, Example 15.2 (k = 1, c = 0.1, d = 1,
e = 0.8): a forced, damped 1-DOF oscillator whose impacting period-1 orbit grazes where the
non-impacting harmonic response just reaches the stop, A_GR(omega) = d |k - omega^2 +
i c omega| (equivalently d_GR = A / |k - omega^2 + i c omega|), in closed form.
"""
import json

import numpy as np
import pytest

from symvi import Model, Stop
from symvi.continuation import continue_orbits
from symvi.curves.grazing import GrazingSystem, continue_grazing
from symvi.curves.start import curve_from_interval
from symvi.errors import ParameterError

from ..fuzz._cli import assert_bad_input, cli

K, C, D, E = 1.0, 0.1, 1.0, 0.8


def coco(amplitude=2.0, gap=D):
    return Model(mass=[1.0], stiffness=[[K]], damping=[[C]], forcing=[amplitude],
                 stops=[Stop(mass=1, gap=gap, restitution=E)])


def H(w):
    return np.abs(K - w ** 2 + 1j * C * w)


def _grazing_on_branch(model, param, a, b, **fixed):
    brs = continue_orbits(model, param, a, b, **fixed)
    return [s for br in brs for s in br.special if s.kind == "grazing"][0]


def test_the_grazing_curve_in_omega_and_amplitude_is_cocos_closed_form():
    sp = _grazing_on_branch(coco(), "forcing[1]", 2.0, 0.2, omega=1.5)
    assert sp.value == pytest.approx(D * H(1.5), rel=1e-12)
    cv = continue_grazing(coco(), ("omega", "forcing[1]"), sp,
                          bounds={"omega": (0.3, 3.0), "forcing[1]": (0.05, 10.0)})
    w, a = cv.values("omega"), cv.values("forcing[1]")
    assert len(cv) > 200 and w.min() == pytest.approx(0.3) and w.max() == pytest.approx(3.0)
    assert cv.ends == ("reached omega = 0.3", "reached omega = 3")
    # the whole curve, through the resonance at omega ~ 1, to the rounding of the solver
    assert np.max(np.abs(a - D * H(w)) / (D * H(w))) < 1e-10
    # every point: an orbit whose impact arrives with zero speed, off the stop in between
    assert all(pt.admissible for pt in cv.points)
    assert max(abs(pt.impact_velocities[0]) for pt in cv.points) < 1e-10
    assert all(pt.times[0] == pytest.approx(2 * np.pi / pt.params["omega"], rel=1e-12)
               for pt in cv.points)


def test_a_grazing_curve_in_two_model_parameters_at_fixed_omega():
    """(forcing[1], gap) at omega = 0.8: the grazing gap is A / |H(0.8)|, a straight line."""
    w = 0.8
    sp = _grazing_on_branch(coco(), "gap", 1.0, 8.0, omega=w)   # grazes at 2 / |H| = 5.42
    cv = continue_grazing(coco(), ("forcing[1]", "gap"), sp,
                          bounds={"forcing[1]": (0.5, 4.0), "gap": (0.1, 20.0)})
    a, g = cv.values("forcing[1]"), cv.values("gap")
    assert np.ptp(a) > 3 and np.max(np.abs(g - a / H(w)) / g) < 1e-10
    assert cv.fixed == {"omega": w}


def test_the_augmented_system_is_regular_at_grazing():
    """The flight time is an unknown: no 1/v pole. The Jacobian of (G, v+) in (u, a) at a
    grazing point is well conditioned, while the monodromy (time eliminated) blows up."""
    model = coco()
    sp = _grazing_on_branch(model, "forcing[1]", 2.0, 0.2, omega=1.5)
    pars = [model.parameter(n) for n in ("omega", "forcing[1]")]
    system = GrazingSystem(model.with_(**{"forcing[1]": sp.value}), 1, 1, pars, 0)
    v = np.append(sp.orbit.u, 1.5)
    F, DF, Fb = system.evaluate(v, sp.value, dparam=True)
    assert np.max(np.abs(F)) < 1e-10
    s = np.linalg.svd(DF, compute_uv=False)
    assert s[-1] / s[0] > 1e-3
    assert max(abs(z) for z in sp.orbit.multipliers) > 1e6      # the pole the curve avoids


def test_curve_from_interval_starts_at_the_branchs_grazing_point():
    cv, start = curve_from_interval(coco(), 1.0, 2.0, ("omega", "forcing[1]"), kind="grazing",
                                    bounds={"omega": (1.0, 2.5), "forcing[1]": (0.5, 6.0)})
    assert start.kind == "grazing" and "impact" in start.coefficients
    # at the model's amplitude 2, the branch in omega grazes where 2 = |H(omega)|
    assert 2.0 == pytest.approx(D * H(start.value), rel=1e-10)
    w = cv.values("omega")
    assert np.max(np.abs(cv.values("forcing[1]") - H(w)) / H(w)) < 1e-10


def test_symvi_curve_kind_grazing_json(tmp_path):
    f = tmp_path / "coco.toml"
    f.write_text("[model]\nmass = [1.0]\nstiffness = [[1.0]]\ndamping = [[0.1]]\n"
                 "forcing = [2.0]\n\n[stop]\nmass = 1\ngap = 1.0\nrestitution = 0.8\n")
    rc, out, err = cli("curve", "--model", f, "--range", "omega=1.0:2.0", "--params",
                       "omega,forcing[1]", "--kind", "grazing", "--bounds", "omega=1.0:2.5",
                       "--bounds", "forcing[1]=0.5:6", "--max-points", "100", "--json",
                       "--plot", tmp_path / "g.png")
    assert rc == 0, err
    d = json.loads(out)
    assert d["kind"] == "grazing" and d["params"] == ["omega", "forcing[1]"]
    assert d["start"]["kind"] == "grazing" and d["notes"]
    assert [s["kind"] for s in d["special"]] == ["RG"]          # at 2 omega_d = 1.9975
    p = d["points"][len(d["points"]) // 2]
    assert set(p) >= {"params", "admissible", "y", "times", "impact_velocities"}
    assert p["params"]["forcing[1]"] == pytest.approx(H(p["params"]["omega"]), rel=1e-10)
    assert (tmp_path / "g.png").read_bytes()[:4] == b"\x89PNG"


def test_grazing_curves_refuse_what_they_do_not_follow(tmp_path):
    elastic = Model(mass=[1.0], stiffness=[[1.0]], damping=[[0.1]], forcing=[2.0],
                    stops=[Stop(mass=1, gap=1.0, stiffness=50.0, damping=0.0)])
    with pytest.raises(ParameterError, match="rigid stops"):
        GrazingSystem(elastic, 1, 1, [elastic.parameter(n) for n in ("omega", "gap")], 0)
    with pytest.raises(ParameterError, match="an impact of the orbit"):
        GrazingSystem(coco(), 1, 1, [coco().parameter(n) for n in ("omega", "gap")], 1)
    assert_bad_input(cli("curve", "--mu-m", "2", "--mu-k", "5", "--f2", "0", "--b", "1.5",
                         "--r", "0.8", "--range", "omega=0.70:0.76", "--params", "omega,b",
                         "--kind", "graze"), "--kind", "grazing")
    # from the command line, naming the flag (it failed inside the rigid flow before)
    from pathlib import Path
    el = Path(__file__).resolve().parents[2] / "examples" / "contacts" / "oscillator_elastic.toml"
    assert_bad_input(cli("curve", "--model", el, "--range", "omega=0.5:4", "--params",
                         "omega,stop[1].gap", "--kind", "grazing"), "--kind", "rigid stops")


def test_a_touch_grazing_curve_of_the_papers_example_1_is_the_closed_forms():
    """The second kind: example 1's period-1 orbit at omega = 0.75 touches the stop inside
    its flight at b = 0.276. The curve in (omega, b) is followed as the 1-2 orbit with the
    touch as a zero-speed impact, reported as the 1-1 orbit; at its points the closed-form
    period-1 orbit (eqs. (10)-(18), no shooting) is the same orbit, and its own
    admissibility check finds the touch at the same time."""
    import symvi
    m = symvi.Model.luo_xie(mu_m=2, mu_k=5, f2=0, b=1.5, r=0.8)
    sp = _grazing_on_branch(m, "b", 1.5, 0.1, omega=0.75)
    assert sp.coefficients["flight"] == 1 and "impact" not in sp.coefficients
    cv = continue_grazing(m, ("omega", "b"), sp, bounds={"omega": (0.6, 0.9), "b": (0.05, 1.5)})
    d = cv.as_dict()
    assert d["grazing"] == "touch" and d["flight"] == 1 and d["orbit"] == "1-1"
    assert cv.ends == ("reached b = 0.05", "reached b = 1.5") and len(cv) > 100
    assert all(pt.admissible and len(pt.y) == 1 and len(pt.times) == 1 for pt in cv.points)
    for pt in cv.points[::50]:
        w, b = pt.params["omega"], pt.params["b"]
        assert pt.times[0] == pytest.approx(2 * np.pi / w, rel=1e-12)
        orbits = symvi.period1_orbits(m.with_(b=b), w)
        o = min(orbits, key=lambda o: np.linalg.norm(np.subtract(o.y, pt.y[0])))
        assert np.linalg.norm(np.subtract(o.y, pt.y[0])) < 1e-10
        assert not o.admissible and "grazing contact" in o.reason
        t_closed = float(o.reason.rsplit("t = ", 1)[1])
        assert t_closed == pytest.approx(pt.touch["t"], rel=1e-5)   # a double root


def test_a_touch_grazing_curve_between_two_stops_is_a_touching_orbit():
    """Two stops (examples/contacts/oscillator_two_stops.toml): the 1-2 orbit's flight 1
    touches stop 2 at omega = 1.0083. Its curve in (omega, stop[2].gap) is walked over every
    guard (the contact walk). At points of it, the reported 1-2 orbit (the split flight
    joined) solves the 1-2 shooting system, and its flight, sampled densely by the exact
    flow, comes to stop 2 with a maximum of zero at the touch time."""
    from pathlib import Path

    from scipy.optimize import minimize_scalar

    import symvi
    from symvi.orbits.periodic import Problem
    m = symvi.load_model(Path(__file__).resolve().parents[2] / "examples" / "contacts"
                         / "oscillator_two_stops.toml")
    brs = continue_orbits(m, "omega", 1.0, 3.5, start_omega=2.0, switch=True)
    sp = next(s for br in brs for s in br.special
              if s.kind == "grazing" and s.coefficients.get("stop") == 2)
    cv = continue_grazing(m, ("omega", "stop[2].gap"), sp,
                          bounds={"omega": (0.8, 3.0), "stop[2].gap": (-1.5, -0.1)})
    assert cv.as_dict()["grazing"] == "touch" and len(cv) > 50
    assert all(pt.admissible and pt.touch["stop"] == 2 for pt in cv.points)
    for pt in cv.points[::max(1, len(cv) // 5)]:
        w, g = pt.params["omega"], pt.params["stop[2].gap"]
        mg = m.with_(**{"stop[2].gap": g})
        pr = Problem(mg, 1, 2, omega=w, signature=sp.orbit.itinerary)
        u = np.concatenate([np.ravel(pt.y), pt.times])
        G = pr.evaluate(u, None, jac=False)[0]
        assert np.max(np.abs(G)) < 1e-9
        fl, (_, flow, F) = pr.flights(u, None)
        i = pt.touch["flight"] - 1
        mo = flow.motion(F, fl[i][0], fl[i][1])
        def x(t, mo=mo):
            return float(flow.to_mass(mo.state(t))[0])

        ts = np.linspace(0, pt.times[i], 4001)
        xs = np.array([x(t) for t in ts])
        # stop 2 is the lower one, at g; the flight starts on it: its interior minimum
        k = min((j for j in range(1, 4000) if xs[j] <= xs[j - 1] and xs[j] <= xs[j + 1]),
                key=lambda j: xs[j])
        r = minimize_scalar(x, bracket=(ts[k - 1], ts[k], ts[k + 1]), tol=1e-12)
        assert abs(r.fun - g) < 1e-9 and r.x == pytest.approx(pt.touch["t"], abs=1e-5)


def test_codimension_two_points_of_the_touch_curve_are_where_the_other_curves_graze():
    """Example 1's touch curve in (omega, b) carries a grazing-NS point and two
    grazing-flip points (the n-p orbit is smooth at its touch: its multipliers are
    finite). The NS curve and the flip curves, continued on their own and ended at their
    located grazing (the curve tracker's interior tangency), end at the same points."""
    import symvi
    from symvi.curves import continue_curve
    m = symvi.Model.luo_xie(mu_m=2, mu_k=5, f2=0, b=1.5, r=0.8)
    sp = _grazing_on_branch(m, "b", 1.5, 0.1, omega=0.75)
    cv = continue_grazing(m, ("omega", "b"), sp, bounds={"omega": (0.6, 0.9), "b": (0.05, 1.5)})
    kinds = [s.kind for s in cv.special]
    assert kinds == ["grazing-NS", "grazing-flip", "grazing-flip"], kinds
    ns = cv.special[0]
    assert ns.coefficients["modulus"] == pytest.approx(1.0, abs=1e-9)
    assert all(abs(s.coefficients["multiplier"] + 1) < 1e-9 for s in cv.special[1:])
    assert [s.index for s in cv.special] == sorted(s.index for s in cv.special)
    # the NS curve from example 1's NS point ends at its grazing: the same point
    ns_curve, _ = curve_from_interval(m, 0.70, 0.76, ("omega", "b"),
                                      bounds={"omega": (0.6, 0.9), "b": (0.2, 1.6)})
    [end] = [s for s in ns_curve.special if s.kind == "grazing"]
    for k in ("omega", "b"):
        assert end.params[k] == pytest.approx(ns.params[k], abs=1e-10)
    # the flip curve through a flip just above the first grazing-flip ends there
    gf = cv.special[1]
    b = gf.params["b"] + 0.01
    brs = continue_orbits(m.with_(b=b), "omega", gf.params["omega"] + 0.03,
                          gf.params["omega"] - 0.03, start_omega=gf.params["omega"])
    flip = next(s for br in brs for s in br.special if s.kind == "flip")
    fc = continue_curve(m.with_(b=b), "flip", ("omega", "b"), flip,
                        bounds={"omega": (0.6, 0.9), "b": (0.05, 1.5)})
    ends = [s for s in fc.special if s.kind == "grazing"]
    assert any(all(abs(e.params[k] - gf.params[k]) < 1e-10 for k in ("omega", "b"))
               for e in ends), [e.params for e in ends]
    d = cv.as_dict()
    assert [s["kind"] for s in d["special"]] == kinds and "multipliers" in d["points"][0]


def test_resonant_grazing_points_of_the_damped_oscillator_are_at_2_omega_d_over_m():
    """Issue 27's closed form: on the grazing curve of a damped 1-DOF oscillator with one
    rigid stop, the resonant grazing points lie at omega* = 2 omega_d / m (omega_d the
    damped natural frequency): the regular fold and flip tests w det(M -+ I) vanish there
    together (a grazing-fold and a grazing-flip point at once)."""
    sp = _grazing_on_branch(coco(), "forcing[1]", 2.0, 0.2, omega=1.5)
    cv = continue_grazing(coco(), ("omega", "forcing[1]"), sp,
                          bounds={"omega": (0.3, 3.0), "forcing[1]": (0.05, 10.0)})
    rg = [s for s in cv.special if s.kind == "RG"]
    wd = np.sqrt(K - C ** 2 / 4)
    expected = sorted(2 * wd / m for m in range(1, 7))       # all of them in [0.3, 3]
    found = sorted(s.params["omega"] for s in rg)
    assert len(found) == len(expected)
    assert np.max(np.abs(np.array(found) - expected)) < 1e-9
    assert [s.kind for s in cv.special] == ["RG"] * 6           # nothing else on this curve
    d = cv.as_dict()["special"][0]
    assert d["kind"] == "RG" and set(d["params"]) == {"omega", "forcing[1]"}
    assert {"fold_test", "flip_test"} <= set(cv.as_dict()["points"][0])


def test_a_fold_curve_that_runs_into_grazing_ends_at_the_resonant_grazing_point():
    """Issue 27: fold curves stopped 5e-7 .. 5e-5 short of grazing ("step below ...", a
    multiplier cut). The damped oscillator's fold curve of impacting orbits from omega = 1.5
    runs into grazing both ways; each end is now solved on the regular test (w det(M - I),
    smooth through zero velocity) and is the resonant grazing point 2 omega_d / m that the
    grazing curve locates on its own."""
    from symvi.curves import continue_curve
    brs = continue_orbits(coco(), "forcing[1]", 2.0, 0.2, omega=1.5)
    fold = next(s for br in brs for s in br.special if s.kind == "fold")
    cv = continue_curve(fold.orbit.model, "fold", ("omega", "forcing[1]"), fold,
                        bounds={"omega": (0.3, 3.0), "forcing[1]": (0.01, 10.0)})
    rg = [s for s in cv.special if s.kind == "RG"]
    assert len(rg) == 2 and all(e.startswith("reached grazing at the resonant grazing point")
                                for e in cv.ends), cv.ends
    assert [s.index for s in rg] == [0, len(cv) - 1]
    wd = np.sqrt(K - C ** 2 / 4)
    ws = sorted(s.params["omega"] for s in rg)
    assert ws == pytest.approx([wd, 2 * wd], abs=1e-9)
    for s in rg:
        w = s.params["omega"]
        assert s.params["forcing[1]"] == pytest.approx(D * H(w), rel=1e-9)   # on A_GR
        assert abs(s.orbit.impact_velocities[0]) < 1e-10
    assert not any(s.kind == "admissibility" for s in cv.special)


def test_the_tangency_coefficients_kappa_at_resonant_grazing():
    """kappa of b = b_graze(a) + kappa (a - a*)^2 for the fold and flip curves leaving the
    damped oscillator's resonant grazing points. kappa_fold is checked against the fold
    curve continued on its own (the ordinary test of M) and the closed form A_GR: a fit of
    A_fold(omega) - A_GR(omega) on its points near omega* (no shared code with kappa's
    Newton solves on the regular test)."""
    from symvi.curves import continue_curve
    sp = _grazing_on_branch(coco(), "forcing[1]", 2.0, 0.2, omega=1.5)
    cv = continue_grazing(coco(), ("omega", "forcing[1]"), sp,
                          bounds={"omega": (0.3, 3.0), "forcing[1]": (0.05, 10.0)})
    rg = {round(s.params["omega"], 6): s for s in cv.special if s.kind == "RG"}
    assert all({"kappa_fold", "kappa_flip"} <= set(s.coefficients) for s in rg.values())
    brs = continue_orbits(coco(), "forcing[1]", 2.0, 0.2, omega=1.5)
    fold = next(s for br in brs for s in br.special if s.kind == "fold")
    fc = continue_curve(fold.orbit.model, "fold", ("omega", "forcing[1]"), fold,
                        bounds={"omega": (0.3, 3.0), "forcing[1]": (0.01, 10.0)})
    w, a = fc.values("omega"), fc.values("forcing[1]")
    landed = [s for s in fc.special if s.kind == "RG"]
    for end in landed:
        ws = end.params["omega"]
        near = rg[round(ws, 6)]
        assert end.coefficients["kappa_fold"] == pytest.approx(near.coefficients["kappa_fold"],
                                                               rel=1e-6)
        dw = w - ws
        sel = (np.abs(dw) > 2e-4) & (np.abs(dw) < 3e-3)
        fit = np.linalg.lstsq(np.column_stack([dw[sel] ** 2, dw[sel] ** 3]),
                              a[sel] - D * H(w[sel]), rcond=None)[0][0]
        assert sel.sum() > 20
        assert fit == pytest.approx(near.coefficients["kappa_fold"], rel=2e-3)


def test_a_grazing_fold_point_of_a_three_mass_chain_is_where_its_fold_curve_ends():
    """With several degrees of freedom the fold and flip curves meet the grazing curve at
    different points (no resonant grazing): the 3-mass chain's impact grazing curve in
    (omega, gap) has a grazing-fold point, and the fold curve from the branch's fold,
    continued on its own, ends there (landed on the regular test), with the same kappa."""
    from pathlib import Path

    import symvi
    from symvi.curves import continue_curve
    ch = symvi.load_model(Path(__file__).resolve().parents[2] / "docs" / "gallery"
                          / "chain3.toml")
    brs = continue_orbits(ch, "omega", 0.6, 1.6)
    g = next(s for br in brs for s in br.special if s.kind == "grazing" and
             "impact" in s.coefficients)
    f = next(s for br in brs for s in br.special if s.kind == "fold")
    box = {"omega": (0.6, 3.0), "gap": (0.05, 3.0)}
    cv = continue_grazing(ch, ("omega", "gap"), g, bounds=box)
    [gf] = [s for s in cv.special if s.kind != "unlocated"]
    assert gf.kind == "grazing-fold" and "kappa_fold" in gf.coefficients
    fc = continue_curve(ch, "fold", ("omega", "gap"), f, bounds=box)
    [end] = [s for s in fc.special if s.kind == "grazing-fold"]
    assert fc.ends[0].startswith("reached grazing at a grazing-fold point")
    for k in ("omega", "gap"):
        assert end.params[k] == pytest.approx(gf.params[k], abs=1e-10)
    assert end.coefficients["kappa_fold"] == pytest.approx(gf.coefficients["kappa_fold"],
                                                           rel=1e-6)


@pytest.mark.slow
def test_through_a_fold_curve_crosses_resonant_grazing_to_its_next_admissible_piece():
    """With through=True the fold curve from omega = 1.5 goes on past the RG point at
    omega_d (its impact speed through zero, the orbit not admissible beyond), on the
    regular test w det(M - I), back to zero speed at the next resonant grazing point
    2 omega_d / 3, where a second admissible piece of the same curve begins and the
    standard test resumes."""
    from symvi.curves import continue_curve
    brs = continue_orbits(coco(), "forcing[1]", 2.0, 0.2, omega=1.5)
    fold = next(s for br in brs for s in br.special if s.kind == "fold")
    cv = continue_curve(fold.orbit.model, "fold", ("omega", "forcing[1]"), fold,
                        bounds={"omega": (0.6, 1.6), "forcing[1]": (0.01, 10.0)},
                        through=True)
    wd = np.sqrt(K - C ** 2 / 4)
    rg = sorted((s for s in cv.special if s.kind == "RG"), key=lambda s: -s.params["omega"])
    assert [s.params["omega"] for s in rg] == pytest.approx([wd, 2 * wd / 3], abs=1e-9)
    for s in rg:
        assert s.params["forcing[1]"] == pytest.approx(D * H(s.params["omega"]), rel=1e-9)
        assert "kappa_fold" in s.coefficients and "kappa_flip" in s.coefficients
    # between the two: not admissible; past the second: admissible, on the standard test
    w = np.array([p.params["omega"] for p in cv.points])
    between = [p for p, x in zip(cv.points, w) if 2 * wd / 3 + 1e-3 < x < wd - 1e-3]
    assert between and not any(p.admissible for p in between)
    after = [p for p, x in zip(cv.points, w) if x < 2 * wd / 3 - 1e-3]
    assert after and all(p.admissible for p in after)
    std = [p for p in after if not getattr(p, "_bridged", False)]
    assert std and all(p.coefficient is not None for p in std)
    assert all(min(abs(z - 1) for z in p.orbit.multipliers) < 1e-8 for p in std[::10])
    assert cv.ends[0].startswith("reached omega = 0.6")
