"""Verification: error against run time (work-precision), the insertion
study, and the Taylor bar.  SI units.  `plyshock verify` (scripts/verify) runs
the default studies; --taylor adds the long one.

Shock problems (exact piecewise-constant velocity profiles, uniaxial-strain
strip, symmetry faces on the sides), finer grids for each shape function:

  plate   hydrodynamic copper onto copper at 500 m/s (Mie-Grueneisen, Steinberg):
          u_p = 250 m/s behind shocks running at Us = c0 + s u_p = 4312 m/s
          relative to the material ahead of them; t = 1 us.
  wave    a 1 m/s velocity step in an elastic strip (E 200 GPa, nu 0.3,
          rho 7800): fronts at c = sqrt((lambda + 2 mu)/rho) both ways,
          0.5 m/s between them; t = 1.5 us.

  For each run: the L1 error of the marker velocities against the exact
  profile at their positions, sum |v_p - v(x_p)| l_p / (jump * length), and
  the plateau error |median(v) - v_plateau| / v_plateau away from the fronts;
  the wall time; the observed order between successive grids.

Smooth problem (the design order; after Steffen, Kirby & Berzins, CMES 2008):

  vibration  the first axial mode of a free-free elastic bar (the wave
          problem's material, length 20 mm, a strip in uniaxial strain inside a
          larger grid): v(x, t) = v0 cos(pi x'/L) cos(pi c t/L), v0 1 mm/s,
          after half a period; RMS marker velocity error / v0.

Insertion (the paper's claim, exact against the lattice fill of other MPM
codes): oblique laminates whose plies are several cells down to a fraction
of a cell thick, wholly inside the grid so each ply's area and centroid are
known exactly; per-ply mass and centroid errors, ply-cell pairs with no marker,
marker count, memory (markers x the code's bytes per marker) and insertion
time, exact (subdivision 1, 2) against lattice (points_per_cell 1 ... 8); then
a downstream error: a plane elastic pulse through an oblique [0/90]2s IM7/8552
laminate in epoxy, arrival time and transmitted velocity at a gauge behind the
plies against a fine exact run, exact and lattice at like marker counts.

Taylor bar (--taylor): plyshock's copper Taylor bar against the independent
axisymmetric Lagrangian solution of the same model (taylor_rz.py), the
verdict (within 2% in length and 3% in foot diameter at plyshock's finest,
converged resolution) and, for each flow-stress model (Johnson-Cook,
Zerilli-Armstrong, MTS), both against the 1983 test.

    mpiexec -n 2 plyshock verify [-o out/verify] [--levels 4] [--docs docs] [--only ...] [--taylor [CELL ...]]
"""
import csv
import os
import time

import numpy as np

from .scene import Body, Box, Contact, Frame, Grid, Laminate, Material, Run, Scene

BONDED = Contact(type="bonded")   # the studies measure the transfers: bodies in one velocity field (docs/contact.md)

CU = dict(rho=8930.0, c0=3940.0, s=1.489, gamma0=2.02)
EL = dict(E=200e9, nu=0.3, rho=7800.0)
LENGTH = 0.02


def _strip(h, bodies, materials, run, width=2):
    cells = [round(LENGTH / h), width]
    return Scene(2, Grid([0.0, 0.0], [LENGTH, width * h], cells,
                         {"x-": "free", "x+": "free", "y-": "symmetry", "y+": "symmetry"}), materials, bodies, run,
                 contact=BONDED).validate()


def plate_problem(h, shape):
    t = 1.0e-6
    W = 2 * h
    mat = Material("cu", density=CU["rho"], eos={"type": "mie-gruneisen", "c0": CU["c0"], "s": CU["s"], "gamma0": CU["gamma0"]})
    scene = _strip(h, [Body("flyer", box=Box([0.002, 0], [0.007, W]), material="cu", velocity=[500.0, 0], subdivision=2),
                       Body("target", box=Box([0.007, 0], [0.017, W]), material="cu", subdivision=2)],
                   [mat], Run(t_end=t, shape=shape, history_interval=100000))
    up = 250.0
    Us = CU["c0"] + CU["s"] * up

    def exact(x):
        xl = 0.007 + (500.0 - Us) * t          # shock into the flyer (lab frame)
        xr = 0.007 + Us * t                     # shock into the target
        return np.where(x < xl, 500.0, np.where(x < xr, up, 0.0))

    def plateau(x):
        return (x > 0.007 + (500.0 - Us) * t + 6 * h) & (x < 0.007 + Us * t - 6 * h)
    return scene, t, exact, plateau, up, 0.015


def wave_problem(h, shape):
    t = 1.5e-6
    E, nu, rho = EL["E"], EL["nu"], EL["rho"]
    c = np.sqrt(E * (1 - nu) / ((1 + nu) * (1 - 2 * nu) * rho))
    mat = Material("el", density=rho, elastic={"type": "isotropic", "E": E, "nu": nu})
    W = 2 * h
    scene = _strip(h, [Body("left", box=Box([0.0, 0], [0.01, W]), material="el", velocity=[1.0, 0], subdivision=2),
                       Body("right", box=Box([0.01, 0], [0.02, W]), material="el", subdivision=2)],
                   [mat], Run(t_end=t, shape=shape, history_interval=100000, artificial_viscosity={"c_linear": 0.0, "c_quadratic": 0.0}))

    def exact(x):
        return np.where(x < 0.01 - c * t, 1.0, np.where(x < 0.01 + c * t, 0.5, 0.0))

    def plateau(x):
        return (x > 0.01 - c * t + 6 * h) & (x < 0.01 + c * t - 6 * h)
    return scene, t, exact, plateau, 0.5, LENGTH


PROBLEMS = {"plate": plate_problem, "wave": wave_problem}


