"""Where a batch's scenes run: in this process, a pool of local worker processes, or Dask.

Every executor has ``map(work, tasks, *args)``, which calls ``work(task, *args)`` for
each task (``work`` is pickled to the workers: a module-level function; a task has a
``name``) and yields ``(task, result, None)``, or ``(task, None, exception)`` for a
call that raised, as the tasks finish.
"""

from __future__ import annotations

import contextlib
import os
import shutil
import socket
import tempfile
import threading
import time
from collections.abc import Sequence
from concurrent.futures import ProcessPoolExecutor, as_completed
from pathlib import Path
from urllib.parse import urlsplit

from armanim.errors import UsageError
from armanim.procs.deferred import interrupts_deferred
from armanim.procs.interrupted import signal_came
from armanim.procs.workers import init_worker, resource_tracker_started, signals_blocked, temp_prefix

CONNECT_SECONDS = 10.0
"""How long a Dask scheduler may take to answer, from the connection to the handshake."""
_BLAS_THREADS = ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS")
_PRELOAD = ["armanim.procs.forkserver_signals"]  # first: it blocks the signals the workers start with
_SOCKET_PATH_BYTES = 107  # AF_UNIX: sun_path holds 108 bytes with its final NUL
_SOCKET_NAME_BYTES = 40  # what multiprocessing adds to TMPDIR: /pymp-XXXXXXXX/listener-XXXXXXXX
_SHORT_TEMP_DIRS = ("/tmp", "/var/tmp", "/dev/shm")


@contextlib.contextmanager
def _one_blas_thread():
    """Workers started meanwhile use one BLAS thread each: the pool already fills every
    core, and BLAS threads on top only contend (as Dask's nanny also sets)."""
    saved = {name: os.environ.get(name) for name in _BLAS_THREADS}
    for name in _BLAS_THREADS:
        os.environ.setdefault(name, "1")
    try:
        yield
    finally:
        for name, value in saved.items():
            if value is None:
                os.environ.pop(name, None)
            else:
                os.environ[name] = value


def _worker_context(preload: Sequence[str] = ()):
    """forkserver with the workers' heavy imports (``preload``, module names) loaded once (each
    worker is then a cheap fork of an importer that runs no threads); spawn where forkserver
    is missing."""
    import multiprocessing

    try:
        context = multiprocessing.get_context("forkserver")
    except ValueError:
        return multiprocessing.get_context("spawn")
    _socket_dir_short_enough()
    context.set_forkserver_preload([*_PRELOAD, *preload])
    return context


def _socket_dir_short_enough() -> None:
    """Make multiprocessing's folder (where the forkserver's socket goes) under a short system
    folder when TMPDIR is too long for a socket path, as Python 3.13 does; otherwise every
    pool fails with "AF_UNIX path too long". The folder is removed at exit as before."""
    from multiprocessing import util

    if len(os.fsencode(tempfile.gettempdir())) + _SOCKET_NAME_BYTES <= _SOCKET_PATH_BYTES:
        return
    short = next((d for d in _SHORT_TEMP_DIRS if os.path.isdir(d) and os.access(d, os.W_OK | os.X_OK)), None)
    if short is None:
        return  # nowhere shorter: the pool reports the error as before
    saved, tempfile.tempdir = tempfile.tempdir, short
    try:
        util.get_temp_dir()  # made once per process and kept: later sockets go there too
    finally:
        tempfile.tempdir = saved


