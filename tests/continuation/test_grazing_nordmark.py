"""A grazing point located on a branch carries Nordmark's map (issue 27, item 3): the
same numbers as symvi.discontinuity_map at its orbit, and the predicted scenario."""
import math

import symvi
from symvi.continuation import continue_orbits


def test_a_branchs_grazing_point_carries_nordmarks_map():
    model = symvi.Model(mass=[1.0], stiffness=[[1.0]], damping=[[3.0]], forcing=[1.0],
                        stop=symvi.Stop(mass=1, gap=0.1, restitution=0.8))
    X = 1 / abs(1 - 4 + 6j)
    br = continue_orbits(model, "gap", 0.3 * X, 2 * X, omega=2.0)[0]
    g = next(s for s in br.special if s.kind == "grazing")
    nm = symvi.discontinuity_map(g.orbit, g, param="gap")
    co = g.coefficients
    assert abs(g.value - X) < 1e-9
    assert co["c_first"] == nm.c_first and co["delta_rate"] == nm.delta_rate
    # the overdamped oscillator: lambda1 = exp(-0.382 pi) on the real axis, in (1/4, 2/3)
    assert co["lambda1_im"] == 0.0
    assert abs(co["lambda1_re"] - math.exp(-(3 - math.sqrt(5)) / 2 * math.pi)) < 1e-9
    assert "period-adding cascade" in g.detail
    assert co["acceleration"] < 0


def test_an_unstable_grazing_orbit_says_no_local_attractor():
    br = continue_orbits(symvi.Model.luo_xie(2, 5, 0, 1.5, 0.8), "omega", 0.5, 1.0)[0]
    g = next(s for s in br.special if s.kind == "grazing")
    assert math.hypot(g.coefficients["lambda1_re"], g.coefficients["lambda1_im"]) > 1
    assert "no local attractor" in g.detail
