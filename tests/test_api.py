"""The public surface of ``import symvi``."""
import subprocess
import sys


def test_public_functions_survive_submodule_imports():
    """symvi.simulate / jet / hopf_points stay functions after their modules load."""
    code = ("import types, symvi, symvi.simulations.diagnostics, symvi.studies.circle_check, "
            "symvi.reporting.scenes;"
            "names = ['simulate', 'jet', 'hopf_points', 'period1_orbits', 'poincare_map'];"
            "bad = [n for n in names if isinstance(getattr(symvi, n), types.ModuleType)"
            " or not callable(getattr(symvi, n))]; print(bad)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "[]"


def test_import_is_light():
    """``import symvi`` loads neither numba, scipy.optimize nor any generated order."""
    code = ("import sys, symvi; print(sorted(m for m in ('numba', 'scipy.optimize', "
            "'symvi._generated.order1', 'symvi._generated.order3') if m in sys.modules))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "[]"


def test_model_api_is_public_and_import_stays_light():
    """symvi.Model, symvi.Stop, symvi.load_model (issue 11); still no numba on import."""
    code = ("import sys, symvi; m = symvi.Model(mass=[1.0], stiffness=[[1.0]], forcing=[1.0], "
            "stop=symvi.Stop(mass=1, gap=0.2, restitution=0.8)); "
            "print(m.n, callable(symvi.load_model), 'numba' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "1 True False"


def test_poincare_map_of_params_is_the_any_model_map_held_to_the_modal_oracle():
    """symvi.poincare_map(Params) runs maps.impact on Model.luo_xie (one owner of the map,
    issue 11); the paper's modal map (symvi.paper.modal_map) agrees with it, and the old
    old names of symvi.poincare are held in tests/test_deprecated_paths.py."""
    import pytest

    import symvi
    from symvi.errors import ParameterError
    from symvi.maps.impact import poincare_map as impact_map
    from symvi.paper import modal_map
    p = symvi.Params(2, 5, 0, 1.5, 0.8)
    y = (-0.4, 0.3, 0.2, 1.0)
    got = symvi.poincare_map(p, 0.74, y)
    same = impact_map(symvi.Model.luo_xie(2, 5, 0, 1.5, 0.8), 0.74, y)
    ref = modal_map.poincare_map(p, 0.74, y)
    assert got.status == ref.status == "impact"
    assert got.y == same.y
    assert max(abs(a - b) for a, b in zip(got.y, ref.y)) < 1e-12
    assert abs(got.t - ref.t) < 1e-12
    with pytest.raises(ParameterError, match="omega"):
        symvi.poincare_map(p, -1.0, y)
