"""Generated jets of N-mass structures against finite differences of the mpmath map
at 40 digits, and the exact parameter derivatives against differences in the parameter."""
import math
import warnings

import mpmath
import numpy as np
import pytest

from symvi import Params, jet
from symvi.codegen.jets import fixed_point_motion, jacobian_at, jet_at, parameter_derivatives
from symvi.errors import NearSingularWarning, SingularCaseError
from symvi.maps.impact import poincare_map
from symvi.orbits import period1_orbits

from tests.zoo import N_MASS_SET

DPS = 40
CASES = [("one", 0.9), ("paper-damped", 0.65), ("three", 0.95), ("four", 1.0)]


def _orbit(name, w):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", NearSingularWarning)
        return [o for o in period1_orbits(N_MASS_SET[name], w) if o.admissible][0]


def _P(model, w, y):
    s = poincare_map(model, w, y, digits=DPS)
    return [*s.y[:-1], s.tau_unwrapped]


def _fd_jacobian(model, w, y, h):
    n = len(y)
    out = np.zeros((n, n))
    with mpmath.mp.workdps(DPS):
        y0 = [mpmath.mpf(v) for v in y]
        for j in range(n):
            yp, ym = list(y0), list(y0)
            yp[j] += h
            ym[j] -= h
            a, b = _P(model, w, yp), _P(model, w, ym)
            out[:, j] = [float((x - z) / (2 * h)) for x, z in zip(a, b)]
    return out


@pytest.mark.parametrize("name,w", CASES)
def test_jacobian_against_fd_of_mpmath_map(name, w):
    o = _orbit(name, w)
    J = jet_at(N_MASS_SET[name], w, o.y, 2 * math.pi / w, 1).jacobian
    with mpmath.mp.workdps(DPS):
        fd = _fd_jacobian(N_MASS_SET[name], w, o.y, mpmath.mpf(10) ** -15)
    assert np.abs(fd - J).max() < 1e-12 * np.abs(J).max()


@pytest.mark.slow
@pytest.mark.parametrize("name,w", [("three", 0.95), ("one", 0.9)])
def test_second_and_third_derivatives_against_fd(name, w):
    """d2 and d3 from differences of the generated Jacobian (mpmath, 40 digits) at
    the perturbed points' own flight times."""
    model = N_MASS_SET[name]
    o = _orbit(name, w)
    jt = jet_at(model, w, o.y, 2 * math.pi / w, 3)
    n = len(o.y)
    with mpmath.mp.workdps(DPS):
        h = mpmath.mpf(10) ** -9
        y0 = [mpmath.mpf(v) for v in o.y]

        def Jat(y):
            return jacobian_at(model, w, y, poincare_map(model, w, y, digits=DPS).t, digits=DPS)
        d2 = np.zeros((n, n, n))
        d3 = np.zeros((n, n, n, n))
        for k in range(n):
            yp, ym = list(y0), list(y0)
            yp[k] += h
            ym[k] -= h
            d2[:, :, k] = np.array((Jat(yp) - Jat(ym)) / (2 * h), dtype=float)
        # one mixed third derivative slice: d/dy_k d/dy_l of J
        for k in range(n):
            for l in (0, n - 1):
                pts = {}
                for a in (1, -1):
                    for b in (1, -1):
                        y = list(y0)
                        y[k] += a * h
                        y[l] += b * h
                        pts[a, b] = Jat(y)
                d3[:, :, k, l] = np.array((pts[1, 1] - pts[1, -1] - pts[-1, 1] + pts[-1, -1])
                                          / (4 * h * h), dtype=float)
    assert np.abs(d2 - jt.d2).max() < 1e-10 * np.abs(jt.d2).max()
    for l in (0, n - 1):
        assert np.abs(d3[:, :, :, l] - jt.d3[:, :, :, l]).max() < 1e-7 * np.abs(jt.d3).max()


NAMES = ["omega", "gap", "restitution", "mass[1]", "stiffness[1,2]", "damping[2,2]",
         "forcing[1]"]


