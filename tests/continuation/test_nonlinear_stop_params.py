"""A stop's gap or restitution as the continued parameter of a model with nonlinear forces
(issue 28): dG/dp of the shooting system moves the flights' ends only (the section, the
level and the reset; :meth:`symvi.orbits.periodic.Problem._dstop`).

Checks that could fail: dG/dp against central differences of G; with the nonlinearity off
the branches in gap and restitution, and their special points with coefficients, are the
exact linear flow's."""
import numpy as np
import pytest

from symvi.continuation.branch import continue_branch
from symvi.continuation.homotopy import period1_orbits
from symvi.model import Model, Stop
from symvi.orbits.periodic import Problem

KW = dict(mass=[1.0], stiffness=[[1.0]], damping=[[0.05]], forcing=[1.0],
          stop=Stop(mass=1, gap=0.0, restitution=0.8))
TWO = dict(mass=[1.0, 2.0], stiffness=[[2.0, -1.0], [-1.0, 1.5]],
           damping=[[0.05, 0.0], [0.0, 0.05]], forcing=[1.0, 0.3],
           stop=Stop(mass=2, gap=0.3, restitution=0.7))


@pytest.mark.parametrize("kw, forces, omega, name", [
    (KW, ["beta*x1**3"], 2.6, "gap"),
    (KW, ["beta*x1**3"], 2.6, "restitution"),
    (TWO, ["beta*x1**3", "beta*(x2 - x1)**3"], 1.1, "gap"),
    (TWO, ["beta*x1**3", "beta*(x2 - x1)**3"], 1.1, "restitution"),
])
def test_dG_dparam_against_central_differences(kw, forces, omega, name):
    m = Model(**kw, nonlinear=forces, parameters={"beta": 0.2})
    o = period1_orbits(m, omega).orbits[0]
    par = m.parameter(name)
    lam = m.value(name)
    pr = Problem(m, 1, 1, omega=omega, param=par)
    u = np.append(o.y, o.times)
    Gl = pr.evaluate(u, lam, jac=False, dparam=True)[2]
    h = 1e-5
    fd = (pr.evaluate(u, lam + h, jac=False)[0] - pr.evaluate(u, lam - h, jac=False)[0]) / (2 * h)
    assert np.max(np.abs(Gl - fd)) < 1e-7 * max(1.0, np.max(np.abs(fd)))
    assert np.max(np.abs(Gl)) > 1e-3              # not trivially zero


@pytest.mark.parametrize("name, start, stop", [("gap", 0.0, 0.3), ("restitution", 0.8, 0.5)])
def test_nonlinearity_off_gives_the_linear_branch(name, start, stop):
    lin = Model(**KW)
    off = Model(**KW, nonlinear=["beta*x1**3"], parameters={"beta": 0.0})
    a = continue_branch(lin, name, start, stop, omega=2.6)
    o = period1_orbits(off, 2.6).orbits[0]
    b = continue_branch(off, name, start, stop, omega=2.6, orbit=o)
    assert a.end.split(" (")[0] == b.end.split(" (")[0]
    assert [s.kind for s in a.special] == [s.kind for s in b.special]
    for sa, sb in zip(a.special, b.special):
        assert abs(sa.value - sb.value) < 1e-9
        for k in ("c", "a", "l1"):
            if k in sa.coefficients:
                assert abs(sa.coefficients[k] - sb.coefficients[k]) < 1e-7 * max(
                    1.0, abs(sa.coefficients[k]))
    if name == "gap":
        assert [s.kind for s in a.special] == ["flip", "grazing"]
