"""Time to a solution of the cells against the Courant number.

1. Accuracy: the quadrants (benchlib.py) on 128^2 cells to t = 0.3 at
   run.cfl 0.2, 0.4 (the default) and 0.8, each one's wall time and steps,
   and its density's L1 error against the same problem on 256^2 cells at
   run.cfl 0.2 (averaged onto the 128^2 cells: the error a user sees, mostly
   the grid's) and against the 128^2 run at run.cfl 0.2 (the error of the
   time step alone).
2. Time: the quadrants on 256^2 cells to t = 0.2, the end time of scripts/
   bench's PyClaw run, at run.cfl 0.4 and 0.8: wall time and steps, which
   bench_table.py sets beside PyClaw's (walls here, extrapolation there: the
   same waves inside, a rarefaction off the walls here).

scripts/bench compares cell-updates per second with PyClaw, which runs at a
Courant number up to 0.9 per direction (its roe_split variant, |u_d| + c)
against the default run.cfl 0.4 of the signal speed c + |v| + q/(rho c)
here: per unit of simulated time it takes fewer steps.  This says what a
larger run.cfl costs the cells in accuracy, and how long each takes to the
same time.

    mpiexec -n 1 python scripts/bench_cfl.py

Lines BENCH cfl_<name> <value> for scripts/bench's table: cfl_wall_0.8_0.4
(wall time at 0.8 over 0.4), cfl_steps_0.8_0.4, cfl_err_0.4 and cfl_err_0.8
(L1 error against 256^2, kg/m^3 per cell), cfl_terr_0.4 and cfl_terr_0.8
(against the 128^2 run at 0.2); cfl_t02_wall_256_<cfl> (s) and
cfl_t02_steps_256_<cfl>.  Any number of ranks (each run's cells gathered
on every rank by verify_cells.cells_global to compare the fields: grids of
a benchmark's size, 256^2 at most).
"""
import sys
import time

import petsc4py

petsc4py.init(sys.argv)
from petsc4py import PETSc  # noqa: E402

import numpy as np  # noqa: E402

from plyshock import core  # noqa: E402
from plyshock.verify_cells import cells_global  # noqa: E402
from benchlib import quadrants_scene  # noqa: E402  (scripts/benchlib.py)

mpi = PETSc.COMM_WORLD.tompi4py()


def density(n, cfl, t_end):
    """The quadrants on n^2 cells at run.cfl cfl to t_end: (density (n, n) kg/m^3, wall s, steps)."""
    m = core.initialize(quadrants_scene(n, cfl, t_end))
    S = core.make_solver(m)
    mpi.Barrier()
    w0, steps = time.perf_counter(), 0
    while S.time < t_end * (1 - 1e-12):
        S.step(t_end)
        steps += 1
    mpi.Barrier()
    wall = time.perf_counter() - w0
    u, nm, ms = cells_global(S, mpi)
    rho = sum(u[..., k * ms + 1] for k in range(nm)) * n * n   # (the materials' masses over the cell's volume 1/n^2)
    if not np.isfinite(rho).all():
        sys.exit(f"bench_cfl.py: the density at {n}^2, run.cfl {cfl} is not finite")
    return rho, wall, steps


t_end = 0.3
fine, _, _ = density(256, 0.2, t_end)
ref = fine.reshape(128, 2, 128, 2).mean(axis=(1, 3))   # (the 2x2 fine cells' mean: the mass in each coarse cell)
runs = {cfl: density(128, cfl, t_end) for cfl in (0.2, 0.4, 0.8)}
err = {cfl: float(np.abs(r[0] - ref).mean()) for cfl, r in runs.items()}
terr = {cfl: float(np.abs(r[0] - runs[0.2][0]).mean()) for cfl, r in runs.items()}
if mpi.rank == 0:
    print(f"quadrants 128^2 to t = {t_end:g} at three run.cfl ({mpi.size} rank(s)); the density's L1 error per cell (kg/m^3)")
    print("  run.cfl  steps  wall s  against 256^2  against run.cfl 0.2 (time step alone)")
    for cfl, (_, wall, steps) in runs.items():
        print(f"  {cfl:7.1f}  {steps:5d}  {wall:6.2f}  {err[cfl]:13.3e}  {terr[cfl]:.3e}")
    print(f"  run.cfl 0.8 against 0.4: {runs[0.8][1] / runs[0.4][1]:.2f}x the wall time, "
          f"{runs[0.8][2] / runs[0.4][2]:.2f}x the steps, {err[0.8] / err[0.4]:.3f}x the error against 256^2")
    print(f"BENCH cfl_wall_0.8_0.4 {runs[0.8][1] / runs[0.4][1]:.6e}")
    print(f"BENCH cfl_steps_0.8_0.4 {runs[0.8][2] / runs[0.4][2]:.6e}")
    for cfl in (0.4, 0.8):
        print(f"BENCH cfl_err_{cfl} {err[cfl]:.6e}")
        print(f"BENCH cfl_terr_{cfl} {terr[cfl]:.6e}")
# 2. to PyClaw's end time at 256^2
for cfl in (0.4, 0.8):
    _, wall, steps = density(256, cfl, 0.2)
    if mpi.rank == 0:
        print(f"quadrants 256^2 to t = 0.2 at run.cfl {cfl}: {steps} steps, {wall:.2f} s")
        print(f"BENCH cfl_t02_wall_256_{cfl} {wall:.6e}")
        print(f"BENCH cfl_t02_steps_256_{cfl} {steps}")
