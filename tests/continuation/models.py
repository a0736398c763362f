"""Models of the continuation tests."""
from symvi.model import Model, Stop

#: one damped mass with the stop at its equilibrium: a flip near omega = 2.656 and a cascade
ONE_DAMPED = Model(mass=[1.0], stiffness=[[1.0]], damping=[[0.05]], forcing=[1.0],
                   stop=Stop(mass=1, gap=0.0, restitution=0.8))
#: the issue's grazing example: stiffness 1, damping 0.1, gap 1, forced at omega = 1
GRAZE = Model(mass=[1.0], stiffness=[[1.0]], damping=[[0.1]], forcing=[0.3],
              stop=Stop(mass=1, gap=1.0, restitution=0.8))
