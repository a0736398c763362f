"""``symvi continue`` on models with several stops (issue 25, items 3 and 5): started from
the attractor a simulation settles on, its signature and symmetry named in text and JSON,
the asymmetric branches followed with --switch, the worked examples' files read."""
import json
import pathlib

from ..fuzz._cli import cli

EXAMPLES = pathlib.Path(__file__).resolve().parents[2] / "examples" / "contacts"
SYM = EXAMPLES / "oscillator_two_stops.toml"


def test_continue_a_symmetric_orbit_json(tmp_path):
    rc, out, err = cli("continue", "--model", str(SYM), "--range", "omega=1.0:1.6", "--switch", "--json")
    assert rc == 0, err
    d = json.loads(out)
    main = d["branches"][0]
    assert main["orbit"] == "1-2" and sorted(main["signature"]) == ["stop1", "stop2"]
    assert "signature" in main["notes"][0] and "simulation" in main["notes"][0]
    pts = [p for p in d["points"] if p["branch"] == 0]
    assert all(p["symmetric"] for p in pts) and all(len(p["signature"]) == 2 for p in pts)
    sb = [s for s in d["special"] if s["kind"] == "symmetry-breaking"]
    assert len(sb) == 2 and all(abs(s["coefficients"]["half_multiplier"] + 1) < 1e-9
                                for s in sb)
    # the switched branches: asymmetric orbits
    others = [p for p in d["points"] if p["branch"] > 0]
    assert others and not any(p["symmetric"] for p in others[len(others) // 2:][:5])


def test_continue_text_names_signature_and_symmetry():
    rc, out, err = cli("continue", "--model", str(SYM), "--range", "omega=1.0:1.2")
    assert rc == 0, err
    assert "1-2 orbits (signature stop" in out and "symmetric)" in out
    assert "symmetry-breaking omega = 1.0082738" in out


def test_no_attractor_anywhere_is_one_line(tmp_path):
    """A start where the run never settles and no value towards the stop where it does:
    exit 2, one line naming --from."""
    f = tmp_path / "stuck.toml"
    # undamped: the run never settles on an attractor
    f.write_text(SYM.read_text().replace("damping = [[0.05]]", "damping = [[0.0]]"))
    rc, out, err = cli("continue", "--model", str(f), "--range", "omega=1.3:1.31")
    assert rc == 2 and out == "" and len(err.strip().splitlines()) == 1
    assert "--range" in err and "Traceback" not in err


def test_the_worked_examples_are_current():
    """Each worked example's JSON is what its model file gives today (the command in
    examples/contacts/README.md): the same branches, signatures and special points."""
    for name in ("oscillator_two_stops", "oscillator_elastic", "chain3_two_stops",
                 "impact_damper"):
        d = json.loads((EXAMPLES / f"{name}.json").read_text())
        args = [str(EXAMPLES / pathlib.Path(a).name) if a.endswith(".toml") else a
                for a in d["command"]]
        rc, out, err = cli(*args)
        assert rc == 0, err
        now = json.loads(out)
        assert [b["signature"] for b in now["branches"]] == \
            [b["signature"] for b in d["branches"]]
        assert [(s["kind"], s["branch"]) for s in now["special"]] == \
            [(s["kind"], s["branch"]) for s in d["special"]]
        for a, b in zip(now["special"], d["special"]):
            assert abs(a["value"] - b["value"]) < 1e-9


def test_orbit_of_a_two_stop_model():
    """symvi orbit with no closed form: the attractor, its n-p and signature, in JSON."""
    rc, out, err = cli("orbit", "--model", str(SYM), "--omega", "1.0", "--json")
    assert rc == 0, err
    o = json.loads(out)["orbits"][0]
    assert (o["n"], o["p"]) == (1, 2) and sorted(o["signature"]) == ["stop1", "stop2"]
    assert o["symmetric"] is True and o["admissible"] and o["residual"] < 1e-12
    assert "attractor" in o["found"]
    rc, out, err = cli("orbit", "--model", str(SYM), "--omega", "1.0")
    assert rc == 0 and "1-2 orbit, signature" in out and "symmetric" in out


def test_orbit_and_branch_of_an_elastic_model():
    """Elastic stops in orbit and continue: the attractor's events name their kind
    (stop1:entry, stop1:exit), and a branch in one stop's stiffness carries them in its
    JSON up to its end (the symmetry is lost as soon as the stiffnesses differ)."""
    el = EXAMPLES / "oscillator_elastic.toml"
    rc, out, err = cli("orbit", "--model", str(el), "--omega", "2.0", "--json")
    assert rc == 0, err
    o = json.loads(out)["orbits"][0]
    assert (o["n"], o["p"]) == (1, 4) and o["symmetric"] is True
    assert sorted(o["signature"]) == ["stop1:entry", "stop1:exit", "stop2:entry",
                                      "stop2:exit"]
    assert o["admissible"] and o["residual"] < 1e-12
    rc, out, err = cli("continue", "--model", str(el), "--range", "stop[1].stiffness=50:80", "--set", "omega=2.0", "--json")
    assert rc == 0, err
    d = json.loads(out)
    assert d["branches"][0]["signature"] == o["signature"]
    assert "reached stop[1].stiffness = 80" in d["branches"][0]["end"]
    pts = d["points"]
    assert pts[0]["symmetric"] and not pts[-1]["symmetric"]
    assert all(p["admissible"] for p in pts) and abs(pts[-1]["value"] - 80.0) < 1e-9


def test_orbit_without_attractor_is_one_line(tmp_path):
    f = tmp_path / "stuck.toml"
    f.write_text(SYM.read_text().replace("damping = [[0.05]]", "damping = [[0.0]]"))
    rc, out, err = cli("orbit", "--model", str(f), "--omega", "1.3")
    assert rc == 2 and out == "" and len(err.strip().splitlines()) == 1
    assert "settles on no periodic orbit" in err


def test_simulate_an_elastic_stop_from_the_command_line(tmp_path):
    """symvi simulate runs a model with an elastic stop beside a rigid one (the walk
    through contact phases): the impacts and contact entries on each stop."""
    f = tmp_path / "el.toml"
    f.write_text(SYM.read_text().replace("gap = 0.5\nrestitution = 0.9",
                                         "gap = 0.5\nstiffness = 50.0\ndamping = 0.5"))
    rc, out, err = cli("simulate", "--model", str(f), "--omega", "1.2", "--y0", "0.5", "0",
                       "--impacts", "100", "--out", str(tmp_path / "el.npz"))
    assert rc == 0, err
    d = json.loads(out)
    assert d["stop"] == "completed" and sum(d["impacts_per_stop"]) == 100
    assert min(d["impacts_per_stop"]) > 0


def test_sweep_of_a_two_stop_model(tmp_path):
    """symvi sweep starts each omega of a several-stop model from the default start on
    stop 1; --classify labels each omega and names each periodic attractor's stops."""
    out = tmp_path / "sw.npz"
    rc, text, err = cli("sweep", "--model", str(SYM), "--range", "omega=1.0:2.0:6", "--out", str(out))
    assert rc == 0, err
    assert json.loads(text)["stops"] == {"completed": 6} and out.exists()
    rc, text, err = cli("sweep", "--model", str(SYM), "--range", "omega=1.0:2.0:6", "--out", str(tmp_path / "c.npz"), "--classify")
    assert rc == 0, err
    d = json.loads(text)
    assert len(d["classes"]) == len(d["signatures"]) == 6 and (tmp_path / "c.npz").exists()
    assert d["classes"][-1] == "period-1" and d["signatures"][-1] == ["stop1", "stop2"]


def test_hopf_of_a_several_stop_model_is_an_uncertified_branch_scan():
    """symvi hopf with no period-1 closed form: the NS points of the branches continued
    from the attractors found in the interval, each once, the same point as symvi continue
    locates (the impact damper's supercritical NS), and said not to be certified."""
    damper = EXAMPLES / "impact_damper.toml"
    rc, out, err = cli("hopf", "--model", str(damper), "--range", "omega=0.8:1.2", "--json")
    assert rc == 0, err
    d = json.loads(out)
    assert d["complete"] is False and d["uncertified"] == [[0.8, 1.2]]
    assert "not searched" in d["uncertified_reasons"][0]
    ns = [p for p in d["points"] if p["kind"] == "ns"]
    assert len(ns) == 1 and ns[0]["coefficients"]["l1"] < 0
    ref = json.loads((EXAMPLES / "impact_damper.json").read_text())
    want = [s["value"] for s in ref["special"] if s["kind"] == "ns"]
    assert abs(ns[0]["value"] - want[0]) < 1e-9
    rc, out, err = cli("hopf", "--model", str(damper), "--range", "omega=0.8:1.2")
    assert rc == 0 and "NOT CERTIFIED" in out and "NS point 1" in out
    for bad in (["--range", "omega=1.2:0.8"],
                ["--range", "omega=0.8:1.2", "--digits", "40"]):
        rc, out, err = cli("hopf", "--model", str(damper), *bad)
        assert rc == 2 and out == "" and len(err.strip().splitlines()) == 1
