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

from symvi.model import Model, Stop  # noqa: E402

#: hypothesis seed 2 (issue 23): an undamped N = 4 chain whose NS point at omega_c =
#: 0.4021245186 sits next to a collision of multiplier pairs, d|lambda1|/domega = 4.4e6;
#: the derivative along the branch said 4426520 (0.47 % off, no caveat), and after a first
#: fix -91 +/- 32 (and -315.22155 +/- 1e-6 at 0.40211928 where (A1)-(A3) give -315.22156).
#: Found on [0.3332, 1.4735] (50 NS points, ~40 s); the explicit example keeps the four
#: points of [0.4015, 0.403] (~4 s), which show both failures
SEED2 = Model(
    mass=[0.7045200879082201, 1.6586080083310386, 2.4259993747067212, 2.579087890984482],
    stiffness=[[3.7917299004260636, -1.313896127027125, 0.12740276182753646,
                0.10231541843913917],
               [-1.313896127027125, 3.458317491060083, -1.8448012063782884,
                0.11080641263192431],
               [0.12740276182753646, -1.8448012063782884, 4.7418055787296804,
                -2.5221574989293125],
               [0.10231541843913917, 0.11080641263192431, -2.5221574989293125,
                5.433044947027741]],
    forcing=[0.46090010033391365, -0.1269277287771404, 0.43608527724720214,
             1.0724153618233292],
    stop=Stop(mass=4, gap=0.6274667725434118, restitution=0.95))