def run_one(problem, h, shape):
    """One run in process (all ranks): (L1 error, plateau error, wall s, markers, steps)."""
    from petsc4py import PETSc
    from . import core
    scene, t_end, exact, plateau, v_plat, L = PROBLEMS[problem](h, shape)
    comm = PETSc.COMM_WORLD.tompi4py()
    comm.Barrier()
    w0 = time.perf_counter()
    m = core.initialize(scene)
    S = core.make_solver(m)
    while S.time < t_end * (1 - 1e-12):
        S.step()
    comm.Barrier()
    wall = time.perf_counter() - w0
    f = core.local_fields(m, ["x", "v", "volume"])
    x, v = f["x"][:, 0], f["v"][:, 0]
    W = scene.grid.upper[1] - scene.grid.lower[1]
    l1 = comm.allreduce(float(np.sum(np.abs(v - exact(x)) * f["volume"][:, 0] / W)))
    sel = plateau(x)
    vals = np.concatenate(comm.allgather(v[sel]))      # the plateau's velocities only (a few hundred)
    plat = abs(np.median(vals) - v_plat) / v_plat
    jump = v_plat if problem == "plate" else 0.5
    return l1 / (jump * L), plat, wall, m.stats["markers"], S.step_count


TAYLOR = dict(L0=25.4e-3, D0=7.62e-3, v=190.0, L=16.21e-3, D=13.56e-3)   # Johnson & Cook 1983


def taylor(cell=0.5e-3, shape="gimp", subdivision=2, fbar=True, t_end=80e-6, transfer="musl", material="OFHC-copper"):
    """The copper Taylor bar (3D quarter model against a rigid frictionless wall;
    material: a copper preset, i.e. its flow-stress model):
    final length and foot diameter after 80 us, and their errors against the
    measured 16.21 mm and 13.56 mm (Johnson & Cook 1983).  fbar: cell-averaged
    volumetric rate against locking (under musl with a 5% PIC share, which keeps
    its zero-energy modes from growing under FLIP; apic needs bspline2)."""
    from .scene import Cylinder
    T = TAYLOR
    side = 9e-3
    scene = Scene(3, Grid([0, 0, 0], [side, side, 26e-3], [round(side / cell), round(side / cell), round(26e-3 / cell)],
                          {"x-": "symmetry", "y-": "symmetry", "z-": "symmetry"}),
                  [Material("cu", preset=material)],
                  [Body("bar", cylinder=Cylinder([0, 0, 0], [0, 0, 1], T["D0"] / 2, T["L0"]), material="cu",
                        velocity=[0, 0, -T["v"]], subdivision=subdivision)],
                  Run(t_end=t_end, shape=shape, transfer=transfer, history_interval=100000, fbar=fbar,
                      pic_fraction=0.05 if fbar and transfer == "musl" else 0.0)).validate()
    return _bar_run(scene, t_end, cell, axisymmetric=False)


def taylor_axi(cell=0.5e-3, shape="bspline2", subdivision=2, fbar=True, t_end=80e-6, material="OFHC-copper", pic_fraction=0.01):
    """The same copper Taylor bar as taylor() in axisymmetric 2D (geometry:
    axisymmetric; the bar a box in r-z, the axis a symmetry face, the wall
    z = 0 a symmetry face): MUSL (axisymmetric runs have no apic) with
    quadratic B-splines, F-bar and a 1% PIC share (the least that keeps
    FLIP's noise down: with none 0.9% of the kinetic energy is left at 80 us
    against 0.02%; a 5% share, the 3D musl bar's, damps the foot: 12.88 mm
    against 13.78 mm at 0.5 mm).  Final length and foot diameter after t_end,
    measured as in taylor() with the marker's half size from its section
    area V / (2 pi r)."""
    T = TAYLOR
    side = 9e-3
    scene = Scene(2, Grid([0, 0], [side, 26e-3], [round(side / cell), round(26e-3 / cell)], {"x-": "symmetry", "y-": "symmetry"}),
                  [Material("cu", preset=material)],
                  [Body("bar", box=Box([0.0, 0.0], [T["D0"] / 2, T["L0"]]), material="cu", velocity=[0, -T["v"]],
                        subdivision=subdivision)],
                  Run(t_end=t_end, shape=shape, transfer="musl", history_interval=100000, fbar=fbar,
                      pic_fraction=pic_fraction), geometry="axisymmetric").validate()
    return _bar_run(scene, t_end, cell, axisymmetric=True)


def _bar_run(scene, t_end, cell, axisymmetric):
    """Run a Taylor-bar scene to t_end and measure it: final length (top less
    the bottom, which may rebound off the frictionless wall) and foot diameter
    (the widest marker within a cell of the bottom), each marker with its half
    size a (3D: from its volume; axisymmetric: from its section area
    V / (2 pi r)); errors against the 1983 test, wall time, kinetic energy left."""
    from petsc4py import PETSc
    from . import core
    T = TAYLOR
    comm = PETSc.COMM_WORLD.tompi4py()
    w0 = time.perf_counter()
    m = core.initialize(scene)
    S = core.make_solver(m)
    ke0 = S.totals()["kinetic"]
    while S.time < t_end * (1 - 1e-12):
        S.step()
    wall = time.perf_counter() - w0
    f = core.local_fields(m, ["x", "volume"])
    x, V = f["x"], f["volume"][:, 0]
    if axisymmetric:
        a, z, r = 0.5 * np.sqrt(V / (2 * np.pi * np.maximum(x[:, 0], 1e-30))), x[:, 1], x[:, 0]
    else:
        a, z, r = 0.5 * np.cbrt(V), x[:, 2], np.hypot(x[:, 0], x[:, 1])
    top = comm.allreduce(float((z + a).max()) if len(x) else 0.0, op=max_op())
    bottom = max(0.0, -comm.allreduce(float(-(z - a).min()) if len(x) else -1e30, op=max_op()))
    top -= bottom
    foot = z < bottom + cell
    rf = comm.allreduce(float((r[foot] + a[foot]).max()) if foot.any() else 0.0, op=max_op())
    return dict(length=top, diameter=2 * rf, err_length=top / T["L"] - 1, err_diameter=2 * rf / T["D"] - 1, wall_s=wall,
                kinetic_left=S.totals()["kinetic"] / ke0, markers=m.stats["markers"], steps=S.step_count)


def max_op():
    from mpi4py import MPI
    return MPI.MAX



