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


# ---------------------------------------------------------------- check_output, atomic_path
import errno  # noqa: E402

import pytest  # noqa: E402

from symvi._io import atomic_path, check_output, distinct_outputs  # noqa: E402
from symvi.errors import OutputError, ParameterError  # noqa: E402


@pytest.fixture
def targets(tmp_path):
    """A folder of things an output path must not replace or write through."""
    (tmp_path / "file.npz").write_bytes(b"mine")
    os.mkfifo(tmp_path / "fifo.npz")
    os.symlink("file.npz", tmp_path / "link.npz")
    os.symlink("nowhere.npz", tmp_path / "dangle.npz")
    (tmp_path / "dir.npz").mkdir()
    if os.geteuid() == 0:
        os.mknod(tmp_path / "node.npz", 0o666 | stat.S_IFCHR, os.makedev(1, 3))
    return tmp_path


@pytest.mark.parametrize("name,word", [
    ("fifo.npz", "FIFO"), ("link.npz", "symlink"), ("dangle.npz", "symlink"),
    ("dir.npz", "folder"), ("new.npz/", "folder"), ("", "empty"), ("file.npz/x.npz", "folder"),
    ("x.txt", "extension"), ("node.npz", "device")])
def test_check_output_refuses(targets, name, word):
    if name == "node.npz" and not (targets / name).exists():
        pytest.skip("mknod needs root")
    path = os.path.join(targets, name) if name else ""
    with pytest.raises(ParameterError) as exc:
        check_output(path, flag="--out", suffixes=(".npz",))
    msg = str(exc.value)
    assert "--out" in msg and word.lower() in msg.lower() and "\n" not in msg


def test_check_output_accepts_new_and_regular_files(targets):
    for name in ("file.npz", "new.npz", "sub/deeper/new.NPZ"):
        assert check_output(str(targets / name), flag="--out", suffixes=(".npz",))
    assert check_output(None, flag="--plot") is None
    assert not (targets / "sub").exists()              # checking creates nothing


@pytest.mark.parametrize("name,ok", [("dir.npz", True), ("dir.npz/", True), ("new", True),
                                     ("new/a/b/", True), ("file.npz", False),
                                     ("file.npz/", False), ("fifo.npz", False),
                                     ("dangle.npz", False), ("file.npz/sub", False), ("", False)])
def test_check_output_folders(targets, name, ok):
    path = os.path.join(targets, name) if name else ""
    if ok:
        assert check_output(path, flag="--out", folder=True) == path
    else:
        with pytest.raises(ParameterError, match="--out"):
            check_output(path, flag="--out", folder=True)


def test_check_output_refuses_root_and_unwritable_places(tmp_path):
    with pytest.raises(ParameterError, match="root"):
        check_output("/", flag="--out", folder=True)
    with pytest.raises(ParameterError, match="names a folder"):
        check_output("/", flag="--out")
    # /proc refuses new files even to root (os.access would say yes)
    if os.path.isdir("/proc/self"):
        with pytest.raises(ParameterError, match="cannot create"):
            check_output("/proc/x.npz", flag="--out")
        with pytest.raises(ParameterError, match="cannot create"):
            check_output("/proc/new-folder", flag="--out", folder=True)
    with pytest.raises(ParameterError, match="--out"):
        check_output(str(tmp_path / ("x" * 300 + ".npz")), flag="--out")     # name too long
    with pytest.raises(ParameterError, match="NUL"):
        check_output("a\0b.npz", flag="--out")
    assert os.listdir(tmp_path) == []                   # the probe file is gone


def test_distinct_outputs(tmp_path):
    a = str(tmp_path / "a.png")
    distinct_outputs(("--out", a), ("--plot", None), ("--x", str(tmp_path / "b.png")))
    with pytest.raises(ParameterError, match="--plot"):
        distinct_outputs(("--out", a), ("--plot", os.path.join(tmp_path, ".", "a.png")))


@pytest.mark.parametrize("name", ["fifo.npz", "link.npz", "dangle.npz", "dir.npz", "node.npz"])
def test_atomic_path_leaves_special_files_alone(targets, name):
    from tests.fuzz._cli import snapshot
    if not os.path.lexists(targets / name):
        pytest.skip("mknod needs root")
    before = snapshot(targets)
    with pytest.raises(OutputError, match="refusing"):
        write_bytes(targets / name, b"data")
    assert snapshot(targets) == before


def test_setuid_bits_are_not_copied(tmp_path):
    p = tmp_path / "s.bin"
    p.write_bytes(b"old")
    os.chmod(p, 0o4755)
    write_bytes(p, b"new")
    assert _mode(p) == 0o755


def test_full_disk_is_one_error_and_loses_nothing(tmp_path):
    p = tmp_path / "keep.txt"
    p.write_text("old")

    def full(*a, **k):
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))
    with pytest.raises(OutputError, match="No space left") as exc:
        with atomic_path(p) as tmp:
            with open(tmp, "w") as fh:
                fh.write("half")
            full()
    assert "\n" not in str(exc.value)
    assert p.read_text() == "old" and os.listdir(tmp_path) == ["keep.txt"]
