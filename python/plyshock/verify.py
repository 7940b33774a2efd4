"""Error against run time (work-precision) for the solver.  SI units.

Two problems with exact piecewise-constant velocity profiles, in a uniaxial
strain strip (symmetry faces on the sides), at successively finer grids for
each shape function:

  plate   hydrodynamic copper onto copper at 500 m/s (Mie-Grueneisen, Steinberg):
          u_p = 250 m/s behind shocks running at Us = c0 + s u_p = 4312 m/s
          relative to the material ahead of them; t = 1 us.
  wave    a 1 m/s velocity step in an elastic strip (E 200 GPa, nu 0.3,
          rho 7800): fronts at c = sqrt((lambda + 2 mu)/rho) both ways,
          0.5 m/s between them; t = 1.5 us.

For each run: the L1 error of the marker velocities against the exact profile
at their positions, sum |v_p - v(x_p)| l_p / (jump * length), and the plateau
error |median(v) - v_plateau| / v_plateau away from the fronts; the wall time;
the observed order of convergence of the L1 error between successive grids.
Writes OUTDIR/verify.csv and OUTDIR/verify.png.

    mpiexec -n 2 plyshock verify [-o out/verify] [--levels 3]
"""
import csv
import os
import time

import numpy as np

from .scene import Body, Box, Grid, Material, Run, Scene

CU = dict(rho=8930.0, c0=3940.0, s=1.489, gamma0=2.02)
EL = dict(E=200e9, nu=0.3, rho=7800.0)
LENGTH = 0.02


def _strip(h, bodies, materials, run, width=2):
    cells = [round(LENGTH / h), width]
    return Scene(2, Grid([0.0, 0.0], [LENGTH, width * h], cells,
                         {"x-": "free", "x+": "free", "y-": "symmetry", "y+": "symmetry"}), materials, bodies, run).validate()


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


def taylor(cell=0.5e-3, shape="gimp", subdivision=2, fbar=True, t_end=80e-6, transfer="musl"):
    """The copper Taylor bar (3D quarter model against a rigid frictionless wall):
    final length and foot diameter after 80 us, and their errors against the
    measured 16.21 mm and 13.56 mm (Johnson & Cook 1983).  fbar: cell-averaged
    volumetric rate against locking (under musl with a 5% PIC share, which keeps
    its zero-energy modes from growing under FLIP; apic needs bspline2)."""
    from petsc4py import PETSc
    from . import core
    from .scene import Cylinder
    T = TAYLOR
    side = 9e-3
    scene = Scene(3, Grid([0, 0, 0], [side, side, 26e-3], [round(side / cell), round(side / cell), round(26e-3 / cell)],
                          {"x-": "symmetry", "y-": "symmetry", "z-": "symmetry"}),
                  [Material("cu", preset="OFHC-copper")],
                  [Body("bar", cylinder=Cylinder([0, 0, 0], [0, 0, 1], T["D0"] / 2, T["L0"]), material="cu",
                        velocity=[0, 0, -T["v"]], subdivision=subdivision)],
                  Run(t_end=t_end, shape=shape, transfer=transfer, history_interval=100000, fbar=fbar,
                      pic_fraction=0.05 if fbar and transfer == "musl" else 0.0)).validate()
    comm = PETSc.COMM_WORLD.tompi4py()
    w0 = time.perf_counter()
    m = core.initialize(scene)
    S = core.make_solver(m)
    ke0 = S.totals()["kinetic"]
    while S.time < t_end * (1 - 1e-12):
        S.step()
    wall = time.perf_counter() - w0
    f = core.local_fields(m, ["x", "volume"])
    x, a = f["x"], 0.5 * np.cbrt(f["volume"][:, 0])        # marker half size
    top = comm.allreduce(float((x[:, 2] + a).max()) if len(x) else 0.0, op=max_op())
    # the bar may rebound off the frictionless wall (z = 0): its length is top - bottom
    bottom = max(0.0, -comm.allreduce(float(-(x[:, 2] - a).min()) if len(x) else -1e30, op=max_op()))
    top -= bottom
    foot = x[:, 2] < bottom + cell
    r = comm.allreduce(float((np.hypot(x[foot, 0], x[foot, 1]) + a[foot]).max()) if foot.any() else 0.0, op=max_op())
    return dict(length=top, diameter=2 * r, err_length=top / T["L"] - 1, err_diameter=2 * r / T["D"] - 1, wall_s=wall,
                kinetic_left=S.totals()["kinetic"] / ke0,
                markers=m.stats["markers"], steps=S.step_count)