@pytest.mark.parametrize("pname", NAMES)
def test_parameter_derivatives_against_fd(pname):
    """dP/dp and dJ/dp at fixed y (exact: generated slots + Frechet derivative of e^{At})
    against central differences in p of the mpmath map, on the damped 3-mass model."""
    model, w = N_MASS_SET["three"], 0.95
    o = _orbit("three", w)
    te = 2 * math.pi / w
    pd = parameter_derivatives(model, w, o.y, te, pname, fixed_point=False)
    h = 2.0 ** -24                       # exact in binary: the perturbed value is v +- h
    if pname == "omega":
        mp_, mm, wp, wm = model, model, w + h, w - h
    else:
        v = model.value(pname)
        mp_, mm, wp, wm = model.with_(**{pname: v + h}), model.with_(**{pname: v - h}), w, w
    with mpmath.mp.workdps(DPS):
        y0 = [mpmath.mpf(v) for v in o.y]
        a, b = _P(mp_, wp, y0), _P(mm, wm, y0)
        dP = np.array([float((x - z) / (2 * h)) for x, z in zip(a, b)])
        # Jacobian at fixed y with each model's own flight time
        ta = poincare_map(mp_, wp, y0, digits=DPS).t
        tb = poincare_map(mm, wm, y0, digits=DPS).t
        Ja = jacobian_at(mp_, wp, y0, ta, digits=DPS)
        Jb = jacobian_at(mm, wm, y0, tb, digits=DPS)
        dJ = np.array((Ja - Jb) / (2 * h), dtype=float)
    scale = max(np.abs(pd.dP).max(), 1e-3)
    assert np.abs(dP - pd.dP).max() < 1e-9 * scale      # O(h^2) = 4e-15 truncation
    assert np.abs(dJ - pd.dJ).max() < 1e-8 * max(np.abs(pd.dJ).max(), 1e-3)


def test_paper_structure_equals_the_papers_own_generated_jets():
    """N = 2 structure at the Luo-Xie preset (what symvi.jet(Params) evaluates) ==
    generated/order3 of the paper's modal derivation (the oracle) at the oracle's own
    orbit, to rounding."""
    from symvi.paper._eval import _evaluate, _orbit_inputs
    from symvi.codegen.jets import fixed_point_motion
    from symvi.paper.modal_orbit import period1_orbits as paper_orbits
    p = Params(2, 5, 0, 1.5, 0.8)
    w = 0.7369
    po = [x for x in paper_orbits(p, w) if x.admissible][0]
    old = _evaluate(3, _orbit_inputs(p, po), False)
    old["dA"] = old["dwJ"] + old["d2"] @ fixed_point_motion(old["J"], old["dwP"], False)
    new = jet(p, w, order=3)
    assert max(abs(a - b) for a, b in zip(new.orbit.y, po.y)) < 1e-12
    for a, b in ((new.jacobian, old["J"]), (new.d2, old["d2"]), (new.d3, old["d3"]),
                 (new.dA, old["dA"]), (new.dP_domega, old["dwP"])):
        assert np.abs(a - b).max() < 1e-11 * max(1, np.abs(b).max())


def test_mpmath_backend_of_generated_code_agrees():
    o = _orbit("four", 1.0)
    f = jet_at(N_MASS_SET["four"], 1.0, o.y, 2 * math.pi, 2)
    m = jet_at(N_MASS_SET["four"], 1.0, o.y, 2 * math.pi, 2, digits=30)
    assert np.abs(np.array(m.d2, dtype=float) - f.d2).max() < 1e-11 * np.abs(f.d2).max()


