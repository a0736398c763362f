"""Two-parameter curves (issue 13): the defining system's exact gradient, NS curves against
hopf_points at fixed second parameter, codimension-two points located to 1e-9, the
stable side, the ends of a curve."""
import math

import numpy as np
import pytest

import symvi
from symvi.continuation import continue_branch
from symvi.curves import continue_curve
from symvi.curves.system import CurveSystem
from symvi.orbits.periodic import periodic_orbit
from tests.zoo import PAPER_EX1

EX1 = dict(mu_m=2, mu_k=5, f2=0, b=1.5, r=0.8)


@pytest.fixture(scope="module")
def ns_point():
    br = continue_branch(PAPER_EX1, "omega", 0.70, 0.76)
    return next(s for s in br.special if s.kind == "ns")


@pytest.fixture(scope="module")
def curve_r(ns_point):
    return continue_curve(PAPER_EX1, "ns", ("omega", "r"), ns_point.orbit,
                          bounds={"omega": (0.5, 1.0), "r": (0.05, 1.0)}, max_points=3000)


def _g_eliminated(system, v, lam):
    """g with the flight time re-solved (the map P itself, not the shooting residual)."""
    pr = system.problem(lam)
    m = pr.size
    u, a = v[:m].copy(), v[m]
    for _ in range(30):
        G, Gu, _ = pr.evaluate(u, a, check=False)
        dt = -G[m - 1] / Gu[m - 1, m - 1]
        u[m - 1] += dt
        if abs(dt) < 1e-15:
            break
    G, Gu, _ = pr.evaluate(u, a, check=False)
    return system.test(pr.monodromy(u, Gu)[1])[0]


@pytest.mark.parametrize("names", [("omega", "b"), ("b", "r"), ("omega", "mu_m")])
@pytest.mark.parametrize("kind", ["ns", "flip", "fold"])
def test_gradient_of_test_function_is_exact(ns_point, names, kind):
    vals = {"omega": ns_point.value, "b": 1.5, "r": 0.8, "mu_m": 2.0}
    system = CurveSystem(PAPER_EX1, 1, 1, names, kind,
                         omega=None if "omega" in names else ns_point.value)
    u = ns_point.orbit.u
    v, lam = np.append(u, vals[names[0]]), vals[names[1]]
    pr = system.problem(lam)
    G, Gu, _ = pr.evaluate(u, v[-1])
    system.set_border(pr.monodromy(u, Gu)[1])
    F, DF, Fb = system.evaluate(v, lam, dparam=True)
    h = 1e-6
    d = pr.d
    for j in list(range(d)) + [len(v) - 1]:
        e = np.zeros(len(v))
        e[j] = h
        num = (_g_eliminated(system, v + e, lam) - _g_eliminated(system, v - e, lam)) / (2 * h)
        assert num == pytest.approx(DF[-1, j], rel=1e-6, abs=1e-7 * np.abs(DF[-1]).max())
    num = (_g_eliminated(system, v, lam + h) - _g_eliminated(system, v, lam - h)) / (2 * h)
    assert num == pytest.approx(Fb[-1], rel=1e-6, abs=1e-8)


@pytest.mark.slow
def test_ns_curve_agrees_with_hopf_points_at_fixed_b(ns_point):
    curve = continue_curve(PAPER_EX1, "ns", ("omega", "b"), ns_point.orbit,
                           bounds={"omega": (0.6, 0.9), "b": (1.0, 2.0)}, max_points=400)
    assert curve.ends[0].startswith("reached b") and curve.ends[1].startswith("reached b")
    b = curve.values("b")
    w = curve.values("omega")
    for bval in (1.0, 1.25, 1.5, 1.75, 2.0):
        i = int(np.argmin(np.abs(b - bval)))
        res = symvi.hopf_points(symvi.Params(**dict(EX1, b=float(b[i]))),
                                w[i] - 2e-3, w[i] + 2e-3)
        assert len(res.points) == 1
        hp = res.points[0]
        assert hp.omega_c == pytest.approx(w[i], abs=1e-9)
        assert hp.l1 == pytest.approx(curve.points[i].l1, rel=1e-6)
        assert curve.points[i].theta == pytest.approx(2 * math.pi * hp.theta_over_2pi, abs=1e-8)
    # the bounds are landed on exactly
    assert {round(b[0], 12), round(b[-1], 12)} == {1.0, 2.0}


