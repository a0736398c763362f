"""The per-user cache of generated code (``$XDG_CACHE_HOME/symvi/generated``): the
structures symvi does not ship (N > 4, orders 4-5 of N > 2), generated on first use and
executed from there.  Code run from a folder must be code symvi wrote, so (issue 23):

* **Who can write it.**  The folders ``symvi/`` and ``symvi/generated/`` and everything
  in them must belong to the current user, be writable by that user alone, and not be
  symbolic links; the folder holding ``symvi/`` must not be writable by others unless
  sticky (``/tmp``).  Else :class:`UnsafeCacheError`, one line naming the folder: nothing
  there is read, let alone run.  symvi creates the folders 0700 and drops group/other
  write bits from what it generates (a umask of 002 would leave them group-writable).
* **What it holds.**  The manifest in that folder is never trusted: a forged one can
  match tampered code.  Before a module runs, its text is read once (no symlink, checked
  on the open descriptor) and checked against what its generation inputs fix:
  the header's input hash equals :func:`derivations.impact_jets.input_hash` recomputed
  now (the derivation script and the SymPy version), ``N``, ``ORDER`` and ``INPUTS``
  equal the structure's (:func:`derivations.impact_jets.inputs`), ``LAYOUT`` indexes
  the returned tuple, and the code is arithmetic only: every statement and expression
  is of the few forms the generator prints (assignments of sums, products, powers by a
  small integer, ``sin``/``cos``; no loops, no names of builtins, no other calls or
  attributes).  So whatever a file says, executing it can do nothing but arithmetic.
  The text checked is the text compiled (no ``.pyc`` is read or written).  A module
  that fails is regenerated (with a warning); one that still fails is an error.
* The only complete content check, the text itself, needs the derivation run again
  (0.3 s for N = 5, order 1; minutes for orders 4-5): ``symvi regenerate --model FILE
  --check`` does it (:func:`stale_text`); loading does not.
"""
import ast
import builtins
import hashlib
import os
import stat
import sys
import types
import warnings
from pathlib import Path

from ..errors import SymviError

#: a generated module larger than this is refused unread (the largest shipped: 0.2 MB)
MAX_BYTES = 64 << 20
#: |k| of the largest power c**k the generator prints (5 at order 5)
MAX_POWER = 16
_BUILTINS = frozenset(dir(builtins))
_PROTECTED = _BUILTINS | {"sin", "cos", "inp", "Q", "math", "mpmath", "_jet", "f64", "mp",
                          "N", "ORDER", "INPUTS", "LAYOUT", "Q_F64"}
_MODULE_NAMES = {"N", "ORDER", "INPUTS", "LAYOUT", "Q_F64"}
_FUNCTIONS = {"_jet": ("inp", "sin", "cos", "Q"), "f64": ("inp",), "mp": ("inp",)}


class UnsafeCacheError(SymviError):
    """The generated-code cache may have been written by someone else."""


def cache_dir():
    """``$XDG_CACHE_HOME/symvi/generated`` (``~/.cache`` when unset or relative)."""
    base = os.environ.get("XDG_CACHE_HOME") or ""
    if not os.path.isabs(base):            # the XDG spec: relative paths are ignored
        base = os.path.join(os.path.expanduser("~"), ".cache")
    return Path(base) / "symvi" / "generated"


def private_dir(d=None, create=False):
    """``d`` (default :func:`cache_dir`) after the ownership checks of the module
    docstring, created 0700 first if ``create``; :class:`UnsafeCacheError` otherwise."""
    d = Path(d) if d is not None else cache_dir()
    top = d.parent
    if create:
        try:
            os.makedirs(top.parent, mode=0o700, exist_ok=True)
            for p in (top, d):
                try:
                    os.mkdir(p, 0o700)
                except FileExistsError:
                    pass
        except OSError as exc:
            raise UnsafeCacheError(f"generated-code cache {d}: cannot create it "
                                   f"({exc.strerror or exc}); set XDG_CACHE_HOME to a "
                                   "folder of yours") from None
    _check_parent(top.parent, d)
    for p in (top, d):
        _check_entry(p, d, folder=True)
    for root, dirs, files in os.walk(d):
        for name in dirs + files:
            _check_entry(Path(root) / name, d, folder=None)
    return d


