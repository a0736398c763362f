"""The Hopf chain at 50 digits: the project's mpmath chain (A) against finite differences of P (B)."""
import mpmath
import pytest

from symvi import Params
from symvi.paper.hopf import hopf_points   # the paper's view: eq. (60)'s f1 too
from symvi.studies.mpcheck import check_point, digits_of_agreement

EX1 = Params(2, 5, 0, 1.5, 0.8)


@pytest.mark.slow
def test_example1_two_chains_agree():
    """Chain A (orbit, generated jets, normal_form on mpmath) and chain B (Newton and
    finite differences of the numeric map, Kuznetsov's formula re-written) share no
    derivation code; they agree to >= 40 digits, and float64 to >= 11."""
    pt = hopf_points(EX1, 0.70, 0.76).points[0]
    chk = check_point(EX1, pt, digits=50)
    ag = chk.agreement
    assert ag["omega_c"]["A-B"] >= 45
    assert ag["dmod_domega"]["A-B"] >= 40
    assert ag["l1"]["A-B"] >= 35
    for k in ("omega_c", "dmod_domega", "l1"):
        assert ag[k]["float-A"] >= 11, k
    # f1 by the corrected eq. (60) in chain A is -l1/4 of chain B to the same digits
    with mpmath.workdps(50):
        assert digits_of_agreement(chk.chain_a.f1_wan, -chk.chain_b.l1 / 4) >= 35


def test_digits_of_agreement():
    assert digits_of_agreement(1.0, 1.0 + 1e-10) == pytest.approx(10, abs=0.01)