def test_codim2_points_of_example1_in_omega_r(curve_r):
    kinds = [s.kind for s in curve_r.special]
    assert kinds.count("CH") == 2 and "R3" in kinds and "R4" in kinds
    for s in curve_r.special:
        mu = np.array(s.orbit.multipliers)
        pair = max(mu, key=lambda z: z.imag)          # the critical pair is on the circle
        crit = min((z for z in mu if z.imag > 0), key=lambda z: abs(abs(z) - 1))
        assert abs(abs(crit) - 1) < 1e-10
        if s.kind == "R3":
            assert abs(crit ** 3 - 1) < 1e-9
        if s.kind == "R4":
            assert abs(crit ** 4 - 1) < 1e-9
        del pair
    # both ends: the conservative limit r -> 1 is diagnosed, not a silent stop
    for end in curve_r.ends:
        assert "conservative limit" in end


def test_chenciner_point_is_located_to_1e_9(curve_r):
    """hopf_points at the located r finds the NS point at the located omega with l1 ~ 0,
    and l1 changes sign across it along the curve."""
    for s in (s for s in curve_r.special if s.kind == "CH"):
        r, w = s.params["r"], s.params["omega"]
        res = symvi.hopf_points(symvi.Params(**dict(EX1, r=r)), w - 2e-3, w + 2e-3)
        hp = res.points[0]
        assert hp.omega_c == pytest.approx(w, abs=1e-9)
        i = s.index
        l1a, l1b = curve_r.points[i].l1, curve_r.points[i + 1].l1
        assert l1a * l1b < 0
        # |l1| at the located point, against its change over the bracketing step
        assert abs(hp.l1) < 1e-6 * abs(l1a - l1b) + 1e-12


def test_stable_side_is_where_the_orbit_is_stable(curve_r):
    """Step off the curve along the reported normal: stable there, unstable opposite."""
    from symvi.curves.curve import stable_sides
    sides = [(i, s) for i, s in stable_sides(curve_r, every=150) if s is not None]
    assert len(sides) >= 4
    span = np.array([0.05, 0.05])
    for i, side in sides:
        pt = curve_r.points[i]
        for sgn, stable in ((1, True), (-1, False)):
            w = pt.params["omega"] + sgn * side[0] * 1e-3 * span[0] / 0.05
            r = pt.params["r"] + sgn * side[1] * 1e-3 * span[1] / 0.05
            if not 0 < r < 1:
                continue
            o = periodic_orbit(PAPER_EX1.with_(r=r), n=1, p=1, guess=pt.orbit, omega=w)
            assert o.stable is stable, (i, sgn, o.multipliers)


@pytest.mark.slow
def test_near_grazing_end_and_pdns(ns_point):
    curve = continue_curve(PAPER_EX1, "ns", ("omega", "b"), ns_point.orbit,
                           bounds={"omega": (0.5, 1.0), "b": (1.5, 3.0)}, max_points=4000,
                           both=False)
    kinds = [s.kind for s in curve.special]
    assert "PDNS" in kinds
    pd = next(s for s in curve.special if s.kind == "PDNS")
    assert min(abs(z + 1) for z in pd.orbit.multipliers) < 1e-9
    # the curve ends at grazing, the grazing-NS point located on the regular test
    assert "grazing-NS" in curve.ends[-1] and curve.special[-1].kind == "grazing-NS"


