"""A stop belongs to the call it stops (issue 57, item 3): Ctrl-C, or a progress callback that
raises, in one thread stops that thread's call, which raises; the solves and capacity searches
of other threads run on to the verdicts they reach alone."""

import os
import signal
import threading
import time

import pytest

SMALL = dict(space="actuation", payload=1.0, population=8, generations=40, seed=0, workers=1)


class Stop(Exception):
    """What the test's handler of INT raises in the main thread."""


def raise_stop(signum, frame):
    raise Stop()


class Background:
    """Threads that repeat `work` until told to finish, keeping every answer (or exception)."""

    def __init__(self, work, count=2):
        self.answers = []
        self.finish = threading.Event()
        self.started = threading.Barrier(count + 1)
        self.threads = [threading.Thread(target=self.repeat, args=(work,)) for _ in range(count)]

    def repeat(self, work):
        self.started.wait()
        while not self.finish.is_set():
            try:
                self.answers.append(work())
            except BaseException as error:  # noqa: B902 - every outcome is checked
                self.answers.append(error)

    def __enter__(self):
        for thread in self.threads:
            thread.start()
        self.started.wait()
        # Every thread is inside its first call.
        time.sleep(0.2)
        return self

    def __exit__(self, *exc):
        # The calls under way when the stop came finish first.
        time.sleep(0.5)
        self.finish.set()
        for thread in self.threads:
            thread.join()
        return False


def solve(planar):
    return planar.solve(payload=1.0, ratios=[50, 12]).to_dict()


def without_times(document):
    document = dict(document)
    document.pop("solve_seconds", None)
    return document


def ctrl_c_during(call):
    """Runs `call` in this (the main) thread and sends INT to the process while it runs; the
    call must end by raising what the handler raises."""
    previous = signal.signal(signal.SIGINT, raise_stop)
    timer = threading.Timer(0.3, os.kill, (os.getpid(), signal.SIGINT))
    try:
        timer.start()
        with pytest.raises(Stop):
            call()
    finally:
        timer.cancel()
        signal.signal(signal.SIGINT, previous)


def test_ctrl_c_in_one_thread_stops_no_solve_of_another(planar):
    alone = without_times(solve(planar))
    assert alone["feasible"]
    with Background(lambda: solve(planar)) as background:
        ctrl_c_during(lambda: planar.capacity(ratios=[50, 12], resolution=1e-6))
    assert background.answers
    for answer in background.answers:
        assert not isinstance(answer, BaseException), repr(answer)
        assert without_times(answer) == alone


def test_ctrl_c_in_one_thread_stops_no_capacity_search_of_another(planar):
    def capacity():
        return planar.capacity(ratios=[50, 12], resolution=0.05).capacity_kg

    alone = capacity()
    with Background(capacity) as background:
        ctrl_c_during(lambda: planar.optimize(**SMALL, progress=False))
    assert background.answers
    assert all(answer == alone for answer in background.answers), background.answers


def test_a_raising_progress_callback_stops_its_run_alone(planar, tmp_path):
    # Short solves, whose IPOPT iterations come every fraction of a millisecond: the run that
    # stops takes milliseconds to, and the stop is asked of several runs in turn.
    def short():
        sol = planar.solve(payload=1.0, ratios=[50, 12], steps=10)
        return sol.feasible, sol.reason, sol.cost

    alone = short()
    assert alone[0]

    def fail(done, total, best):
        if done == 3:
            raise RuntimeError("enough")

    with Background(short, count=3) as background:
        for attempt in range(4):
            with pytest.raises(RuntimeError, match="enough"):
                planar.optimize(**SMALL, log=tmp_path / f"r{attempt}.log.jsonl", progress=fail)
    assert background.answers
    assert all(answer == alone for answer in background.answers), set(map(repr, background.answers))
