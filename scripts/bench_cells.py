"""Eulerian-cell benchmark.  Cases (-bench_case):

  quadrants1 the Liska-Wendroff "quadrants" 2D Riemann problem (the initial data
             of clawpack.pyclaw.examples.euler_2d.quadrants: the unit square cut
             at x = y = 0.8, gamma 1.4, four states) as PyClaw runs it, one
             gas: one material, each quadrant a body at its own density and
             pressure (the body key `density`).  Walls all round (PyClaw
             extrapolates; the waves reach the boundaries late).
  quadrants  the same problem with each quadrant a material of its own
             (identical gases), so the quadrants' contacts are material
             interfaces (Youngs' PLIC, mixed cells): the harder problem, which
             the sessions before the body key `density` ran as the quadrants.
  pure       one gas in uniform motion (rho 1, p 1, v (0.5, 0.3)): every face
             carries flux, every cell pure.
  mixed      the same flow with two identical gases in stripes one cell wide,
             offset by half a cell: every cell holds half of each, so every
             cell takes the mixed-cell path (closure, interface reconstruction,
             each material's part of the donor slab).  mixed / pure is the cost
             of a mixed cell against a pure one.
  boxes      the pure case's flow with four identical gases, one in each of
             the quadrants' four boxes (cut at x = y = 0.8): the quadrants'
             materials and interfaces without their waves.  boxes / pure is
             what the four materials and their two interfaces cost (an
             interface crossing a row cuts its run of one gas, and each run
             repeats its work: scans, lanes loops' set-up and remainders;
             -bench_layout columns puts the four in columns a quarter wide
             instead, three interfaces across every row).

-bench_apart (quadrants and quadrants1): each rank runs its own slab of the
quadrants, the rows [r n/p, (r + 1) n/p) of the n^2 grid (walls at its cut,
the bodies that reach into it), as a solver of its own (PETSc.COMM_SELF): the
ranks share the machine, its L3 and memory, as p ranks of one run do, and
each slab's own work, but exchange nothing and never wait for each other in
a step.  Its rate per core (the slowest rank's time, as a run's) over the
1-rank rate is a ceiling for the p-rank efficiency on this machine
(scripts/bench_pairs.py --efficiency); its lines' name is "apart" ("apart1" for quadrants1).

Runs a number of steps after a warm-up and prints cell-updates per second per
core (cells x steps / wall time of the steps), the figure PyClaw's peer script
prints (../shared/peers/pyclaw_euler.py, run by scripts/bench); the best of
-bench_reps runs (default 3), each from the initial state, as scripts/bench
takes PyClaw's best of as many (this machine's speed drifts from one run to
the next).

    mpiexec -n 2 python scripts/bench_cells.py [-bench_case quadrants|quadrants1|pure|mixed|boxes] [-bench_n 256] [-bench_steps 100] [-bench_reps 3] [-bench_layout quadrants] [-bench_apart]

The line BENCH cells_<case>_<n>_<ranks> <rate> (case columns for the boxes in columns) is for scripts/bench's table;
so is BENCH cells_flux_ns_<case>_<n>_<ranks>: the remap's flux phase (event
PSCellsFlux without PSCellsKEBehind, the KE fix it runs behind the cells'
update, the slowest rank: the fractions, faces, dual fluxes and cell
updates, as the stripped sweep computes its densities per row) in ns per cell
and sweep, which the table sets beside scripts/sweep_floor.c's stripped sweep
of the pure case; and BENCH cells_bytes_per_cell_<case>_<n>_<ranks>: the
process's resident growth over the first run's setup and warm-up, per cell
of the rank that grew most.  Then each phase's event in ns per cell-update.
"""
import sys

import petsc4py

petsc4py.init(sys.argv)
from petsc4py import PETSc  # noqa: E402
from mpi4py import MPI  # noqa: E402

from plyshock import Body, Box, Grid, Material, Run, Scene  # noqa: E402
from plyshock import core  # noqa: E402
from benchlib import GAS, QUADRANTS, WALLS, quadrants_scene, resident_bytes, timed_steps  # noqa: E402  (scripts/benchlib.py)
from bench_table import CELL_PHASES  # noqa: E402  (the Lagrangian phases' events and labels)

