"""A pool of figure workers forked from one server process that has imported matplotlib once.

Each worker of a plain fork pool imports matplotlib for itself (~0.66 s CPU a worker on the
2-core machine this was measured on), and a pool forked from the main process at its start
would also import, in each worker, every module the jobs' pickles name (~0.6 s). Here one
server process is forked from the caller, imports what the jobs need (``preload``), and forks
the workers from itself: every import is paid once, in the server, where it overlaps the
caller's stages. The workers (and the server) run at a lower priority (``nice``), so that on a
busy machine the caller's stages, which the run waits for, keep their CPU and the figures take
what is left.

:class:`ServerPool` is what :class:`profilegen.output.report.FigureWorkers` needs of a
``concurrent.futures`` executor: ``submit(func, *args)`` → a Future, ``shutdown(wait=True,
cancel_futures=True)``, and ``stop()`` (end every process now). A job's Future can be cancelled
while the server has not handed it to a worker (a round trip to the server). A job that fails
sets its exception; a worker or the server that dies sets ``BrokenProcessPool`` on every job
not finished.

The server and its workers ignore SIGINT (a Ctrl-C reaches the whole process group; the caller
decides), die on SIGTERM, and die with their parent (Linux: PR_SET_PDEATHSIG): a caller that is
killed takes the server with it, and the server its workers.
"""

from __future__ import annotations

import contextlib
import importlib
import logging
import os
import pickle
import queue
import signal
import threading
from collections.abc import Callable, Sequence
from concurrent.futures import Future
from concurrent.futures.process import BrokenProcessPool
from functools import partial
from typing import Any

__all__ = ["ServerPool", "NICE", "die_with"]

log = logging.getLogger(__name__)

#: How much lower the server and its workers run than the caller (os.nice increment): with the
#: server and two workers beside the caller's stages on two cores, equal priority gave the caller
#: ~2/3 of a core and slowed the stages the run waits for (profilegen design, quiet machine, 2
#: workers, 3 alternating runs: stage sum 4.40-4.46 s at 0, 3.47-3.55 s at 5; wall 6.30-6.50 s
#: at 0, 6.08-6.22 s at 5).
NICE = 5
_STOP_SIGNALS = (signal.SIGINT, signal.SIGTERM)


def die_with(parent: int) -> None:
    """This worker ends when ``parent`` does (a killed run leaves no worker waiting for work):
    PR_SET_PDEATHSIG on Linux, else a thread that watches the parent id."""
    try:
        import ctypes

        libc = ctypes.CDLL(None, use_errno=True)
        if libc.prctl(1, int(signal.SIGKILL), 0, 0, 0) != 0:  # PR_SET_PDEATHSIG = 1
            raise OSError(ctypes.get_errno(), "prctl")
    except (OSError, AttributeError):
        import threading
        import time

        def watch() -> None:
            while os.getppid() == parent:
                time.sleep(0.5)
            os._exit(1)

        threading.Thread(target=watch, name="profilegen-figure-parent-watch", daemon=True).start()
    if os.getppid() != parent:  # the parent died before the watch began
        os._exit(1)