# ----------------------------------------------------------- smooth problem --
VIB = dict(L=0.02, v0=1.0e-3, pad=4)          # bar length (m), velocity amplitude (m/s), cells of grid either side
VIB_CELLS = (20, 40, 80, 160, 320)             # cells along the bar
VIB_CASES = (("linear", "musl"), ("gimp", "musl"), ("bspline2", "musl"), ("bspline2", "apic"))


def vibration_problem(n, shape, transfer="musl"):
    """The first axial mode of a free-free bar, n cells long, after half a period."""
    E, nu, rho = EL["E"], EL["nu"], EL["rho"]
    c = np.sqrt(E * (1 - nu) / ((1 + nu) * (1 - 2 * nu) * rho))
    L, pad = VIB["L"], VIB["pad"]
    h = L / n
    a = pad * h
    t = L / c                                              # half a period 2L/c
    scene = Scene(2, Grid([0.0, 0.0], [L + 2 * a, 2 * h], [n + 2 * pad, 2],
                          {"x-": "free", "x+": "free", "y-": "symmetry", "y+": "symmetry"}),
                  [Material("el", density=rho, elastic={"type": "isotropic", "E": E, "nu": nu})],
                  [Body("bar", box=Box([a, 0.0], [a + L, 2 * h]), material="el", subdivision=2)],
                  Run(t_end=t, shape=shape, transfer=transfer, history_interval=10**6,
                      artificial_viscosity={"c_linear": 0.0, "c_quadratic": 0.0})).validate()

    def exact(x, time):
        return VIB["v0"] * np.cos(np.pi * (x - a) / L) * np.cos(np.pi * c * time / L)
    return scene, t, exact


def run_vibration(n, shape, transfer="musl"):
    """(RMS velocity error / v0, wall s, markers, steps) of one run, all ranks."""
    from petsc4py import PETSc
    from . import core
    scene, t_end, exact = vibration_problem(n, shape, transfer)
    comm = PETSc.COMM_WORLD.tompi4py()
    comm.Barrier()
    w0 = time.perf_counter()
    m = core.initialize(scene)
    x = m.sw.getField("x").reshape(-1, 2)
    v = m.sw.getField("v").reshape(-1, 2)
    v[:, 0], v[:, 1] = exact(x[:, 0], 0.0), 0.0               # the mode, at rest in stress
    m.sw.restoreField("v")
    m.sw.restoreField("x")
    S = core.make_solver(m)
    while S.time < t_end * (1 - 1e-12):
        S.step()
    comm.Barrier()
    wall = time.perf_counter() - w0
    f = core.local_fields(m, ["x", "v"])
    e2 = comm.allreduce(float(np.sum((f["v"][:, 0] - exact(f["x"][:, 0], S.time)) ** 2)))
    return np.sqrt(e2 / m.stats["markers"]) / VIB["v0"], wall, m.stats["markers"], S.step_count


def vibration_study(print0):
    rows = []
    for shape, transfer in VIB_CASES:
        for n in VIB_CELLS:
            err, wall, nm, steps = run_vibration(n, shape, transfer)
            rows.append(dict(shape=shape, transfer=transfer, cells=n, h=VIB["L"] / n, markers=nm, steps=steps, wall_s=wall, rms=err))
            print0(f"vibration {shape:8s} {transfer:4s} {n:4d} cells  markers {nm:6d}  steps {steps:5d}  wall {wall:6.2f} s  RMS {err:.3e}")
    return rows


def observed_orders(err, h):
    """Orders between successive grids and the least-squares slope over all."""
    err, h = np.asarray(err, float), np.asarray(h, float)
    pair = np.log(err[:-1] / err[1:]) / np.log(h[:-1] / h[1:])
    fit = np.polyfit(np.log(h), np.log(err), 1)[0]
    return pair, fit


# ---------------------------------------------------------- insertion study --
INSERT = {2: dict(cells=100, size=0.02, layup="[0/45/90/-45]s", thick=(4.0, 1.0, 0.25), lattice=(1, 2, 4, 8), exact=(1, 2)),
          3: dict(cells=24, size=0.012, layup="[0/90]s", thick=(2.0, 0.5), lattice=(1, 2, 3), exact=(1, 2))}


def insertion_scene(dim, t_cells, insertion, n):
    """An oblique laminate wholly inside the grid (so every ply's exact area or
    volume and centroid are known), plies t_cells cells thick."""
    P = INSERT[dim]
    h = P["size"] / P["cells"]
    t = t_cells * h
    from .layup import parse_layup
    nply = len(parse_layup(P["layup"], "layup"))
    if dim == 2:
        # a generic angle and length (a lattice-aligned one, 30 deg and a whole number
        # of cells, can make the lattice's ply areas right by coincidence)
        e3 = np.array([np.cos(np.radians(27.3)), np.sin(np.radians(27.3))])
        e1 = np.array([e3[1], -e3[0]])
        size = [0.587 * P["size"]]
        c = np.full(2, 0.5 * P["size"])
        o = c - 0.5 * size[0] * e1 - 0.5 * nply * t * e3
        frame = Frame(o.tolist(), (o + 1e-3 * e3).tolist(), (o + 1e-3 * e1).tolist())
    else:
        e3 = np.array([0.3, 0.5, 0.81]) / np.linalg.norm([0.3, 0.5, 0.81])
        e1 = np.cross([0.0, 0.0, 1.0], e3)
        e1 /= np.linalg.norm(e1)
        e2 = np.cross(e3, e1)
        size = [0.487 * P["size"], 0.513 * P["size"]]
        c = np.full(3, 0.5 * P["size"])
        o = c - 0.5 * size[0] * e1 - 0.5 * size[1] * e2 - 0.5 * nply * t * e3
        frame = Frame(o.tolist(), (o + 1e-3 * e3).tolist(), (o + 1e-3 * e1).tolist())
    lam = Laminate.from_layup(frame, size, P["layup"], t, "cfrp")
    kw = {"points_per_cell": n} if insertion == "lattice" else {"subdivision": n}
    cfrp = Material("cfrp", density=1570.0, elastic=dict(_ply_elastic()))
    return Scene(dim, Grid([0.0] * dim, [P["size"]] * dim, [P["cells"]] * dim), [cfrp],
                 [Body("plate", laminate=lam, insertion=insertion, **kw)]).validate()


