"""frechet_exp (symvi.codegen.layout): d/de e^{(A + e dA) t}, held to scipy's expm_frechet."""
import warnings

import numpy as np
import pytest
from scipy.linalg import expm_frechet

from symvi.codegen.layout import frechet_exp
from symvi.flow.linear import LinearFlow
from symvi.model import Model, Stop

K3 = [[1, -1, 0], [-1, 1.7, -0.7], [0, -0.7, 2.7]]
C3 = [[0.015, -0.005, 0], [-0.005, 0.0235, -0.0035], [0, -0.0035, 0.0215]]


@pytest.mark.parametrize("m1,tol", [(1.0, 1e-13), (1e-3, 1e-11)])
def test_frechet_equals_scipy(m1, tol):
    m = Model(mass=[m1, 1.5, 0.8], stiffness=K3, damping=C3, forcing=[1, 0.5, 0],
              stop=Stop(mass=2, gap=0.5, restitution=0.8))
    f = LinearFlow.of(m)
    A = np.real(np.asarray(f.A, dtype=complex))
    dA = np.random.default_rng(1).standard_normal(A.shape)
    t = 2 * np.pi / 0.95
    R = expm_frechet(A * t, dA * t, compute_expm=False)
    assert np.abs(frechet_exp(f, t, dA) - R).max() <= tol * np.abs(R).max()


def test_stiff_mode_gives_no_nan_and_no_warning():
    """mass[1] = 1e-8: Re(l_i - l_j) t ~ 1e3 overflowed expm1 (inf * 0 = NaN, and numpy's
    overflow warning reached the user)."""
    m = Model(mass=[1e-8, 1.5, 0.8], stiffness=K3, damping=C3, forcing=[1, 0.5, 0],
              stop=Stop(mass=2, gap=0.5, restitution=0.8))
    f = LinearFlow.of(m)
    dA = np.random.default_rng(2).standard_normal((6, 6))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        G = frechet_exp(f, 2 * np.pi / 0.95, dA)
    assert np.isfinite(G).all()
