"""The numba kernels a command is known to compile on its first run, with their signatures,
so that :func:`symvi._compiled.warm_up` compiles them in parallel and says so.

A row is (module, function, argument types, seconds it took to compile on a 2-core
machine: the order of the work and the estimate printed).  A row that no longer matches
the code costs a wasted compile, never a wrong result; tests/cli/test_startup.py checks
that after the warm-up the command compiles nothing more.
"""
_C1, _C2 = "complex128[::1]", "complex128[:, ::1]"
_F1, _F2 = "float64[::1]", "float64[:, ::1]"
_F = "float64"


def _sig(*types):
    return "(" + ", ".join(types) + ",)"


#: period-1 orbits with their multipliers (symvi.orbits.period1_orbits, compiled path);
#: period1 compiles symvi.orbits._shooting.shoot1 (and shoot) and monodromy inside it, with the argument
#: types the Hopf scan calls them with (int64 and boolean, not literals), so they have no
#: rows of their own: a row would compile them a second time in another process
ORBIT = [
    ("symvi.flow._steady", "_steady", _sig(_F2, _F2, _F2, _F1, _F), 1.4),
    ("symvi.orbits._period1", "period1",
     _sig(_C1, _C2, _C2, _F2, _F1, _F1, _F, _F1, _F1, _F, _F, "boolean"), 7.4),
    ("symvi.flow.compiled", "_offsets", _sig("int64"), 0.1),
    ("symvi.flow.compiled", "_first_impact_from", _sig(_F1, _F1, _F, "int64"), 3.1),
]
#: the Hopf scan: the orbits, the located crossings (shooting, compiled with period1) and
#: the order-3 jets
HOPF = ORBIT + [
    ("symvi.codegen._assemble", "assemble64",
     _sig(_C1, _C2, _C2, _F2, _F1, _F1, _F1, _F1, _F, _F1, _F1, _F, "int64", "boolean"),
     0.5),
    ("symvi.codegen._assemble", "fixed_solve64", _sig(_F2, _F1), 0.9),
]
#: compiled inside period1 with these argument types (tests/cli/test_startup.py checks them)
INSIDE = [
    ("symvi.orbits._shooting", "shoot1",
     _sig(_C1, _C2, _C2, _F2, _F1, _F1, _F1, _F1, _F, _F1, "int64", _F1, "int64",
          "boolean", "boolean"), 0.3),
    ("symvi.orbits._shooting", "shoot",
     _sig(_C1, _C2, _C2, _F2, _F2, _F1, _F1, _F1, _F1, _F, _F2, "int64[:, ::1]",
          "int64[::1]", "int64", _F1, "int64", "boolean", "boolean"), 2.5),
    ("symvi.orbits._shooting", "monodromy", _sig(_F2, "int64", "int64"), 0.3),
]


def warm(kernels, what):
    """Compile what ``kernels`` lists and the cache lacks (a message on stderr when it does)."""
    from .._compiled import warm_up
    return warm_up(kernels, what)