def _ply_elastic():
    from .materials import PRESETS
    return PRESETS["IM7/8552"]["elastic"]


def insertion_errors(scene, m, exact_pairs=None):
    """Per-ply mass and centroid errors against the plies' exact area/volume and
    centroid, the (cell, ply) pairs that hold markers, and how many of the exact
    insertion's pairs have none here."""
    from . import core
    dim, b = scene.dimension, scene.bodies[0]
    E = np.asarray(b._axes)
    axes = [E[0], E[2]] if dim == 2 else [E[0], E[1], E[2]]
    o = np.array(b.laminate.frame.origin)
    lat = list(b.laminate.size)
    f = core.local_fields(m, ["x", "mass", "ply"])
    comm = m.sw.getComm().tompi4py()
    nply = len(b._z) - 1
    M = np.zeros(nply)
    Mx = np.zeros((nply, dim))
    np.add.at(M, f["ply"][:, 0], f["mass"][:, 0])
    np.add.at(Mx, f["ply"][:, 0], f["mass"][:, :1] * f["x"])
    M, Mx = comm.allreduce(M), comm.allreduce(Mx)
    rho = scene.materials[0].density
    h = np.array(scene.grid.h)
    mass_err, cen_err = [], []
    for k in range(nply):
        t = b._z[k + 1] - b._z[k]
        V = float(np.prod(lat)) * t
        cen = o + sum(0.5 * L * a[:dim] for L, a in zip(lat, axes[:-1])) + 0.5 * (b._z[k] + b._z[k + 1]) * axes[-1][:dim]
        mass_err.append(abs(M[k] - rho * V) / (rho * V))
        cen_err.append(np.linalg.norm(Mx[k] / M[k] - cen) / h.max() if M[k] > 0 else np.inf)
    cells = np.floor((f["x"] - np.array(scene.grid.lower)) / h).astype(np.int64)
    key = cells[:, 0] + scene.grid.cells[0] * (cells[:, 1] + (scene.grid.cells[1] * cells[:, 2] if dim == 3 else 0))
    key = key * (nply + 1) + f["ply"][:, 0]
    pairs = np.unique(np.concatenate(comm.allgather(np.unique(key))))
    missing = 0.0 if exact_pairs is None else 1.0 - np.isin(exact_pairs, pairs).sum() / len(exact_pairs)
    return max(mass_err), max(cen_err), pairs, missing


def insertion_seconds():
    """This rank's time so far in the insertion's log events (s)."""
    from petsc4py import PETSc
    return sum(PETSc.Log.Event(e).getPerfInfo()["time"] for e in ("PSInsertPieces", "PSInsertFill"))


def insertion_study(print0):
    from petsc4py import PETSc
    from . import core
    comm = PETSc.COMM_WORLD.tompi4py()
    PETSc.Log.begin()
    rows = []
    for dim, P in INSERT.items():
        for tc in P["thick"]:
            exact_pairs = None
            for insertion, ns in (("exact", P["exact"]), ("lattice", P["lattice"])):
                for n in ns:
                    scene = insertion_scene(dim, tc, insertion, n)
                    best = np.inf
                    for _ in range(3):
                        # insertion time: the kernel and the swarm fill (log events PSInsertPieces,
                        # PSInsertFill) on the slower rank, the best of three
                        t0 = insertion_seconds()
                        m = core.initialize(scene)
                        best = min(best, comm.allreduce(insertion_seconds() - t0, op=max_op()))
                    me, ce, pairs, missing = insertion_errors(scene, m, exact_pairs)
                    if insertion == "exact" and n == 1:
                        exact_pairs = pairs
                    nm = m.stats["markers"]
                    rows.append(dict(dim=dim, ply_cells=tc, insertion=insertion, n=n, markers=nm,
                                     bytes=nm * m.bytes_per_marker, bytes_per_marker=m.bytes_per_marker, time_s=best,
                                     mass_err=me, centroid_err_cells=ce, missing_pairs=missing))
                    print0(f"insertion {dim}D plies {tc:5.2f} cells  {insertion:7s} n {n}  markers {nm:8d}  "
                           f"{nm * m.bytes_per_marker / 2**20:8.2f} MiB  {1e3 * best:8.3f} ms  ply mass error {me:.2e}  "
                           f"centroid error {ce:.2e} h  ply-cell pairs without a marker {100 * missing:5.1f}%")
    return rows


# -------------------------------------------- downstream: a wave through plies --
LW = dict(W=2.0e-3, LX=8.0e-3, theta=30.0, tply=0.15e-3, layup="[0/90]2s", v=20.0, gauge=6.0e-3, t_end=3.2e-6,
          face=2.5e-3, flyer=1.0e-3)
EPOXY = dict(E=4.5e9, nu=0.35, rho=1198.0)     # a representative epoxy (isotropic, linear elastic)
LW_RUNS = [(h, ins, n) for h in (0.4e-3, 0.2e-3, 0.1e-3) for ins, n in (("exact", 1), ("exact", 2), ("lattice", 1), ("lattice", 2), ("lattice", 3))]
LW_REFERENCE = (0.05e-3, "exact", 2)


