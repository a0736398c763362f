"""The one classifier on models with several rigid stops (issue 25): the period of the
joint sequence (stop hit, section point), the signature of a periodic attractor, the
quasi-periodic and chaotic judgement on the section of the stop hit most often; the
plane's batch, ``simulate --classify`` and ``sweep --classify`` agree, and the one-stop
path is untouched.  Independent checks: the orbit refined by Newton on the simulation
(``orbits.periodic.from_simulation``: its n-p, signature and symmetry) and the QR
Lyapunov spectrum of the run."""
import json

import numpy as np
import pytest

from symvi import simulate
from symvi.flow import compiled as cf
from symvi.model import load_model
from symvi.orbits.periodic import from_simulation
from symvi.simulations import classifier as cl
from symvi.simulations import diagnostics as dg
from symvi.simulations.simulation import default_start, sweep
from tests.cli.test_cli_itinerary import SYM as SYM_FILE
from tests.continuation.test_itinerary_normal_forms import chain
from tests.fuzz._cli import cli

#: examples/contacts/oscillator_two_stops.toml: 1-DOF between rigid stops at +-0.5;
#: symmetry-breaking pitchforks of its symmetric 1-2 orbit at omega = 1.0083 and 1.5745
SYM = load_model(SYM_FILE)


def _batch(model, omegas, n_keep=1000, transient=3000):
    """classify_runs (the plane's path) from the default start on stop 1."""
    C = np.array([cf.constants(model, w) for w in omegas])
    Y0 = np.array([default_start(model, w) for w in omegas])
    return cl.classify_runs(C, Y0, n_keep, transient)


def _sim(model, omega, n=1000, transient=3000):
    return simulate(model, omega, y0=default_start(model, omega), n_impacts=n,
                    transient=transient)


def test_symmetric_orbit_is_1_2_with_signature_stop1_stop2():
    """omega = 2.0 (past the pitchfork at 1.5745): the symmetric 1-2 orbit is the
    attractor.  Both callers say period-1 with 2 impacts, signature [stop1, stop2]; the
    orbit Newton refines from the run is the symmetric 1-2 orbit, and every exponent is
    negative."""
    r = _batch(SYM, [2.0])
    assert r.labels()[0] == "period-1" and r.impacts[0] == 2
    assert r.signature == ((0, 1),) and r.signature_names() == [["stop1", "stop2"]]
    sim = _sim(SYM, 2.0)
    c = dg.classify(sim)
    assert c.label == "period-1" and c.impacts == 2 and c.signature == (0, 1)
    assert c.signature_names == ["stop1", "stop2"]
    assert max(c.lyapunov.exponents) < -0.05
    o = from_simulation(sim)
    assert (o.n, o.p) == (1, 2) and sorted(o.signature) == [0, 1] and o.symmetric is True
    # the plane's exponent (tangent map along the run) and the QR spectrum's largest
    assert abs(r.lyapunov[0] - c.lyapunov.largest) < 1e-3


def test_asymmetric_orbits_between_the_pitchforks():
    """Between the pitchforks the symmetric orbit is unstable: at omega = 1.45 the run
    settles on an asymmetric 1-2 orbit (signature [stop1, stop2], its two impact speeds
    differ), at 1.34 on a 1-3 orbit hitting stop 1 twice, at 1.26 on a 2-5 orbit (two
    forcing periods); each as Newton's orbit from the same run says."""
    r = _batch(SYM, [1.45, 1.34, 1.26])
    assert list(r.labels()) == ["period-1", "period-1", "period-2"]
    assert list(r.impacts) == [2, 3, 5]
    assert r.signature == ((0, 1), (0, 0, 1), (0, 0, 1, 0, 1))
    for w, k, q, sig in zip([1.45, 1.34, 1.26], r.period, r.impacts, r.signature):
        o = from_simulation(_sim(SYM, w))
        assert (o.n, o.p) == (k, q)
        assert cl.signature(o.signature) == sig
    o = from_simulation(_sim(SYM, 1.45))
    assert o.symmetric is False
    v = sorted(abs(float(y[0])) for y in o.points)         # the speeds leaving each stop
    assert v[1] - v[0] > 0.05