def _as_worker(parent: int, nice: int) -> None:
    """This process: SIGINT ignored, SIGTERM ends it, it dies with ``parent``, ``nice`` lower."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.signal(signal.SIGTERM, signal.SIG_DFL)
    if hasattr(signal, "pthread_sigmask"):
        signal.pthread_sigmask(signal.SIG_UNBLOCK, _STOP_SIGNALS)
    die_with(parent)
    if nice:
        with contextlib.suppress(OSError, AttributeError):
            os.nice(nice)


def _run(payload: bytes) -> bytes:
    """A job in a worker: ``payload`` is the pickled (function, arguments); the result pickled."""
    func, args = pickle.loads(payload)
    return pickle.dumps(func(*args), protocol=pickle.HIGHEST_PROTOCOL)


def _failure(exc: BaseException) -> bytes:
    try:
        return pickle.dumps(exc, protocol=pickle.HIGHEST_PROTOCOL)
    except Exception:  # noqa: BLE001 - an exception that does not pickle: its type and text
        return pickle.dumps(RuntimeError(f"{type(exc).__name__}: {exc}"))


def _serve(conn, other_end, parent: int, workers: int, preload: Sequence[str], nice: int) -> None:
    """The server process: imports ``preload``, then hands each job it receives to a pool of
    ``workers`` processes forked from itself and sends the results back, until told to stop."""
    other_end.close()  # the caller's end: without it here, the caller's death reads as EOF
    _as_worker(parent, nice)
    for name in preload:
        try:
            importlib.import_module(name)
        except Exception as exc:  # noqa: BLE001 - a job that needs it imports it (and fails) itself
            log.info("figure server: preloading %s failed (%s: %s)", name, type(exc).__name__, exc)
    import multiprocessing
    from concurrent.futures import ProcessPoolExecutor

    pool = ProcessPoolExecutor(max_workers=workers, mp_context=multiprocessing.get_context("fork"),
                               initializer=_as_worker, initargs=(os.getpid(), 0))  # nice inherited
    send = threading.Lock()
    running: dict[int, Future] = {}

    def deliver(jid: int, fut: Future) -> None:
        if fut.cancelled():
            return
        exc = fut.exception()
        msg = ("done", jid, True, fut.result()) if exc is None else ("done", jid, False, _failure(exc))
        with send, contextlib.suppress(OSError, ValueError):
            conn.send(msg)

    try:
        while True:
            try:
                msg = conn.recv()
            except (EOFError, OSError):
                break
            if msg is None:
                break
            kind, jid = msg[0], msg[1]
            if kind == "job":
                fut = pool.submit(_run, msg[2])
                running[jid] = fut
                fut.add_done_callback(partial(deliver, jid))
            elif kind == "cancel":
                pending = running.get(jid)
                ok = pending is not None and pending.cancel()
                with send:
                    conn.send(("cancelled", jid, ok))
    finally:
        pool.shutdown(wait=True, cancel_futures=True)
        with contextlib.suppress(OSError):
            conn.close()


def _end_at_exit(proc) -> None:
    if proc.exitcode is None:
        with contextlib.suppress(OSError, ValueError, AttributeError):
            proc.kill()  # its workers die with it
        proc.join(2.0)


class _Job(Future):
    """A job's Future in the caller; ``cancel()`` asks the server (True while no worker has it)."""

    def __init__(self, pool: "ServerPool", jid: int):
        super().__init__()
        self._pool, self._jid = pool, jid

    def cancel(self) -> bool:
        if self.done() or not self._pool._cancel(self._jid):
            return False
        return super().cancel()


