"""One writer per plane store (issue 23, item 13): a second run on the same ``--out`` is
refused with one line while the first holds ``<store>.lock``; a dead run's lock is taken
over; a full disk mid-run is one line and the store resumes to the same result."""
import errno
import fcntl
import hashlib
import os
import subprocess
import sys

import pytest

from symvi.plane import PlaneStore
from tests.fuzz._cli import assert_bad_input, cli, snapshot

FLAGS = ["--mu-m", "2", "--mu-k", "5", "--f2", "0", "--b", "1.5", "--r", "0.8"]
PLANE = ["plane", *FLAGS, "--x", "omega:0.7:0.8:4", "--y", "b:1.3:1.7:4", "--impacts", "20",
         "--transient", "20", "--workers", "0", "--chunk-rows", "1", "--out"]


def _dead_pid():
    p = subprocess.Popen([sys.executable, "-c", "pass"])
    p.wait()
    return p.pid


def _data(store):
    """sha256 of every chunk and array header (the root attrs hold the command: skipped)."""
    out = {}
    for root, _, files in os.walk(store):
        for f in files:
            rel = os.path.relpath(os.path.join(root, f), store)
            if rel not in (".zattrs", ".zmetadata"):
                with open(os.path.join(root, f), "rb") as fh:
                    out[rel] = hashlib.sha256(fh.read()).hexdigest()
    return out


@pytest.mark.parametrize("exists", [False, True])
def test_second_run_refused_while_the_first_holds_the_lock(tmp_path, exists):
    store = tmp_path / "p.zarr"
    if exists:
        assert cli(*PLANE, store)[0] == 0
    lock = tmp_path / "p.zarr.lock"
    fd = os.open(lock, os.O_RDWR | os.O_CREAT)       # another run: its own open file
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        os.write(fd, b"4242\n")
        before = snapshot(tmp_path)
        line = assert_bad_input(cli(*PLANE, store), "--out", "another symvi plane run")
        assert "4242" in line and str(lock) in line
        assert snapshot(tmp_path) == before                # its lock and store untouched
    finally:
        os.close(fd)
    assert cli(*PLANE, store)[0] == 0                      # free again once it is released
    assert not lock.exists()


def test_lock_of_a_dead_run_is_taken_over(tmp_path):
    store, lock = tmp_path / "p.zarr", tmp_path / "p.zarr.lock"
    lock.write_text(f"{_dead_pid()}\n")
    rc, out, err = cli(*PLANE, store)
    assert rc == 0, err
    assert "16 points" in out and not lock.exists()


def test_lock_path_that_is_a_symlink_is_refused(tmp_path):
    target = tmp_path / "victim.txt"
    target.write_text("mine")
    os.symlink(target, tmp_path / "p.zarr.lock")
    before = snapshot(tmp_path)
    assert_bad_input(cli(*PLANE, tmp_path / "p.zarr"), "--out", "symlink")
    assert snapshot(tmp_path) == before


def test_lock_is_reentrant_in_one_process(tmp_path):
    st = PlaneStore(tmp_path / "p.zarr", None)
    with st.lock():
        assert (tmp_path / "p.zarr.lock").read_text().strip() == str(os.getpid())
        with st.lock():
            pass
        assert (tmp_path / "p.zarr.lock").exists()
    assert not (tmp_path / "p.zarr.lock").exists()


def test_full_disk_mid_run_is_one_line_and_resumes_identically(tmp_path, monkeypatch):
    ref = tmp_path / "ref.zarr"
    assert cli(*PLANE, ref)[0] == 0
    store = tmp_path / "p.zarr"
    write, calls = PlaneStore.write, []

    def full_after_one(self, *a):
        calls.append(a[:2])
        if len(calls) > 1:
            raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC), self.path)
        return write(self, *a)
    monkeypatch.setattr(PlaneStore, "write", full_after_one)
    assert_bad_input(cli(*PLANE, store), "No space left")
    monkeypatch.setattr(PlaneStore, "write", write)
    assert PlaneStore.read(store).done().sum() == 1       # the first block was kept
    assert not (tmp_path / "p.zarr.lock").exists()
    rc, out, _ = cli(*PLANE, store)
    assert rc == 0 and "3 blocks computed, 1 already there" in out
    assert _data(store) == _data(ref)