def laminate_wave_scene(h, insertion, n):
    """A 20 m/s epoxy flyer onto epoxy holding an oblique [0/90]2s IM7/8552
    laminate (0.15 mm plies, stacking axis 30 deg from x, no failure), in a strip
    with symmetry faces; a gauge in the epoxy behind the plies."""
    W, th = LW["W"], np.radians(LW["theta"])
    e3 = np.array([np.cos(th), np.sin(th)])
    e1 = np.array([e3[1], -e3[0]])
    L1 = 2 * W / np.cos(th) + 2e-3                     # long enough to cross the strip: clipped by its faces
    o = np.array([LW["face"], W / 2]) - 0.5 * L1 * e1
    lam = Laminate.from_layup(Frame(o.tolist(), (o + 1e-3 * e3).tolist(), (o + 1e-3 * e1).tolist()), [L1], LW["layup"],
                              LW["tply"], "cfrp")
    kw = dict(insertion=insertion, **({"points_per_cell": n} if insertion == "lattice" else {"subdivision": n}))
    mats = [Material("cfrp", density=1570.0, elastic=dict(_ply_elastic())),
            Material("epoxy", density=EPOXY["rho"], elastic={"type": "isotropic", "E": EPOXY["E"], "nu": EPOXY["nu"]})]
    bodies = [Body("flyer", box=Box([0.0, 0.0], [LW["flyer"], W]), material="epoxy", velocity=[LW["v"], 0.0], **kw),
              Body("matrix", box=Box([LW["flyer"], 0.0], [LW["LX"], W]), material="epoxy", **kw),
              Body("plies", laminate=lam, priority=1, clip=True, **kw)]
    return Scene(2, Grid([0.0, 0.0], [LW["LX"], W], [round(LW["LX"] / h), round(W / h)], {"y-": "symmetry", "y+": "symmetry"}),
                 mats, bodies, Run(t_end=LW["t_end"], history_interval=1, progress_interval=10**9,
                                   artificial_viscosity={"c_linear": 0.0, "c_quadratic": 0.0}),
                 gauges=[{"name": "behind", "point": [LW["gauge"], W / 2]}], contact=BONDED).validate()


def run_scratch(scene, read, workdir=None):
    """Run scene to its t_end with its outputs into a scratch directory (under
    workdir, or the system's), timed on every rank between barriers; read(dir)
    on rank 0 after the run, its result broadcast; the directory removed.
    Returns (that result, wall s, the markers' state m, the solver S)."""
    import shutil
    import tempfile
    from petsc4py import PETSc
    from . import core
    comm = PETSc.COMM_WORLD.tompi4py()
    if comm.rank == 0 and workdir:
        os.makedirs(workdir, exist_ok=True)
    d = comm.bcast(tempfile.mkdtemp(dir=workdir, prefix="plyshock-") if comm.rank == 0 else None, root=0)
    comm.Barrier()
    w0 = time.perf_counter()
    m = core.initialize(scene)
    S = core.make_solver(m)
    core.run(m, d, scene.to_yaml(), S)
    comm.Barrier()
    wall = time.perf_counter() - w0
    res = None
    if comm.rank == 0:
        res = read(d)
        shutil.rmtree(d, ignore_errors=True)
    return comm.bcast(res, root=0), wall, m, S


def run_laminate_wave(h, insertion, n, workdir):
    """(gauge time, vx, x, wall s, markers) of one run."""
    def gauge(d):
        g = np.genfromtxt(os.path.join(d, "gauges.csv"), delimiter=",", names=True)
        return g["time"], g["vx"], g["x"]
    (t, v, x), wall, m, _ = run_scratch(laminate_wave_scene(h, insertion, n), gauge, workdir)
    return t, v, x, wall, m.stats["markers"]


def gauge_measures(t, v, x, v_half):
    """Arrival: the first time the gauge passes v_half (interpolated), moved by
    the gauge marker's offset from the gauge point at the epoxy's wave speed;
    transmitted displacement: how far the gauge has moved at t_end (m), the
    pulse's whole passage (the flyer's 0.8 us pulse has passed, the back
    face's reflection not yet come back)."""
    E, nu, rho = EPOXY["E"], EPOXY["nu"], EPOXY["rho"]
    c = np.sqrt(E * (1 - nu) / ((1 + nu) * (1 - 2 * nu) * rho))
    k = int(np.argmax(v >= v_half))
    ta = t[k - 1] + (v_half - v[k - 1]) * (t[k] - t[k - 1]) / (v[k] - v[k - 1])
    return ta - (x[0] - LW["gauge"]) / c, float(x[-1] - x[0])


def laminate_wave_study(print0, workdir):
    os.makedirs(workdir, exist_ok=True)
    t, v, x, wall, nm = run_laminate_wave(*LW_REFERENCE, workdir)
    v_half = 0.5 * np.max(v)
    ta_ref, u_ref = gauge_measures(t, v, x, v_half)
    print0(f"laminate wave reference (h {LW_REFERENCE[0] * 1e3:.3f} mm, {LW_REFERENCE[1]} {LW_REFERENCE[2]}, {nm} markers, "
           f"{wall:.1f} s): arrival {ta_ref * 1e6:.4f} us, transmitted displacement {u_ref * 1e6:.4f} um")
    rows = [dict(h=LW_REFERENCE[0], insertion=LW_REFERENCE[1], n=LW_REFERENCE[2], markers=nm, wall_s=wall, arrival_s=ta_ref,
                 displacement=u_ref, arrival_err=0.0, displacement_err=0.0, reference=1)]
    # the runs, and the lattice at the reference's own grid (the insertion's share of the reference)
    for h, ins, n in LW_RUNS + [(LW_REFERENCE[0], "lattice", LW_REFERENCE[2])]:
        t, v, x, wall, nm = run_laminate_wave(h, ins, n, workdir)
        ta, u = gauge_measures(t, v, x, v_half)
        rows.append(dict(h=h, insertion=ins, n=n, markers=nm, wall_s=wall, arrival_s=ta, displacement=u,
                         arrival_err=abs(ta - ta_ref) / ta_ref, displacement_err=abs(u - u_ref) / u_ref,
                         reference=2 if h == LW_REFERENCE[0] else 0))
        print0(f"laminate wave h {h * 1e3:.3f} mm ({LW['tply'] / h:4.2f} cells per ply) {ins:7s} n {n}  markers {nm:6d}  "
               f"wall {wall:6.2f} s  arrival {ta * 1e6:.4f} us (error {100 * rows[-1]['arrival_err']:.2f}%)  "
               f"displacement {u * 1e6:.4f} um (error {100 * rows[-1]['displacement_err']:.2f}%)")
    return rows


# --------------------------------------------------------------- the Taylor bar --
TAYLOR_MODELS = (("Johnson-Cook", "OFHC-copper"), ("Zerilli-Armstrong", "OFHC-copper-ZA"), ("MTS", "OFHC-copper-MTS"))
TAYLOR_CRITERION = dict(length=0.02, diameter=0.03)   # plyshock against taylor_rz (the same model), at plyshock's finest grid
TAYLOR_REFERENCE_ZONES = (24, 160)                     # taylor_rz's finest (its length changes 0.3% from 16 x 107)