def max_op():
    from mpi4py import MPI
    return MPI.MAX


def main(outdir="out/verify", levels=3, shapes=("linear", "gimp", "bspline2"), taylor_cell=None):
    from petsc4py import PETSc
    rank = PETSc.COMM_WORLD.getRank()
    hs = [100e-6 / 2**k for k in range(levels)]
    rows = []
    for problem in PROBLEMS:
        for shape in shapes:
            for h in hs:
                l1, plat, wall, n, steps = run_one(problem, h, shape)
                rows.append(dict(problem=problem, shape=shape, h=h, markers=n, steps=steps, wall_s=wall, L1=l1, plateau=plat))
                if rank == 0:
                    print(f"{problem:5s} {shape:8s} h {h * 1e6:6.2f} um  markers {n:6d}  steps {steps:5d}  "
                          f"wall {wall:7.2f} s  L1 {l1:.3e}  plateau {plat:.2e}", flush=True)
    if rank == 0:
        os.makedirs(outdir, exist_ok=True)
        with open(os.path.join(outdir, "verify.csv"), "w", newline="") as f:
            w = csv.DictWriter(f, fieldnames=list(rows[0]))
            w.writeheader()
            w.writerows(rows)
        orders = plot(rows, os.path.join(outdir, "verify.png"))
        for (problem, shape), p in orders.items():
            print(f"observed L1 order {problem} {shape}: " + ", ".join(f"{x:.2f}" for x in p))
        print(f"wrote {outdir}/verify.csv and {outdir}/verify.png")
    if taylor_cell:
        # plyshock (APIC, quadratic B-splines, F-bar), then the same model by an
        # independent axisymmetric Lagrangian solution (taylor_rz.py, rank 0):
        # the first error is the method's, the second the model's
        tb = taylor(taylor_cell, shape="bspline2", transfer="apic")
        if rank == 0:
            from . import taylor_rz
            w0 = time.perf_counter()
            ref = taylor_rz.solve()
            ref_wall = time.perf_counter() - w0
            print(f"Taylor bar ({taylor_cell * 1e3:.2f} mm cells, {tb['markers']} markers, {tb['steps']} steps, {tb['wall_s']:.1f} s): "
                  f"length {tb['length'] * 1e3:.2f} mm ({100 * tb['err_length']:+.1f}% against 16.21 mm), "
                  f"foot diameter {tb['diameter'] * 1e3:.2f} mm ({100 * tb['err_diameter']:+.1f}% against 13.56 mm)")
            print(f"  the same model, axisymmetric Lagrangian reference ({ref['zones']} zones, {ref_wall:.0f} s): "
                  f"length {ref['length'] * 1e3:.2f} mm ({100 * (ref['length'] / TAYLOR['L'] - 1):+.1f}% against the test), "
                  f"foot {ref['diameter'] * 1e3:.2f} mm ({100 * (ref['diameter'] / TAYLOR['D'] - 1):+.1f}%); "
                  f"plyshock against it: length {100 * (tb['length'] / ref['length'] - 1):+.1f}%, "
                  f"foot {100 * (tb['diameter'] / ref['diameter'] - 1):+.1f}%")
            tb.update({f"reference_{k}": v for k, v in ref.items()})
            with open(os.path.join(outdir, "taylor.csv"), "w") as f:
                f.write(",".join(tb) + "\n" + ",".join(str(v) for v in tb.values()) + "\n")
    return rows


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
