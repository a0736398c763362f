"""Atomic outputs (symvi._io): renamed into place with the usual permissions."""
import os
import stat

from symvi._io import write_bytes, write_text


def _mode(path):
    return stat.S_IMODE(os.stat(path).st_mode)


def test_new_file_gets_umask_mode_not_0600(tmp_path):
    old = os.umask(0o022)
    try:
        write_text(tmp_path / "a.txt", "x")
        plain = tmp_path / "plain.txt"
        plain.write_text("x")
    finally:
        os.umask(old)
    assert _mode(tmp_path / "a.txt") == _mode(plain) == 0o644


def test_replaced_file_keeps_its_mode(tmp_path):
    p = tmp_path / "b.bin"
    p.write_bytes(b"old")
    os.chmod(p, 0o640)
    write_bytes(p, b"new")
    assert p.read_bytes() == b"new" and _mode(p) == 0o640
