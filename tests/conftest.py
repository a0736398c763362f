import os

import pytest
from hypothesis import settings

# The test command explores a fixed set of examples with no example database (a landing
# must not depend on luck or on files left by an earlier run).  SYMVI_HYPOTHESIS=explore
# draws new examples; what it finds becomes an explicit @example.
settings.register_profile("ci", derandomize=True, database=None, print_blob=True)
settings.register_profile("explore", database=None, print_blob=True)
settings.load_profile("explore" if os.environ.get("SYMVI_HYPOTHESIS") == "explore" else "ci")

from symvi import Params

#: the paper's two examples, Sec. 4
EX1 = Params(2, 5, 0, 1.5, 0.8)
EX2 = Params(4, 2, 0, 1.8, 0.8)
#: a set of our own: force on both masses, another gap and restitution
OWN = Params(1.5, 3.0, 0.3, 0.9, 0.7)


@pytest.fixture(params=["ex1", "ex2"])
def example(request):
    return {"ex1": (EX1, [0.7219, 0.73, 0.7368, 0.7396, 0.745]),
            "ex2": (EX2, [0.458, 0.47, 0.4906, 0.4944])}[request.param]
