"""CPU-bound work in worker processes, never on the event loop: the pool that runs the jobs of server/jobs.py.

Every job is submitted through `Workers.call`, which handles for all callers what can happen to a worker
process: a job over the time limit (counted from its start) ends its process, a process that dies is
replaced and its job retried once; see the class. Heavy jobs (everything but check, run and the live
re-runs) never take the last free process, and one user has only so many heavy requests at a time
(`Workers.admit`); results of pure jobs on content (pictures, drawings, task sheets) are kept by that content
(`Workers.cached`).
"""

from __future__ import annotations

import asyncio
import contextlib
import hashlib
import json
import logging
import multiprocessing
import threading
from collections import Counter, OrderedDict, deque
from collections.abc import Callable, Iterator
from concurrent.futures import Future, ProcessPoolExecutor
from concurrent.futures.process import BrokenProcessPool
from multiprocessing.connection import wait as mp_wait
from typing import Any, TypeVar

from server.errors import ApiError
from server.jobs import LIGHT_JOBS, job_warm

log = logging.getLogger("paltrainer.server")
T = TypeVar("T")

# Workers fork from one process that imported the jobs' modules once (multiprocessing's fork server, itself a
# fresh interpreter: none of the server's threads or connections): a new or replacing worker costs a tenth of a
# second of processor time, not the second of imports a fresh interpreter takes for each one.
_PROCESSES = multiprocessing.get_context("forkserver")
_PROCESSES.set_forkserver_preload(["server.jobs", "core.sim", "core.grading"])


def content_key(*parts: Any) -> str:
    """A key for job results that depend on nothing but `parts` (an exercise's document, the language …)."""
    text = json.dumps(parts, sort_keys=True, separators=(",", ":"), default=str)
    return hashlib.sha256(text.encode("utf-8", errors="surrogatepass")).hexdigest()


class _Results:
    """Results of pure jobs by their content key, the least recently used dropped first beyond `budget` bytes."""

    def __init__(self, budget: int) -> None:
        self.budget, self.size = budget, 0
        self.items: OrderedDict[str, bytes | str] = OrderedDict()
        self.lock = threading.Lock()

    def get(self, key: str) -> bytes | str | None:
        with self.lock:
            value = self.items.get(key)
            if value is not None:
                self.items.move_to_end(key)
            return value

    def put(self, key: str, value: Any) -> None:
        if not isinstance(value, bytes | str) or len(value) > self.budget // 8:
            return
        with self.lock:
            old = self.items.pop(key, None)
            self.size += len(value) - (len(old) if old is not None else 0)
            self.items[key] = value
            while self.size > self.budget and self.items:
                _, dropped = self.items.popitem(last=False)
                self.size -= len(dropped)


# --- the pool -------------------------------------------------------------------------------


class _Job:
    """One job handed to a worker: its future, the worker generation it runs in, and whether it ran out of time."""

    __slots__ = ("future", "generation", "name", "timed_out")

    def __init__(self, future: Future[Any], generation: int, name: str) -> None:
        self.future, self.generation, self.name, self.timed_out = future, generation, name, False


_RESERVED = object()  # a slot handed to a caller that has not submitted its job yet


class _Requeue(Exception):
    """The job never started (its process went away first): it waits for a process again, not counted as a failure."""


class _Slot:
    """One worker process (a ProcessPoolExecutor of one) that runs one job at a time. Each replacement of
    the process is a new generation; callbacks of an older generation find nothing left to do."""

    def __init__(self, index: int) -> None:
        self.index = index
        self.pool: ProcessPoolExecutor | None = None
        self.process: Any = None  # multiprocessing.Process
        self.generation = 0
        self.ready = False  # warmed up and not known dead
        self.job: Any = None  # _Job, _RESERVED or None (free)
        self.heavy = False  # the job it holds is heavy
        self.watched: int | None = None  # the sentinel file descriptor the event loop watches

    def dead(self) -> bool:
        """Whether the process has ended (its sentinel is readable), without reaping it."""
        return self.process is None or bool(mp_wait([self.process.sentinel], 0))