def _uid():
    return os.geteuid() if hasattr(os, "geteuid") else None


def _refuse(d, what, why):
    raise UnsafeCacheError(
        f"generated-code cache {d}: {what} {why}; symvi runs code from there only if it "
        "belongs to you and only you can write it (fix with chmod go-w / chown, or "
        f"remove {d}, or set XDG_CACHE_HOME)")


def _check_parent(p, d):
    try:
        st = os.stat(p)
    except OSError:
        return                              # absent: nothing there to run
    if st.st_mode & 0o002 and not st.st_mode & stat.S_ISVTX:
        _refuse(d, f"its parent {p}", f"is writable by everyone (mode {_mode(st)}) "
                                      "without the sticky bit")


def _check_entry(p, d, folder):
    """``p``: owned by us, no group/other write, not a symlink; a folder when ``folder``
    is True, a regular file or a folder when it is None."""
    try:
        st = os.lstat(p)
    except FileNotFoundError:
        return                              # not created yet, or gone: nothing to run
    what = "the folder itself" if Path(p) == d else str(p)
    if stat.S_ISLNK(st.st_mode):
        _refuse(d, what, "is a symbolic link")
    if folder and not stat.S_ISDIR(st.st_mode):
        _refuse(d, what, "is not a folder")
    if not (stat.S_ISDIR(st.st_mode) or stat.S_ISREG(st.st_mode)):
        _refuse(d, what, "is not a regular file or folder")
    _check_owner(st, d, what)


def _check_owner(st, d, what):
    uid = _uid()
    if uid is not None and st.st_uid != uid:
        _refuse(d, what, f"belongs to uid {st.st_uid}, not to you (uid {uid})")
    if st.st_mode & 0o022:
        who = "its group and others" if st.st_mode & 0o022 == 0o022 else \
            "its group" if st.st_mode & 0o020 else "others"
        _refuse(d, what, f"is writable by {who} (mode {_mode(st)})")


def _mode(st):
    return f"{stat.S_IMODE(st.st_mode):04o}"


def secure(d, names):
    """Drop group/other write bits from the files ``names`` symvi just wrote into ``d``
    (their mode came from the umask)."""
    for name in names:
        p = Path(d) / name
        try:
            st = os.lstat(p)
        except FileNotFoundError:
            continue
        if stat.S_ISREG(st.st_mode) and st.st_mode & 0o022 and st.st_uid == _uid():
            os.chmod(p, stat.S_IMODE(st.st_mode) & ~0o022)


def generate(d, n, orders, force=False, starts=False):
    """Generate structure ``n``'s ``orders`` (with ``starts``, their variants from each
    coordinate's section too) into the private folder ``d`` (created and checked first)
    and secure what was written.  Returns (written, manifest) as
    :func:`derivations.impact_jets.generate`."""
    from .._derivations import impact_jets as ij
    private_dir(d, create=True)
    written, man = ij.generate(d, (n,), tuple(orders), force=force, starts=starts)
    secure(d, [*written, ij.MANIFEST, "__init__.py"])
    return written, man


def load(n, order, start=None):
    """The module ``impact_n<n>_order<order>`` (``start`` s: ``impact_n<n>_s<s>_order<K>``,
    a flight from coordinate s's section) from the per-user cache, generated there first
    when missing or stale, verified (module docstring) before it runs."""
    from .._derivations import impact_jets as ij
    name = ij.module_name(n, order, start)
    d = private_dir(create=True)
    high = order > max(ij.ORDERS)
    # a high order serves l2 alone (it holds all lower state derivatives): only it
    orders = (order,) if high else tuple(range(1, order + 1))
    starts = start is not None
    # the manifest says only whether to regenerate
    stale = ij.check(d, (n,), (order,), starts=starts)
    bad = None
    if not stale:
        text, bad = _read_verified(d, name, n, order, start)
        if bad:
            warnings.warn(f"generated-code cache {d}: {name}.py {bad}; regenerating it",
                          stacklevel=5)
    if stale or bad:
        warnings.warn(f"generating the order-{order} jets of the {n}-mass structure into {d} "
                      f"(once; may take {'minutes' if high else 'a minute'})", stacklevel=5)
        generate(d, n, orders, force=bool(bad), starts=starts)
        text, bad = _read_verified(d, name, n, order, start)
        if bad:
            raise SymviError(f"generated-code cache {d}: {name}.py, just generated, {bad}")
    return _execute(text, d / f"{name}.py", f"symvi_user_generated.{name}")


