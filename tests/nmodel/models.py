"""Models of the N-mass tests: N = 1, the paper's, the paper's with damping,
N = 3 (stop on the middle mass, forcing on two masses, damped) and N = 4."""
from symvi.model import Model, Stop

ONE = Model(mass=[1.0], stiffness=[[1.0]], forcing=[1.0],
            stop=Stop(mass=1, gap=0.2, restitution=0.8))
PAPER = Model.luo_xie(2, 5, 0, 1.5, 0.8)
PAPER_DAMPED = Model(mass=[1.0, 2.0], stiffness=[[1.0, -1.0], [-1.0, 6.0]],
                     damping=[[0.02, -0.01], [-0.01, 0.03]], forcing=[1.0, 0.0],
                     stop=Stop(mass=1, gap=1.5, restitution=0.8))
THREE = Model(mass=[1.0, 1.5, 0.8],
              stiffness=[[1.0, -1.0, 0.0], [-1.0, 1.7, -0.7], [0.0, -0.7, 2.7]],
              damping=[[0.015, -0.005, 0.0], [-0.005, 0.0235, -0.0035], [0.0, -0.0035, 0.0215]],
              forcing=[1.0, 0.5, 0.0], stop=Stop(mass=2, gap=0.5, restitution=0.8))
FOUR = Model(mass=[1.0, 1.2, 0.9, 1.1],
             stiffness=[[2.0, -1.0, 0.0, 0.0], [-1.0, 2.0, -1.0, 0.0],
                        [0.0, -1.0, 2.0, -1.0], [0.0, 0.0, -1.0, 1.5]],
             damping=[[0.01, 0.0, 0.0, 0.0], [0.0, 0.01, 0.0, 0.0],
                      [0.0, 0.0, 0.01, 0.0], [0.0, 0.0, 0.0, 0.01]],
             forcing=[0.0, 0.0, 0.0, 1.0], stop=Stop(mass=4, gap=0.3, restitution=0.7))
ALL = {"one": ONE, "paper": PAPER, "paper-damped": PAPER_DAMPED, "three": THREE, "four": FOUR}
