"""Eulerian-cell benchmark: the Liska-Wendroff "quadrants" 2D Riemann problem
(the initial data of clawpack.pyclaw.examples.euler_2d.quadrants: the unit
square cut at x = y = 0.8, gamma 1.4, four states), in cells.  Each quadrant is
a material of its own (the contract's material density is the initial density,
so four densities need four materials; they are identical gases), so the
quadrants' contacts are material interfaces.  Walls all round (PyClaw
extrapolates; the waves reach the boundaries only late).  Runs a number of steps
after a warm-up and prints cell-updates per second per core (cells x steps /
wall time of the steps), the figure PyClaw's peer script prints
(../shared/peers/pyclaw_euler.py, run by scripts/bench).

    mpiexec -n 2 python scripts/bench_cells.py [-bench_n 256] [-bench_steps 100]

The line CELLS_RATE <n> <rate> is for scripts/bench.
"""
import sys
import time

import petsc4py

petsc4py.init(sys.argv)
from petsc4py import PETSc  # noqa: E402

from plyshock import Body, Box, Grid, Material, Run, Scene  # noqa: E402
from plyshock import core  # noqa: E402

opts = PETSc.Options()
n = opts.getInt("bench_n", 256)
steps = opts.getInt("bench_steps", 100)
comm = PETSc.COMM_WORLD
mpi = comm.tompi4py()

# the quadrants: (x range, y range, rho, u, v, p)
Q = [("ur", (0.8, 1.0), (0.8, 1.0), 1.5, 0.0, 0.0, 1.5),
     ("ul", (0.0, 0.8), (0.8, 1.0), 0.532258064516129, 1.206045378311055, 0.0, 0.3),
     ("ll", (0.0, 0.8), (0.0, 0.8), 0.137992831541219, 1.206045378311055, 1.206045378311055, 0.029032258064516),
     ("lr", (0.8, 1.0), (0.0, 0.8), 0.532258064516129, 0.0, 1.206045378311055, 0.3)]
mats = [Material(name, density=rho, eos={"type": "ideal-gas", "gamma": 1.4}) for name, xr, yr, rho, u, v, p in Q]
bodies = [Body(name, box=Box([xr[0], yr[0]], [xr[1], yr[1]]), material=name, representation="cells", pressure=p, velocity=[u, v])
          for name, xr, yr, rho, u, v, p in Q]
scene = Scene(2, Grid([0, 0], [1, 1], [n, n], {"x-": "symmetry", "x+": "symmetry", "y-": "symmetry", "y+": "symmetry"}),
              mats, bodies, Run(t_end=10.0, cfl=0.4)).validate()
m = core.initialize(scene)
S = core.make_solver(m)
for _ in range(5):
    S.step()
mpi.Barrier()
t = time.perf_counter()
for _ in range(steps):
    S.step()
mpi.Barrier()
t = time.perf_counter() - t
rate = n * n * steps / t / comm.getSize()
if comm.getRank() == 0:
    print(f"cells benchmark (quadrants, {n}^2 cells, 4 gas materials, {steps} steps): {comm.getSize()} rank(s)")
    print(f"  {t:.3f} s: {rate / 1e6:.3f} M cell-updates/s/core, t = {S.time:.4f}")
    print(f"CELLS_RATE {n} {rate:.6e}")
