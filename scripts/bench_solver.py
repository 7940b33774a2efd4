"""Solver benchmark: the standard elastic-block workload, on the ordinary code path.

3D, 64^3 cells on the unit cube, the middle third filled with 2 x 2 x 2 markers
per cell (74,088 markers), quadratic B-splines, linear elastic (E 1e3, nu 0.3,
rho 1), initial velocity 0.5 in x, dt = 0.3 h / (c + 1), 30 steps after a
warm-up of 3 (best of five such runs), under each transfer scheme (run.transfer apic, the MLS-MPM form
the peer uses, then musl).  Prints marker-steps per second per core and bytes
per marker; the line RATE gives apic's, RATE_MUSL musl's (-bench_transfer
apic|musl runs one of them).  The peer reference
is ../shared/peers/taichi_mpm3d.py (scripts/bench runs it in the same script).
"""
import sys
import time

import petsc4py

petsc4py.init(sys.argv)
from petsc4py import PETSc  # noqa: E402

PETSc.Log.begin()   # the events' counts: a scene without cells must not enter the cells' phases
import numpy as np  # noqa: E402

from plyshock import Body, Box, Grid, Material, Run, Scene  # noqa: E402
from plyshock import core  # noqa: E402

N = 64
h = 1.0 / N
E, nu, rho = 1e3, 0.3, 1.0
c = np.sqrt(E * (1 - nu) / ((1 + nu) * (1 - 2 * nu) * rho))
dt = 0.3 * h / (c + 1)
lo = 21 * h + 0.0
comm = PETSc.COMM_WORLD
mpi = comm.tompi4py()


def bench(transfer, shape="bspline2"):
    block = Body("block", box=Box([lo] * 3, [lo + 21 * h] * 3), material="el", velocity=[0.5, 0, 0], subdivision=2)
    scene = Scene(3, Grid([0, 0, 0], [1, 1, 1], [N] * 3), [Material("el", density=rho, elastic={"type": "isotropic", "E": E, "nu": nu})],
                  [block], Run(t_end=1.0, cfl=1.0, dt_max=dt, shape=shape, transfer=transfer,
                               artificial_viscosity={"c_linear": 0, "c_quadratic": 0})).validate()
    m = core.initialize(scene)
    S = core.make_solver(m)
    for _ in range(3):
        S.step()
    ts = []
    for _ in range(5):      # best of five 30-step runs: this machine's timings vary between runs
        mpi.Barrier()
        t = time.perf_counter()
        for _ in range(30):
            S.step()
        mpi.Barrier()
        ts.append(time.perf_counter() - t)
    t = min(ts)
    n = m.stats["markers"]
    rate = n * 30 / t / comm.getSize()
    if comm.getRank() == 0:
        print(f"solver benchmark (elastic block, {shape}, transfer {transfer}, 64^3 cells, {n} markers, 30 steps): {comm.getSize()} rank(s)")
        print(f"  best 30 steps {t:.3f} s: {rate / 1e6:.3f} M marker-steps/s/core, dt {dt:.3e} s, {m.bytes_per_marker} bytes per marker")
    return rate


# -bench_transfer apic|musl: one scheme only (e.g. to read -log_view for it)
only = PETSc.Options().getString("bench_transfer", "")
apic = bench("apic") if only in ("", "apic") else None
musl = bench("musl", "gimp") if only in ("", "musl") else None          # the default path
muslb = bench("musl", "bspline2") if only in ("", "musl") else None
if comm.getRank() == 0:
    if apic and musl:
        print(f"  musl/gimp (the default) runs {musl / apic:.2f}x apic, musl/bspline2 {muslb / apic:.2f}x apic")
    r = comm.getSize()
    if apic:
        print(f"RATE {apic:.6e}")
        print(f"BENCH block_apic_{r} {apic:.6e}")
    if musl:
        print(f"RATE_MUSL {musl:.6e}")
        print(f"RATE_MUSL_BSPLINE {muslb:.6e}")
        print(f"BENCH block_musl_{r} {musl:.6e}")
        print(f"BENCH block_musl_bspline2_{r} {muslb:.6e}")
    # what a scene without cell bodies pays for the cells: their phases' calls
    calls = sum(PETSc.Log.Event(e).getPerfInfo()["count"] for e in ("PSCellsP2G", "PSCellsLagrange", "PSCellsRemap"))
    print(f"  cell phases entered by this scene without cells: {calls} times")
    print(f"BENCH nocells_calls {calls}")