def taylor_study(cells, print0, models=TAYLOR_MODELS):
    """The bar by plyshock at each cell size for each model, the same model by
    taylor_rz; the verdict for Johnson-Cook at the finest cell."""
    from petsc4py import PETSc
    from . import taylor_rz
    comm = PETSc.COMM_WORLD.tompi4py()
    cells = sorted(cells, reverse=True)
    # the references: each rank solves some of the models (numpy, serial), then all share them
    mine = {}
    for k, (name, preset) in enumerate(models):
        if k % comm.size == comm.rank:
            w0 = time.perf_counter()
            mine[name] = dict(taylor_rz.solve(*TAYLOR_REFERENCE_ZONES, material=preset), wall_s=time.perf_counter() - w0)
    ref = {}
    for d in comm.allgather(mine):
        ref.update(d)
    rows = []
    T = TAYLOR
    for name, preset in models:
        r = ref[name]
        print0(f"Taylor bar, {name} ({preset}): axisymmetric Lagrangian reference ({r['zones']} zones, {r['wall_s']:.0f} s): "
               f"length {r['length'] * 1e3:.2f} mm, foot {r['diameter'] * 1e3:.2f} mm")
        for cell in cells:
            tb = taylor(cell, shape="bspline2", transfer="apic", material=preset)
            row = dict(model=name, preset=preset, cell=cell, markers=tb["markers"], steps=tb["steps"], wall_s=tb["wall_s"],
                       length=tb["length"], diameter=tb["diameter"], kinetic_left=tb["kinetic_left"],
                       ref_length=r["length"], ref_diameter=r["diameter"], ref_zones=r["zones"],
                       vs_ref_length=tb["length"] / r["length"] - 1, vs_ref_diameter=tb["diameter"] / r["diameter"] - 1,
                       vs_test_length=tb["length"] / T["L"] - 1, vs_test_diameter=tb["diameter"] / T["D"] - 1,
                       ref_vs_test_length=r["length"] / T["L"] - 1, ref_vs_test_diameter=r["diameter"] / T["D"] - 1)
            rows.append(row)
            print0(f"  plyshock {cell * 1e3:.3f} mm cells ({tb['markers']} markers, {tb['steps']} steps, {tb['wall_s']:.0f} s): "
                   f"length {tb['length'] * 1e3:.2f} mm, foot {tb['diameter'] * 1e3:.2f} mm; against the reference "
                   f"{100 * row['vs_ref_length']:+.1f}% / {100 * row['vs_ref_diameter']:+.1f}%; against the test "
                   f"{100 * row['vs_test_length']:+.1f}% / {100 * row['vs_test_diameter']:+.1f}%")
    return rows


def taylor_report(rows):
    """The table (one row per model at the finest cell) and the verdict lines."""
    finest = min(r["cell"] for r in rows)
    out = [f"Taylor bar against the 1983 test (16.21 mm, 13.56 mm) and against the same model's axisymmetric reference, "
           f"plyshock at {finest * 1e3:.3f} mm cells:",
           "| model | plyshock length, foot (mm) | vs test | reference length, foot (mm) | reference vs test | plyshock vs reference |",
           "|---|---|---|---|---|---|"]
    for r in rows:
        if r["cell"] != finest:
            continue
        out.append(f"| {r['model']} | {r['length'] * 1e3:.2f}, {r['diameter'] * 1e3:.2f} | "
                   f"{100 * r['vs_test_length']:+.1f}%, {100 * r['vs_test_diameter']:+.1f}% | "
                   f"{r['ref_length'] * 1e3:.2f}, {r['ref_diameter'] * 1e3:.2f} | "
                   f"{100 * r['ref_vs_test_length']:+.1f}%, {100 * r['ref_vs_test_diameter']:+.1f}% | "
                   f"{100 * r['vs_ref_length']:+.1f}%, {100 * r['vs_ref_diameter']:+.1f}% |")
    jc = [r for r in rows if r["model"] == "Johnson-Cook"]
    if jc:
        f = min(jc, key=lambda r: r["cell"])
        ok = abs(f["vs_ref_length"]) <= TAYLOR_CRITERION["length"] and abs(f["vs_ref_diameter"]) <= TAYLOR_CRITERION["diameter"]
        conv = ""
        if len(jc) > 1:
            c = sorted(jc, key=lambda r: r["cell"])
            conv = (f"; from {c[1]['cell'] * 1e3:.3f} to {c[0]['cell'] * 1e3:.3f} mm the length changed "
                    f"{100 * (c[0]['length'] / c[1]['length'] - 1):+.1f}% and the foot {100 * (c[0]['diameter'] / c[1]['diameter'] - 1):+.1f}%")
        out.append(f"Verdict (Johnson-Cook, criterion: within {100 * TAYLOR_CRITERION['length']:.0f}% in length and "
                   f"{100 * TAYLOR_CRITERION['diameter']:.0f}% in foot of taylor_rz at plyshock's finest grid, "
                   f"{f['cell'] * 1e3:.3f} mm): {'PASS' if ok else 'FAIL'}: length {100 * f['vs_ref_length']:+.1f}%, "
                   f"foot {100 * f['vs_ref_diameter']:+.1f}%{conv}.  The gap to the test, {100 * f['vs_test_length']:+.1f}% "
                   f"in length and {100 * f['vs_test_diameter']:+.1f}% in foot, is reported, not tuned.")
    return out


# --------------------------------------------------------------------- main --
STUDIES = ("shock", "vibration", "insertion", "laminate", "cells", "contact")


def _write_csv(path, rows):
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)