class Workers:
    """Worker processes with a time limit per job: one single-process pool per slot, so that a live
    document can stay on one process (`affinity`) while other jobs go to a free slot.

    Every job goes through `call`, which owns the failure handling for all callers: a job is handed to
    a process only when that process is free, so its time limit counts from its start and a process
    killed for running over time takes no other job with it; a process that dies (kill -9, the
    out-of-memory killer) is replaced at once, and the job that was in it runs once more (jobs are
    pure); a job that kills its process twice is answered 503 WORKER_FAILED.

    Heavy jobs (all but LIGHT_JOBS: pictures, drawings, task sheets, grading, simulations, 3D scenes and
    deviations) run in at most `heavy_processes` processes at once, one fewer than there are: however many
    of them wait, a check, a run or a live update finds a process within one light job's time. `admit`
    counts each user's heavy requests, `cached` keeps the results of jobs on content.
    """

    queue_seconds = 60.0  # longest wait for a free process before 503 BUSY
    respawn_delay = 1.0  # pause before starting again a process that failed to start
    cache_bytes = 64 * 1024 * 1024  # results kept by `cached` (pictures, drawings, task sheets)

    def __init__(self, processes: int, seconds: float) -> None:
        self.processes, self.seconds = max(1, processes), seconds
        self.heavy_processes = self.processes - 1 if self.processes > 1 else 1
        self._slots: list[_Slot] = []
        self._documents = [0] * self.processes  # live documents per slot
        self._waiting: deque[tuple[int | None, bool, asyncio.Future[_Slot]]] = deque()
        self._loop: asyncio.AbstractEventLoop | None = None
        self._owners: Counter[str] = Counter()  # heavy requests under way, per user, key or address
        self._owners_lock = threading.Lock()
        self._results = _Results(self.cache_bytes)
        self._flights: dict[str, asyncio.Future[Any]] = {}  # `cached` jobs under way, by key

    # -- life cycle

    def start(self) -> None:
        """Start the processes and wait until each is warm (called in the app's start-up)."""
        with contextlib.suppress(RuntimeError):
            self._loop = asyncio.get_running_loop()
        self._slots = [_Slot(k) for k in range(self.processes)]
        warms = [self._spawn(slot) for slot in self._slots]
        for slot, warm in zip(self._slots, warms, strict=True):
            warm.result()
            slot.ready = True

    def stop(self) -> None:
        slots, self._slots = self._slots, []
        for slot in slots:
            slot.generation += 1  # callbacks still under way find nothing to do
            self._unwatch(slot)
            if slot.process is not None and slot.job is not None:
                slot.process.kill()  # jobs are pure: nothing is lost
            if slot.pool is not None:
                slot.pool.shutdown(wait=True, cancel_futures=True)
        for _, _, waiter in self._waiting:
            if not waiter.done():
                waiter.set_exception(ApiError("NOT_READY", detail="workers stopped"))
        self._waiting.clear()

    @property
    def alive(self) -> bool:
        """Started and not stopped."""
        return bool(self._slots)

    @property
    def ready(self) -> bool:
        """Whether some process can take a job now or after the one it runs (GET /readyz)."""
        return any(slot.ready and not slot.dead() for slot in self._slots)

    def pids(self) -> list[int]:
        """The worker processes' ids, one per slot."""
        return [slot.process.pid for slot in self._slots if slot.process is not None]

    @property
    def waiting(self) -> int:
        """Callers waiting for a process."""
        return sum(1 for _, _, waiter in self._waiting if not waiter.done())

    @property
    def busy(self) -> int:
        """Processes running a job (or handed one)."""
        return sum(1 for slot in self._slots if slot.job is not None)

    @staticmethod
    def is_heavy(fn: Callable[..., Any]) -> bool:
        """Whether a job leaves the last free process to the light ones (all but LIGHT_JOBS)."""
        return fn not in LIGHT_JOBS

    # -- heavy requests per user, and results by content

    @contextlib.contextmanager
    def admit(self, owner: str, limit: int) -> Iterator[None]:
        """One heavy request of `owner` (a user, key or address) while the block runs; 429 TOO_MANY_JOBS when
        `owner` has `limit` of them under way already. Counted in this process (each replica on its own)."""
        with self._owners_lock:
            if self._owners[owner] >= limit:
                raise ApiError("TOO_MANY_JOBS", headers={"Retry-After": "2"}, limit=limit)
            self._owners[owner] += 1
        try:
            yield
        finally:
            with self._owners_lock:
                self._owners[owner] -= 1
                if self._owners[owner] <= 0:
                    del self._owners[owner]

    async def cached(self, key: str, fn: Any, *args: Any) -> Any:
        """`call(fn, *args)` for a pure job whose result depends on nothing but `key` (content_key of its
        input): a result made before is answered from memory (cache_bytes, least recently used dropped first),
        and callers asking for the same key at once share one job."""
        hit = self._results.get(key)
        if hit is not None:
            return hit
        loop = asyncio.get_running_loop()
        flight = self._flights.get(key)
        if flight is None or flight.get_loop() is not loop:
            flight = asyncio.ensure_future(self.call(fn, *args))
            self._flights[key] = flight
            flight.add_done_callback(lambda done: self._landed(key, done))
        return await asyncio.shield(flight)  # a caller that goes away leaves the job to the others

    def _landed(self, key: str, flight: asyncio.Future[Any]) -> None:
        if self._flights.get(key) is flight:
            del self._flights[key]
        if not flight.cancelled() and flight.exception() is None:
            self._results.put(key, flight.result())

    def _attach(self) -> asyncio.AbstractEventLoop:
        """The event loop the pool reports to: the one start() ran in, else the first caller's."""
        if self._loop is None:
            self._loop = asyncio.get_running_loop()
            for slot in self._slots:
                self._watch(slot)
        return self._loop

    def _rehome(self) -> None:
        for slot in self._slots:
            slot.watched = None  # registered with the old loop, which is gone
        self._waiting.clear()
        self._loop = None
        self._attach()

    def _spawn(self, slot: _Slot) -> Future[bool]:
        """A new process for `slot`, warming up; the slot takes jobs once it is warm."""
        pool = ProcessPoolExecutor(1, mp_context=_PROCESSES)
        warm = pool.submit(job_warm)  # starts the process
        slot.generation += 1
        slot.pool, slot.ready, slot.job = pool, False, None
        slot.process = next(iter(getattr(pool, "_processes", {}).values()), None)
        if self._loop is not None:
            self._watch(slot)
            generation = slot.generation
            warm.add_done_callback(lambda f: self._soon(self._warmed, slot, generation, f))
        return warm

    def _replace(self, slot: _Slot, reason: str) -> None:
        """End `slot`'s process (if it still runs) and start a new one."""
        log.warning(
            "worker process replaced (slot %d, pid %s): %s",
            slot.index,
            getattr(slot.process, "pid", None),
            reason,
        )
        self._unwatch(slot)
        if slot.process is not None:
            slot.process.kill()
        if slot.pool is not None:
            # not cancel_futures: a job still queued in it fails as BrokenProcessPool, and its caller retries
            slot.pool.shutdown(wait=False)
        slot.ready, slot.job = False, None
        try:
            self._spawn(slot)
        except OSError:  # no process to be had now (memory, descriptors): try again shortly
            log.exception("worker process could not be started (slot %d)", slot.index)
            if self._loop is not None:
                self._loop.call_later(self.respawn_delay, self._respawn_if, slot, slot.generation)

    def _soon(self, fn: Any, *args: Any) -> None:
        """Run `fn(*args)` on the event loop (from a pool's thread); nothing when the loop has ended."""
        if self._loop is not None:
            with contextlib.suppress(RuntimeError):
                self._loop.call_soon_threadsafe(fn, *args)

    def _watch(self, slot: _Slot) -> None:
        # the sentinel becomes readable when the process ends: a dead idle worker is replaced at once
        if self._loop is not None and slot.process is not None and slot.watched is None:
            slot.watched = slot.process.sentinel
            self._loop.add_reader(slot.watched, self._died, slot, slot.generation)

    def _unwatch(self, slot: _Slot) -> None:
        if slot.watched is not None and self._loop is not None:
            with contextlib.suppress(RuntimeError):  # the loop may be closed already
                self._loop.remove_reader(slot.watched)
        slot.watched = None

    def _died(self, slot: _Slot, generation: int) -> None:
        self._unwatch(slot)
        if generation == slot.generation and slot in self._slots:
            self._replace(slot, f"process ended (exit code {slot.process.exitcode})")
            self._dispatch()

    def _warmed(self, slot: _Slot, generation: int, warm: Future[bool]) -> None:
        if generation != slot.generation or slot not in self._slots:
            return
        if warm.cancelled() or warm.exception() is not None:
            log.error("worker process failed to start (slot %d)", slot.index)
            self._unwatch(slot)
            assert self._loop is not None
            self._loop.call_later(self.respawn_delay, self._respawn_if, slot, generation)
            return
        slot.ready = True
        self._dispatch()

    def _respawn_if(self, slot: _Slot, generation: int) -> None:
        if generation == slot.generation and slot in self._slots:
            self._replace(slot, "failed to start")

    # -- handing out slots

    def take_slot(self) -> int:
        """The slot for a new live document: the one holding the fewest; give it back with `release_slot`."""
        slot = min(range(self.processes), key=self._documents.__getitem__)
        self._documents[slot] += 1
        return slot

    def release_slot(self, slot: int) -> None:
        self._documents[slot] = max(0, self._documents[slot] - 1)

    def _free(self, affinity: int | None, heavy: bool = False) -> _Slot | None:
        """A slot that can start a job now: the document's own, or any (those with fewer live documents first);
        for a heavy job none while `heavy_processes` run heavy jobs."""
        if not self._slots:
            return None
        if heavy and sum(1 for s in self._slots if s.job is not None and s.heavy) >= self.heavy_processes:
            return None
        if affinity is not None:
            candidates = [self._slots[affinity % len(self._slots)]]
        else:
            candidates = sorted(self._slots, key=lambda s: self._documents[s.index % self.processes])
        for slot in candidates:
            if slot.ready and slot.job is None:
                if slot.dead():  # died since; its watcher has not run yet
                    self._replace(slot, "process ended")
                    continue
                return slot
        return None

    def _dispatch(self) -> None:
        """Hand free slots to the waiting callers, oldest first (a heavy one that must wait lets the light ones
        behind it go first)."""
        for item in list(self._waiting):
            affinity, heavy, waiter = item
            if waiter.done():
                self._waiting.remove(item)
                continue
            slot = self._free(affinity, heavy)
            if slot is not None:
                slot.job, slot.heavy = _RESERVED, heavy
                waiter.set_result(slot)
                self._waiting.remove(item)

    def _release(self, slot: _Slot, job: Any) -> None:
        if slot.job is job:
            slot.job, slot.heavy = None, False
            self._dispatch()

    async def _acquire(self, affinity: int | None, heavy: bool = False) -> _Slot:
        loop = self._attach()
        waiter: asyncio.Future[_Slot] = loop.create_future()
        item = (affinity, heavy, waiter)
        self._waiting.append(item)
        self._dispatch()
        try:
            async with asyncio.timeout(self.queue_seconds):
                return await waiter
        except BaseException as err:
            if item in self._waiting:
                self._waiting.remove(item)
            if waiter.done() and not waiter.cancelled() and waiter.exception() is None:
                slot = waiter.result()
                self._release(slot, _RESERVED)  # handed over just as the caller gave up
            if isinstance(err, TimeoutError):
                raise ApiError("BUSY", seconds=self.queue_seconds) from None
            raise

    # -- running jobs

    def _finished(self, slot: _Slot, job: _Job, timer: asyncio.TimerHandle) -> None:
        timer.cancel()
        if job.generation == slot.generation:
            error = None if job.future.cancelled() else job.future.exception()
            if isinstance(error, BrokenProcessPool):
                self._replace(slot, "process ended during a job")
                self._dispatch()
                return
        self._release(slot, job)

    def _overtime(self, slot: _Slot, job: _Job) -> None:
        """The time limit, counted from the job's start: end its process (it runs nothing else)."""
        if not job.future.done() and job.generation == slot.generation:
            job.timed_out = True
            log.warning("job over time limit, restarting its worker", extra={"job": job.name})
            self._replace(slot, "time limit")
            self._dispatch()

    async def _run_once(self, slot: _Slot, fn: Any, args: tuple[Any, ...]) -> Any:
        loop = self._attach()
        name = getattr(fn, "__name__", "job")
        if slot.job is not _RESERVED or not slot.ready or slot.pool is None:
            self._release(slot, _RESERVED)
            raise _Requeue  # the process was replaced between the hand-over and now
        try:
            future: Future[Any] = slot.pool.submit(fn, *args)
        except (BrokenProcessPool, RuntimeError):  # it died before its watcher noticed, or the pool stopped
            if slot not in self._slots:
                raise ApiError("NOT_READY", detail="workers stopped") from None
            self._replace(slot, "broken pool")
            self._dispatch()
            raise _Requeue from None
        job = _Job(future, slot.generation, name)
        slot.job = job
        timer = loop.call_later(self.seconds, self._overtime, slot, job)
        future.add_done_callback(lambda _: self._soon(self._finished, slot, job, timer))
        try:
            return await asyncio.wrap_future(future)
        except BrokenProcessPool:
            if job.timed_out:
                raise ApiError("TIME_LIMIT", seconds=self.seconds) from None
            raise

    async def call(self, fn: Any, *args: Any, affinity: int | None = None, heavy: bool | None = None) -> Any:
        """Run `fn(*args)` in a worker: TIME_LIMIT (503) when it runs longer than the limit, WORKER_FAILED (503)
        when its process dies twice, BUSY (503) when no process is free for `queue_seconds`. `heavy` (by default
        `is_heavy(fn)`): the job waits while `heavy_processes` run heavy jobs."""
        if not self._slots:
            raise ApiError("NOT_READY", detail="workers not started")
        heavy = self.is_heavy(fn) if heavy is None else heavy
        home, loop = self._loop, asyncio.get_running_loop()
        if home is not None and home is not loop:
            if home.is_running():  # the pool's state belongs to its loop: the call runs there
                return await asyncio.wrap_future(
                    asyncio.run_coroutine_threadsafe(
                        self.call(fn, *args, affinity=affinity, heavy=heavy), home
                    )
                )
            self._rehome()  # the loop start() ran in has ended: this one takes the pool over
        failures = 0
        while True:
            if not self._slots:
                raise ApiError("NOT_READY", detail="workers stopped")
            slot = await self._acquire(affinity, heavy)
            try:
                return await self._run_once(slot, fn, args)
            except _Requeue:
                continue
            except BrokenProcessPool:
                failures += 1
                log.warning(
                    "worker process lost during a job (%d of 2)",
                    failures,
                    extra={"job": getattr(fn, "__name__", "job")},
                )
                if failures >= 2:
                    raise ApiError("WORKER_FAILED") from None