def _read_verified(d, name, n, order, start=None):
    """(text, None) when ``d/name.py`` passes every check, else (text or None, reason)."""
    private_dir(d)                          # again: checked right before reading
    path = Path(d) / f"{name}.py"
    flags = os.O_RDONLY | getattr(os, "O_NOFOLLOW", 0) | getattr(os, "O_CLOEXEC", 0)
    try:
        fd = os.open(path, flags)
    except OSError as exc:
        return None, f"cannot be read ({exc.strerror or exc})"
    with os.fdopen(fd, "rb") as fh:
        st = os.fstat(fh.fileno())
        if not stat.S_ISREG(st.st_mode):
            _refuse(d, str(path), "is not a regular file")
        _check_owner(st, d, str(path))     # the file opened, not a name swapped since
        if st.st_size > MAX_BYTES:
            return None, f"is larger than {MAX_BYTES >> 20} MB"
        data = fh.read(MAX_BYTES + 1)
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError:
        return None, "is not UTF-8 text"
    return text, verify(text, n, order, start)


def verify(text, n, order, start=None):
    """None if ``text`` is what the generator writes for structure ``n``, order ``order``
    as far as can be told without running the derivation (module docstring); else the
    reason, a few words."""
    from .._derivations import impact_jets as ij
    lines = text.splitlines()
    if len(lines) < 2 or "DO NOT EDIT" not in lines[0]:
        return "lacks the generator's header"
    if lines[1].strip() != f"# input-hash: {ij.input_hash()}":
        return ("was generated from other inputs (derivation script or SymPy version; "
                "input hash recomputed now)")
    try:
        tree = ast.parse(text)
    except (SyntaxError, ValueError, RecursionError, MemoryError) as exc:
        return f"does not parse ({type(exc).__name__})"
    try:
        values, width = _check_module(tree)
    except _Refused as exc:
        return f"holds code the generator never writes ({exc})"
    except RecursionError:
        return "holds code the generator never writes (nested too deeply)"
    if values.get("N") != n or values.get("ORDER") != order:
        return f"is not the structure N = {n}, order {order}"
    if values.get("INPUTS") != ij.inputs(n, order, start):
        return "has other INPUTS than the structure's"
    idx = _indices(values.get("LAYOUT"))
    if idx is None or not idx or max(idx) >= width or min(idx) < 0:
        return "has a LAYOUT that does not index its result"
    return None


class _Refused(Exception):
    pass


def _check_module(tree):
    """Walk the module: the allowed statements only.  Returns (the literal module
    constants, the length of the tuple ``_jet`` returns)."""
    values, seen, width = {}, set(), -1
    for i, node in enumerate(tree.body):
        if isinstance(node, ast.Expr) and i == 0 and _is_str(node.value):
            continue
        if isinstance(node, ast.Import):
            if any(a.name not in ("math", "mpmath") or a.asname for a in node.names):
                raise _Refused("an import other than math, mpmath")
            continue
        if isinstance(node, ast.Assign) and len(node.targets) == 1 \
                and isinstance(node.targets[0], ast.Name) \
                and node.targets[0].id in _MODULE_NAMES - seen:
            seen.add(node.targets[0].id)
            values[node.targets[0].id] = _literal(node.value)
            continue
        if isinstance(node, ast.FunctionDef) and node.name in _FUNCTIONS.keys() - seen:
            seen.add(node.name)
            w = _check_function(node)
            if node.name == "_jet":
                width = w
            continue
        raise _Refused(f"an unexpected statement ({type(node).__name__}) at line {node.lineno}")
    if seen != _MODULE_NAMES | _FUNCTIONS.keys():
        raise _Refused(f"missing {', '.join(sorted(_MODULE_NAMES | _FUNCTIONS.keys() - seen))}")
    return values, width


