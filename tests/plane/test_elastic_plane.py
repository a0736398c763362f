"""Parameter planes of models with elastic stops (issue 25): each point is one walk of the
contact phases from the default start (orbits._phases.default_state), judged on every
event; a small plane over omega and a stop's stiffness agrees point by point with the
direct classification of each point's run, and --follow carries a row's attractor on."""
import json

import numpy as np
import pytest

from symvi.errors import ParameterError
from symvi.model import load_model
from symvi.plane import PlaneSpec, PlaneStore, compute_serial, parse_axis, run_plane
from symvi.simulations import diagnostics as dg
from symvi.simulations.simulation import contact_run
from tests.cli.test_cli_itinerary import EXAMPLES
from tests.fuzz._cli import cli

ELASTIC_FILE = EXAMPLES / "oscillator_elastic.toml"
ELASTIC = load_model(ELASTIC_FILE)
X, Y = "omega:0.9:1.3:3", "stop[1].stiffness:40:60:2"


def _spec(impacts=60, transient=300, **kw):
    return PlaneSpec(model=ELASTIC, x=parse_axis(X, "--x"), y=parse_axis(Y, "--y"),
                     impacts=impacts, transient=transient, **kw)


def test_small_elastic_plane_agrees_with_each_points_classification(tmp_path):
    """3 x 2 points of the oscillator between two elastic stops: the stored attractor,
    events per orbit and exponent of each point are those of classify on the same walk
    (contact_run from the default start, 60 records after 300)."""
    spec = _spec()
    run = run_plane(spec, tmp_path / "p.zarr", workers=0, progress=False)
    assert run.computed == run.blocks
    ds = PlaneStore.read(tmp_path / "p.zarr").dataset()
    lab = np.asarray(ds["attractor"]).astype(str)
    q = np.asarray(ds["impacts_per_orbit"])
    lyap = np.asarray(ds["lyapunov"])
    assert not np.asarray(ds["own_start"]).any()
    for i in range(2):
        for j in range(3):
            model, omega = spec.point(i, j)
            c = dg.classify(contact_run(model, omega, 60, 300), max_period=64)
            assert c.label == lab[i, j], (i, j)
            assert (c.impacts or 0) == q[i, j], (i, j)
            if c.label == "chaos":
                assert c.lyapunov.largest > 0.05 and lyap[i, j] > 0.05
            else:
                assert lyap[i, j] < 0, (i, j)
    # not trivial: chaos, a 1-6 and a 2-12 orbit, and at omega = 1.3 the symmetric 1-4
    # orbit (an entry and an exit on each stop)
    assert {"chaos", "period-1", "period-2"} <= set(lab.ravel())
    assert np.all(lab[:, 2] == "period-1") and np.all(q[:, 2] == 4)
    assert np.all(q % 2 == 0)                    # every contact enters and leaves


def test_follow_on_an_elastic_plane():
    """--follow: the points after the first of a row start from the previous run's last
    event (state, phase, contacts) where it reached an attractor; the first never does."""
    from symvi.simulations.simulation import classify_walked
    spec = _spec(follow=True)
    pts = [spec.point(i, j) for i in range(2) for j in range(3)]
    res = classify_walked(pts, 60, 300, follow=True, row_len=3)
    assert not res.followed[0] and not res.followed[3]
    assert res.followed[1] and res.followed[2]   # after chaos, after a periodic orbit
    # a followed run starts on its neighbour's attractor: the 1-4 orbit at omega = 1.3
    assert list(res.labels()[[2, 5]]) == ["period-1"] * 2
    assert list(res.impacts[[2, 5]]) == [4, 4]


def test_cli_plane_of_an_elastic_model_and_its_bad_input(tmp_path):
    out = tmp_path / "e.zarr"
    rc, text, err = cli("plane", "--model", str(ELASTIC_FILE), "--x", X, "--y", Y,
                        "--impacts", "60", "--transient", "300", "--out", str(out),
                        "--workers", "0", "--json")
    assert rc == 0, err
    counts = json.loads(text)["attractors"]
    ref = compute_serial(_spec())["attractor"].ravel().tolist()
    assert counts == {k: ref.count(k) for k in set(ref)}
    # a floor of 4 records per symbol (two elastic stops: entries and exits, 16)
    rc, text, err = cli("plane", "--model", str(ELASTIC_FILE), "--x", X, "--y", Y,
                        "--impacts", "15", "--transient", "300", "--out",
                        str(tmp_path / "f.zarr"), "--workers", "0")
    assert rc == 2 and text == "" and len(err.strip().splitlines()) == 1
    assert "--impacts" in err and "16" in err
    with pytest.raises(ParameterError, match="--impacts"):
        _spec(impacts=15)


def test_a_contact_phase_resonance_on_the_grid_is_refused():
    """omega at a natural frequency of an undamped contact phase (x'' + (1 + 50) x = ...:
    sqrt(51)) is refused before any run, in one line, naming the flag; beside it is not."""
    from symvi.model import Model, Stop
    m = Model(mass=[1.0], stiffness=[[1.0]], damping=[[0.0]], forcing=[1.0],
              stop=Stop(mass=1, gap=0.5, stiffness=50.0, damping=0.0))
    w = 51 ** 0.5
    PlaneSpec(model=m, x=parse_axis(f"omega:{w + 0.1}:{w + 0.5}:2", "--x"),
              y=parse_axis("stop[1].gap:0.4:0.6:2", "--y"), impacts=60, transient=10)
    with pytest.raises(ParameterError, match="contact phases") as exc:
        PlaneSpec(model=m, x=parse_axis(f"omega:{w}:{w + 0.5}:2", "--x"),
                  y=parse_axis("stop[1].gap:0.4:0.6:2", "--y"), impacts=60, transient=10)
    assert "--x" in str(exc.value) and "\n" not in str(exc.value)
