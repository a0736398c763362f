"""Lyapunov exponents and attractor classes of runs with elastic stops (issue 25): per
event (impact, entry, exit), the map Jacobians DP_i from the shooting system
(diagnostics.event_jacobians), checked against the orbits Newton refines from the same
runs (their multipliers, n-p and signature), and sweeps judged point by point."""
import math

import numpy as np
import pytest

from symvi.model import Signature
from symvi.orbits.periodic import Problem, from_simulation
from symvi.plane.engine import run_sweep
from symvi.simulations import diagnostics as dg
from symvi.simulations.simulation import contact_run, sweep
from tests.orbits.test_elastic_orbits import CHAIN, MIX, ONE, _orbit

CASES = {"one": (ONE, 1.2), "mix": (MIX, 1.3), "chain-1-6": (CHAIN, 0.9),
         "chain-1-3": (CHAIN, 1.3)}


@pytest.fixture(scope="module", params=sorted(CASES))
def settled(request):
    """(model, omega, a run settled on its orbit, the orbit Newton refines from it)."""
    model, omega = CASES[request.param]
    sim = contact_run(model, omega, 120, 400)
    return model, omega, sim, from_simulation(sim.events)


def _rotation_of(names, ref):
    return any(list(names) == list(ref[i:]) + list(ref[:i]) for i in range(len(ref)))


def test_lyapunov_exponents_of_a_periodic_elastic_orbit():
    """On the 1-2 orbit of one mass against an elastic stop (entry, exit) the exponents per
    event sum to log |det M| / p (the product of whole periods of DP_i is the monodromy)
    and each is log |mu_i| / p within 0.02 (the finite-time QR mean of a complex pair)."""
    orbit = _orbit(ONE, 1.2)
    sim = contact_run(ONE, 1.2, 200, 600)
    lya = dg.lyapunov(sim)
    assert lya.n % orbit.p == 0 and lya.n > 100
    det = math.log(abs(np.prod(orbit.multipliers))) / orbit.p
    assert abs(lya.exponents.sum() - det) < 1e-10
    mu = np.sort(np.log(np.abs(orbit.multipliers)) / orbit.p)[::-1]
    assert np.max(np.abs(lya.exponents - mu)) < 0.02


def test_the_event_jacobians_compose_to_the_monodromy(settled):
    """p consecutive DP_i of the run (chunks of the shooting system cut at a repeated
    (stop, phase)) multiply to a matrix with the orbit's multipliers: rigid impacts,
    entries and exits, one mass or two, in the free flow and in contact."""
    model, omega, sim, orbit = settled
    mats, te = dg.event_jacobians(sim.events)
    assert len(mats) >= 2 * orbit.p and np.all(te > 0)
    M = np.eye(mats.shape[1])
    for D in mats[-orbit.p:]:
        M = D @ M
    got = np.sort_complex(np.linalg.eigvals(M))
    want = np.sort_complex(np.asarray(orbit.multipliers, dtype=complex))
    assert np.max(np.abs(got - want)) < 1e-4      # the run still settles (mix: 0.87)


def test_each_jacobian_uses_only_its_own_flight(settled):
    """The claim event_jacobians rests on: in a chunk's shooting system DP_i depends on
    flight i alone, so the chunk's wrap-around residual (the last flight back to point 0,
    never closed) does not enter: moving point j (or the periods n of the wrap-around)
    changes DP_j only, every other DP_i bit for bit."""
    model, omega, sim, orbit = settled
    ev = sim.events
    a, K = 11, orbit.p                  # one period from an event: a valid signature
    sig = Signature(tuple(int(h) for h in ev.hits[a:a + K]), contact=ev.active[a])
    Y = np.array(ev.section[a:a + K])
    T = np.diff(ev.t[a:a + K + 1])
    for i in range(1, K):               # tau unwrapped along the chunk
        Y[i, -1] += 2 * math.pi * round((Y[0, -1] + omega * (ev.t[a + i] - ev.t[a])
                                         - Y[i, -1]) / (2 * math.pi))
    u = np.concatenate([Y.ravel(), T])

    def run(n, u):
        pr = Problem(model, n=n, p=K, omega=omega, signature=sig)
        G, Gu, _ = pr.evaluate(u, None)
        return G, pr.monodromy(u, Gu)[0]
    G, base = run(orbit.n, u)
    assert np.max(np.abs(G)) < 1e-5             # the run's points close the orbit
    G, other = run(orbit.n + 2, u)
    assert np.max(np.abs(G)) > 1.0              # the wrap-around is 4 pi off
    for D0, D1 in zip(base, other):
        assert np.array_equal(D0, D1)
    d = Y.shape[1]
    for j in range(K):                  # the first and the last point too
        v = u.copy()
        v[j * d] += 1e-3
        moved = run(orbit.n, v)[1]
        for i in range(K):
            assert np.array_equal(moved[i], base[i]) == (i != j), (i, j)


