"""``symvi sweep --classify`` and ``sweep(..., classify=True)`` (issue 24, item 5): the
sweep labels each omega with the one classifier, and agrees with ``simulate --classify``.

Example 1 of the paper (b = 1.5, r = 0.8): the period-1 orbit is stable below the
Neimark-Sacker point omega ~ 0.7368 and an invariant circle is born there; at
omega = 0.738 the run from y* spirals out for ~2500 impacts, then settles on the circle
(tests/simulations/test_classifier.py)."""
import json

import numpy as np
import pytest

from symvi import Params
from symvi.cli import main
from symvi.errors import ParameterError
from symvi.simulations import classifier as cl
from symvi.simulations.diagnostics import classify
from symvi.simulations.simulation import classify_sweep, simulate, sweep

EX1 = ["--mu-m", "2", "--mu-k", "5", "--f2", "0", "--b", "1.5", "--r", "0.8"]
P = Params(2, 5, 0, 1.5, 0.8)


def test_sweep_classes_agree_with_simulate_classify():
    res = sweep(P, [0.72, 0.738], n_impacts=1000, transient=2000, classify=True)
    assert list(res.labels()) == ["period-1", "circle"]
    # the same runs as the sweep's: each ends on the sweep's last stored point
    last = res.section[np.arange(2), res.counts - 1]
    assert np.array_equal(res.classes.y_end, last)
    # simulate --classify (5000 impacts from the same start) says the same at both omegas
    for i, w in enumerate((0.72, 0.738)):
        mine = classify(simulate(P, w))
        assert mine.code == res.classes.code[i], (w, mine)
    assert classify(simulate(P, 0.738)).kind == "invariant circle"
    assert res.classes.code[1] == cl.CIRCLE and cl.kind(cl.CIRCLE, 0) == "invariant circle"


def test_unclassified_sweep_is_unchanged():
    plain = sweep(P, [0.72, 0.738], n_impacts=50, transient=100)
    both = sweep(P, [0.72, 0.738], n_impacts=50, transient=100, classify=True)
    assert plain.classes is None and plain.labels() is None
    assert np.array_equal(plain.section, both.section)
    assert list(classify_sweep(plain).code) == list(both.classes.code)


def test_too_few_impacts_to_classify_is_refused():
    with pytest.raises(ParameterError, match="n_impacts"):
        sweep(P, [0.72, 0.738], n_impacts=3, transient=10, classify=True)


def test_cli_sweep_classify_adds_keys_only(tmp_path, capsys):
    argv = ["sweep", *EX1, "--range", "omega=0.72:0.738:2",
            "--impacts", "1000", "--transient", "2000"]
    assert main([*argv, "--out", str(tmp_path / "a.npz")]) == 0
    plain = json.loads(capsys.readouterr().out)
    assert main([*argv, "--out", str(tmp_path / "b.npz"), "--classify"]) == 0
    got = json.loads(capsys.readouterr().out)
    assert got["classes"] == ["period-1", "circle"]
    assert got["class_counts"] == {"circle": 1, "period-1": 1}
    assert "classes" not in plain
    plain["outputs"] = got["outputs"]
    assert {k: v for k, v in got.items() if k not in ("classes", "class_counts")} == plain
    with np.load(tmp_path / "b.npz") as z:
        assert list(z["classes"]) == ["period-1", "circle"]


def test_cli_sweep_classify_needs_four_impacts(tmp_path, capsys):
    rc = main(["sweep", *EX1, "--range", "omega=0.72:0.738:2",
               "--impacts", "3", "--out", str(tmp_path / "a.npz"), "--classify"])
    assert rc == 2
    assert "--impacts" in capsys.readouterr().err


def test_run_sweep_classifies_as_sweep_does():
    """The engine's sweep with ``classify`` (what ``symvi sweep --classify`` calls): the
    same classes as one call of ``sweep``, and their counts by name."""
    from symvi.plane.engine import run_sweep
    one = sweep(P, [0.72, 0.738], n_impacts=1000, transient=2000, classify=True)
    res = run_sweep(P, [0.72, 0.738], n_impacts=1000, transient=2000, workers=0,
                    classify=True)
    assert list(res.labels()) == list(one.labels()) == ["period-1", "circle"]
    assert res.class_counts() == {"circle": 1, "period-1": 1}
    assert run_sweep(P, [0.72, 0.738], n_impacts=5, transient=10, workers=0).class_counts() \
        is None
    with pytest.raises(ParameterError, match="n_impacts"):
        run_sweep(P, [0.72, 0.738], n_impacts=3, transient=10, workers=0, classify=True)


def test_omega_grid_checks_every_point_naming_the_arguments():
    from symvi import modal
    from symvi.simulations.simulation import omega_grid
    assert np.array_equal(omega_grid(P, 0.7, 0.76, 4), np.linspace(0.7, 0.76, 4))
    w2 = modal(P).omega2
    with pytest.raises(ParameterError, match=r"steps = 3 .*grid point 1 is omega = "):
        omega_grid(P, 0.5, 2 * w2 - 0.5, 3)                # the midpoint: omega_2
    with pytest.raises(ParameterError, match=r"--steps = 3 .*\(--a, --b, --steps\)"):
        omega_grid(P, 0.5, 2 * w2 - 0.5, 3, names={"omega_min": "--a", "omega_max": "--b",
                                                   "steps": "--steps"})
    with pytest.raises(ParameterError, match="omega_max = 0.7 .*greater than omega_min"):
        omega_grid(P, 0.8, 0.7, 3)
