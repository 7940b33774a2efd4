"""What the solver benchmarks share: the wall time of a number of steps,
between barriers so that every rank's share is in it."""
import time


def timed_steps(S, steps, mpi):
    """Seconds of wall time for `steps` steps of solver S on all ranks of mpi."""
    mpi.Barrier()
    t = time.perf_counter()
    for _ in range(steps):
        S.step()
    mpi.Barrier()
    return time.perf_counter() - t
