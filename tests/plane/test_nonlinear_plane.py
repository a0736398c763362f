"""Sweeps and parameter planes of a model with nonlinear forces (issue 28): each point is
one run of the numerical flow (symvi.flow.nonlinear) from the default start, judged as
``symvi simulate --classify`` judges it; checked point by point against those direct runs,
with a period-1 point on the orbit the homotopy finds and a period-2 point past the flip
continuation locates (omega = 2.7474 at beta = 0.2)."""
import math

import numpy as np
import pytest

import symvi
from symvi.continuation.homotopy import period1_orbits
from symvi.errors import ParameterError
from symvi.model import Model, Stop
from symvi.plane import PlaneSpec, PlaneStore, parse_axis, run_plane
from symvi.simulations import diagnostics as dg
from symvi.simulations.simulation import default_start, sweep
from tests.fuzz._cli import cli

DUFFING = Model(mass=[1.0], stiffness=[[1.0]], damping=[[0.05]], forcing=[1.0],
                stop=Stop(mass=1, gap=0.0, restitution=0.8), nonlinear=["beta*x1**3"],
                parameters={"beta": 0.2})


def test_sweep_rows_are_the_direct_runs():
    omegas = [2.2, 2.6, 2.75]
    res = sweep(DUFFING, omegas, n_impacts=60, transient=300, classify=True)
    labels = res.classes.labels()
    for i, w in enumerate(omegas):
        sim = symvi.simulate(DUFFING, w, y0=default_start(DUFFING, w), n_impacts=60,
                             transient=300)
        np.testing.assert_array_equal(res.section[i], sim.section)
        assert labels[i] == dg.classify(sim, max_period=64).label
    assert labels[0] == "period-1" and labels[2] == "period-2"
    # the period-1 point is one of the orbits continued from the linear part
    ys = [o.y for o in period1_orbits(DUFFING, 2.2).orbits if o.stable]
    last = res.section[0][-1]
    assert min(abs(last[0] - y[0]) + abs((last[1] - y[1] + math.pi) % (2 * math.pi) - math.pi)
               for y in ys) < 1e-8


def test_small_nonlinear_plane_agrees_with_each_points_classification(tmp_path):
    spec = PlaneSpec(model=DUFFING, x=parse_axis("omega:2.2:2.75:3", "--x"),
                     y=parse_axis("beta:0.15:0.2:2", "--y"), impacts=60, transient=300)
    run = run_plane(spec, tmp_path / "p.zarr", workers=0, progress=False)
    assert run.computed == run.blocks
    ds = PlaneStore.read(tmp_path / "p.zarr").dataset()
    lab = np.asarray(ds["attractor"]).astype(str)
    for i in range(2):
        for j in range(3):
            model, omega = spec.point(i, j)
            sim = symvi.simulate(model, omega, n_impacts=60, transient=300)
            assert dg.classify(sim, max_period=64).label == lab[i, j], (i, j)
    assert np.all(lab[:, 0] == "period-1") and np.all(lab[:, 2] == "period-2")


def test_nonlinear_plane_refuses_omega_out_of_range(tmp_path):
    f = tmp_path / "d.toml"
    f.write_text('[model]\nmass = [1.0]\nstiffness = [[1.0]]\ndamping = [[0.05]]\n'
                 'forcing = [1.0]\nnonlinear = ["beta*x1**3"]\n[model.parameters]\n'
                 'beta = 0.2\n[stop]\nmass = 1\ngap = 0.0\nrestitution = 0.8\n')
    rc, out, err = cli("plane", "--model", str(f), "--x", "omega=0:1:3", "--y",
                       "beta=0.1:0.2:2", "--impacts", "10", "--transient", "10", "--out",
                       str(tmp_path / "p.zarr"))
    assert rc == 2 and err.count("\n") == 1 and "--x" in err
    with pytest.raises(ParameterError):
        PlaneSpec(model=DUFFING, x=parse_axis("omega:0:1:3", "--x"),
                  y=parse_axis("beta:0.1:0.2:2", "--y"), impacts=10, transient=10)