def _is_str(node):
    return isinstance(node, ast.Constant) and isinstance(node.value, str)


def _literal(node):
    """A constant of numbers, strings, lists, tuples and dicts, and quotients of numbers
    (``Q_F64``); its value."""
    if isinstance(node, ast.Constant) and type(node.value) in (int, float, str):
        return node.value
    if isinstance(node, (ast.List, ast.Tuple)):
        return [_literal(e) for e in node.elts]
    if isinstance(node, ast.Dict) and None not in node.keys:
        return {_literal(k): _literal(v) for k, v in zip(node.keys, node.values)}
    if isinstance(node, ast.UnaryOp) and isinstance(node.op, ast.USub) \
            and isinstance(node.operand, ast.Constant) \
            and type(node.operand.value) in (int, float):
        return -node.operand.value
    if isinstance(node, ast.BinOp) and isinstance(node.op, ast.Div):
        a, b = _literal(node.left), _literal(node.right)
        if type(a) in (int, float) and type(b) in (int, float) and b != 0:
            return a / b
    raise _Refused(f"a non-literal constant at line {getattr(node, 'lineno', '?')}")


def _check_function(fn):
    """``_jet(inp, sin, cos, Q)``: assignments of arithmetic, then one return of a tuple;
    ``f64(inp)``, ``mp(inp)``: a docstring and ``return _jet(inp, ...)``.  Returns the
    length of the returned tuple (``_jet``) or -1."""
    a = fn.args
    if (fn.decorator_list or fn.returns or a.vararg or a.kwarg or a.kwonlyargs
            or a.defaults or a.kw_defaults or getattr(a, "posonlyargs", [])
            or tuple(x.arg for x in a.args) != _FUNCTIONS[fn.name]
            or any(x.annotation for x in a.args)):
        raise _Refused(f"the signature of {fn.name}")
    jet = fn.name == "_jet"
    body = fn.body[1:] if fn.body and isinstance(fn.body[0], ast.Expr) \
        and _is_str(fn.body[0].value) else fn.body
    if not body or not isinstance(body[-1], ast.Return) or body[-1].value is None:
        raise _Refused(f"{fn.name} does not end in a return")
    for st in body[:-1]:
        if not jet or not isinstance(st, ast.Assign) or len(st.targets) != 1:
            raise _Refused(f"an unexpected statement ({type(st).__name__}) in {fn.name} at "
                           f"line {st.lineno}")
        t = st.targets[0]
        names = t.elts if isinstance(t, ast.Tuple) else [t]
        for x in names:
            if not isinstance(x, ast.Name) or x.id in _PROTECTED or x.id.startswith("__"):
                raise _Refused(f"an assignment to {ast.unparse(x)[:30]} at line {st.lineno}")
        _check_expr(st.value, jet)
        if not any(isinstance(x, ast.Name) for x in ast.walk(st.value)):
            # every value derives from the (float or mpf) inputs: no integer arithmetic
            raise _Refused(f"a constant-only assignment at line {st.lineno}")
    ret = body[-1].value
    _check_expr(ret, jet)
    if jet:
        if not isinstance(ret, ast.Tuple):
            raise _Refused("_jet does not return a tuple")
        return len(ret.elts)
    if not (isinstance(ret, ast.Call) and isinstance(ret.func, ast.Name)
            and ret.func.id == "_jet"):
        raise _Refused(f"{fn.name} does not return _jet(...)")
    return -1


