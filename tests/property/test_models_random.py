"""Random models (N = 1..4, damping or none, the stop on any mass, forcing anywhere):
whatever the period-1 solver returns is a fixed point of the exact map with the
determinant identity, its Jacobian agrees with differences of the map, and nothing
crashes with anything but a SymviError."""
import math
import warnings

import numpy as np
import pytest
from hypothesis import HealthCheck, assume, event, example, given, settings
from hypothesis import strategies as st

from symvi.codegen.jets import jacobian_at
from symvi.errors import NearSingularWarning, SymviError
from symvi.maps.impact import poincare_map
from symvi.model import Model, Stop
from symvi.orbits import period1_orbits


@st.composite
def models(draw):
    n = draw(st.integers(1, 4))
    rng = np.random.default_rng(draw(st.integers(0, 2 ** 32 - 1)))
    masses = rng.uniform(0.3, 3.0, n)
    # a chain to the ground with random springs, plus a random SPD perturbation
    k = rng.uniform(0.3, 3.0, n + 1)
    K = np.diag(k[:-1] + k[1:]) - np.diag(k[1:-1], 1) - np.diag(k[1:-1], -1)
    Q = rng.normal(size=(n, n)) * 0.2
    K = K + Q @ Q.T
    damped = draw(st.booleans())
    C = None
    if damped:
        R = rng.normal(size=(n, n)) * draw(st.sampled_from([0.01, 0.05, 0.3]))
        C = (R @ R.T).tolist()
    P = rng.normal(size=n)
    stop = Stop(mass=int(rng.integers(1, n + 1)), gap=float(rng.uniform(-1, 2)),
                restitution=float(draw(st.sampled_from([0.3, 0.7, 0.95, 1.0]))))
    return Model(mass=masses.tolist(), stiffness=K.tolist(), damping=C, forcing=P.tolist(),
                 stop=stop)


@settings(max_examples=15, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(models(), st.floats(0.2, 3.0))
def test_period1_orbits_are_fixed_points_with_the_determinant_identity(model, omega):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", NearSingularWarning)
        try:
            orbits = period1_orbits(model, omega)
        except SymviError as exc:
            event(f"refused: {exc.kind if hasattr(exc, 'kind') else 'parameter'}")
            return                                  # a refusal, with its reason
    trMC = float(np.trace(np.linalg.solve(model.mass, model.damping)))
    T = 2 * math.pi / omega
    r = model.stop.restitution
    for o in orbits:
        assert len(o.y) == model.dim and all(math.isfinite(float(v)) for v in o.y)
        if not o.admissible:
            assert o.reason
            event("inadmissible orbit")
            continue
        event("admissible orbit checked")
        assert o.y[0] < 0 < o.impact_velocity
        s = poincare_map(model, omega, o.y)
        assert s.status == "impact" and abs(s.t - T) < 1e-8 * T
        d = np.array(s.y, dtype=float) - np.array(o.y, dtype=float)
        d[-1] = (d[-1] + math.pi) % (2 * math.pi) - math.pi
        assert np.abs(d).max() < 1e-7 * (1 + np.abs(np.array(o.y, dtype=float)).max())
        det = np.prod(np.array(o.multipliers)).real
        assert abs(det / (r * r * math.exp(-trMC * T)) - 1) < 1e-6


@settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(models(), st.floats(0.2, 3.0), st.integers(0, 2 ** 32 - 1))
def test_jacobian_at_transient_points_against_differences(model, omega, seed):
    """Any section point that leaves the stop: the generated DP against central
    differences of the float64 map, where the flight is transversal and short."""
    rng = np.random.default_rng(seed)
    y = rng.normal(size=model.dim)
    y[0] = -abs(y[0]) - 0.2                         # leaves the stop
    y[-1] = rng.uniform(0, 2 * math.pi)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", NearSingularWarning)
        try:
            s = poincare_map(model, omega, y)
        except SymviError:
            return
        assume(s.status == "impact" and s.impact_velocity > 0.05 and s.t < 20 * math.pi / omega)
        J = jacobian_at(model, omega, y, s.t)
        h = 1e-6
        fd = np.empty_like(J)
        for j in range(model.dim):
            e = np.zeros(model.dim)
            e[j] = h
            a, b = poincare_map(model, omega, y + e), poincare_map(model, omega, y - e)
            assume(a.status == b.status == "impact" and abs(a.t - b.t) < 1e-3)
            fa = np.array([*a.y[:-1], a.tau_unwrapped])
            fb = np.array([*b.y[:-1], b.tau_unwrapped])
            fd[:, j] = (fa - fb) / (2 * h)
    event(f"Jacobian compared, N = {model.n}")
    assert np.abs(fd - J).max() < 1e-5 * max(1.0, np.abs(J).max())


def _eig_rounding(model, p):
    """Rounding bound of the critical multiplier: 100 eps ||J|| kappa, kappa = 1/|u^H v|
    the condition number of the simple eigenvalue (unit left and right vectors).  Near
    grazing J has multipliers ~1e5 and kappa ~1e3: |lambda| = 1 holds only to ~1e-9."""
    import scipy.linalg

    from symvi.simulations.diagnostics import jacobian
    J = jacobian(model, p.omega_c, p.orbit.y)
    w, vl, vr = scipy.linalg.eig(J, left=True, right=True)
    i = int(np.argmin(np.abs(w - p.multiplier)))
    u, v = vl[:, i] / np.linalg.norm(vl[:, i]), vr[:, i] / np.linalg.norm(vr[:, i])
    kappa = 1.0 / max(abs(np.vdot(u, v)), 1e-300)
    return 100 * np.finfo(float).eps * np.linalg.norm(J, 2) * kappa


from tests.property.strategies import SEED2  # noqa: E402


@pytest.mark.slow
@settings(max_examples=15, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(models(), st.floats(0.3, 1.5), st.floats(0.5, 1.5))
@example(SEED2, 0.4015, 0.0015)
def test_hopf_points_of_random_models(model, a, width):
    """Every reported Neimark-Sacker point sits on the unit circle; d|lambda1|/domega
    along the branch either confirms (A1)-(A3) to 1e-4 or carries a caveat, and when its
    own error estimate says it is certain it must confirm them; refusals are
    SymviErrors."""
    from symvi import hopf_points
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", NearSingularWarning)
        try:
            res = hopf_points(model, a, a + width)
        except SymviError as exc:
            event(f"refused: {getattr(exc, 'kind', 'parameter')}")
            return
    event(f"{len(res.points)} NS points")
    for p in res.points:
        assert abs(abs(p.multiplier) - 1) < max(1e-9, _eig_rounding(model, p))
        if p.trusted("dmod_domega") and abs(p.dmod_domega) > 1e-3:
            d, v, e = p.dmod_domega, p.dmod_domega_branch, p.dmod_domega_branch_error
            if not (math.isfinite(v) and math.isfinite(e)):
                assert p.branch_caveat                  # says it could not be computed
                event("branch derivative not computable")
                continue
            # its stated error covers the distance to (A1)-(A3), themselves trusted to
            # rel_err: a wrong (A1)-(A3) or an error bar that misses the truth fails here
            rel = p.precision.dmod_domega.rel_err if p.precision is not None else 0.0
            assert abs(v - d) <= 10 * e + (10 * rel + 1e-12) * abs(d), (d, v, e)
            # and printed without a caveat, it confirms them
            agree = abs(v / d - 1) < 1e-4
            assert agree or p.branch_caveat, (d, v, e)
            event("branch derivative " + ("confirms" if agree else "uncertain"))
