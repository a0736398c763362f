"""Start-up (issue 24, item 10): the first run after install says what it compiles, on
stderr, and compiles the Hopf scan's kernels before the scan, so that the scan itself
compiles nothing more; --json stdout stays one JSON object.  numba's cache is redirected
to a temporary directory (NUMBA_CACHE_DIR), so the real cache is never touched."""
import json
import os
import subprocess
import sys

import pytest

from symvi._compiled import _dispatcher, _signature, is_cached
from symvi.cli._kernels import HOPF, INSIDE, ORBIT
from symvi.progress import shown

HOPF_ARGS = ["hopf", "--mu-m", "2", "--mu-k", "5", "--f2", "0", "--b", "1.5", "--r", "0.8",
             "--range", "omega=0.70:0.76", "--json"]


def _symvi(args, cache, progress="1"):
    env = dict(os.environ, NUMBA_CACHE_DIR=str(cache), SYMVI_PROGRESS=progress)
    return subprocess.run([sys.executable, "-m", "symvi", *args], capture_output=True,
                          text=True, env=env)


@pytest.mark.slow
def test_cold_cache_says_what_it_compiles_and_stdout_stays_json(tmp_path):
    cold = _symvi(HOPF_ARGS, tmp_path)
    assert cold.returncode == 0, cold.stderr
    lines = cold.stderr.splitlines()
    n = len(HOPF)
    assert any(f"first run after install: compiling {n} numba kernels" in s for s in lines), \
        cold.stderr
    done = [s for s in lines if s.startswith("symvi: compiled ") and f"/{n} " in s]
    assert len(done) == n and all(" in " in s and " s" in s for s in done), cold.stderr
    # the list in cli/_kernels.py matches the code: the scan compiled nothing more (shoot
    # and monodromy included: period1 compiled them with the scan's argument types)
    assert not [s for s in lines if s.startswith("symvi: compiling ")], cold.stderr
    obj = json.loads(cold.stdout)
    assert obj["complete"] and len(obj["points"]) == 1
    # warm: silent, and the same numbers to the last bit
    warm = _symvi(HOPF_ARGS, tmp_path)
    assert warm.returncode == 0 and warm.stderr == "", warm.stderr
    assert warm.stdout == cold.stdout


@pytest.mark.slow
def test_a_compile_outside_the_list_is_announced(tmp_path):
    """`symvi orbit --model` compiles kernels no warm-up lists: each is named on stderr."""
    (tmp_path / "m.toml").write_text(
        "[model]\nmass = [1.0, 2.0]\nstiffness = [[6.0, -5.0], [-5.0, 5.0]]\n"
        "damping = [[0.0, 0.0], [0.0, 0.0]]\nforcing = [1.0, 0.0]\n"
        "[stop]\nmass = 1\ngap = 1.5\nrestitution = 0.8\n")
    r = _symvi(["orbit", "--model", str(tmp_path / "m.toml"), "--omega", "0.73", "--json"],
               tmp_path / "cache")
    assert r.returncode == 0, r.stderr
    named = [s for s in r.stderr.splitlines() if s.startswith("symvi: compiling ")]
    assert any("period1 (symvi.orbits._period1)" in s for s in named), r.stderr
    json.loads(r.stdout)
    quiet = _symvi(["orbit", "--model", str(tmp_path / "m.toml"), "--omega", "0.73", "--json"],
                   tmp_path / "cache2", progress="0")
    assert quiet.returncode == 0 and quiet.stderr == "", quiet.stderr


def test_kernel_lists_name_existing_kernels_with_valid_signatures():
    for module, name, sig, secs in HOPF + ORBIT + INSIDE:
        disp = _dispatcher(module, name)
        assert hasattr(disp, "compile") and secs > 0, (module, name)
        args = _signature(sig)
        assert len(args) == disp.py_func.__code__.co_argcount, (name, sig)


def test_is_cached_answers_for_an_empty_cache(tmp_path, monkeypatch):
    """A kernel whose cache index is absent is not cached (the cold-cache test is an index
    lookup, no code loaded)."""
    module, name, sig, _ = ORBIT[0]
    cache = _dispatcher(module, name)._cache._cache_file
    monkeypatch.setattr(cache, "_index_path", str(tmp_path / "absent.nbi"))
    assert is_cached(module, name, sig) is False


def test_progress_switch(monkeypatch):
    class Tty:
        def isatty(self):
            return True
    monkeypatch.setenv("SYMVI_PROGRESS", "0")
    assert not shown(Tty())
    monkeypatch.setenv("SYMVI_PROGRESS", "1")
    assert shown(open(os.devnull, "w"))
    monkeypatch.delenv("SYMVI_PROGRESS")
    assert shown(Tty()) and not shown(open(os.devnull, "w"))