class _LocalExecutor:
    """Scenes in this process (jobs=1) or in a pool of worker processes, whose forkserver
    imports ``preload`` (module names) once."""

    def __init__(self, jobs: int, preload: Sequence[str] = ()):
        self.jobs = jobs
        self.preload = tuple(preload)

    def map(self, work, tasks, *args):
        """``(task, work(task, *args), None)`` or ``(task, None, exception)`` per task, as each ends."""
        if self.jobs <= 1 or len(tasks) <= 1:
            for task in tasks:
                try:
                    yield task, work(task, *args), None
                except Exception as exc:  # reported per scene; the batch goes on
                    if signal_came():  # a Ctrl-C a library turned into its own error: the batch stops
                        raise
                    yield task, None, exc
            return
        pool = None
        try:
            # the pool's processes (and the forkserver, the first time) start with SIGINT and SIGTERM
            # blocked, until init_worker has put its handlers in place, and a Ctrl-C meanwhile is
            # raised only once every started worker is in the pool's list: no traceback from a
            # preload or an initializer, and no worker left running, whatever moment it comes
            with _one_blas_thread(), signals_blocked():
                context = _worker_context(self.preload)
                resource_tracker_started(context)  # before the forkserver, which would unblock the signals
                pool = ProcessPoolExecutor(
                    max_workers=min(self.jobs, len(tasks)),
                    mp_context=context,
                    initializer=init_worker,
                    initargs=(os.getpid(),),
                )
                futures = {pool.submit(work, task, *args): task for task in tasks}  # starts the workers
            for future in as_completed(futures):
                error = future.exception()
                yield futures[future], (None if error else future.result()), error
        except BaseException:
            if pool is not None:
                with interrupts_deferred():  # a second Ctrl-C must not leave workers behind
                    _stop_pool(pool)
            raise
        pool.shutdown(wait=True)


def _stop_pool(pool: ProcessPoolExecutor, grace: float = 5.0) -> None:
    """Stop a pool at once: queued scenes are dropped, running ones get SIGTERM (a worker's
    quiet exit: its ffmpeg is killed, its temporary folder removed); none is waited for to finish."""
    processes = list((getattr(pool, "_processes", None) or {}).values())  # the executor has no public way
    manager = getattr(pool, "_executor_manager_thread", None)  # before shutdown, which forgets it
    pool.shutdown(wait=False, cancel_futures=True)
    for process in processes:
        with contextlib.suppress(Exception):
            process.terminate()
    deadline = time.monotonic() + grace
    for process in processes:
        process.join(max(0.0, deadline - time.monotonic()))
        if process.is_alive():
            process.kill()
            process.join(1.0)
    # The executor's manager thread closes its wakeup pipe as it sees the workers gone, and Python's
    # exit writes to every such pipe with no lock between its check and its write: on 3.11 a pipe
    # closed in between is a traceback ("Exception ignored in: <module 'threading'>": Bad file
    # descriptor; the signal sweep's batch at ffmpeg+0.1 s). The stopped pool's pipe is taken out
    # of the exit's list; the thread ends by itself, as Python's exit joins it.
    if manager is not None:
        from concurrent.futures import process as futures_process

        getattr(futures_process, "_threads_wakeups", {}).pop(manager, None)  # a private name: absent, nothing to do
    remove_worker_folders()


def remove_worker_folders() -> None:
    """Remove the temporary folders this process's workers left (a worker killed outright)."""
    with contextlib.suppress(OSError):
        for folder in Path(tempfile.gettempdir()).glob(temp_prefix() + "*"):
            shutil.rmtree(folder, ignore_errors=True)


class _DaskExecutor:
    """Scenes on a Dask cluster: an existing scheduler address, or ``local``."""

    def __init__(self, scheduler: str, jobs: int):
        try:
            from dask.distributed import Client, LocalCluster
        except ImportError:
            raise UsageError("--scheduler needs Dask, an optional extra: pip install -e '.[dask]'") from None
        self._client_cls, self._cluster_cls = Client, LocalCluster
        self.scheduler, self.jobs = scheduler, jobs

    def map(self, work, tasks, *args):
        """``(task, work(task, *args), None)`` or ``(task, None, exception)`` per task, as each ends
        (:func:`_as_they_end`: a scheduler lost, or left without workers, fails the tasks left)."""
        cluster = None
        if self.scheduler == "local":
            cluster = self._cluster_cls(
                n_workers=self.jobs, threads_per_worker=1, processes=True, dashboard_address=None
            )
            client = self._client_cls(cluster)
        else:
            client = connect_client(self._client_cls, self.scheduler)
        quiet = _dask_logs_quiet()  # a lost scheduler is the scenes' failure, said once, not Dask's tracebacks
        try:
            futures = {
                client.submit(work, task, *args, retries=2, pure=False, key=f"armanim-{i}-{task.name}"): task
                for i, task in enumerate(tasks)
            }
            yield from _as_they_end(client, futures, self.scheduler)
        finally:
            client.close()
            if cluster is not None:
                cluster.close()
            quiet.close()


