"""The public surface of ``import symvi``."""
import subprocess
import sys


def test_public_functions_survive_submodule_imports():
    """symvi.simulate / jet / hopf_points stay functions after their modules load."""
    code = ("import types, symvi, symvi.diagnostics, symvi.circle_check, symvi.scenes;"
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