def _check_expr(node, jet):
    """Arithmetic: names (no builtins), numbers, + - * /, ** by a small integer, unary
    -, tuples; in ``_jet`` calls of its ``sin``, ``cos``; in ``f64``/``mp`` calls of
    ``_jet`` and ``mpmath.mpf`` and the attributes math/mpmath .sin/.cos/.mpf."""
    stack = [node]
    while stack:
        e = stack.pop()
        if isinstance(e, ast.Name):
            if e.id in _BUILTINS or e.id.startswith("__") or not isinstance(e.ctx, ast.Load):
                raise _Refused(f"the name {e.id} at line {e.lineno}")
        elif isinstance(e, ast.Constant):
            if type(e.value) not in (int, float):
                raise _Refused(f"a {type(e.value).__name__} constant at line {e.lineno}")
        elif isinstance(e, ast.BinOp):
            if isinstance(e.op, ast.Pow):
                k = e.right.operand if isinstance(e.right, ast.UnaryOp) \
                    and isinstance(e.right.op, ast.USub) else e.right
                if not (isinstance(e.left, ast.Name) and isinstance(k, ast.Constant)
                        and type(k.value) is int and k.value <= MAX_POWER):
                    raise _Refused(f"a power other than of a name by a small integer at "
                                   f"line {e.lineno}")
                stack.append(e.left)
                continue
            if not isinstance(e.op, (ast.Add, ast.Sub, ast.Mult, ast.Div)):
                raise _Refused(f"the operator {type(e.op).__name__} at line {e.lineno}")
            stack += [e.left, e.right]
        elif isinstance(e, ast.UnaryOp):
            if not isinstance(e.op, (ast.USub, ast.UAdd)):
                raise _Refused(f"the operator {type(e.op).__name__} at line {e.lineno}")
            stack.append(e.operand)
        elif isinstance(e, ast.Tuple):
            if not isinstance(e.ctx, ast.Load):
                raise _Refused(f"a tuple target at line {e.lineno}")
            stack += e.elts
        elif isinstance(e, ast.Call):
            f = e.func
            ok = (isinstance(f, ast.Name) and f.id in (("sin", "cos") if jet else ("_jet",))
                  or not jet and _attribute(f) == "mpmath.mpf")
            if not ok or e.keywords or any(isinstance(x, ast.Starred) for x in e.args):
                raise _Refused(f"a call of {ast.unparse(f)[:30]} at line {e.lineno}")
            stack += e.args
        elif isinstance(e, ast.Attribute) and not jet:
            if _attribute(e) not in ("math.sin", "math.cos", "mpmath.sin", "mpmath.cos"):
                raise _Refused(f"the attribute {ast.unparse(e)[:30]} at line {e.lineno}")
        else:
            raise _Refused(f"a {type(e).__name__} at line {getattr(e, 'lineno', '?')}")


def _attribute(e):
    if isinstance(e, ast.Attribute) and isinstance(e.value, ast.Name):
        return f"{e.value.id}.{e.attr}"
    return None


def _indices(layout):
    """All integers of a LAYOUT (name -> int or nested lists of ints), or None."""
    if not isinstance(layout, dict) or not all(isinstance(k, str) for k in layout):
        return None
    out, stack = [], list(layout.values())
    while stack:
        v = stack.pop()
        if isinstance(v, list):
            stack += v
        elif type(v) is int:
            out.append(v)
        else:
            return None
    return out


def _execute(text, path, name):
    """Compile ``text`` (already verified) and run it as module ``name``; the text
    checked is the text run, and no .pyc is read or written."""
    code = compile(text, str(path), "exec", dont_inherit=True)
    mod = types.ModuleType(name)
    mod.__file__ = str(path)
    sys.modules[name] = mod
    try:
        exec(code, mod.__dict__)           # noqa: S102 -- verified arithmetic only
    except BaseException:
        sys.modules.pop(name, None)
        raise
    return mod


def stale_text(d, n, orders):
    """The complete check of ``symvi regenerate --model FILE --check``: each module's
    text against the derivation run again (its SHA-256), never against the manifest.
    Reasons it differs (empty when every module is exactly what symvi writes)."""
    from .._derivations import impact_jets as ij
    d = private_dir(d)
    ihash = ij.input_hash()
    why = []
    for K in orders:
        name = f"{ij.module_name(n, K)}.py"
        p = d / name
        if not p.is_file():
            why.append(f"{name} is missing")
            continue
        want = hashlib.sha256(ij.render(n, K, ihash).encode("utf-8")).hexdigest()
        if ij.file_hash(p) != want:
            why.append(f"{name} differs from what the derivation writes now")
    return why
