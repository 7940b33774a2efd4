"""Solver benchmark: the standard elastic-block workload, on the ordinary code path.

3D, 64^3 cells on the unit cube, the middle third filled with 2 x 2 x 2 markers
per cell (74,088 markers), quadratic B-splines, linear elastic (E 1e3, nu 0.3,
rho 1), initial velocity 0.5 in x, dt = 0.3 h / (c + 1), 30 steps after a
warm-up of 3 (best of five such runs, the schemes taking turns), under each transfer scheme (run.transfer apic, the MLS-MPM form
the peer uses, and musl with GIMP and with B-splines).  Prints marker-steps per second per core and bytes
per marker; the line RATE gives apic's, RATE_MUSL musl's (-bench_transfer
apic|musl runs one of them).  The peer reference
is ../shared/peers/taichi_mpm3d.py (scripts/bench runs it in the same script).
"""
import sys

import petsc4py

petsc4py.init(sys.argv)
from petsc4py import PETSc  # noqa: E402

PETSc.Log.begin()   # the events' counts: a scene without cells must not enter the cells' phases
import numpy as np  # noqa: E402

from plyshock import Body, Box, Grid, Material, Run, Scene  # noqa: E402
from plyshock import core  # noqa: E402
from benchlib import timed_steps  # noqa: E402  (scripts/benchlib.py)

N = 64
h = 1.0 / N
E, nu, rho = 1e3, 0.3, 1.0
c = np.sqrt(E * (1 - nu) / ((1 + nu) * (1 - 2 * nu) * rho))
dt = 0.3 * h / (c + 1)
lo = 21 * h + 0.0
comm = PETSc.COMM_WORLD
mpi = comm.tompi4py()


def setup(transfer, shape="bspline2"):
    """The block under one transfer and shape: (its solver, markers, bytes per marker), warmed up by 3 steps."""
    block = Body("block", box=Box([lo] * 3, [lo + 21 * h] * 3), material="el", velocity=[0.5, 0, 0], subdivision=2)
    scene = Scene(3, Grid([0, 0, 0], [1, 1, 1], [N] * 3), [Material("el", density=rho, elastic={"type": "isotropic", "E": E, "nu": nu})],
                  [block], Run(t_end=1.0, cfl=1.0, dt_max=dt, shape=shape, transfer=transfer,
                               artificial_viscosity={"c_linear": 0, "c_quadratic": 0})).validate()
    m = core.initialize(scene)
    S = core.make_solver(m)
    for _ in range(3):
        S.step()
    return S, m.stats["markers"], m.bytes_per_marker


def bench(cases):
    """Best of five 30-step runs of each case, the cases taking turns (apic,
    gimp, bspline2, apic, ...): this machine's speed drifts within a script
    (the first minute runs fastest), and timing one case's five runs before
    the next's handed the drift to whichever ran first.  {case: rate}."""
    solvers = {name: setup(*how) for name, how in cases.items()}
    best = {name: float("inf") for name in cases}
    for _ in range(5):
        for name, (S, n, b) in solvers.items():
            best[name] = min(best[name], timed_steps(S, 30, mpi))
    rates = {}
    for name, (S, n, b) in solvers.items():
        t = best[name]
        rates[name] = n * 30 / t / comm.getSize()
        transfer, shape = cases[name][0], cases[name][1] if len(cases[name]) > 1 else "bspline2"
        if comm.getRank() == 0:
            print(f"solver benchmark (elastic block, {shape}, transfer {transfer}, 64^3 cells, {n} markers, 30 steps): {comm.getSize()} rank(s)")
            print(f"  best 30 steps {t:.3f} s: {rates[name] / 1e6:.3f} M marker-steps/s/core, dt {dt:.3e} s, {b} bytes per marker")
    return rates


# -bench_transfer apic|musl: one scheme only (e.g. to read -log_view for it)
only = PETSc.Options().getString("bench_transfer", "")
cases = {}
if only in ("", "apic"):
    cases["apic"] = ("apic",)
if only in ("", "musl"):
    cases["musl"] = ("musl", "gimp")          # the default path
    cases["muslb"] = ("musl", "bspline2")
R = bench(cases)
apic, musl, muslb = R.get("apic"), R.get("musl"), R.get("muslb")
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