def main(outdir="out/verify", levels=4, shapes=("linear", "gimp", "bspline2"), taylor_cells=None, docs=None, only=STUDIES):
    """Every study in `only` (and the Taylor bar with taylor_cells); CSVs and
    pictures in outdir, copied to docs when given (scripts/verify: docs/)."""
    from petsc4py import PETSc
    rank = PETSc.COMM_WORLD.getRank()

    def print0(*a):
        if rank == 0:
            print(*a, flush=True)
    if rank == 0:
        os.makedirs(outdir, exist_ok=True)
    PETSc.COMM_WORLD.barrier()
    made = []
    if "shock" in only:
        hs = [100e-6 / 2**k for k in range(levels)]
        rows = []
        for problem in PROBLEMS:
            for shape in shapes:
                for h in hs:
                    l1, plat, wall, n, steps = run_one(problem, h, shape)
                    rows.append(dict(problem=problem, shape=shape, h=h, markers=n, steps=steps, wall_s=wall, L1=l1, plateau=plat))
                    print0(f"{problem:5s} {shape:8s} h {h * 1e6:6.2f} um  markers {n:6d}  steps {steps:5d}  "
                           f"wall {wall:7.2f} s  L1 {l1:.3e}  plateau {plat:.2e}")
        if rank == 0:
            _write_csv(os.path.join(outdir, "verify.csv"), rows)
            orders = plot(rows, os.path.join(outdir, "verify.png"))
            for (problem, shape), p in orders.items():
                print(f"observed L1 order {problem} {shape}: " + ", ".join(f"{x:.2f}" for x in p))
            print("  (discontinuous solutions: first order at best in L1; linear hats add cell-crossing noise, "
                  "and the artificial viscosity spreads the plate's shocks over a few cells)")
        made += ["verify.csv", "verify.png"]
    if "vibration" in only:
        rows = vibration_study(print0)
        if rank == 0:
            _write_csv(os.path.join(outdir, "vibration.csv"), rows)
            for shape, transfer in VIB_CASES:
                rs = [r for r in rows if r["shape"] == shape and r["transfer"] == transfer]
                pair, fit = observed_orders([r["rms"] for r in rs], [r["h"] for r in rs])
                print(f"observed order vibration {shape} {transfer}: " + ", ".join(f"{x:.2f}" for x in pair) + f"; fit {fit:.2f}")
            plot_vibration(rows, os.path.join(outdir, "verify_vibration.png"))
        made += ["vibration.csv", "verify_vibration.png"]
    if "insertion" in only:
        rows = insertion_study(print0)
        if rank == 0:
            _write_csv(os.path.join(outdir, "insertion.csv"), rows)
            plot_insertion(rows, os.path.join(outdir, "insertion.png"))
        made += ["insertion.csv", "insertion.png"]
    if "laminate" in only:
        rows = laminate_wave_study(print0, os.path.join(outdir, "runs"))
        if rank == 0:
            _write_csv(os.path.join(outdir, "laminate_wave.csv"), rows)
            plot_laminate_wave(rows, os.path.join(outdir, "laminate_wave.png"))
        made += ["laminate_wave.csv", "laminate_wave.png"]
    if "cells" in only:
        from . import verify_cells
        rows = verify_cells.cells_study(print0)
        profiles = verify_cells.loaded_profiles()
        if rank == 0:
            _write_csv(os.path.join(outdir, "verify_cells.csv"), rows)
            verify_cells.plot_cells(rows, profiles, os.path.join(outdir, "verify_cells.png"), os.path.join(outdir, "cells_state.png"))
            for prob in ("sod", "disk"):
                rs = [r for r in rows if r["problem"] == prob]
                pair, fit = observed_orders([r["error"] for r in rs], [1.0 / r["size"] for r in rs])
                print(f"observed order {prob}: " + ", ".join(f"{x:.2f}" for x in pair) + f"; fit {fit:.2f}")
        made += ["verify_cells.csv", "verify_cells.png", "cells_state.png"]
    if "contact" in only:
        from . import verify_contact
        rows = verify_contact.contact_study(print0)
        if rank == 0:
            _write_csv(os.path.join(outdir, "verify_contact.csv"), rows)
            verify_contact.plot_contact(rows, os.path.join(outdir, "verify_contact.png"))
        made += ["verify_contact.csv", "verify_contact.png"]
    if taylor_cells:
        rows = taylor_study(taylor_cells, print0)
        if rank == 0:
            _write_csv(os.path.join(outdir, "taylor.csv"), rows)
            for line in taylor_report(rows):
                print(line)
        made += ["taylor.csv"]
    if rank == 0:
        print(f"wrote {', '.join(made)} in {outdir}")
        if docs:
            import shutil
            os.makedirs(docs, exist_ok=True)
            for name in made:
                shutil.copy(os.path.join(outdir, name), os.path.join(docs, name))
            print(f"copied them to {docs}")
    PETSc.COMM_WORLD.barrier()


# ------------------------------------------------------------------- plots --
def _plt():
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt


def plot_vibration(rows, png):
    """The smooth problem: RMS error against wall time and against h, per shape function."""
    plt = _plt()
    fig, ax = plt.subplots(1, 2, figsize=(11, 4.5))
    for shape, transfer in VIB_CASES:
        rs = [r for r in rows if r["shape"] == shape and r["transfer"] == transfer]
        pair, fit = observed_orders([r["rms"] for r in rs], [r["h"] for r in rs])
        lab = f"{shape} ({transfer}), order {pair[-1]:.2f} (fit {fit:.2f})"
        ls = "--" if shape == "gimp" else "-"
        ax[0].loglog([r["wall_s"] for r in rs], [r["rms"] for r in rs], "o" + ls, label=lab)
        ax[1].loglog([r["h"] * 1e3 for r in rs], [r["rms"] for r in rs], "o" + ls, label=lab)
    h = np.array([r["h"] for r in rows if r["shape"] == "linear"]) * 1e3
    e0 = [r["rms"] for r in rows if r["shape"] == "linear"][0]
    ax[1].loglog(h, e0 * (h / h[0]) ** 2, "k:", label="slope 2")
    ax[0].set_xlabel("wall time, 2 ranks (s)")
    ax[1].set_xlabel("cell size h (mm)")
    for a in ax:
        a.set_ylabel("RMS velocity error / v0")
        a.grid(True, which="both", alpha=0.3)
        a.legend(fontsize=8)
    fig.suptitle("vibration of a free-free elastic bar (first axial mode, half a period): smooth, so the design order shows")
    fig.tight_layout()
    fig.savefig(png, dpi=110)
    plt.close(fig)


