"""The per-user cache of generated code is run only if it is the user's alone and holds
what the generator writes (issue 23, defect 10): a group-writable folder, a file of
another uid, a symlink, a forged manifest that matches tampered code."""
import json
import os
import shutil
import stat
import warnings

import pytest

from symvi._derivations import impact_jets as ij
from symvi.codegen import _usercache as uc
from symvi.model import dumps
from tests.fuzz._cli import assert_bad_input, cli
from tests.zoo import FIVE_CHAIN_STOP3

NAME = "impact_n5_order1"


@pytest.fixture(scope="module")
def pristine(tmp_path_factory):
    """A cache folder holding N = 5, order 1, generated once for the module."""
    d = tmp_path_factory.mktemp("pristine") / "symvi" / "generated"
    uc.generate(d, 5, (1,))
    return d


@pytest.fixture
def cache(pristine, tmp_path, monkeypatch):
    """A private copy of the pristine cache under $XDG_CACHE_HOME (this test's)."""
    base = tmp_path / "xdg"
    shutil.copytree(pristine.parent, base / "symvi")
    monkeypatch.setenv("XDG_CACHE_HOME", str(base))
    d = base / "symvi" / "generated"
    assert uc.cache_dir() == d
    return d


def _forge(d, text):
    """Write ``text`` as the module and make the manifest in the folder agree with it."""
    p = d / f"{NAME}.py"
    p.write_text(text)
    man = json.loads((d / ij.MANIFEST).read_text())
    man["files"][p.name] = ij.file_hash(p)
    (d / ij.MANIFEST).write_text(json.dumps(man))
    assert ij.check(d, (5,), (1,)) == []          # the manifest alone would accept it
    return p


def _load_quietly():
    with warnings.catch_warnings(record=True) as w:
        warnings.simplefilter("always")
        mod = uc.load(5, 1)
    return mod, [str(x.message) for x in w]


def test_pristine_cache_loads_without_regenerating(cache):
    before = (cache / f"{NAME}.py").stat().st_mtime_ns
    mod, msgs = _load_quietly()
    assert mod.N == 5 and mod.INPUTS == ij.inputs(5, 1) and msgs == []
    assert (cache / f"{NAME}.py").stat().st_mtime_ns == before
    assert not (cache / "__pycache__").exists()            # no .pyc written or read


@pytest.mark.parametrize("where", ["folder", "file", "parent"])
def test_writable_by_others_refused_naming_the_folder(cache, where):
    target = {"folder": cache, "file": cache / f"{NAME}.py", "parent": cache.parent}[where]
    os.chmod(target, stat.S_IMODE(os.stat(target).st_mode) | 0o020)
    with pytest.raises(uc.UnsafeCacheError) as e:
        uc.load(5, 1)
    msg = str(e.value)
    assert str(cache) in msg and "writable by its group" in msg and "\n" not in msg


def test_world_writable_base_without_sticky_bit_refused(cache):
    base = cache.parent.parent
    os.chmod(base, 0o777)
    with pytest.raises(uc.UnsafeCacheError, match="writable by everyone"):
        uc.load(5, 1)
    os.chmod(base, 0o777 | stat.S_ISVTX)             # /tmp-like: allowed
    assert uc.load(5, 1).N == 5


@pytest.mark.skipif(not hasattr(os, "geteuid") or os.geteuid() != 0,
                    reason="giving a file to another uid needs root")
@pytest.mark.parametrize("what", [f"{NAME}.py", ij.MANIFEST, "."])
def test_file_of_another_uid_refused(cache, what):
    os.chown(cache / what, 65534, 65534)
    with pytest.raises(uc.UnsafeCacheError, match="belongs to uid 65534"):
        uc.load(5, 1)


def test_symlinked_folder_refused(cache, tmp_path):
    elsewhere = tmp_path / "elsewhere"
    cache.rename(elsewhere)
    cache.symlink_to(elsewhere, target_is_directory=True)
    with pytest.raises(uc.UnsafeCacheError, match="symbolic link"):
        uc.load(5, 1)


def test_forged_manifest_matching_tampered_code_is_not_run(cache, tmp_path):
    marker = tmp_path / "ran"
    p = cache / f"{NAME}.py"
    good = p.read_text()
    evil = good.replace("import math\n", f"import math\nopen({str(marker)!r}, 'w')\n", 1)
    _forge(cache, evil)
    mod, msgs = _load_quietly()
    assert not marker.exists()                              # never executed
    assert any("never writes" in m and "regenerating" in m for m in msgs), msgs
    assert p.read_text() == good and mod.N == 5             # regenerated as the generator writes


