"""In-process command-line runs for the fuzz suites (no interpreter start per case)."""
import contextlib
import hashlib
import io
import os

from symvi.cli import main


def cli(*argv, cwd=None):
    """Run ``symvi ARGV`` in this process; return (exit code, stdout, stderr)."""
    out, err = io.StringIO(), io.StringIO()
    old = os.getcwd()
    try:
        if cwd is not None:
            os.chdir(cwd)
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
            try:
                rc = main([str(a) for a in argv])
            except SystemExit as exc:      # argparse
                rc = exc.code if isinstance(exc.code, int) else 2
    finally:
        os.chdir(old)
    return rc, out.getvalue(), err.getvalue()


def assert_bad_input(result, *words):
    """Exit 2, exactly one line on stderr starting with 'symvi: error', no traceback, no
    internal error; each of ``words`` (case-insensitive) in that line."""
    rc, out, err = result
    lines = [ln for ln in err.splitlines() if ln.strip()]
    assert "Traceback" not in err and "internal error" not in err, err
    assert rc == 2, (rc, err, out[-300:])
    assert len(lines) == 1, err
    assert lines[0].startswith("symvi: error"), lines[0]
    for w in words:
        assert w.lower() in lines[0].lower(), (w, lines[0])
    return lines[0]


def snapshot(folder):
    """{relative path: (kind, sha256 or link target)} of everything under ``folder``."""
    out = {}
    for root, dirs, files in os.walk(folder):
        for f in files + [d for d in dirs if os.path.islink(os.path.join(root, d))]:
            p = os.path.join(root, f)
            rel = os.path.relpath(p, folder)
            st = os.lstat(p)
            if os.path.islink(p):
                out[rel] = ("link", os.readlink(p))
            elif os.path.isfile(p):
                with open(p, "rb") as fh:
                    out[rel] = ("file", st.st_mode, hashlib.sha256(fh.read()).hexdigest())
            else:
                out[rel] = ("special", st.st_mode, st.st_rdev)
    return out
