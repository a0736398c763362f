"""Chenciner points of a curve of a model with nonlinear forces, the forces off (issue 28:
codimension-two points, l2 included): Luo & Xie's example 1 written with a cubic spring
of coefficient 0 runs on the nonlinear engine (Taylor flights, series jets of order 5
in omega and the restitution) and its NS curve in (omega, r) has the exact linear
flow's two Chenciner points (generated jets, an independent path) with their l2."""
import pytest

from symvi.curves import curve_from_interval
from symvi.model import Model, Stop

LX = dict(mass=[1.0, 2.0], stiffness=[[1.0, -1.0], [-1.0, 6.0]], damping=[[0, 0], [0, 0]],
          forcing=[1.0, 0.0], stop=Stop(mass=1, gap=1.5, restitution=0.8))
BOUNDS = {"omega": (0.5, 1.0), "restitution": (0.05, 1.0)}


def _ch(model):
    curve = curve_from_interval(model, 0.70, 0.76, ("omega", "restitution"), bounds=BOUNDS)[0]
    return sorted((s for s in curve.special if s.kind == "CH"), key=lambda s: s.params["restitution"])


@pytest.mark.slow
def test_chenciner_points_with_the_forces_off():
    lin = _ch(Model(**LX))
    off = _ch(Model(**LX, nonlinear=["beta*x1**3", "0"], parameters={"beta": 0.0}))
    assert len(lin) == 2 and len(off) == 2
    for a, b in zip(lin, off):
        for k in ("omega", "restitution"):
            assert abs(a.params[k] - b.params[k]) < 1e-9
        l2a, l2b = a.coefficients["l2"], b.coefficients["l2"]
        assert abs(l2a - l2b) < 1e-7 * abs(l2a)
