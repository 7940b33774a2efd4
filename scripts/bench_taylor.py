"""Solver benchmark with full shock physics: the copper Taylor bar in 3D.

Cylinder radius 3.8 mm, length 25.4 mm, 190 m/s against a rigid frictionless
wall (symmetry face at z = 0), cells of 0.25 mm, one marker per cell, the
default path (run.transfer musl, run.shape gimp; -bench_shape linear|bspline2
for another shape), Mie-Grueneisen + Johnson-Cook + artificial viscosity, 200
steps after a warm-up of 5, no output.  Peer figure (Karamelo, the same bar without
artificial viscosity): 0.50 M marker-steps/s on one rank, 0.87 M on two,
measured on the project's machines, quoted not re-run.
"""
import sys

import petsc4py

petsc4py.init(sys.argv[:1] + [a for a in sys.argv[1:] if a.startswith("-")])
from petsc4py import PETSc  # noqa: E402

from plyshock import Body, Cylinder, Grid, Material, Run, Scene  # noqa: E402
from plyshock import core  # noqa: E402
from benchlib import timed_steps  # noqa: E402  (scripts/benchlib.py)

h = 0.25e-3
R, L = 3.8e-3, 25.4e-3
half = 4.5e-3
cells = [round(2 * half / h), round(2 * half / h), round(26e-3 / h)]
scene = Scene(3, Grid([-half, -half, 0.0], [half, half, 26e-3], cells, {"z-": "symmetry"}),
              [Material("cu", preset="OFHC-copper")],
              [Body("bar", cylinder=Cylinder([0, 0, 0], [0, 0, 1], R, L), material="cu", velocity=[0, 0, -190.0])],
              Run(t_end=1.0, shape=PETSc.Options().getString("bench_shape", "gimp"))).validate()
comm = PETSc.COMM_WORLD
mpi = comm.tompi4py()
steps = 200
m = core.initialize(scene)
S = core.make_solver(m)
for _ in range(5):
    S.step()
t = timed_steps(S, steps, mpi)
n = m.stats["markers"]
if comm.getRank() == 0:
    rate = n * steps / t
    ref = {1: 0.50e6, 2: 0.87e6}.get(comm.getSize())
    print(f"solver benchmark (Taylor bar, musl/{scene.run.shape}, MG + JC + AV, {n} markers, {steps} steps): {comm.getSize()} rank(s)")
    print(f"  {t:.2f} s: {rate / 1e6:.3f} M marker-steps/s ({rate / comm.getSize() / 1e6:.3f} M/s/core), {m.bytes_per_marker} bytes per marker"
          + (f"; {rate / ref:.2f} x Karamelo's {ref / 1e6:.2f} M/s on {comm.getSize()} rank(s)" if ref else ""))
    print(f"BENCH taylor_{scene.run.shape}_{comm.getSize()} {rate:.6e}")