NO_WORKERS_SECONDS = 60.0
"""How long a batch waits on a Dask scheduler that has no worker (none started yet, or the last one
gone) before it gives up the scenes not yet done: a scheduler alone would keep them waiting without
end and without a word (campaign 17)."""
_POLL_SECONDS = 2.0


def _dask_logs_quiet():
    """Dask's client logs at ERROR, with tracebacks, as it tries to reconnect to a scheduler that is
    gone (campaign 17): its ``distributed`` loggers are held to CRITICAL until the returned object's
    ``close()``; the scenes' failures say what happened."""
    import logging

    loggers = [logging.getLogger(name) for name in ("distributed", "distributed.client")]
    levels = [logger.level for logger in loggers]
    for logger in loggers:
        logger.setLevel(logging.CRITICAL)

    class Restore:
        def close(self) -> None:
            for logger, level in zip(loggers, levels, strict=True):
                logger.setLevel(level)

    return Restore()


class SchedulerLost(RuntimeError):
    """The Dask scheduler went away, or kept no worker, before a scene was done: the scene failed."""


def _as_they_end(client, futures: dict, address: str, alone_s: float | None = None):
    """``(task, result, None)`` or ``(task, None, exception)`` for each of ``futures`` (future ->
    task) as it ends. Every :data:`_POLL_SECONDS` with none ended the scheduler is asked for its
    workers: once it is gone (campaign 17: a scheduler killed mid-run ended the command in Dask's
    traceback, exit 1), or has had none for ``alone_s`` seconds, every task left ends with a
    :class:`SchedulerLost` saying so, and the batch reports those scenes failed (``alone_s``:
    :data:`NO_WORKERS_SECONDS` unless given)."""
    from dask.distributed import wait as dask_wait

    alone_s = NO_WORKERS_SECONDS if alone_s is None else alone_s
    left = dict(futures)
    alone_since: float | None = None
    while left:
        try:
            done, _ = dask_wait(list(left), timeout=_POLL_SECONDS, return_when="FIRST_COMPLETED")
        except TimeoutError:
            done = set()
        except Exception as exc:  # noqa: BLE001  (Dask's own: the connection lost, the client closed)
            yield from _all_lost(left, _lost(address, exc))
            return
        for future in done:
            task = left.pop(future)
            try:
                if future.status == "error":
                    yield task, None, future.exception()
                else:
                    yield task, future.result(), None
            except Exception as exc:  # noqa: BLE001  (cancelled, or lost with the scheduler)
                yield task, None, _lost(address, exc)
        if done or not left:
            continue
        try:
            workers = len(client.nthreads())
        except Exception as exc:  # noqa: BLE001
            yield from _all_lost(left, _lost(address, exc))
            return
        alone_since = None if workers else (alone_since or time.monotonic())
        if alone_since is not None and time.monotonic() - alone_since >= alone_s:
            yield from _all_lost(
                left,
                SchedulerLost(
                    f"the Dask scheduler at {address} has had no worker for {alone_s:g} s: start some "
                    f"with `dask worker {address}`, then run again"
                ),
            )
            return


def _lost(address: str, exc: BaseException) -> SchedulerLost:
    """The error of a scene the scheduler at ``address`` was lost before: one line (Dask's own
    message lists every future cancelled, over several lines)."""
    return SchedulerLost(
        f"the Dask scheduler at {address} was lost mid-batch ({type(exc).__name__}): start it again, then run again"
    )


def _all_lost(left: dict, error: Exception):
    """``(task, None, error)`` for every task of ``left`` (future -> task)."""
    for task in left.values():
        yield task, None, error
    left.clear()