class ServerPool:
    """``workers`` figure workers forked from a server process that imported ``preload`` first
    (see the module docstring). The server is forked now, from the calling thread (fork start
    method only: ValueError elsewhere)."""

    def __init__(self, workers: int, *, preload: Sequence[str] = (), nice: int = NICE):
        import multiprocessing

        ctx = multiprocessing.get_context("fork")
        self._conn, theirs = ctx.Pipe(duplex=True)
        self._proc = ctx.Process(target=_serve, name="profilegen-figures",
                                 args=(theirs, self._conn, os.getpid(), int(workers), tuple(preload), int(nice)))
        self._proc.start()
        theirs.close()
        # at exit, before multiprocessing joins its children: a server nobody closed (the caller
        # stopped between forking it and taking it) is ended, not waited for
        from multiprocessing import util

        util.Finalize(self, _end_at_exit, args=(self._proc,), exitpriority=100)
        self._lock = threading.Lock()  # the sends, the tables below
        self._jobs: dict[int, _Job] = {}
        self._answers: dict[int, list] = {}
        self._next = 0
        self._broken = False
        # the messages go out from a thread of their own: a send blocks while the pipe is full, i.e.
        # while the server is still importing (the jobs given with the envelope come before it is done)
        self._outbox: queue.SimpleQueue = queue.SimpleQueue()
        self._sender = threading.Thread(target=self._send, name="profilegen-figures-sender", daemon=True)
        self._sender.start()
        self._reader = threading.Thread(target=self._read, name="profilegen-figures-reader", daemon=True)
        self._reader.start()

    def _send(self) -> None:
        while True:
            msg = self._outbox.get()
            try:
                self._conn.send(msg)
            except (OSError, ValueError):  # the server has ended: the reader fails the jobs still out
                return
            if msg is None:
                return

    def submit(self, func: Callable, *args) -> Future:
        with self._lock:
            jid, self._next = self._next, self._next + 1
            job = _Job(self, jid)
            if self._broken:
                job.set_exception(BrokenProcessPool("the figure server has ended"))
                return job
            try:
                payload = pickle.dumps((func, args), protocol=pickle.HIGHEST_PROTOCOL)
            except Exception as exc:  # noqa: BLE001 - as an executor does: the job's exception
                job.set_exception(exc)
                return job
            self._jobs[jid] = job
            self._outbox.put(("job", jid, payload))
        return job

    def _cancel(self, jid: int) -> bool:
        answer: list[Any] = [threading.Event(), False]
        with self._lock:
            if self._broken or jid not in self._jobs:
                return False
            self._answers[jid] = answer
            self._outbox.put(("cancel", jid))
        answer[0].wait(30.0)
        with self._lock:
            self._answers.pop(jid, None)
            if answer[1]:
                self._jobs.pop(jid, None)
        return bool(answer[1])

    def _read(self) -> None:
        while True:
            try:
                msg = self._conn.recv()
            except (EOFError, OSError, ValueError):
                break
            kind, jid = msg[0], msg[1]
            if kind == "cancelled":
                with self._lock:
                    answer = self._answers.get(jid)
                if answer is not None:
                    answer[1] = bool(msg[2])
                    answer[0].set()
                continue
            with self._lock:
                job = self._jobs.pop(jid, None)
            if job is None or job.done():
                continue
            try:
                value = pickle.loads(msg[3])
            except Exception as exc:  # noqa: BLE001 - a result that does not unpickle here
                job.set_exception(exc)
                continue
            if msg[2]:
                job.set_result(value)
            else:
                job.set_exception(value)
        with self._lock:  # the server has ended: every job still out fails, every question is answered no
            self._broken = True
            jobs, self._jobs = list(self._jobs.values()), {}
            answers = list(self._answers.values())
        for job in jobs:
            if not job.done():
                job.set_exception(BrokenProcessPool("the figure server ended before the job did"))
        for answer in answers:
            answer[0].set()

    def shutdown(self, wait: bool = True, *, cancel_futures: bool = False) -> None:
        """Tell the server to stop once its workers have finished what they run (jobs no worker
        has started are dropped), and wait for it with ``wait``."""
        self._outbox.put(None)
        if wait:
            self._sender.join()
            self._proc.join()
            self._reader.join(5.0)
            with contextlib.suppress(OSError):
                self._conn.close()

    def stop(self, grace_s: float = 2.0) -> None:
        """End the server now (SIGTERM, SIGKILL after ``grace_s``); its workers die with it."""
        with contextlib.suppress(OSError, ValueError, AttributeError):
            self._proc.terminate()
        self._proc.join(grace_s)
        if self._proc.exitcode is None:
            with contextlib.suppress(OSError, ValueError, AttributeError):
                self._proc.kill()
            self._proc.join(grace_s)
        self._outbox.put(None)  # the sender ends: its send fails on the closed pipe, or it sends this
        self._sender.join(grace_s)
        if not self._sender.is_alive():  # (never close a descriptor another thread may still write to)
            with contextlib.suppress(OSError):
                self._conn.close()
        self._reader.join(grace_s)
        if self._proc.exitcode is None:
            log.warning("figures: the server process %s did not stop", self._proc.pid)
