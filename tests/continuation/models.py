"""Models of the continuation tests."""
from symvi.model import Model, Stop

#: one damped mass with the stop at its equilibrium: a flip near omega = 2.656 and a cascade
ONE_DAMPED = Model(mass=[1.0], stiffness=[[1.0]], damping=[[0.05]], forcing=[1.0],
                   stop=Stop(mass=1, gap=0.0, restitution=0.8))
#: the issue's grazing example: stiffness 1, damping 0.1, gap 1, forced at omega = 1
GRAZE = Model(mass=[1.0], stiffness=[[1.0]], damping=[[0.1]], forcing=[0.3],
              stop=Stop(mass=1, gap=1.0, restitution=0.8))
#: lightly damped, the stop at equilibrium: a stable 1-2 orbit (two impacts per period)
#: at omega = 0.7 and 1-3, 1-5 orbits at lower omega
LIGHT = Model(mass=[1.0], stiffness=[[1.0]], damping=[[0.02]], forcing=[1.0],
              stop=Stop(mass=1, gap=0.0, restitution=0.9))
