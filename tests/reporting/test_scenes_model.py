"""Scenes on any model: ``model = "FILE"`` in [params], ``symvi run --model``, and the
paper-only outputs refused for a model."""
import subprocess
import sys

import pytest

from symvi.model import dumps
from symvi.reporting.scenes import SceneError, load_scene, with_model

from tests.zoo import PAPER_EX1, THREE_STOP2_GAP05

SCENE = """[scene]
name = "chain3"
title = "Damped 3-mass chain"

[params]
model = "m.toml"

[[output]]
kind = "multipliers"
omega_min = 0.9
omega_max = 1.0
steps = 12

[[output]]
kind = "hopf"
omega_min = 0.99
omega_max = 1.02

[[output]]
kind = "section"
omega = 0.95
impacts = 200
transient = 200
"""


def test_scene_with_a_model_file_runs(tmp_path):
    (tmp_path / "m.toml").write_text(dumps(THREE_STOP2_GAP05))
    f = tmp_path / "s.toml"
    f.write_text(SCENE)
    r = subprocess.run([sys.executable, "-m", "symvi", "run", str(f), "--out",
                        str(tmp_path / "out")], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    md = (tmp_path / "out" / "report.md").read_text()
    assert "0.999711422" in md and "chain3-section.png" in md
    assert (tmp_path / "out" / "chain3-multipliers.png").exists()


def test_run_with_model_overrides_the_params(tmp_path):
    from symvi.cli import main
    (tmp_path / "m.toml").write_text(dumps(THREE_STOP2_GAP05))
    (tmp_path / "p.toml").write_text(dumps(PAPER_EX1))
    f = tmp_path / "s.toml"
    f.write_text(SCENE.replace('model = "m.toml"', "mu_m = 2\nmu_k = 5\nf2 = 0\nb = 1.5\nr = 0.8")
                 .replace("omega_min = 0.99\nomega_max = 1.02", "omega_min = 0.70\nomega_max = 0.76")
                 .replace("omega = 0.95", "omega = 0.7369"))
    scene = with_model(load_scene(f), load_model_(tmp_path / "p.toml"))
    assert scene.params_for(scene.outputs[0]) == PAPER_EX1
    assert main(["run", str(f), "--out", str(tmp_path / "o"), "--model",
                 str(tmp_path / "p.toml")]) == 0


def load_model_(path):
    from symvi.model import load_model
    return load_model(path)


@pytest.mark.parametrize("name", ["formula_audit", "numbers"])
def test_paper_only_outputs_refuse_a_model(name):
    from symvi.reporting.scenes import paper_scenes
    scene = {s.name: s for s in paper_scenes()}[name]
    with pytest.raises(SceneError, match="printed formulas"):
        with_model(scene, THREE_STOP2_GAP05)


def test_missing_model_file_names_it(tmp_path):
    f = tmp_path / "s.toml"
    f.write_text(SCENE)
    r = subprocess.run([sys.executable, "-m", "symvi", "run", str(f), "--out",
                        str(tmp_path / "out")], capture_output=True, text=True)
    assert r.returncode == 2 and "m.toml" in r.stderr and "no such file" in r.stderr
