"""Run a plane on Dask: one task per block of rows, each one compiled batch
(:func:`symvi.simulations.classifier.classify_runs`, the one classifier), written to the
store by the client as it completes.

* Tasks are pure functions of (spec, rows): a worker that dies loses only its running
  task, which Dask reruns elsewhere; a task's result is the same wherever it runs.
* Only the client writes the store, so workers need no access to its file system
  (``--scheduler`` on a cluster whose nodes do not share the disk works).
* Blocks already flagged done in the store are skipped: a restarted run computes only
  what is missing.
"""
import contextlib
import dataclasses
import functools
import json
import math
import os
import re
import sys
import time
from dataclasses import dataclass

import numpy as np

from ..errors import ParameterError, SymviError
from ..simulations.simulation import STOP_NAMES, _walked
from .grid import PlaneSpec, block_inputs
from .store import PlaneStore

#: seconds to wait for a scheduler given by address: connection and Dask's handshake
#: (read at each call, so tests may shorten it)
CONNECT_TIMEOUT = 10
#: what --scheduler accepts
SCHEDULER_FORM = "tcp://host:port (or tls://host:port; host a name, an IPv4 address or [IPv6], " \
                 "port 1 .. 65535)"
_ADDRESS = re.compile(r"(?:tcp|tls)://(?:\[[0-9A-Fa-f:.]+\]|[A-Za-z0-9_](?:[A-Za-z0-9_.-]{0,252}"
                      r"[A-Za-z0-9_])?):([0-9]{1,5})")


@functools.lru_cache(maxsize=8)
def _spec(text):
    # one validation per worker process and spec, not one per task
    return PlaneSpec.from_dict(json.loads(text))


