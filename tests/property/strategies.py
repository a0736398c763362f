"""Hypothesis strategies over the valid parameter space of eq. (4)."""
from hypothesis import strategies as st

from symvi import Params


def _f(lo, hi):
    return st.floats(lo, hi, allow_nan=False, allow_infinity=False)


#: the region where the paper's examples live (moderate ratios, gap of order 1)
params_typical = st.builds(Params, mu_m=_f(0.2, 6), mu_k=_f(0.2, 8), f2=_f(0, 1),
                           b=_f(-2, 3), r=_f(0.05, 1))
omega_typical = _f(0.15, 3.5)

#: the whole valid space, extremes included
params_wide = st.builds(Params, mu_m=_f(1e-3, 1e3), mu_k=_f(1e-3, 1e3), f2=_f(-2, 3),
                        b=_f(-20, 20), r=st.one_of(_f(1e-3, 1), st.just(1.0)))
omega_wide = st.one_of(_f(1e-3, 1e2), st.sampled_from([1e-3, 0.5, 1.0, 2.0, 10.0]))
