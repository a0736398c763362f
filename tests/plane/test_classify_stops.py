"""Parameter planes of models with several rigid stops (issue 25): each point starts from
the default start on stop 1 and is judged by the one classifier over the stops' sections;
a small plane agrees with the direct classification of each point's simulation
(``simulate`` then ``diagnostics.classify``: the QR logs, not the run loop's tangent);
too few kept impacts are refused in one line (elastic stops count entries and exits apart)."""
import json

import numpy as np
import pytest

from symvi.errors import ParameterError
from symvi.model import load_model
from symvi.plane import PlaneSpec, PlaneStore, compute_serial, parse_axis, run_plane
from symvi.simulations import diagnostics as dg
from symvi.simulations.simulation import default_start, simulate
from tests.cli.test_cli_itinerary import SYM as SYM_FILE
from tests.fuzz._cli import cli

SYM = load_model(SYM_FILE)


def _spec(model=SYM, impacts=1000, transient=3000, **kw):
    # omega 1.1 (chaos at gap -0.5), 1.55, 2.0 (the 1-2 orbits) by the lower stop's gap
    return PlaneSpec(model=model, x=parse_axis("omega:1.1:2.0:3", "--x"),
                     y=parse_axis("stop[2].gap:-0.6:-0.4:3", "--y"), impacts=impacts,
                     transient=transient, **kw)


def test_small_plane_agrees_with_each_points_classification(tmp_path):
    spec = _spec()
    run = run_plane(spec, tmp_path / "p.zarr", workers=0, progress=False)
    assert run.computed == run.blocks
    ds = PlaneStore.read(tmp_path / "p.zarr").dataset()
    ref = compute_serial(spec)
    for v in ("attractor", "impacts_per_orbit", "period", "lyapunov"):
        assert np.array_equal(np.asarray(ds[v]), ref[v], equal_nan=v == "lyapunov"), v
    lab = np.asarray(ds["attractor"]).astype(str)
    # not trivial: several-stop periodic orbits of 1 and more forcing periods, and chaos
    assert {"period-1", "chaos"} <= set(lab.ravel()) and len(set(lab.ravel())) >= 3
    assert not np.asarray(ds["own_start"]).any()         # the default start, not y*
    q = np.asarray(ds["impacts_per_orbit"])
    for i in range(3):
        for j in range(3):
            model, omega = spec.point(i, j)
            sim = simulate(model, omega, y0=default_start(model, omega), n_impacts=1000,
                           transient=3000)
            c = dg.classify(sim)
            assert c.label == lab[i, j], (i, j)
            assert (c.impacts or 0) == q[i, j], (i, j)
            if c.label == "chaos":
                assert c.lyapunov.largest > 0.1 and float(ds["lyapunov"][i, j]) > 0.1
    # the 1-2 orbits at omega = 2.0 hit both stops: 2 impacts a forcing period
    assert np.all(lab[:, 2] == "period-1") and np.all(q[:, 2] == 2)


def test_follow_plane_of_two_stops(tmp_path):
    """--follow on a several-stop plane: a followed point starts on the stop its
    neighbour's run ended on; the plane is the serial computation's."""
    spec = _spec(follow=True, impacts=400, transient=1000)
    run_plane(spec, tmp_path / "f.zarr", workers=0, progress=False)
    ds = PlaneStore.read(tmp_path / "f.zarr").dataset()
    ref = compute_serial(spec)
    assert np.array_equal(np.asarray(ds["attractor"]), ref["attractor"])
    assert np.asarray(ds["attractor"])[:, 1:].astype(str).tolist() == \
        [["period-1", "period-1"]] * 3


def test_too_few_impacts_per_stop_refused():
    with pytest.raises(ParameterError, match="--impacts") as exc:
        _spec(impacts=7)
    assert "4 per stop" in str(exc.value) and "\n" not in str(exc.value)
    _spec(impacts=8)                                      # 4 on each of two stops


def test_elastic_stop_taken_and_short_runs_refused_in_one_line(tmp_path):
    """A plane of an elastic + rigid model is a plane like the others (issue 25); its
    floor on kept records counts an elastic stop's entries and exits apart (4 each)."""
    f = tmp_path / "el.toml"
    f.write_text(SYM_FILE.read_text().replace("gap = 0.5\nrestitution = 0.9",
                                              "gap = 0.5\nstiffness = 50.0\ndamping = 0.5"))
    _spec(model=load_model(f))
    with pytest.raises(ParameterError, match="--impacts") as exc:
        _spec(model=load_model(f), impacts=8)
    assert "entries and exits" in str(exc.value) and "\n" not in str(exc.value)
    out = tmp_path / "el.zarr"
    rc, text, err = cli("plane", "--model", str(f), "--x", "omega:1.1:2.0:2", "--y",
                        "stop[2].gap:-0.6:-0.4:2", "--impacts", "8", "--transient", "10",
                        "--out", str(out), "--workers", "0")
    assert rc == 2 and text == "" and len(err.strip().splitlines()) == 1
    assert "--impacts" in err and not out.exists()


def test_cli_plane_of_a_two_stop_model(tmp_path):
    out = tmp_path / "c.zarr"
    rc, text, err = cli("plane", "--model", str(SYM_FILE), "--x", "omega:1.55:2.0:2", "--y",
                        "stop[2].gap:-0.6:-0.4:2", "--impacts", "400", "--transient", "2000",
                        "--out", str(out), "--workers", "0", "--json")
    assert rc == 0, err
    assert json.loads(text)["attractors"] == {"period-1": 4}
