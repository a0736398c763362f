"""A conservative model's orbits (r = 1, no damping, no force of a velocity): the map
preserves volume, so no orbit is asymptotically stable, and one whose multipliers sit
on the unit circle is neutral (elliptic) -- rounding alone decided ``stable`` before."""
import pytest

import symvi
from symvi.cli import main
from symvi.continuation.start import nonlinear_period1
from symvi.model import Model, Stop

ONE = dict(mass=[1.0], stiffness=[[1.0]], damping=[[0.0]], forcing=[1.0],
           stop=Stop(mass=1, gap=0.0, restitution=1.0))


def test_a_velocity_force_is_not_conservative():
    assert Model(**ONE).conservative
    assert Model(**ONE, nonlinear=["beta*x1**3"], parameters={"beta": 0.2}).conservative
    assert not Model(**ONE, nonlinear=["beta*v1**3"], parameters={"beta": 0.2}).conservative
    assert not Model(**{**ONE, "stop": Stop(mass=1, gap=0.0, restitution=0.9)}).conservative


def test_linear_period1_orbit_of_a_conservative_model_is_neutral():
    o = [o for o in symvi.period1_orbits(Model(**ONE), 2.6) if o.admissible][0]
    assert all(abs(abs(z) - 1) < 1e-12 for z in o.multipliers)
    assert (o.stable, o.neutral) == (False, True)
    assert o.as_dict()["neutral"] is True


def test_nonlinear_orbits_of_a_conservative_model():
    """The cubic spring keeps the model conservative: an elliptic orbit is neutral, a
    saddle (real multipliers mu, 1/mu) is unstable and not neutral, none is stable."""
    model = Model(**ONE, nonlinear=["beta*x1**3"], parameters={"beta": 0.2})
    found = nonlinear_period1(model, 2.6)
    assert found.orbits
    kinds = set()
    for o in found.orbits:
        prod = abs(o.multipliers[0] * o.multipliers[1])
        assert abs(prod - 1) < 1e-9                      # det DP = 1
        assert not o.stable
        assert o.neutral == all(abs(abs(z) - 1) < 1e-9 for z in o.multipliers)
        kinds.add(o.neutral)
    assert True in kinds


def test_symvi_orbit_prints_neutral(tmp_path, capsys):
    f = tmp_path / "c.toml"
    f.write_text('[model]\nmass = [1.0]\nstiffness = [[1.0]]\ndamping = [[0.0]]\n'
                 'forcing = [1.0]\n[stop]\nmass = 1\ngap = 0.0\nrestitution = 1.0\n')
    assert main(["orbit", "--model", str(f), "--omega", "2.6"]) == 0
    out = capsys.readouterr().out
    assert "neutral (conservative model" in out and " stable" not in out