def test_bad_input():
    with pytest.raises(symvi.errors.ParameterError, match="two different"):
        CurveSystem(PAPER_EX1, 1, 1, ("omega", "omega"), "ns")
    with pytest.raises(symvi.errors.ParameterError, match="ns, flip or fold"):
        CurveSystem(PAPER_EX1, 1, 1, ("omega", "b"), "hopf")
    with pytest.raises(symvi.errors.ParameterError, match="forcing frequency"):
        CurveSystem(PAPER_EX1, 1, 1, ("b", "r"), "ns")
    with pytest.raises(symvi.errors.ParameterError):
        CurveSystem(PAPER_EX1, 1, 1, ("omega", "stiffness[9,9]"), "ns")


def test_start_from_a_hopf_point_of_the_paper_chain_in_omega_mu_m():
    """From hopf_points' own point (the paper's Params): the curve in (omega, mu_m) meets
    hopf_points again at another mass ratio."""
    p = symvi.Params(**EX1)
    hp = symvi.hopf_points(p, 0.70, 0.76).points[0]
    curve = continue_curve(p, "ns", ("omega", "mu_m"), hp, max_points=60)
    mu = curve.values("mu_m")
    i = int(np.argmax(np.abs(mu - 2.0)))
    other = symvi.hopf_points(symvi.Params(**dict(EX1, mu_m=float(mu[i]))),
                              curve.points[i].params["omega"] - 2e-3,
                              curve.points[i].params["omega"] + 2e-3).points[0]
    assert other.omega_c == pytest.approx(curve.points[i].params["omega"], abs=1e-9)
    assert abs(mu[i] - 2.0) > 0.05


def test_fold_curve_agrees_with_the_fold_of_branches_at_fixed_b():
    from symvi.curves import curve_from_interval
    curve, start = curve_from_interval(PAPER_EX1, 1.4, 1.6, ("omega", "b"), kind="fold",
                                       bounds={"omega": (0.5, 3.0), "b": (1.0, 2.0)})
    assert start.kind == "fold" and curve.ends[0].startswith("reached b")
    for pt in curve.points[::40]:
        assert min(abs(z - 1) for z in pt.orbit.multipliers) < 1e-9
    i = int(np.argmin(np.abs(curve.values("b") - 1.8)))
    pt = curve.points[i]
    w = pt.params["omega"]
    from symvi.orbits.periodic import ConvergenceError
    folds = []
    for a, z in ((w + 0.02, w - 0.02), (w - 0.02, w + 0.02)):   # orbits on one side only
        try:
            br = continue_branch(PAPER_EX1.with_(b=pt.params["b"]), "omega", a, z,
                                 guess=pt.orbit.y)
        except ConvergenceError:
            continue
        folds += [s for s in br.special if s.kind == "fold"]
    assert folds and folds[0].value == pytest.approx(w, abs=1e-9)
    assert folds[0].coefficients["a"] == pytest.approx(pt.coefficient, rel=1e-6)


def test_curve_params_are_two_parameters_of_the_model():
    """``symvi curve --params``: names of the model, not one parameter twice."""
    from symvi.curves import curve_params
    from symvi.errors import ParameterError
    from symvi.model import Model
    m = Model.luo_xie(**EX1)
    assert curve_params(m, "omega,b") == ("omega", "b")
    assert curve_params(m, "gap,restitution") == ("gap", "restitution")
    for text, why in (("b,gap", "two different parameters"), ("omega,zz", "omega, gap"),
                      ("omega", "two different names")):
        with pytest.raises(ParameterError, match=why) as exc:
            curve_params(m, text)
        assert exc.value.name == "--params"


def test_curves_of_a_plane_without_omega_are_none_with_a_note():
    from symvi.curves import curves_of_plane
    from symvi.model import Model
    from symvi.plane import PlaneSpec, parse_axis
    spec = PlaneSpec(model=Model.luo_xie(**EX1), x=parse_axis("b:1.3:1.7:3", "--x"),
                     y=parse_axis("r:0.7:0.8:3", "--y"), impacts=10, transient=10,
                     omega=0.74)
    assert curves_of_plane(spec) == ([], ["no curves: neither axis is omega"])
