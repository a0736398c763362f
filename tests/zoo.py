"""The named models of the tests, each defined once under one name that says what it is.

Names read ``<N masses>_<what sets it apart>``; ``STOPk`` is the mass the stop acts on,
``GAPb`` the gap (``GAP12`` is 1.2).  A test imports the model it needs by name:
``from tests.zoo import THREE_STOP2_GAP05``.  (``tests.property.strategies.SEED2``, the
hypothesis-drawn N = 4 model, stays with its strategies.)
"""
import numpy as np

from symvi.model import Model, Stop

# --- N = 1 -------------------------------------------------------------------------------
#: undamped, gap 0.2, r 0.8: natural frequency 1
ONE_UNDAMPED = Model(mass=[1.0], stiffness=[[1.0]], forcing=[1.0],
                     stop=Stop(mass=1, gap=0.2, restitution=0.8))
#: damping 0.02, gap 0.2, r 0.8
ONE_DAMPED_GAP02 = Model(mass=[1.0], stiffness=[[1.0]], damping=[[0.02]], forcing=[1.0],
                         stop=Stop(mass=1, gap=0.2, restitution=0.8))
#: damping 0.05, the stop at equilibrium (gap 0), r 0.8: a flip near omega = 2.656 and a cascade
ONE_DAMPED_GAP0 = Model(mass=[1.0], stiffness=[[1.0]], damping=[[0.05]], forcing=[1.0],
                        stop=Stop(mass=1, gap=0.0, restitution=0.8))
#: lightly damped (0.02), the stop at equilibrium, r 0.9: a stable 1-2 orbit (two impacts per
#: period) at omega = 0.7 and 1-3, 1-5 orbits at lower omega
ONE_LIGHT_GAP0 = Model(mass=[1.0], stiffness=[[1.0]], damping=[[0.02]], forcing=[1.0],
                       stop=Stop(mass=1, gap=0.0, restitution=0.9))
#: the grazing example: damping 0.1, gap 1, forcing 0.3, forced at omega = 1
ONE_GRAZING = Model(mass=[1.0], stiffness=[[1.0]], damping=[[0.1]], forcing=[0.3],
                    stop=Stop(mass=1, gap=1.0, restitution=0.8))

# --- N = 2 -------------------------------------------------------------------------------
#: the paper's model, example 1 (Luo & Xie 1998, Sec. 4): mu_m 2, mu_k 5, f2 0, b 1.5, r 0.8
PAPER_EX1 = Model.luo_xie(2, 5, 0, 1.5, 0.8)
#: the paper's masses and springs (example 1) with damping, gap 1.5, r 0.8
PAPER_DAMPED = Model(mass=[1.0, 2.0], stiffness=[[1.0, -1.0], [-1.0, 6.0]],
                     damping=[[0.02, -0.01], [-0.01, 0.03]], forcing=[1.0, 0.0],
                     stop=Stop(mass=1, gap=1.5, restitution=0.8))
#: the paper's example 2 (Sec. 4): mu_m 4, mu_k 2, f2 0, b 1.8, r 0.8
PAPER_EX2 = Model.luo_xie(4, 2, 0, 1.8, 0.8)
#: an overdamped mode: two real eigenvalues and one conjugate pair; stop on mass 2, gap 0.5
TWO_OVERDAMPED = Model(mass=[1.0, 1.0], stiffness=[[2.0, -1.0], [-1.0, 2.0]],
                       damping=[[3.0, -0.5], [-0.5, 0.1]], forcing=[0.3, 1.0],
                       stop=Stop(mass=2, gap=0.5, restitution=0.7))

# --- N = 3 -------------------------------------------------------------------------------
#: damped, stop on the middle mass with gap 1.2, forcing on two masses (the benchmark's model)
THREE_STOP2_GAP12 = Model(mass=[1.0, 1.5, 0.8],
                          stiffness=[[1.0, -1.0, 0.0], [-1.0, 1.7, -0.7], [0.0, -0.7, 2.7]],
                          damping=[[0.015, -0.005, 0.0], [-0.005, 0.0235, -0.0035],
                                   [0.0, -0.0035, 0.0215]],
                          forcing=[1.0, 0.5, 0.0], stop=Stop(mass=2, gap=1.2, restitution=0.8))
#: THREE_STOP2_GAP12 with the gap 0.5
THREE_STOP2_GAP05 = Model(mass=[1.0, 1.5, 0.8],
                          stiffness=[[1.0, -1.0, 0.0], [-1.0, 1.7, -0.7], [0.0, -0.7, 2.7]],
                          damping=[[0.015, -0.005, 0.0], [-0.005, 0.0235, -0.0035],
                                   [0.0, -0.0035, 0.0215]],
                          forcing=[1.0, 0.5, 0.0], stop=Stop(mass=2, gap=0.5, restitution=0.8))

# --- N = 4 -------------------------------------------------------------------------------
#: a chain, damping 0.01/0.02/0.01/0.03, stop on mass 3 (gap 0.3, r 0.7), forcing on masses 1, 4
FOUR_STOP3 = Model(mass=[1.0, 1.2, 0.9, 1.1],
                   stiffness=[[2.0, -1.0, 0.0, 0.0], [-1.0, 2.0, -1.0, 0.0],
                              [0.0, -1.0, 2.0, -1.0], [0.0, 0.0, -1.0, 1.5]],
                   damping=[[0.01, 0.0, 0.0, 0.0], [0.0, 0.02, 0.0, 0.0],
                            [0.0, 0.0, 0.01, 0.0], [0.0, 0.0, 0.0, 0.03]],
                   forcing=[0.6, 0.0, 0.0, 1.0], stop=Stop(mass=3, gap=0.3, restitution=0.7))
#: the same chain, damping 0.01 on each mass, stop on mass 4 (gap 0.3, r 0.7), forced on mass 4
FOUR_STOP4 = Model(mass=[1.0, 1.2, 0.9, 1.1],
                   stiffness=[[2.0, -1.0, 0.0, 0.0], [-1.0, 2.0, -1.0, 0.0],
                              [0.0, -1.0, 2.0, -1.0], [0.0, 0.0, -1.0, 1.5]],
                   damping=[[0.01, 0.0, 0.0, 0.0], [0.0, 0.01, 0.0, 0.0],
                            [0.0, 0.0, 0.01, 0.0], [0.0, 0.0, 0.0, 0.01]],
                   forcing=[0.0, 0.0, 0.0, 1.0], stop=Stop(mass=4, gap=0.3, restitution=0.7))

# --- N = 5 -------------------------------------------------------------------------------
#: a uniform chain (springs 2, -1), damping 0.02 on each mass, stop on mass 3 (gap 0.3, r 0.8),
#: forced on mass 1: beyond the committed structures (N <= 4), generated on first use
FIVE_CHAIN_STOP3 = Model(mass=[1.0] * 5,
                         stiffness=(2 * np.eye(5) - np.eye(5, k=1) - np.eye(5, k=-1)).tolist(),
                         damping=(0.02 * np.eye(5)).tolist(), forcing=[1.0, 0, 0, 0, 0],
                         stop=Stop(mass=3, gap=0.3, restitution=0.8))

#: the N-mass set the period-1, jet and shooting tests run over (keys are test ids)
N_MASS_SET = {"one": ONE_UNDAMPED, "paper": PAPER_EX1, "paper-damped": PAPER_DAMPED,
              "three": THREE_STOP2_GAP05, "four": FOUR_STOP4}
