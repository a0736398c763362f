"""--scheduler: a malformed address is refused before any connection, and an address where
no scheduler answers (silent port, refused port, garbage) ends within the connect timeout
with one line, exit 2, nothing left behind and nothing printed at exit (issue 23, defect 6).

The CLI waits CONNECT_TIMEOUT = 10 s; these tests shorten it to keep the suite fast."""
import socket
import subprocess
import sys
import threading

import pytest

import symvi.plane.engine as eng
from symvi.errors import ParameterError, SymviError
from tests.fuzz._cli import assert_bad_input, cli

FLAGS = ["--mu-m", "2", "--mu-k", "5", "--f2", "0", "--b", "1.5", "--r", "0.8"]
PLANE = ["plane", *FLAGS, "--x", "omega:0.7:0.8:4", "--y", "b:1.3:1.7:4", "--impacts", "20",
         "--transient", "20"]
SWEEP = ["sweep", *FLAGS, "--range", "omega=0.73:0.75:4"]
SHORT = 1.5   # long enough that a loaded machine still connects before it


class Server:
    """A local TCP port that accepts connections and then only does ``behaviour``:
    "silent" (never a byte), "garbage" (a few bytes that are not Dask's, then close)."""

    def __init__(self, behaviour="silent"):
        self.sock = socket.socket()
        self.sock.bind(("127.0.0.1", 0))
        self.sock.listen(8)
        self.address = f"tcp://127.0.0.1:{self.sock.getsockname()[1]}"
        self.behaviour, self.conns = behaviour, []
        threading.Thread(target=self._serve, daemon=True).start()

    def _serve(self):
        while True:
            try:
                c, _ = self.sock.accept()
            except OSError:                 # closed
                return
            self.conns.append(c)
            if self.behaviour == "garbage":
                c.sendall(b"HTTP/1.1 400 Bad Request\r\n\r\n" * 4)
                c.close()

    def close(self):
        for c in self.conns:
            c.close()
        self.sock.close()


@pytest.fixture
def short(monkeypatch):
    monkeypatch.setattr(eng, "CONNECT_TIMEOUT", SHORT)


def _free_port():
    with socket.socket() as s:             # bound then closed: nothing listens there
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


@pytest.mark.parametrize("address", [
    "nonsense::", "127.0.0.1:8786", "tcp://", "tcp://host", "tcp://host:", "tcp://host:0",
    "tcp://host:99999", "tcp://host:87x6", "http://host:8786", "tcp://ho st:8786",
    "tcp://host:8786/path", "tcp://[::1:8786", "tcp://-host:8786", "",
])
def test_malformed_address_refused_up_front(address):
    with pytest.raises(ParameterError) as e:
        eng.check_scheduler(address)
    assert "--scheduler" in str(e.value) and "tcp://host:port" in str(e.value)


@pytest.mark.parametrize("address", ["tcp://127.0.0.1:8786", "tcp://node-7.cluster.local:1",
                                     "tls://sched:65535", "tcp://[::1]:8786", "tcp://h_1:80"])
def test_wellformed_address_accepted(address):
    assert eng.check_scheduler(address) == address


@pytest.mark.parametrize("argv", [PLANE, SWEEP])
def test_malformed_address_one_line_nothing_written(tmp_path, argv):
    out = tmp_path / ("p.zarr" if argv is PLANE else "s.png")
    line = assert_bad_input(cli(*argv, "--out", out, "--scheduler", "nonsense::"),
                            "--scheduler", "tcp://host:port")
    assert "nonsense::" in line and not out.exists()


def test_silent_port_gives_up_within_the_timeout(tmp_path, short):
    srv = Server("silent")
    try:
        out = tmp_path / "p.zarr"
        line = assert_bad_input(cli(*PLANE, "--out", out, "--scheduler", srv.address),
                                "--scheduler", "could not reach scheduler", srv.address,
                                f"within {SHORT:g} s", "handshake")
        assert srv.conns, "the probe never connected"
        assert not out.exists(), line                 # nothing half-made is left behind
    finally:
        srv.close()


@pytest.mark.parametrize("behaviour", ["refused", "garbage"])
def test_no_scheduler_there_one_line(tmp_path, monkeypatch, behaviour):
    # a refusal or garbage ends at once; a generous timeout keeps a loaded machine (the
    # probe thread starting late) from turning it into a timeout
    monkeypatch.setattr(eng, "CONNECT_TIMEOUT", 5.0)
    srv = Server("garbage") if behaviour == "garbage" else None
    address = srv.address if srv else f"tcp://127.0.0.1:{_free_port()}"
    try:
        argv, out = (PLANE, tmp_path / "p.zarr") if srv is None else (SWEEP, tmp_path / "s.png")
        line = assert_bad_input(cli(*argv, "--out", out, "--scheduler", address),
                                "--scheduler", "could not reach scheduler", address)
        assert not out.exists() and "0x" not in line      # no object reprs
        if behaviour == "refused":
            assert "connection refused" in line
    finally:
        if srv:
            srv.close()


@pytest.mark.filterwarnings("ignore:Port 8787 is already in use")
def test_reach_a_real_scheduler_and_refuse_a_worker():
    """A scheduler is recognised by its identity; a worker's port answers Dask's
    handshake but is not a scheduler."""
    import logging

    from distributed import LocalCluster
    with LocalCluster(n_workers=1, threads_per_worker=1, processes=False, host="127.0.0.1", protocol="tcp://",
                      dashboard_address=None, worker_dashboard_address=None,
                      silence_logs=logging.ERROR) as lc:
        assert eng.reach_scheduler(lc.scheduler_address, 5)["type"] == "Scheduler"
        worker = next(iter(lc.scheduler_info["workers"]))
        with pytest.raises(SymviError, match="not a scheduler"):
            eng.reach_scheduler(worker, 5)


@pytest.mark.slow
def test_nothing_printed_at_exit():
    """A fresh interpreter: a malformed address and a silent port, then exit; stderr holds
    exactly the two error lines (no 'Exception ignored ... Client.__del__' traceback)."""
    code = f"""
import socket, sys
import symvi.plane.engine as eng
from symvi.cli import main
eng.CONNECT_TIMEOUT = {SHORT}
s = socket.socket(); s.bind(("127.0.0.1", 0)); s.listen(4)
argv = {PLANE!r} + ["--out", "p.zarr", "--scheduler"]
codes = [main(argv + ["nonsense::"]), main(argv + ["tcp://127.0.0.1:%d" % s.getsockname()[1]])]
print(codes)
"""
    import tempfile
    with tempfile.TemporaryDirectory() as d:
        r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                           cwd=d, timeout=60)
    lines = r.stderr.strip().splitlines()
    assert r.returncode == 0 and r.stdout.strip() == "[2, 2]", r.stderr
    assert len(lines) == 2 and all(ln.startswith("symvi: error: --scheduler") for ln in lines), \
        r.stderr