def test_forged_header_of_other_inputs_is_regenerated(cache):
    p = cache / f"{NAME}.py"
    good = p.read_text()
    lines = good.splitlines(keepends=True)
    lines[1] = "# input-hash: " + "0" * 64 + "\n"
    _forge(cache, "".join(lines))
    _, msgs = _load_quietly()
    assert any("other inputs" in m for m in msgs) and p.read_text() == good


def test_tampered_arithmetic_caught_by_the_complete_check(cache):
    """Arithmetic alone cannot be told from the generator's without running it: loading
    takes it (it is the user's own private file), `regenerate --model --check` does not."""
    p = cache / f"{NAME}.py"
    _forge(cache, p.read_text().replace("c0 = 1/omega", "c0 = 2/omega", 1))
    assert uc.verify(p.read_text(), 5, 1) is None
    (p.parent / "m5.toml").write_text(dumps(FIVE_CHAIN_STOP3))
    rc, out, err = cli("regenerate", "--model", p.parent / "m5.toml", "--order", "1", "--check")
    assert rc == 1 and f"{NAME}.py differs from what the derivation writes now" in err


def test_group_writable_cache_one_line_exit_2(cache, tmp_path):
    f = tmp_path / "m5.toml"
    f.write_text(dumps(FIVE_CHAIN_STOP3))
    os.chmod(cache, 0o775)
    assert_bad_input(cli("regenerate", "--model", f, "--order", "1", "--check"),
                     "generated-code cache", str(cache), "writable by its group")


def test_generated_under_umask_002_is_private(tmp_path, monkeypatch):
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "xdg"))
    old = os.umask(0o002)
    try:
        uc.generate(uc.cache_dir(), 1, (1,))
    finally:
        os.umask(old)
    d = uc.cache_dir()
    for p in [d, d.parent, *d.iterdir()]:
        assert not os.stat(p).st_mode & 0o022, p
    assert uc.private_dir() == d


# --------------------------------------------------------------------- what may be run
def _shipped():
    import symvi._generated as g
    return open(os.path.join(os.path.dirname(g.__file__), "impact_n1_order1.py")).read()


@pytest.mark.parametrize("n,K", [(1, 1), (1, 2), (1, 3), (1, 4), (1, 5), (3, 2)])
def test_shipped_modules_pass(n, K):
    """The shipped modules come from the same generator: each form it prints passes."""
    import symvi._generated as g
    f = os.path.join(os.path.dirname(g.__file__), f"impact_n{n}_order{K}.py")
    assert uc.verify(open(f).read(), n, K) is None


@pytest.mark.parametrize("line", [
    "c0 = __import__('os')",
    "c0 = eval",
    "sin = eval",
    "c0 = 'x'",
    "c0 = omega.__class__",
    "c0 = [y0 for y0 in inp]",
    "c0 = (lambda: y0)()",
    "c0 = y0 ** y0",
    "c0 = y0 ** 100",
    "c0 = 2 ** 16",
    "c0 = 2",
    "c0 = inp[0]",
    "c0 = open",
    "c0 = math.sin(y0)",
    "c0 = len(inp)",
    "c0 = y0 if y0 else b",
    "c0 = y0 @ y0",
    "c0 = y0 << 2",
    "c0 = y0 < b",
    "c0 = f'{y0}'",
    "c0 = _jet(inp, sin, cos, Q)",
    "c0: float = y0",
    "c0 += y0",
    "del c0",
    "import os",
    "for k in Q: pass",
    "global c0",
])
def test_anything_but_the_generators_arithmetic_is_refused(line):
    text = _shipped()
    marker = "    c0 = 1/omega\n"
    assert marker in text and uc.verify(text, 1, 1) is None
    bad = text.replace(marker, marker + "    " + line + "\n", 1)
    assert "never writes" in (uc.verify(bad, 1, 1) or "") or "parse" in uc.verify(bad, 1, 1)


@pytest.mark.parametrize("edit,why", [
    (lambda t: t.replace("N = 1\n", "N = 2\n"), "structure"),
    (lambda t: t.replace("'te']", "'te', 'x']"), "INPUTS"),
    (lambda t: t.replace("'g_theta': 6", "'g_theta': 60"), "LAYOUT"),
    (lambda t: t.replace("import mpmath\n", "import mpmath\nimport os\n"), "never writes"),
    (lambda t: t.replace("def f64(inp):", "@staticmethod\ndef f64(inp):"), "never writes"),
    (lambda t: t + "\nprint(1)\n", "never writes"),
    (lambda t: t.replace("DO NOT EDIT", ""), "header"),
])
def test_module_level_changes_refused(edit, why):
    assert why in uc.verify(edit(_shipped()), 1, 1)
