"""Smooth nonlinear forces of a model (issue 28): parsed safely, held with their parameters.

The equation of motion gains one term per mass on the left-hand side::

    M x'' + C x' + K x + f(x, v) = P sin(omega t + tau)

with f_i an expression in x1..xN, v1..vN and named parameters (``beta``), written as a
model file says it (``nonlinear = ["beta*x1**3"]``, ``[model.parameters] beta = 0.5``).

Parsing is closed: the text first passes a small tokenizer (identifiers, numbers, the
operators + - * / **, parentheses and commas; no ``__``, no attribute access, no strings,
at most MAX_CHARS characters), every identifier must be an allowed symbol or one of the
smooth functions of :data:`FUNCTIONS`, numeric powers are bounded, and only then does
SymPy's ``parse_expr`` see it, with an explicit ``global_dict`` (those functions and the
number classes, Add, Mul and Pow for the unevaluated pass, no builtins) and a ``local_dict`` of the allowed symbols.  Nothing is
passed to ``eval`` or ``sympify`` as raw text.  Every refusal is one ParameterError line
naming the key (``nonlinear[1]``, ``parameters.beta``).
"""
import math
import re
from tokenize import TokenError
from dataclasses import dataclass

from ..errors import ParameterError

#: the longest expression text accepted (a model's force is a line, not a program)
MAX_CHARS = 1000
#: the largest |integer exponent| of a numeric power (2**10**10 would hang SymPy)
MAX_POWER = 64
#: the longest number literal
MAX_DIGITS = 40
#: at most this many named parameters
MAX_PARAMETERS = 32

#: the smooth elementary functions an expression may use
FUNCTIONS = ("sin", "cos", "tan", "exp", "log", "sqrt", "sinh", "cosh", "tanh", "atan")
#: named to say why they are refused (a force must be smooth: the jets need it)
NON_SMOOTH = ("Abs", "abs", "sign", "Max", "Min", "max", "min", "floor", "ceiling", "ceil",
              "Heaviside", "Piecewise", "Mod", "frac", "re", "im", "arg", "DiracDelta")
#: names a parameter may not take: the built-in parameters, the constants, the functions
RESERVED = frozenset({"omega", "gap", "restitution", "b", "r", "mu_m", "mu_k", "f2", "t",
                      "tau", "pi", "E", "I", "e", "mass", "stiffness", "damping", "forcing",
                      "stop", "nonlinear", "parameters", *FUNCTIONS, *NON_SMOOTH})

_TOKEN = re.compile(r"\s*(?:(?P<num>(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?)"
                    r"|(?P<name>[A-Za-z_][A-Za-z0-9_]*)|(?P<op>\*\*|[-+*/(),]))")
_PARAM_NAME = re.compile(r"^[A-Za-z][A-Za-z0-9_]{0,31}$")
_STATE_NAME = re.compile(r"^[xv]\d+$")
_ALLOWED = "expressions in x1..xN, v1..vN, the named parameters, numbers, + - * / **, " \
           "and " + ", ".join(FUNCTIONS) + ", pi"


def _tokens(key, text):
    """The identifiers of ``text``, after checking every token (module docstring)."""
    if not isinstance(text, str):
        raise ParameterError(key, text, "a string: " + _ALLOWED)
    if not text.strip():
        raise ParameterError(key, text, _ALLOWED, "empty")
    if len(text) > MAX_CHARS:
        raise ParameterError(key, f"{len(text)} characters", f"at most {MAX_CHARS} characters")
    for name in re.findall(r"[A-Za-z_][A-Za-z0-9_]*", text):
        if name in NON_SMOOTH:                  # said first: the syntax may not be ours
            raise ParameterError(key, text, _ALLOWED,
                                 f"{name} is not smooth (a force must be: the jets need it)")
    names, i = [], 0
    end = len(text.rstrip())
    while i < end:
        m = _TOKEN.match(text, i)
        if m is None or m.end() == i:
            c = text[i:].lstrip()[:1]
            what = ("'^': write powers as **" if c == "^" else
                    "attribute access" if c == "." else f"the character {c!r}")
            raise ParameterError(key, text, _ALLOWED, f"syntax error at {what}")
        if m.group("name"):
            if "__" in m.group("name"):
                raise ParameterError(key, text, _ALLOWED, "a name with '__'")
            names.append(m.group("name"))
        elif m.group("num") and len(m.group("num")) > MAX_DIGITS:
            raise ParameterError(key, text, f"numbers of at most {MAX_DIGITS} characters")
        i = m.end()
    return names


def _namespace():
    import sympy
    from sympy import Float, Integer, Rational, Symbol
    g = {name: getattr(sympy, name) for name in FUNCTIONS}
    g.update(pi=sympy.pi, Integer=Integer, Float=Float, Rational=Rational, Symbol=Symbol,
             Add=sympy.Add, Mul=sympy.Mul, Pow=sympy.Pow, __builtins__={})
    return g


