"""The GIL is released during long solves and runs: a Python thread keeps counting while another
thread is inside cbps.solve or Simulation.run. With the GIL held the counting thread would wait
for the whole call. Ctrl-C (SIGINT) stops both."""
import os
import signal
import threading
import time

import numpy as np
import pytest
import scipy.sparse as sp

import cbps


def activity_during(call):
    """Runs call() in a thread while this thread counts, stamping the time every 100 counts;
    returns how many stamps fall in the middle half of the call, and the call's duration (s).
    With the GIL held for the whole call this thread could not run then: no stamp there."""
    stamps = []
    span = {}
    done = threading.Event()

    def worker():
        span["start"] = time.perf_counter()
        call()
        span["end"] = time.perf_counter()
        done.set()

    thread = threading.Thread(target=worker)
    thread.start()
    count = 0
    while not done.is_set():
        count += 1
        if count % 100 == 0:
            stamps.append(time.perf_counter())
    thread.join()
    start, end = span["start"], span["end"]
    quarter = (end - start) / 4
    return sum(start + quarter < t < end - quarter for t in stamps), end - start


def long_problem(c=2000):
    """A tridiagonal A (a chain's shape: 2 on the diagonal, -1 beside), b = 1, unbounded."""
    A = sp.diags([-np.ones(c - 1), 2 * np.ones(c), -np.ones(c - 1)], [-1, 0, 1], format="csr")
    return A, np.ones(c), np.full(c, -np.inf), np.full(c, np.inf)


def long_enough(make_call):
    """activity_during(make_call(k)) for k = 1, 2, 4, ... until the call lasts 0.1 s, long beside
    the 5 ms switch interval, so that its middle half can tell (machines differ tenfold)."""
    k = 1
    while True:
        middle, seconds = activity_during(make_call(k))
        if seconds > 0.1 or k >= 256:
            return middle, seconds
        k *= 2


def test_solve_releases_the_gil():
    A, b, cmin, cmax = long_problem()
    # k x 300 PGS sweeps over 6000 nonzeros with a residual after each.
    middle, seconds = long_enough(lambda k: lambda: cbps.solve(
        A, b, cmin, cmax, "pgs", iterations=300 * k, tolerance=0))
    assert seconds > 0.1
    # Stamps come every few microseconds while the counter runs: hundreds in the middle half.
    assert middle > 10, (middle, seconds)


def test_run_releases_the_gil():
    sim = cbps.Simulation(cbps.scene("chain", n=30))
    middle, seconds = long_enough(lambda k: lambda: sim.run(steps=100 * k))
    assert seconds > 0.1
    assert middle > 10, (middle, seconds)


def test_two_threads_share_a_simulation():
    """Calls on one Simulation from two threads are serialised: 2 x 50 steps make 100."""
    sim = cbps.Simulation(cbps.scene("chain", n=5))
    threads = [threading.Thread(target=lambda: sim.run(steps=50)) for _ in range(2)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert sim.steps_done == 100


def test_run_stops_on_ctrl_c():
    """SIGINT during a long run: KeyboardInterrupt within about 0.1 s of the signal (the run
    looks every 0.1 s), the steps done stay done."""
    sim = cbps.Simulation(cbps.scene("chain", n=50))
    timer = threading.Timer(0.3, lambda: os.kill(os.getpid(), signal.SIGINT))
    timer.start()
    t0 = time.perf_counter()
    with pytest.raises(KeyboardInterrupt):
        sim.run(steps=10**8)  # hours
    seconds = time.perf_counter() - t0
    timer.join()
    assert 0.3 <= seconds < 2.0, seconds
    assert 0 < sim.steps_done < 10**8
    assert sim.time == sim.steps_done * sim.scene.dt


@pytest.mark.parametrize("method,kwargs", [
    ("pgs", {}),
    ("pgs", {"history": False}),
    ("apgd", {}),
    ("nncg", {}),
    ("jacobi:0.5", {}),
    ("pgs", {"split_islands": True}),
], ids=["pgs", "pgs-without-history", "apgd", "nncg", "jacobi", "pgs-islands"])
def test_solve_stops_on_ctrl_c(method, kwargs):
    """SIGINT during a solve of 2**31 - 1 sweeps with no tolerance (hours on the tridiagonal
    problem): KeyboardInterrupt within about 0.1 s of the signal (the sweeps look every 0.1 s),
    for every iterative method and with islands solved apart (the chain of 2000 rows cut into
    two islands by one zero off-diagonal pair)."""
    A, b, cmin, cmax = long_problem()
    if kwargs.get("split_islands"):
        A = A.tolil()
        A[999, 1000] = A[1000, 999] = 0.0
        A = A.tocsr()
        A.eliminate_zeros()
    timer = threading.Timer(0.3, lambda: os.kill(os.getpid(), signal.SIGINT))
    timer.start()
    t0 = time.perf_counter()
    with pytest.raises(KeyboardInterrupt):
        cbps.solve(A, b, cmin, cmax, method, iterations=2**31 - 1, tolerance=0, **kwargs)
    seconds = time.perf_counter() - t0
    timer.join()
    assert 0.3 <= seconds < 1.3, seconds