def test_period_doubled_orbit_of_a_two_stop_chain():
    """The chain of examples/contacts/chain3_two_stops.toml (gaps 0.4, -0.6): its 1-1
    orbit on stop 1 flips at omega = 1.23448 (supercritical); just before it a run settles
    on the doubled 2-2 orbit (tests/continuation/test_itinerary_normal_forms.py), stop 2
    untouched: period-2, 2 impacts, signature [stop1, stop1]."""
    m = chain(0.4, -0.6)
    w = 1.2344752970188386 - 1.6e-3
    r = _batch(m, [w], n_keep=400, transient=60000)
    assert r.labels()[0] == "period-2" and r.impacts[0] == 2 and r.signature == ((0, 0),)
    assert r.lyapunov[0] < 0


def test_circle_and_chaos_on_several_stops():
    """Quasi-periodic and chaotic attractors are judged on one stop's section.  The chain
    with gaps 0.6, -0.3 has supercritical NS points of its 1-2 orbit at omega = 1.36971 and
    1.43835 (unstable between them): at 1.435 and 1.37 a closed curve, exponent ~ 0.  The
    oscillator at 1.1 (symmetric orbit unstable, no asymmetric one) is chaotic: the QR
    spectrum's largest exponent is clearly positive."""
    m = chain(0.6, -0.3)
    r = _batch(m, [1.435, 1.37], n_keep=2000, transient=20000)
    assert list(r.labels()) == ["circle", "circle"]
    assert np.all(np.abs(r.lyapunov) < 2e-3) and r.signature == ((), ())
    c = _batch(SYM, [1.1])
    assert c.labels()[0] == "chaos" and c.signature == ((),)
    s = dg.classify(_sim(SYM, 1.1, n=2000))
    assert s.label == "chaos" and s.signature is None and s.lyapunov.largest > 0.1


def test_mixed_sections_are_not_one_curve():
    """Why one stop's section: the circle at 1.435 judged on all its points (two stops'
    sections in one space, as the old path did) is not one closed curve."""
    m = chain(0.6, -0.3)
    sim = simulate(m, 1.435, y0=default_start(m, 1.435), n_impacts=2000, transient=20000)
    logs = np.zeros(0)
    mixed = cl.classify_section(sim.section, sim.t, sim.omega, logs)[0]
    joint = cl.classify_section(sim.section, sim.t, sim.omega, logs, hits=sim.hits)[0]
    assert joint == cl.CIRCLE and mixed != cl.CIRCLE


def test_one_stop_path_is_unchanged_by_hits():
    """A run on one section, given its hits (all 0), is judged bit for bit as without them
    (example 1 just past its NS point: a circle)."""
    from tests.zoo import PAPER_EX1
    from symvi.simulations import simulation
    sim = simulation.simulate(PAPER_EX1, 0.738, n_impacts=2000)
    logs = dg._logs(sim, 4000)[0][:, 0]
    a = cl.classify_section(sim.section, sim.t, sim.omega, logs)
    b = cl.classify_section(sim.section, sim.t, sim.omega, logs, hits=sim.hits)
    assert a[0] == cl.CIRCLE and np.array_equal(np.array(a), np.array(b))
    assert len(set(sim.hits)) == 1


def test_signature_is_read_from_its_smallest_rotation():
    assert cl.signature([1, 0]) == cl.signature([0, 1]) == (0, 1)
    assert cl.signature([1, 0, 0]) == (0, 0, 1)
    assert cl.signature([]) == ()


def test_follow_continues_on_the_stop_it_ended_on():
    """follow=True along a row of several-stop points: a followed point starts from the
    previous point's y_end on the stop that run ended on (k_end), not on stop 1: the same
    run as the shared loop started there by hand."""
    ws = [1.9, 2.0]
    C = np.array([cf.constants(SYM, w) for w in ws])
    Y0 = np.array([default_start(SYM, w) for w in ws])
    r = cl.classify_runs(C, Y0, 200, 1001, follow=True)
    assert list(r.followed) == [False, True]
    assert list(r.labels()) == ["period-1", "period-1"]
    _, sec, _, _, _, hits = cf.run(C[0], Y0[0], 200, 1001, hits=True)
    assert hits[-1] == 1 and r.k_end[0] == 1          # ended on stop 2's section
    assert np.array_equal(sec[-1], r.y_end[0])
    _, sec, _, _, _, hits = cf.run(C[1], r.y_end[0], 200, 1001, k=1, hits=True)
    assert np.array_equal(sec[-1], r.y_end[1]) and r.k_end[1] == hits[-1]
    assert cl.signature(hits[-2:]) == r.signature[1] == (0, 1)