def compute_block(spec_text, r0, r1):
    """Rows r0 .. r1-1 of the plane of ``spec_text`` (JSON of :meth:`PlaneSpec.as_dict`):
    name -> array (r1 - r0, nx).  What a Dask task runs; also the serial reference."""
    from ..simulations.classifier import classify_runs
    spec = _spec(spec_text)
    if _walked(spec.model):             # contact phases, nonlinear forces: point by point
        from ..simulations.simulation import classify_walked
        pts = [spec.point(i, j) for i in range(r0, r1) for j in range(spec.x.n)]
        res = classify_walked(pts, spec.impacts, spec.transient, follow=spec.follow,
                                row_len=spec.x.n)
        own = np.zeros(len(pts), dtype=bool)   # no period-1 orbit to start from
    else:
        C, Y0, own = block_inputs(spec, r0, r1)
        # a run that sticks goes on through it (its model per point: the held motion)
        nx = spec.x.n
        models = lambda p: spec.point(r0 + p // nx, p % nx)[0]     # noqa: E731
        res = classify_runs(C, Y0, spec.impacts, spec.transient, follow=spec.follow,
                            row_len=spec.x.n, models=models)
    shape = (r1 - r0, spec.x.n)
    own = own & ~res.followed          # a followed point did not start from its own orbit
    return {"attractor": res.labels().astype("<U16").reshape(shape),
            "stop": np.array([STOP_NAMES[k] for k in res.stop], dtype="<U16").reshape(shape),
            "period": res.period.astype(np.int32).reshape(shape),
            "impacts_per_orbit": res.impacts.astype(np.int32).reshape(shape),
            "lyapunov": res.lyapunov.reshape(shape),
            "rotation": res.rotation.reshape(shape),
            "impacts_per_period": res.impacts_per_period.reshape(shape),
            "max_velocity": res.max_velocity.reshape(shape),
            "own_start": own.reshape(shape)}


def compute_serial(spec):
    """The whole plane in this process, block by block (the reference of the tests)."""
    text = spec.text()
    blocks = [compute_block(text, r0, r1) for r0, r1 in spec.blocks()]
    return {k: np.concatenate([b[k] for b in blocks]) for k in blocks[0]}


@dataclass(frozen=True)
class PlaneRun:
    """What a call of :func:`run_plane` did."""

    path: str
    shape: tuple
    blocks: int           # blocks of the plane
    computed: int         # blocks computed by this call (the rest were in the store)
    workers: int
    seconds: float
    counts: dict          # attractor label -> number of points

    def as_dict(self):
        return {"out": self.path, "shape": list(self.shape), "points": int(np.prod(self.shape)),
                "blocks": self.blocks, "computed_blocks": self.computed,
                "resumed_blocks": self.blocks - self.computed, "workers": self.workers,
                "seconds": round(self.seconds, 3), "attractors": self.counts}


def run_plane(spec, out, *, scheduler=None, workers=None, progress=None, command=None,
              client=None):
    """Compute the plane of ``spec`` into the zarr store ``out``, resuming it if present.

    ``scheduler``: address of a running Dask scheduler; else a local cluster of
    ``workers`` processes (default: the CPU count) is started and stopped here;
    ``workers=0`` runs in this process without Dask.  ``client``: an existing
    :class:`distributed.Client` (tests).  ``progress``: True, False or None (a bar on
    stderr when it is a terminal).
    """
    t0 = time.perf_counter()
    check_workers(scheduler, workers)
    check_scheduler(scheduler)
    store = PlaneStore(out, spec)
    with store.lock():                     # a second run on this store is refused
        return _run_plane(store, spec, scheduler, workers, progress, command, client, t0)


def _run_plane(store, spec, scheduler, workers, progress, command, client, t0):
    from .. import __version__
    exists = store.check()                 # refuses a path holding anything else
    todo = store.missing_blocks() if exists else spec.blocks()
    text = spec.text()
    in_process = workers == 0 and client is None and scheduler is None
    # connect before creating anything: an unreachable scheduler leaves no empty store
    with (contextlib.nullcontext(client) if in_process or not todo
          else _client(scheduler, workers, client)) as cl:
        if not exists:
            store.create(command, __version__)
        if _enabled(progress) and exists and todo:
            sys.stderr.write(f"plane: resuming, {len(spec.blocks()) - len(todo)} of "
                             f"{len(spec.blocks())} blocks already in {store.path}\n")

        def done(block, result):
            store.write(*block, result)
        tasks = [(f"{r0}-{r1}", (r0, r1), (text, r0, r1)) for r0, r1 in todo]
        n_workers = run_tasks(compute_block, tasks, done, workers=workers, client=cl,
                              name=f"plane-{_token(text)}", progress=progress)
    return PlaneRun(store.path, spec.shape, len(spec.blocks()), len(todo), n_workers,
                    time.perf_counter() - t0, _counts(store))


def check_workers(scheduler, workers):
    """--workers and --scheduler: an integer 0 .. 1024, and not both."""
    if workers is not None and not (isinstance(workers, int) and 0 <= workers <= 1024):
        raise ParameterError("--workers", workers, "an integer in 0 .. 1024")
    if scheduler is not None and workers is not None:
        raise ParameterError("--workers", workers, "not with --scheduler (the cluster has "
                             "its own workers)")


def check_scheduler(address):
    """--scheduler: ``tcp://host:port`` (or ``tls://``), checked before any connection
    (distributed would try a malformed address for its whole timeout).  None passes."""
    if address is None:
        return None
    m = _ADDRESS.fullmatch(address) if isinstance(address, str) else None
    if m is None or not 1 <= int(m.group(1)) <= 65535:
        raise ParameterError("--scheduler", address, SCHEDULER_FORM)
    return address


def reach_scheduler(address, timeout=None):
    """Check within ``timeout`` seconds (default :data:`CONNECT_TIMEOUT`) that a Dask
    scheduler answers at ``address``: connect, Dask's handshake, its ``identity``.

    distributed's ``connect`` bounds the TCP connection but not the handshake that
    follows, so a port that accepts and never speaks blocks ``Client`` for ever; here the
    whole exchange runs under one ``asyncio.wait_for`` on a loop of its own (a thread, so
    a caller's running loop is no obstacle).  Raises :class:`SymviError` (one line) if
    nothing answers in time, or if what answers is not a scheduler."""
    import asyncio
    import threading
    timeout = CONNECT_TIMEOUT if timeout is None else timeout

    async def identify():
        from distributed.comm import connect
        from distributed.security import Security
        # a plain TCP connection first: a refused port ends here at once (distributed
        # retries a refusal until its timeout)
        host, port = address.split("://", 1)[1].rsplit(":", 1)
        _, writer = await asyncio.open_connection(host.strip("[]"), int(port))
        writer.close()
        # the TCP part gives up a little earlier, so the outer timeout means: connected,
        # but no answer
        comm = await connect(address, timeout=0.9 * timeout,
                             **Security().get_connection_args("client"))
        try:
            await comm.write({"op": "identity", "reply": True})
            return await comm.read()
        finally:
            comm.abort()

    def run():
        try:
            state["reply"] = asyncio.run(asyncio.wait_for(identify(), timeout))
        except BaseException as exc:   # noqa: BLE001 -- reported below, in the caller
            state["error"] = exc
    state = {}
    probe = threading.Thread(target=run, name="symvi-scheduler-probe", daemon=True)
    probe.start()
    probe.join(timeout + 5)            # wait_for ends it by then; never wait for ever
    reply, exc = state.get("reply"), state.get("error")
    if isinstance(reply, dict) and reply.get("type") == "Scheduler":
        return reply
    if isinstance(reply, dict):
        why = f"a Dask {str(reply.get('type', 'server'))[:40]} answers there, not a scheduler"
    elif exc is None or isinstance(exc, (TimeoutError, asyncio.TimeoutError)):
        why = "the port accepts connections but does not answer Dask's handshake"
    else:
        while str(exc).startswith("Timed out") and (exc.__cause__ or exc.__context__):
            exc = exc.__cause__ or exc.__context__    # why the attempts failed
        if isinstance(exc, ConnectionRefusedError) or "Connection refused" in str(exc):
            exc = "connection refused"
        why = _first_line(exc)
    raise SymviError(f"--scheduler: could not reach scheduler {address} within "
                     f"{timeout:g} s ({why})")


def _first_line(exc):
    text = re.sub(r"^in <[^>]*>: ", "", str(exc).strip())     # distributed's connector prefix
    return text.splitlines()[0][:200] if text else type(exc).__name__


def run_tasks(fn, tasks, on_result, *, scheduler=None, workers=None, client=None,
              name="symvi", progress=None):
    """For each (key, tag, args) of ``tasks`` run ``fn(*args)`` and call
    ``on_result(tag, result)`` in this process as each finishes, in completion order.
    ``key`` (a string unique in ``tasks``) names the Dask task ``{name}-{key}``.

    In this process when ``workers == 0`` (and no scheduler or client), else as Dask
    tasks (a local cluster unless ``scheduler`` or ``client`` is given).  A task whose
    worker dies is rerun by Dask.  Returns the number of Dask workers (0 in-process).
    ``progress`` (True, False, None: when stderr is a terminal): a tqdm bar in-process,
    Dask's progress bar (on stderr) on a cluster.
    """
    if not tasks:
        return 0
    if workers == 0 and client is None and scheduler is None:
        from ..progress import Progress
        with Progress(len(tasks), name.split("-")[0], enabled=progress) as bar:
            for _, tag, a in tasks:
                on_result(tag, fn(*a))
                bar.update(1)
        return 0
    from distributed import as_completed
    with _client(scheduler, workers, client) as cl:
        n_workers = len(cl.scheduler_info().get("workers", {}))
        futs = {}
        for key, tag, a in tasks:
            futs[cl.submit(fn, *a, key=f"{name}-{key}", pure=False, retries=2)] = tag
        if _enabled(progress):
            _dask_bar(cl, list(futs))
        try:
            for f in as_completed(list(futs), loop=cl.loop):
                on_result(futs[f], f.result())
                f.release()
        except BaseException:
            for f in futs:
                f.cancel()
            raise
    return n_workers


def _enabled(progress):
    return sys.stderr.isatty() if progress is None else bool(progress)


def _dask_bar(cl, futures):
    """Dask's text progress bar of ``futures`` on stderr (Dask draws on stdout, which
    ``--json`` keeps for its one object), listening in a background thread."""
    import threading

    from distributed.diagnostics.progressbar import TextProgressBar

    class StderrBar(TextProgressBar):
        def _draw_bar(self, remaining, all, **kwargs):
            frac = (1 - remaining / all) if all else 1.0
            sys.stderr.write(f"\r[{'#' * int(self.width * frac):<{self.width}}] | "
                             f"{int(100 * frac)}% Completed | {all - remaining}/{all} "
                             f"tasks | {self.elapsed:.1f}s")
            sys.stderr.flush()

        def _draw_stop(self, **kwargs):
            sys.stderr.write("\n")
            sys.stderr.flush()

    def listen():
        try:
            StderrBar(futures, scheduler=cl.scheduler.address, interval="200ms")
        except Exception:   # noqa: BLE001 -- a progress bar never fails a run
            pass
    threading.Thread(target=listen, daemon=True).start()


def _token(text):
    import hashlib
    return hashlib.sha256(text.encode()).hexdigest()[:12]


class _client:
    """Context: the given client, a client of ``scheduler``, or a local cluster."""

    def __init__(self, scheduler, workers, client):
        self.scheduler, self.workers, self.client = scheduler, workers, client
        self._own = []

    def __enter__(self):
        if self.client is not None:
            return self.client
        import logging

        from distributed import Client, LocalCluster
        if self.scheduler is not None:
            import dask
            address = check_scheduler(self.scheduler)
            timeout = CONNECT_TIMEOUT
            reach_scheduler(address, timeout)      # bounded: connection and handshake
            try:
                with dask.config.set({"distributed.comm.timeouts.connect": f"{timeout}s"}):
                    cl = Client(address, timeout=timeout, set_as_default=False)
            except (OSError, TimeoutError, ValueError, TypeError) as exc:
                # it answered a moment ago (reach_scheduler): gone since
                raise SymviError(f"--scheduler: could not reach scheduler {address} within "
                                 f"{timeout:g} s ({_first_line(exc)})") from None
            self._own.append(cl)
            return cl
        n = self.workers or os.cpu_count() or 1
        cluster = LocalCluster(n_workers=n, threads_per_worker=1, processes=True,
                               dashboard_address=None, silence_logs=logging.ERROR,
                               host="127.0.0.1")
        self._own.append(cluster)
        cl = Client(cluster, set_as_default=False)
        self._own.append(cl)
        return cl

    def __exit__(self, *exc):
        for obj in reversed(self._own):
            try:
                obj.close()
            except Exception:   # noqa: BLE001 -- closing after an error must not mask it
                pass
        return False


def _counts(store):
    import zarr
    g = zarr.open_group(store.path, mode="r")
    labels = np.asarray(g["attractor"][:])
    vals, cnt = np.unique(labels[labels != ""], return_counts=True)
    return {str(v): int(c) for v, c in zip(vals, cnt)}


def _sweep_block(params, omegas, starts, n_impacts, transient, classify=False):
    # one Dask task of a sweep: the compiled batch of symvi.simulations.simulation.sweep
    # (an elastic model's walks, classified in the task: a walk is too slow to run twice)
    from ..simulations.simulation import sweep
    return sweep(params, omegas, n_impacts=n_impacts, transient=transient, starts=starts,
                 classify=classify)


def _joined(parts):
    """One Classified of the tasks' ones, in order."""
    from ..simulations.classifier import Classified
    tuples = ("signature", "kinds")
    return Classified(**{f.name: None if any(getattr(p, f.name) is None for p in parts) else
                         tuple(x for p in parts for x in getattr(p, f.name))
                         if f.name in tuples else
                         np.concatenate([getattr(p, f.name) for p in parts])
                         for f in dataclasses.fields(Classified)})


def run_sweep(params, omegas, *, n_impacts, transient, scheduler=None, workers=None,
              chunk=None, progress=None, client=None, classify=False):
    """:func:`symvi.simulations.simulation.sweep` as tasks of ``chunk`` omegas on this engine (a local
    cluster, ``scheduler``, or in-process with ``workers=0``); the same Sweep, bit for
    bit, as one call of ``sweep``.  ``classify``: also label each omega's attractor
    (:func:`symvi.simulations.simulation.classify_sweep`, in this process), in
    ``Sweep.classes``."""
    from ..model import Model
    from ..simulations.simulation import (MAX_STORED, Sweep, _check_classifiable,
                                          _positive_int, classify_sweep, sweep_starts)
    check_workers(scheduler, workers)
    check_scheduler(scheduler)
    omegas = np.asarray(omegas, dtype=float)
    m = len(omegas)
    # the limits of one sweep call over all omegas (chunks would allow more)
    n_impacts = _positive_int("n_impacts", n_impacts, maximum=max(1, MAX_STORED // m))
    if classify:
        _check_classifiable(n_impacts, params=params)
    starts = sweep_starts(params, omegas)
    chunk = chunk or max(1, math.ceil(m / 32))
    parts = {}
    walked = _walked(Model.of(params))     # classified in the task: too slow to run twice
    tasks = [(str(lo), lo, (params, omegas[lo:lo + chunk], starts[lo:lo + chunk], n_impacts,
                            transient, classify and walked)) for lo in range(0, m, chunk)]

    def done(lo, res):
        parts[lo] = res
    run_tasks(_sweep_block, tasks, done, scheduler=scheduler, workers=workers, client=client,
              name=f"sweep-{_token(repr((params, omegas.tobytes())))}", progress=progress)
    got = [parts[k] for k in sorted(parts)]
    res = Sweep(params, np.concatenate([g.omegas for g in got]),
                np.concatenate([g.section for g in got]),
                np.concatenate([g.counts for g in got]),
                tuple(s for g in got for s in g.stops), np.concatenate([g.starts for g in got]),
                transient, sum(g.impacts_total for g in got))
    if classify and walked:
        return dataclasses.replace(res, classes=_joined([g.classes for g in got]))
    return dataclasses.replace(res, classes=classify_sweep(res)) if classify else res