opts = PETSc.Options()
case = opts.getString("bench_case", "quadrants")
n = opts.getInt("bench_n", 256)
steps = opts.getInt("bench_steps", 100)
reps = opts.getInt("bench_reps", 3)
layout = opts.getString("bench_layout", "quadrants")
apart = opts.getBool("bench_apart", False)
tag = "columns" if case == "boxes" and layout == "columns" else ("apart1" if case == "quadrants1" else "apart") if apart else case  # (the BENCH lines' name)
if reps < 1:
    sys.exit(f"bench_cells.py: -bench_reps must be >= 1, got {reps}")
if case not in ("quadrants", "quadrants1", "pure", "mixed", "boxes"):
    sys.exit(f"bench_cells.py: -bench_case must be quadrants, quadrants1, pure, mixed or boxes, got {case!r}")
if layout not in ("quadrants", "columns"):
    sys.exit(f"bench_cells.py: -bench_layout must be quadrants or columns, got {layout!r}")
if layout != "quadrants" and case != "boxes":
    sys.exit(f"bench_cells.py: -bench_layout {layout} is for -bench_case boxes only, got -bench_case {case}")
comm = PETSc.COMM_WORLD
mpi = comm.tompi4py()
if apart and case not in ("quadrants", "quadrants1"):
    sys.exit(f"bench_cells.py: -bench_apart is for -bench_case quadrants or quadrants1 only, got -bench_case {case}")
if apart and n % comm.getSize():
    sys.exit(f"bench_cells.py: -bench_apart needs -bench_n a multiple of the ranks ({comm.getSize()}), got {n}")