def test_sweep_classify_of_a_two_stop_model():
    """sweep(classify=True) of a several-stop model: one label and signature per omega,
    the same as the batch from the same starts."""
    ws = [1.34, 1.45, 2.0]
    res = sweep(SYM, ws, n_impacts=1000, transient=3000, classify=True)
    ref = _batch(SYM, ws)
    assert list(res.labels()) == list(ref.labels()) == ["period-1"] * 3
    assert res.signatures() == [["stop1", "stop1", "stop2"], ["stop1", "stop2"],
                                ["stop1", "stop2"]]
    with pytest.raises(Exception, match="4 per stop"):
        sweep(SYM, ws, n_impacts=7, transient=10, classify=True)


def test_cli_simulate_and_sweep_classify(tmp_path):
    """simulate --classify and sweep --classify take the two-stop file: the class, the
    impacts per orbit and the signature in JSON; one-stop keys are unchanged."""
    out = tmp_path / "s.npz"
    rc, text, err = cli("simulate", "--model", str(SYM_FILE), "--omega", "2.0", "--y0",
                        "-0.2", "0", "--impacts", "1000", "--transient", "3000", "--out",
                        str(out), "--classify")
    assert rc == 0, err
    d = json.loads(text)
    assert d["attractor"] == "period-1" and d["impacts_per_orbit"] == 2
    assert d["signature"] == ["stop1", "stop2"] and d["impacts_per_stop"] == [500, 500]
    assert max(d["lyapunov"]) < 0
    rc, text, err = cli("sweep", "--model", str(SYM_FILE), "--range", "omega=1.34:2.0:3", "--impacts", "1000",
                        "--transient", "3000", "--out", str(tmp_path / "w.npz"), "--classify")
    assert rc == 0, err
    d = json.loads(text)
    assert d["classes"] == ["period-1"] * 3
    assert d["signatures"][0] == ["stop1", "stop1", "stop2"]
    assert d["signatures"][2] == ["stop1", "stop2"]
    rc, text, err = cli("sweep", "--model", str(SYM_FILE), "--range", "omega=1.34:2.0:3", "--impacts", "6",
                        "--out", str(tmp_path / "x.npz"), "--classify")
    assert rc == 2 and len(err.strip().splitlines()) == 1 and "--impacts" in err
    assert "4 per stop" in err and not (tmp_path / "x.npz").exists()


def test_an_elastic_stop_is_classified_too(tmp_path):
    """An elastic stop beside a rigid one (issue 25): simulate --classify names the events
    of its orbit ("stop1:entry", "stop1:exit", "stop2"), the Python classify agrees, and a
    too short run is still refused in one line (exit 2)."""
    f = tmp_path / "el.toml"
    f.write_text(SYM_FILE.read_text().replace("gap = 0.5\nrestitution = 0.9",
                                              "gap = 0.5\nstiffness = 50.0\ndamping = 0.5"))
    out = tmp_path / "el.npz"
    rc, text, err = cli("simulate", "--model", str(f), "--omega", "1.2", "--y0", "0.5", "0",
                        "--impacts", "100", "--transient", "300", "--out", str(out),
                        "--classify")
    assert rc == 0, err
    got = json.loads(text)
    m = load_model(f)
    sim = simulate(m, 1.2, y0=(0.5, 0.0), n_impacts=100, transient=300)
    cl = dg.classify(sim)
    assert got["class"] == cl.kind and got.get("signature") == cl.signature_names
    assert dg.classifiable(m) and dg.classifiable(SYM)
    if cl.signature is not None:
        assert any(":entry" in n for n in cl.signature_names)
    rc, text, err = cli("simulate", "--model", str(f), "--omega", "1.2", "--y0", "0.5", "0",
                        "--impacts", "10", "--out", str(out), "--classify")
    assert rc == 2 and text == "" and len(err.strip().splitlines()) == 1


def test_rotation_is_per_return_to_the_judged_stop():
    """On the chain's circle at omega = 1.435 the rotation is measured per return to one
    stop: each stop is hit once per turn of the 1-2 orbit, so it is that of the orbit's
    monodromy (P over both impacts) near the NS point: its critical pair at 1.435 has
    arg / 2 pi = 0.4104 (|multiplier| 1.019; continue_orbits from 1.445)."""
    m = chain(0.6, -0.3)
    r = _batch(m, [1.435], n_keep=2000, transient=20000)
    assert abs(r.rotation[0] - 0.4104) < 5e-3