@pytest.mark.parametrize("name", ["paper", "three", "four"])
def test_compiled_input_assembly_equals_numpy(name):
    """codegen/_assemble.py (one numba call) builds the layout of codegen.layout exactly as
    the numpy expressions do: Phi(t) A^k = Re(W diag(e^{lambda t} lambda^k) W^-1), U, V,
    the omega-derivatives, zero parameter slots, omega, the guard (g0, level) and the reset's
    column R[:, 0] of the flow's constraint, y, t_e."""
    from symvi.codegen.layout import assemble, module
    from symvi.flow.linear import LinearFlow
    model = N_MASS_SET[name]
    fl = LinearFlow.of(model)
    F = fl.forcing(0.95)
    y = tuple(np.random.default_rng(3).normal(size=2 * fl.n))
    te = 5.3
    for K in (1, 2, 3):
        got = assemble(fl, F, y, te, K)
        e = np.exp(fl.lam * te)
        parts = [((fl.W * (e * fl.lam ** k)) @ fl.Winv).real.ravel() for k in range(K + 1)]
        parts += [F.U, F.V]
        extra = ()
        if K in (2, 3):
            z, zn = np.zeros((2 * fl.n) ** 2), np.zeros(fl.n)
            parts += [F.dU, F.dV, z, z, zn, zn]
            extra = (0.0,) * (1 + fl.n)
        ref = np.array(list(np.concatenate(parts)) + [0.95, fl.guard[0], fl.level,
                                                      *fl.reset[:, 0], *extra, *y, te])
        assert len(got) == len(ref) == len(module(fl.n, K)[0].INPUTS)
        scale = max(1.0, float(np.abs(ref).max()))
        assert np.abs(np.array(got) - ref).max() < 1e-13 * scale, (name, K)


def test_compiled_fixed_point_solve_equals_numpy():
    """codegen/_assemble.fixed_solve64 (one numba call) gives numpy's (I - J)^-1 dP and the
    Hadamard ratio |det(I - J)| / prod of row norms that fixed_point_motion's fold test
    reads; an exactly singular I - J gives ratio 0 (so the fold checks run)."""
    from symvi.codegen._assemble import fixed_solve64
    rng = np.random.default_rng(7)
    for n in (1, 2, 4, 8, 16):
        for _ in range(10):
            J, d = rng.normal(size=(n, n)), rng.normal(size=n)
            M = np.eye(n) - J
            x, h = fixed_solve64(J, d)
            h0 = abs(np.linalg.det(M)) / np.prod(np.linalg.norm(M, axis=1))
            assert np.abs(x - np.linalg.solve(M, d)).max() < 1e-9 * max(1, np.abs(x).max())
            assert abs(h - h0) <= 1e-10 * h0
    assert fixed_solve64(np.eye(3), np.ones(3))[1] == 0.0
    with pytest.raises(SingularCaseError, match="multiplier-one"):
        fixed_point_motion(np.diag([1.0, 0.5]), np.ones(2), False)


def test_jet_and_multipliers_at_digits_keep_the_flight_time_at_that_precision():
    """symvi.jet(model, digits=50) and jets.multipliers_of at a 50-digit orbit take
    te = 2 pi / omega at 50 digits (it was once formed at mpmath's default 15 digits,
    which left the 50-digit Jacobian right to 2e-15 only)."""
    import symvi
    from symvi.paper.jets import multipliers_of
    m = N_MASS_SET["paper"]
    j = jet(m, 0.7369, 2, digits=50)
    o = [x for x in period1_orbits(m, 0.7369, digits=50) if x.admissible][0]
    with mpmath.workdps(50):
        ref = jet_at(m, o.omega, o.y, 2 * mpmath.pi / o.omega, 2, digits=50)
        assert max(abs(a - b) for a, b in zip(j.jacobian.ravel(), ref.jacobian.ravel())) \
            < mpmath.mpf(10) ** -40
        po = [x for x in symvi.period1_orbits(Params(2, 5, 0, 1.5, 0.8), 0.7369, digits=50)
              if x.admissible][0]
        lam = multipliers_of(Params(2, 5, 0, 1.5, 0.8), po)
        assert max(abs(a - b) for a, b in zip(lam, po.multipliers)) < mpmath.mpf(10) ** -40