def plot_insertion(rows, png):
    """Exact against lattice insertion: per-ply mass error, centroid error and
    ply-cell pairs without a marker against memory, and insertion time."""
    plt = _plt()
    dims = sorted({r["dim"] for r in rows})
    fig, ax = plt.subplots(len(dims), 4, figsize=(17, 4.2 * len(dims)), squeeze=False)
    for i, dim in enumerate(dims):
        thick = sorted({r["ply_cells"] for r in rows if r["dim"] == dim}, reverse=True)
        colors = plt.rcParams["axes.prop_cycle"].by_key()["color"]
        for c, tc in zip(colors, thick):
            for ins, mk, ls in (("exact", "s", "--"), ("lattice", "o", "-")):
                rs = [r for r in rows if r["dim"] == dim and r["ply_cells"] == tc and r["insertion"] == ins]
                mem = [r["bytes"] / 2**20 for r in rs]
                lab = f"{ins}, plies {tc:g} cells" + (" (n = " + ",".join(str(r["n"]) for r in rs) + ")" if ins == "lattice" else " (s = " + ",".join(str(r["n"]) for r in rs) + ")")
                ax[i, 0].loglog(mem, [max(r["mass_err"], 1e-16) for r in rs], mk + ls, color=c, label=lab)
                ax[i, 1].loglog(mem, [min(max(r["centroid_err_cells"], 1e-16), 10.0) for r in rs], mk + ls, color=c, label=lab)
                ax[i, 2].semilogx(mem, [100 * r["missing_pairs"] for r in rs], mk + ls, color=c, label=lab)
                ax[i, 3].loglog(mem, [r["time_s"] * 1e3 for r in rs], mk + ls, color=c, label=lab)
        titles = ("largest per-ply mass error (relative)", "largest per-ply centroid error (cells)",
                  "ply-cell pairs with no marker (%)", "insertion time, slower of 2 ranks (ms)")
        for j in range(4):
            ax[i, j].set_title(f"{dim}D: {titles[j]}", fontsize=10)
            ax[i, j].set_xlabel("marker memory (MiB, markers x bytes per marker)")
            ax[i, j].grid(True, which="both", alpha=0.3)
        ax[i, 0].legend(fontsize=7)
    fig.suptitle("exact insertion (squares) against the lattice fill (circles), oblique laminates; exact errors are round-off (floored at 1e-16)")
    fig.tight_layout()
    fig.savefig(png, dpi=100)
    plt.close(fig)


def plot_laminate_wave(rows, png):
    """Downstream: the gauge's arrival time and transmitted displacement errors against wall time."""
    plt = _plt()
    fig, ax = plt.subplots(1, 2, figsize=(12, 4.8))
    runs = [r for r in rows if r["reference"] == 0]
    for ins, n in sorted({(r["insertion"], r["n"]) for r in runs}):
        rs = sorted([r for r in runs if r["insertion"] == ins and r["n"] == n], key=lambda r: -r["h"])
        mk = "s--" if ins == "exact" else "o-"
        lab = f"{ins} {'subdivision' if ins == 'exact' else 'points_per_cell'} {n}"
        for a, key in zip(ax, ("arrival_err", "displacement_err")):
            a.loglog([r["wall_s"] for r in rs], [max(r[key], 1e-5) for r in rs], mk, label=lab)
            for r in rs:
                a.annotate(f"{r['h'] * 1e3:g}", (r["wall_s"], max(r[key], 1e-5)), fontsize=6)
    for r in rows:
        if r["reference"] == 2:      # the lattice on the reference's grid: the insertion's share at that resolution
            for a, key in zip(ax, ("arrival_err", "displacement_err")):
                a.loglog([r["wall_s"]], [max(r[key], 1e-5)], "k*", ms=10, label=f"lattice {r['n']} on the reference's grid")
    ax[0].set_title("arrival time at the gauge: relative error against the reference", fontsize=10)
    ax[1].set_title("transmitted displacement of the gauge: relative error", fontsize=10)
    for a in ax:
        a.set_xlabel("wall time, 2 ranks (s)")
        a.grid(True, which="both", alpha=0.3)
        a.legend(fontsize=8)
    ref = [r for r in rows if r["reference"] == 1][0]
    fig.suptitle(f"a 20 m/s pulse through an oblique [0/90]2s IM7/8552 laminate (0.15 mm plies) in epoxy; cell sizes (mm) marked; "
                 f"reference: exact, h {ref['h'] * 1e3:g} mm, subdivision {ref['n']}", fontsize=10)
    fig.tight_layout()
    fig.savefig(png, dpi=110)
    plt.close(fig)


def plot(rows, png):
    """Work-precision: L1 and plateau error against wall time, per problem and shape."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(2, 2, figsize=(11, 8))
    orders = {}
    for j, problem in enumerate(PROBLEMS):
        for shape in sorted({r["shape"] for r in rows}):
            rs = [r for r in rows if r["problem"] == problem and r["shape"] == shape]
            wall = [r["wall_s"] for r in rs]
            axes[0, j].loglog(wall, [r["L1"] for r in rs], "o-", label=shape)
            axes[1, j].loglog(wall, [max(r["plateau"], 1e-6) for r in rs], "o-", label=shape)
            orders[(problem, shape)] = [np.log(rs[k]["L1"] / rs[k + 1]["L1"]) / np.log(rs[k]["h"] / rs[k + 1]["h"]) for k in range(len(rs) - 1)]
        axes[0, j].set_title(f"{problem}: L1 velocity error / (jump x length)")
        axes[1, j].set_title(f"{problem}: plateau error")
        for i in range(2):
            axes[i, j].set_xlabel("wall time (s)")
            axes[i, j].grid(True, which="both", alpha=0.3)
            axes[i, j].legend()
    fig.suptitle("plyshock work-precision (uniaxial strain, h = 100, 50, 25 um ...)")
    fig.tight_layout()
    fig.savefig(png, dpi=110)
    return orders