def parse_force(key, text, symbols):
    """The SymPy expression of ``text`` (one mass's force), checked as the module says.

    ``symbols`` maps each allowed name (x1..xN, v1..vN, the parameters) to its Symbol."""
    import sympy
    from sympy.parsing.sympy_parser import auto_number, parse_expr
    for name in _tokens(key, text):
        if name not in symbols and name not in FUNCTIONS and name != "pi":
            raise ParameterError(key, text, _ALLOWED, f"unknown symbol {name}")
    g = _namespace()
    try:
        raw = parse_expr(text, local_dict=dict(symbols), global_dict=g,
                         transformations=(auto_number,), evaluate=False)
    except (SyntaxError, TypeError, ValueError, AttributeError, NameError,
            TokenError) as exc:
        raise ParameterError(key, text, _ALLOWED,
                             f"syntax error ({type(exc).__name__})") from None
    if not isinstance(raw, sympy.Expr):
        raise ParameterError(key, text, _ALLOWED, "not one expression")
    for p in sympy.preorder_traversal(raw):
        if isinstance(p, sympy.Pow) and p.exp.is_number and not p.exp.free_symbols:
            e = p.exp
            if not (e.is_Number and abs(float(e)) <= MAX_POWER):
                raise ParameterError(key, text, f"numeric exponents with |e| <= {MAX_POWER}")
    expr = parse_expr(text, local_dict=dict(symbols), global_dict=_namespace(),
                      transformations=(auto_number,))
    if expr.has(sympy.zoo, sympy.nan, sympy.oo, -sympy.oo, sympy.I):
        raise ParameterError(key, text, _ALLOWED, "not finite and real (a division by zero?)")
    for a in expr.atoms(sympy.Number):
        try:
            ok = math.isfinite(float(a))
        except (OverflowError, TypeError):
            ok = False
        if not ok:
            raise ParameterError(key, text, "finite numbers (float64)", f"{str(a)[:20]} is not")
    extra = expr.free_symbols - set(symbols.values())
    if extra:                                   # not reached after the token check
        raise ParameterError(key, text, _ALLOWED, f"unknown symbol {sorted(map(str, extra))[0]}")
    return expr


def _parameter(name, value, n):
    key = f"parameters.{name}" if isinstance(name, str) else "parameters"
    if not isinstance(name, str) or not _PARAM_NAME.match(name) or "__" in name:
        raise ParameterError(key, name, "a name of letters, digits and _ (starting with a "
                             "letter, at most 32 characters)")
    if name in RESERVED or _STATE_NAME.match(name):
        raise ParameterError(key, name, "a name that is not a built-in parameter, a "
                             "function, a constant or a state variable (x1, v1, ...)",
                             "clashes with a built-in name")
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise ParameterError(key, value, "a finite real number")
    v = float(value)
    if not math.isfinite(v):
        raise ParameterError(key, v, "a finite real number")
    return v


@dataclass(frozen=True)
class Forces:
    """The nonlinear forces of a model: the texts (one per mass), the named parameters
    ((name, value) pairs, in order) and their SymPy expressions (built on demand)."""

    texts: tuple
    parameters: tuple

    @classmethod
    def of(cls, nonlinear, parameters, n):
        """Checked forces of a model of n masses (refusals: see the module docstring)."""
        if isinstance(nonlinear, str) or not isinstance(nonlinear, (list, tuple)):
            raise ParameterError("nonlinear", nonlinear, f"a list of {n} expressions (one "
                                 "per mass)")
        if len(nonlinear) != n:
            raise ParameterError("nonlinear", f"{len(nonlinear)} expressions",
                                 f"a list of {n} expressions (one per mass)",
                                 f"it has {len(nonlinear)}, not {n}")
        parameters = {} if parameters is None else parameters
        if not isinstance(parameters, dict):
            raise ParameterError("parameters", parameters, "a table of name = value")
        if len(parameters) > MAX_PARAMETERS:
            raise ParameterError("parameters", f"{len(parameters)} names",
                                 f"at most {MAX_PARAMETERS} named parameters")
        pars = tuple((name, _parameter(name, v, n)) for name, v in parameters.items())
        f = cls(tuple(nonlinear), pars)
        f.exprs(n)                              # every text parses
        return f

    @property
    def names(self):
        return tuple(name for name, _ in self.parameters)

    def value(self, name):
        return dict(self.parameters)[name]

    def with_value(self, name, value):
        v = _parameter(name, value, 0)
        return Forces(self.texts, tuple((k, v if k == name else x) for k, x in self.parameters))

    def symbols(self, n):
        """The allowed names and their Symbols: x1..xN, v1..vN, then the parameters."""
        import sympy
        names = ([f"x{i + 1}" for i in range(n)] + [f"v{i + 1}" for i in range(n)]
                 + list(self.names))
        return {name: sympy.Symbol(name, real=True) for name in names}

    def exprs(self, n):
        """The forces f_1..f_N as SymPy expressions (cached per texts)."""
        return _exprs(self.texts, self.names, n)

    def velocity_free(self, n):
        """Whether no force depends on a velocity v1..vN (then they do not change the
        flow's volume: its divergence is -tr(M^-1 (C + df/dv))); cached per texts, as the
        expressions (``Model.conservative`` asks it for every orbit)."""
        key = (self.texts, self.names, n, "velocity_free")
        out = _CACHE.get(key)
        if out is None:
            vs = {f"v{i + 1}" for i in range(n)}
            out = _CACHE[key] = not any(str(s) in vs for e in self.exprs(n)
                                        for s in e.free_symbols)
        return out

    def key(self, n):
        """Every number and expression (the expressions as SymPy prints them, so that
        x1**3*beta and beta*x1**3 are one force)."""
        return (tuple(str(e) for e in self.exprs(n)), self.parameters)


_CACHE = {}


def _exprs(texts, names, n):
    key = (texts, names, n)
    out = _CACHE.get(key)
    if out is None:
        sym = Forces(texts, tuple((k, 0.0) for k in names)).symbols(n)
        out = tuple(parse_force(f"nonlinear[{i + 1}]", t, sym) for i, t in enumerate(texts))
        if len(_CACHE) > 256:
            _CACHE.clear()
        _CACHE[key] = out
    return out
