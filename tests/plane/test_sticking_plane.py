"""A plane over an oscillator that chatters and sticks every forcing period (issue 27,
item 4): its points are the sticking period-1 orbit, not "sticking" (the plane's format
unchanged: attractor period-1, stop completed, no exponent across a held phase)."""
import numpy as np

from symvi.model import Model, Stop
from symvi.plane import PlaneSpec, compute_serial, parse_axis
from symvi.simulations.diagnostics import classify
from symvi.simulations.simulation import simulate

ONE = Model(mass=[1.0], stiffness=[[1.0]], damping=[[0.1]], forcing=[1.0],
            stop=Stop(mass=1, gap=0.0, restitution=0.5))


def test_a_plane_of_sticking_orbits():
    spec = PlaneSpec(model=ONE, x=parse_axis("omega:0.45:0.5:2", "--x"),
                     y=parse_axis("restitution:0.4:0.5:2", "--y"), impacts=200,
                     transient=500)
    r = compute_serial(spec)
    assert (r["attractor"] == "period-1").all() and (r["stop"] == "completed").all()
    assert np.isnan(r["lyapunov"]).all()
    # fewer exact impacts per chatter at the smaller r (down to the same grazing speed)
    assert (r["impacts_per_orbit"][0] < r["impacts_per_orbit"][1]).all()
    # the same orbit as simulate --classify finds from the same start
    model, omega = spec.point(1, 1)
    sim = simulate(model, omega, y0=(-omega * 0.1, 0.0), n_impacts=200, transient=500)
    c = classify(sim)
    assert c.label == "period-1" and c.impacts == r["impacts_per_orbit"][1, 1]