def connect_client(client_cls, address: str, seconds: float = CONNECT_SECONDS):
    """A Dask ``Client`` of the scheduler at ``address``, or a UsageError within ``seconds``.

    ``Client(timeout=...)`` bounds the connection but not the handshake: a server that
    accepts and never answers would keep it waiting without end. So the client is made
    on a thread that is given up after the deadline (it is a daemon: it cannot hold the exit).
    A refused port is reported at once: the port is asked first (see ``_refuse_if_nothing_listens``),
    and the time that takes counts against the same ``seconds``.

    Raises
    ------
    UsageError
        Not an address, not reachable, or no answer within ``seconds`` (exit 2).
    """
    deadline = time.monotonic() + seconds
    _refuse_if_nothing_listens(address, seconds)
    left = max(deadline - time.monotonic(), 0.01)
    outcome: dict = {}

    def attempt() -> None:
        try:
            outcome["client"] = client_cls(address, timeout=f"{left}s")
        except Exception as exc:  # noqa: BLE001  (reported below, in the caller's thread)
            outcome["error"] = exc

    thread = threading.Thread(target=attempt, name="armanim-dask-connect", daemon=True)
    thread.start()
    thread.join(left + 1.0)
    error = outcome.get("error")
    if "client" in outcome:
        return outcome["client"]
    if isinstance(error, ValueError):  # Dask's word for an address it cannot parse
        raise UsageError(
            f"--scheduler: {address!r} is not a scheduler address ({error}; expected tcp://HOST:PORT or local)"
        )
    if error is not None:
        raise _unreachable(address, str(error))
    raise _no_answer(address, seconds)


def _tcp_endpoint(address: str) -> tuple[str, int] | None:
    """The host and port a ``tcp://`` or ``tls://`` scheduler address names, or None
    where it names none plainly (another scheme, no port): Dask then judges it alone.

    >>> _tcp_endpoint("tcp://10.0.0.5:8786"), _tcp_endpoint("[::1]:8786"), _tcp_endpoint("ucx://h:1")
    (('10.0.0.5', 8786), ('::1', 8786), None)
    >>> _tcp_endpoint("tcp://[::1"), _tcp_endpoint("tcp://h:99999"), _tcp_endpoint("garbage")
    (None, None, None)
    """
    try:
        parts = urlsplit(address if "://" in address else f"tcp://{address}")
        port = parts.port
    except ValueError:
        return None
    if parts.scheme not in ("tcp", "tls") or not parts.hostname or port is None:
        return None
    return parts.hostname, port


def _refuse_if_nothing_listens(address: str, seconds: float) -> None:
    """Raise at once where the scheduler's host refuses the connection: Dask's client
    would retry a refused port until its whole timeout has passed and then call it a timeout.

    Raises
    ------
    UsageError
        The port is closed, or the host has no address (exit 2).
    """
    endpoint = _tcp_endpoint(address)
    if endpoint is None:
        return
    try:
        socket.create_connection(endpoint, timeout=seconds).close()
    except ConnectionRefusedError:
        raise _unreachable(
            address,
            f"connection refused: nothing listens on port {endpoint[1]} there; start one "
            "with `dask scheduler`, or check the address and port",
        ) from None
    except socket.gaierror as exc:
        raise _unreachable(address, f"no such host {endpoint[0]!r}: {exc.strerror}") from None
    except TimeoutError:
        raise _no_answer(address, seconds) from None
    except OSError:
        return  # an unreachable network, say: Dask's own attempt reports it in its words


def _unreachable(address: str, why: str) -> UsageError:
    return UsageError(f"--scheduler: cannot reach the Dask scheduler at {address} ({why})")


def _no_answer(address: str, seconds: float) -> UsageError:
    return UsageError(
        f"--scheduler: the Dask scheduler at {address} did not answer within {seconds:g} s "
        "(is a Dask scheduler running there? check the address and port)"
    )


def local_executor(jobs: int, preload: Sequence[str] = ()) -> _LocalExecutor:
    """The local pool of ``jobs`` worker processes (this process where ``jobs`` is 1), whatever
    scheduler the environment names: work that must run on this machine (``armanim warm``)."""
    return _LocalExecutor(jobs, preload)


def executor_for(jobs: int, scheduler: str | None, preload: Sequence[str] = ()):
    """The local pool (its forkserver importing ``preload``, the workers' heavy modules, once),
    or Dask when a scheduler is named (argument or ARMANIM_SCHEDULER)."""
    scheduler = scheduler or os.environ.get("ARMANIM_SCHEDULER") or None
    return _DaskExecutor(scheduler, jobs) if scheduler else _LocalExecutor(jobs, preload)