if case in ("quadrants", "quadrants1"):
    scene = quadrants_scene(n, one_gas=case == "quadrants1")   # (benchlib.py: the four states, one gas or each a material)
    what = "quadrants, one gas" if case == "quadrants1" else "quadrants, 4 gas materials"
    if apart:
        # this rank's slab alone: the rows a run on as many ranks gives it
        # (the DMDA splits n rows evenly along y), its bodies, their materials
        p, r = comm.getSize(), comm.getRank()
        lo, hi = r / p, (r + 1) / p
        bodies = [bd for bd in scene.bodies if bd.box.lower[1] < hi and bd.box.upper[1] > lo]
        mats = [mt for mt in scene.materials if mt.name in {bd.material for bd in bodies}]
        scene = Scene(2, Grid([0, lo], [1, hi], [n, n // p], WALLS), mats, bodies, scene.run).validate()
        what += f", each of {p} ranks its slab of {n} x {n // p} apart"
else:
    # uniform flow (walls all round: in the steps timed the gas moves a few
    # cells, and only the cells next to the walls feel them)
    v = [0.5, 0.3]
    h = 1.0 / n
    if case == "pure":
        mats = [Material("a", density=1.0, eos=GAS)]
        bodies = [Body("a", box=Box([0, 0], [1, 1]), material="a", representation="cells", pressure=1.0, velocity=v)]
    elif case == "boxes":
        mats = [Material(f"g{k}", density=1.0, eos=GAS) for k in range(4)]
        if layout == "quadrants":
            boxes = [Box([xr[0], yr[0]], [xr[1], yr[1]]) for _, xr, yr, *_ in QUADRANTS]
        else:
            boxes = [Box([k / 4, 0.0], [(k + 1) / 4, 1.0]) for k in range(4)]
        bodies = [Body(f"b{k}", box=boxes[k], material=f"g{k}", representation="cells", pressure=1.0, velocity=v) for k in range(4)]
    else:
        mats = [Material("a", density=1.0, eos=GAS), Material("b", density=1.0, eos=GAS)]
        bodies = [Body(f"s{i}", box=Box([max(0.0, (i - 0.5) * h), 0], [min(1.0, (i + 0.5) * h), 1]), material="ab"[i % 2],
                       representation="cells", pressure=1.0, velocity=v) for i in range(n + 1)]
    what = "uniform flow, " + {"pure": "one gas", "mixed": "two gases in half-cell stripes, every cell mixed",
                               "boxes": f"four gases in the {layout}' boxes"}[case]
    scene = Scene(2, Grid([0, 0], [1, 1], [n, n], WALLS), mats, bodies, Run(t_end=10.0, cfl=0.4)).validate()
# the remap's flux phase per cell and sweep (its log event; scripts/bench sets
# it beside the stripped sweep of scripts/sweep_floor.c)
PETSc.Log.begin()
best = None
grown = None
for _ in range(reps):
    rss0 = resident_bytes()
    m = core.initialize(scene, comm=PETSc.COMM_SELF) if apart else core.initialize(scene)
    S = core.make_solver(m)
    for _ in range(5):
        S.step()
    # what the scene's arrays hold: the process's resident growth over the
    # first run's setup and warm-up (every array of the step exists after its
    # first step; the huge pages' advice, memory.c, has run), per cell of the
    # rank that grew most
    if grown is None:
        grown = mpi.allreduce((resident_bytes() - rss0) / (n * n / comm.getSize()), op=MPI.MAX)
    t = timed_steps(S, steps, mpi)
    best = t if best is None else min(best, t)
rate = n * n * steps / best / comm.getSize()
if comm.getRank() == 0:
    print(f"cells benchmark ({what}, {n}^2 cells, {steps} steps, best of {reps} runs): {comm.getSize()} rank(s)")
    print(f"  {best:.3f} s: {rate / 1e6:.3f} M cell-updates/s/core, t = {S.time:.4f}")
    print(f"BENCH cells_{tag}_{n}_{comm.getSize()} {rate:.6e}")
    print(f"  resident growth over setup and warm-up: {grown:.0f} bytes per cell, {grown * n * n / comm.getSize() / 2**20:.1f} MiB per rank")
    print(f"BENCH cells_bytes_per_cell_{tag}_{n}_{comm.getSize()} {grown:.6e}")
flux = PETSc.Log.Event("PSCellsFlux").getPerfInfo()
behind = PETSc.Log.Event("PSCellsKEBehind").getPerfInfo()  # (the KE fix behind the cells' update, inside PSCellsFlux)
# (the sweeps: PSCellsHalo's count, once at each sweep's end; PSCellsFlux
# counts the units the first sweep runs behind the Lagrangian phase too)
nsweep = PETSc.Log.Event("PSCellsHalo").getPerfInfo()["count"]
ns = mpi.allreduce(flux["time"] - behind["time"], op=MPI.MAX) / max(nsweep, 1) / (n * n / comm.getSize()) * 1e9
if comm.getRank() == 0:
    print(f"  the remap's flux phase: {ns:.1f} ns per cell and sweep ({nsweep} sweeps)")
    print(f"BENCH cells_flux_ns_{tag}_{n}_{comm.getSize()} {ns:.6e}")
# where a cell-update's time goes: each phase's log event (the slowest rank's
# time, warm-up steps and every run included) in ns per cell and step, so the
# phases can be set beside the time a target rate leaves for a whole step
# (2x PyClaw's rate: 1e9 / (2 rate) ns).  At 128^2 the arrays (about 10 MB)
# sit in the caches, and the rate no longer depends on the size (one gas: the
# same from 64^2 to 256^2), so that size's figures are the phases' arithmetic
# (PSCellsKEBehind, the KE fix's units run behind the cells' update where
# they can, lies inside PSCellsFlux: the remap's rows take its time from the
# one and give it to the other).  Each phase: its label, its BENCH key's
# event, and the events whose times it adds and subtracts
phases = [(label, ev, [ev], []) for label, ev in CELL_PHASES + [("remap", "PSCellsRemap"), ("nodal velocities", "PSCellsPrep")]]
phases += [("fractions+faces+cells", "PSCellsFlux", ["PSCellsFlux"], ["PSCellsKEBehind"]),
           ("halo+masses", "PSCellsHalo", ["PSCellsHalo"], []),
           ("KE fix", "PSCellsKE", ["PSCellsKE", "PSCellsKEBehind"], [])]
nstep = max(PETSc.Log.Event("PSTimeStep").getPerfInfo()["count"], 1)  # (once a step; PSCellsRemap is also logged at each unit run behind the Lagrangian phase)
parts = []
for label, ev, plus, minus in phases:
    tt = sum(PETSc.Log.Event(e).getPerfInfo()["time"] for e in plus) - sum(PETSc.Log.Event(e).getPerfInfo()["time"] for e in minus)
    t = mpi.allreduce(tt, op=MPI.MAX) / nstep / (n * n / comm.getSize()) * 1e9
    parts.append(f"{label} {t:.1f}")
    if comm.getRank() == 0:
        print(f"BENCH cells_phase_ns_{ev}_{tag}_{n}_{comm.getSize()} {t:.6e}")
if comm.getRank() == 0:
    print(f"  ns per cell-update by phase (remap = nodal velocities + fractions+faces+cells + halo+masses + KE fix): {', '.join(parts)}")
