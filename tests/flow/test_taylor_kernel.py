"""A tape's own Taylor kernel (:mod:`symvi.flow.taylor_kernel`): the same coefficients as the
interpreter, to the last bit, on one and several masses and a stop between masses; a tape
with functions has none; a run takes it once the process has run enough impacts on the
tape, and a run with it is the interpreted run, bit for bit."""
import numpy as np
import pytest

from symvi.flow import nonlinear as nl
from symvi.flow import taylor, taylor_kernel
from symvi.model import Model, Stop

ONE = dict(mass=[1.0], stiffness=[[1.0]], damping=[[0.1]], forcing=[1.0],
           stop=Stop(mass=1, gap=0.5, restitution=0.8))
TWO = dict(mass=[[1.0, 0.2], [0.2, 2.0]], stiffness=[[2.0, -1.0], [-1.0, 1.5]],
           damping=[[0.05, 0.0], [0.0, 0.05]], forcing=[1.0, 0.3],
           stop=Stop(between=(1, 2), gap=0.4, restitution=0.7))
#: (linear part, forces, parameters, omega and a section point whose run has 300 impacts)
CASES = [(ONE, ["beta*x1**3"], {"beta": 0.5}, 1.3, (0.1, 0.3)),
         (ONE, ["beta*x1**3 + 0.3*x1**2*v1 - 0.5 + gamma*(x1 + 1)**4"],
          {"beta": 0.2, "gamma": 0.01}, 2.2, (0.1, 0.3)),
         (TWO, ["beta*(x1 - x2)**3 + eps*x1**2*v1", "-beta*(x1 - x2)**3 + 3*v2**2*x2"],
          {"beta": 0.7, "eps": 0.05}, 2.2, (0.2, 0.5, -0.4, 1.0))]


def _flow(case):
    lin, forces, pars = case[:3]
    return nl.NonlinearFlow(Model(**lin, nonlinear=forces, parameters=pars))


def _own(flow):
    k = taylor_kernel.kernel(flow.tape[0], flow.tape[2], 2 * flow.n)
    assert k is not None
    return k


@pytest.mark.filterwarnings("ignore::numba.core.errors.NumbaExperimentalFeatureWarning")
@pytest.mark.parametrize("case", CASES)
def test_the_kernel_is_the_interpreter_to_the_last_bit(case):
    """A flight of 25 steps without events (taylor._taylor_integrate) from a state away
    from the stop: the state by the kernel and by the interpreted tape are equal, bit for
    bit (the kernel does the interpreter's operations in its order)."""
    flow = _flow(case)
    dim = 2 * flow.n
    sy = flow._system(1.3, 0.4)
    z = np.linspace(-0.4, 0.3, dim)
    h = flow._cap(1.3)
    a = taylor._taylor_integrate(sy, flow._taylor_work(), z.copy(), 25 * 0.8 * h, h)
    b = taylor._taylor_integrate(sy, flow._taylor_work(_own(flow)), z.copy(), 25 * 0.8 * h,
                                 h)
    assert np.all(np.isfinite(a)) and not np.array_equal(a, z)
    assert np.array_equal(a, b)


@pytest.mark.parametrize("case", CASES)
def test_a_run_with_the_kernel_is_the_interpreted_run(case, monkeypatch):
    """Runs of 300 impacts: the section points, times, approach speeds and hits with the
    kernel (KERNEL_IMPACTS set to 0, so the first run compiles it) equal the interpreted
    run's (KERNEL_IMPACTS out of reach), bit for bit."""
    flow = _flow(case)
    omega, y0 = case[3:]
    monkeypatch.setattr(taylor_kernel, "KERNEL_IMPACTS", 10 ** 18)
    monkeypatch.setattr(taylor_kernel, "_CACHE", {})
    monkeypatch.setattr(taylor_kernel, "_RAN", {})
    a = flow.run(omega, y0, 300)
    assert taylor_kernel._CACHE == {}            # interpreted: nothing compiled
    monkeypatch.setattr(taylor_kernel, "KERNEL_IMPACTS", 0)
    b = flow.run(omega, y0, 300)
    assert len(taylor_kernel._CACHE) == 1
    assert a[0] == b[0] and len(a[1]) == 300
    for u, v in zip(a[1:], b[1:]):
        assert np.array_equal(u, v)


def test_a_tape_with_functions_has_no_kernel():
    """exp, sin and a real power are not written out: the tape stays interpreted."""
    for forces in (["beta*sin(x1)"], ["beta*exp(v1)*x1"], ["beta*x1**2.5"]):
        flow = _flow((ONE, forces, {"beta": 0.5}))
        assert taylor_kernel.source(flow.tape[0], flow.tape[2], 2) is None
        assert taylor_kernel.kernel(flow.tape[0], flow.tape[2], 2) is None


def test_the_source_is_deterministic_and_fixed_by_the_tape():
    """The same tape gives the same text; a parameter's value is not in it (the kernel
    reads the constant rows), so one kernel serves every beta."""
    f1 = _flow((ONE, ["beta*x1**3"], {"beta": 0.5}))
    f2 = _flow((ONE, ["beta*x1**3"], {"beta": -3.0}))
    s1 = taylor_kernel.source(f1.tape[0], f1.tape[2], 2)
    assert s1 == taylor_kernel.source(f2.tape[0], f2.tape[2], 2)
    assert "0.5" not in s1 and "3.0" not in s1


def test_a_process_compiles_the_kernel_once_it_has_run_enough(monkeypatch):
    """for_run: None while the impacts run on the tape (counted by ran) and the run asked
    stay below KERNEL_IMPACTS; the kernel once they reach it, and from then on."""
    flow = _flow(CASES[0])
    tp, roots = flow.tape[0], flow.tape[2]
    monkeypatch.setattr(taylor_kernel, "KERNEL_IMPACTS", 1000)
    monkeypatch.setattr(taylor_kernel, "_CACHE", {})
    monkeypatch.setattr(taylor_kernel, "_RAN", {})
    assert taylor_kernel.for_run(tp, roots, 2, 999) is None
    taylor_kernel.ran(tp, roots, 2, 600)
    assert taylor_kernel.for_run(tp, roots, 2, 399) is None
    own = taylor_kernel.for_run(tp, roots, 2, 400)
    assert own is not None
    assert taylor_kernel.for_run(tp, roots, 2, 1) is own
    flow.run(1.3, (0.1, 0.3), 50)                # interpreted runs are not counted now
    assert taylor_kernel._RAN[taylor_kernel._key(tp, roots, 2)] == 600