def test_classes_agree_with_the_refined_orbit(settled):
    """classify judges every event with its (stop, kind): a periodic attractor reports the
    n-p of the orbit Newton refines from the same run, its signature names (a rotation of
    Signature.names) and per-event exponents near log |mu_i| / p."""
    model, omega, sim, orbit = settled
    cl = dg.classify(sim)
    assert cl.kind == f"period-{orbit.n}" and cl.label == f"period-{orbit.n}"
    assert (cl.period, cl.impacts) == (orbit.n, orbit.p)
    assert _rotation_of(cl.signature_names, orbit.signature_names)
    assert cl.signature_names == [f"stop{k + 1}" + ("" if kd == "impact" else f":{kd}")
                                  for k, kd in zip(cl.signature, cl.kinds)]
    mu = np.sort(np.log(np.abs(orbit.multipliers)) / orbit.p)[::-1]
    assert np.max(np.abs(cl.lyapunov.exponents - mu)) < 0.02


def test_one_elastic_stop_judges_its_entries():
    """Entries and exits are two symbols: a 1-2 orbit (entry, exit) is q = 2 events in one
    period, its signature ("stop1:entry", "stop1:exit")."""
    cl = dg.classify(contact_run(ONE, 1.2, 100, 600))
    assert cl.signature_names == ["stop1:entry", "stop1:exit"]
    assert dg.event_symbols(MIX) == ((0, "entry"), (0, "exit"), (1, "impact"))


def test_sweep_classes_are_each_omegas_classification():
    """sweep(classify=True) of an elastic + rigid model: each omega's class, signature and
    largest exponent are those of classify on the same walk (contact_run from the default
    start), and the engine's run_sweep gives the same Sweep."""
    omegas = [1.0, 1.3]
    res = sweep(MIX, omegas, n_impacts=80, transient=300, classify=True)
    for i, w in enumerate(omegas):
        sim = contact_run(MIX, w, 80, 300)
        assert np.array_equal(res.section[i, :res.counts[i]], sim.section)
        cl = dg.classify(sim, max_period=64)
        assert res.labels()[i] == cl.label
        assert res.signatures()[i] == cl.signature_names
    assert res.labels()[1] == "period-2"
    eng = run_sweep(MIX, omegas, n_impacts=80, transient=300, workers=0, classify=True)
    assert np.array_equal(eng.section, res.section, equal_nan=True)
    assert list(eng.labels()) == list(res.labels())
    assert np.array_equal(eng.classes.lyapunov, res.classes.lyapunov, equal_nan=True)


def test_cli_sweep_of_an_elastic_model(tmp_path):
    """symvi sweep [--classify] runs an elastic model (one walk per omega from the default
    start) and prints each periodic attractor's events; too few records for its symbols
    (4 per entry or exit) is refused in one line."""
    import json

    from tests.cli.test_cli_itinerary import EXAMPLES
    from tests.fuzz._cli import cli
    f = str(EXAMPLES / "oscillator_elastic.toml")
    rc, text, err = cli("sweep", "--model", f, "--range", "omega=1.2:1.3:2", "--impacts", "40", "--transient", "300",
                        "--classify", "--out", str(tmp_path / "s.npz"))
    assert rc == 0, err
    got = json.loads(text)
    assert got["classes"] == ["period-1", "period-1"] and got["stops"] == {"completed": 2}
    assert got["signatures"][1] == ["stop1:entry", "stop1:exit", "stop2:entry", "stop2:exit"]
    rc, text, err = cli("sweep", "--model", f, "--range", "omega=1.2:1.3:2", "--impacts", "40", "--out", str(tmp_path / "t.npz"))
    assert rc == 0, err
    rc, text, err = cli("sweep", "--model", f, "--range", "omega=1.2:1.3:2", "--impacts", "15", "--classify",
                        "--out", str(tmp_path / "u.npz"))
    assert rc == 2 and text == "" and len(err.strip().splitlines()) == 1
    assert "entries and exits" in err
