"""Verification of the Eulerian cells (`plyshock verify --only cells`): error
against run time for

* Sod's shock tube in cells (two gas materials, so the contact is a material
  interface) against the exact Riemann solution (riemann.py);
* a copper flyer on markers onto a copper target in cells against impedance
  matching (p = 9.63 GPa, u_p = 250 m/s);
* a disk of one gas carried diagonally through another (volume-fraction error
  against the exact translated disk: the interface reconstruction);
* the paper's Figures 1-3 measured: the same elastic-plastic slab, once on
  markers and once in cells, its left half carrying plastic strain 1 and its
  right half 0 (a 0/1 state), carried N cells across the grid at uniform
  velocity and then loaded against a wall: the error of its state against
  run time for both representations.

SI units.  Runs in process on all ranks (scripts/verify: 2 ranks); the
arrays compared are small strips, gathered for the measurement only.
"""
import os
import time

import numpy as np

WALLS = {"x-": "symmetry", "x+": "symmetry", "y-": "symmetry", "y+": "symmetry"}


def _gas(name, rho, gamma=1.4):
    from .scene import Material
    return Material(name, density=rho, eos={"type": "ideal-gas", "gamma": gamma})


def _copper():
    from .scene import Material
    return Material("cu", density=8930.0, eos={"type": "mie-gruneisen", "c0": 3940.0, "s": 1.489, "gamma0": 2.02})


def cells_global(S, comm):
    """Every rank's owned cells into one (ny, nx, dof) array (2D, small problems)."""
    c = S.cells()
    parts = comm.allgather((c["start"], c["state"][0]))
    ny = max(s[1] + a.shape[0] for s, a in parts)
    nx = max(s[0] + a.shape[1] for s, a in parts)
    out = np.zeros((ny, nx, parts[0][1].shape[-1]))
    for s, a in parts:
        out[s[1]:s[1] + a.shape[0], s[0]:s[0] + a.shape[1]] = a
    return out, c["nmat"], c["ms"]


def _run(scene, t_end):
    """Run a scene to t_end in process; (solver, markers, wall s, steps)."""
    from petsc4py import PETSc
    from . import core
    comm = PETSc.COMM_WORLD.tompi4py()
    comm.Barrier()
    w0 = time.perf_counter()
    m = core.initialize(scene)
    S = core.make_solver(m)
    while S.time < t_end * (1 - 1e-12):
        S.step(t_end)
    comm.Barrier()
    return S, m, time.perf_counter() - w0, S.step_count


def sod(n):
    """Sod on n cells (4 across): density L1 error / jump, wall s, steps."""
    from petsc4py import PETSc
    from .scene import Body, Box, Grid, Run, Scene
    from . import riemann
    h = 1.0 / n
    scene = Scene(2, Grid([0, 0], [1.0, 4 * h], [n, 4], WALLS), [_gas("left", 1.0), _gas("right", 0.125)],
                  [Body("L", box=Box([0, 0], [0.5, 1]), material="left", representation="cells", pressure=1.0),
                   Body("R", box=Box([0.5, 0], [1, 1]), material="right", representation="cells", pressure=0.1)],
                  Run(t_end=0.2)).validate()
    S, m, wall, steps = _run(scene, 0.2)
    u, nm, ms = cells_global(S, PETSc.COMM_WORLD.tompi4py())
    rho = sum(u[1, :, k * ms + 1] for k in range(nm)) / (h * h)
    x = (np.arange(n) + 0.5) * h
    exact = riemann.solve(1.0, 0.0, 1.0, 0.125, 0.0, 0.1).profile(x, 0.2, 0.5)[0]
    return float(np.mean(np.abs(rho - exact)) / 0.875), wall, steps, x, rho, exact


def impact(h):
    """Copper flyer (markers, 500 m/s) onto copper in cells: relative errors of
    the shocked target's pressure and particle velocity, wall s, steps."""
    from petsc4py import PETSc
    from .scene import Body, Box, Grid, Run, Scene
    cu = _copper()
    nx = round(6e-3 / h)
    scene = Scene(2, Grid([0, 0], [6e-3, 4 * h], [nx, 4], {"x-": "free", "x+": "free", "y-": "symmetry", "y+": "symmetry"}),
                  [cu], [Body("flyer", box=Box([0, 0], [2e-3, 4 * h]), material="cu", velocity=[500.0, 0.0], subdivision=2),
                         Body("target", box=Box([2e-3, 0], [6e-3, 4 * h]), material="cu", representation="cells")],
                  Run(t_end=0.5e-6)).validate()
    S, m, wall, steps = _run(scene, 0.5e-6)
    u, nm, ms = cells_global(S, PETSc.COMM_WORLD.tompi4py())
    from .core import scene_to_c  # noqa: F401  (the scene's EOS is the one the solver used)
    x = (np.arange(nx) + 0.5) * h
    t = S.time
    us = 3940.0 + 1.489 * 250.0
    sel = (x > 2e-3 + 250.0 * t + 3 * h) & (x < 2e-3 + us * t - 4 * h)
    V, M, E = u[1, sel, 0], u[1, sel, 1], u[1, sel, 2]
    J = 8930.0 * V / M
    mu = 1.0 / J - 1.0
    pH = 8930.0 * 3940.0 ** 2 * mu * (1 + mu) / (1 - 0.489 * mu) ** 2
    p = pH * (1 - 1.01 * mu / (1 + mu)) + 2.02 * 8930.0 * E / M
    pm = float(np.median(p))
    return abs(pm - 9.63e9) / 9.63e9, wall, steps


def disk(n):
    """A disk (density 2) in a gas (density 1), both at (1, 1) m/s and equal
    pressure, carried 0.2 m diagonally on an n x n grid of the unit square:
    the volume-fraction L1 error over the grid / the disk's area."""
    from petsc4py import PETSc
    from .scene import Body, Box, Grid, Run, Scene, Sphere
    h = 1.0 / n
    scene = Scene(2, Grid([0, 0], [1.0, 1.0], [n, n], WALLS), [_gas("out", 1.0), _gas("in", 2.0)],
                  [Body("out", box=Box([0, 0], [1, 1]), material="out", representation="cells", pressure=1.0, velocity=[1.0, 1.0]),
                   Body("disk", sphere=Sphere([0.35, 0.35], 0.15), material="in", representation="cells", pressure=1.0,
                        velocity=[1.0, 1.0], priority=1)],
                  Run(t_end=0.2, artificial_viscosity={"c_linear": 0.0, "c_quadratic": 0.0})).validate()
    S, m, wall, steps = _run(scene, 0.2)
    u, nm, ms = cells_global(S, PETSc.COMM_WORLD.tompi4py())
    a = u[..., ms] / (h * h)
    s = (np.arange(16) + 0.5) / 16
    xs = (np.arange(n)[:, None] + s[None, :]).ravel() * h
    X, Y = np.meshgrid(xs, xs)
    t = S.time
    inside = ((X - 0.35 - t) ** 2 + (Y - 0.35 - t) ** 2 < 0.15 ** 2).reshape(n, 16, n, 16).mean(axis=(1, 3))
    return float(np.abs(a - inside).sum() * h * h / (np.pi * 0.15 ** 2)), wall, steps


AL = dict(density=2703.0, eos={"type": "mie-gruneisen", "c0": 5240.0, "s": 1.40, "gamma0": 1.97},
          shear_modulus=27.6e9, strength={"type": "elastic-plastic", "yield_stress": 276e6})   # 6061-T6 (Steinberg; Y 276 MPa)


def slab(representation, n_carry, h=0.5e-3, load=True):
    """The paper's slab (Figures 1-3): 6061-T6 aluminium, 40 cells long, its
    left half at plastic strain 1 and its right half at 0 (a 0/1 state),
    carried n_carry cells at 200 m/s (a third of a cell a step at most), then,
    with load, against a wall for 4 us.  Returns (x, plastic strain per cell
    of the slab region along the middle row, wall s, steps)."""
    from petsc4py import PETSc
    from .scene import Body, Box, Contact, Grid, Material, Run, Scene
    from . import core
    L, v = 40 * h, 200.0
    x0 = 2 * h
    t_carry = n_carry * h / v
    t_end = t_carry + (4e-6 if load else 0.0)
    nx = 40 + n_carry + 6 + 1
    al = Material("al", **AL)
    rep = dict(representation=representation) if representation == "cells" else dict(subdivision=2)
    scene = Scene(2, Grid([0, 0], [nx * h, 4 * h], [nx, 4], {"x-": "free", "x+": "symmetry" if load else "free",
                                                             "y-": "symmetry", "y+": "symmetry"}),
                  [al], [Body("strained", box=Box([x0, 0], [x0 + L / 2, 4 * h]), material="al", velocity=[v, 0.0], plastic_strain=1.0, **rep),
                         Body("virgin", box=Box([x0 + L / 2, 0], [x0 + L, 4 * h]), material="al", velocity=[v, 0.0], **rep)],
                  Run(t_end=t_end, cfl=0.3), contact=Contact(type="bonded")).validate()   # one slab in two bodies: welded
    S, m, wall, steps = _run(scene, t_end)
    comm = PETSc.COMM_WORLD.tompi4py()
    edges = np.arange(nx + 1) * h
    if representation == "cells":
        u, nm, ms = cells_global(S, comm)
        M = u[1, :, 1]
        ep = np.where(M > 0, u[1, :, 3 + 4] / np.maximum(M, 1e-300), np.nan)      # M eps_p after the 2D deviator (4)
        mass = M
    else:
        f = core.local_fields(m, ["x", "mass", "plastic_strain"])
        x, mk, e = f["x"][:, 0], f["mass"][:, 0], f["plastic_strain"][:, 0]
        sel = (f["x"][:, 1] > h) & (f["x"][:, 1] < 2 * h)
        mass = np.histogram(x[sel], edges, weights=mk[sel])[0]
        me = np.histogram(x[sel], edges, weights=(mk * e)[sel])[0]
        mass, me = comm.allreduce(mass), comm.allreduce(me)
        ep = np.where(mass > 0, me / np.maximum(mass, 1e-300), np.nan)
    return 0.5 * (edges[:-1] + edges[1:]), ep, mass, wall, steps


def state_error(x, ep, mass, n_carry, h=0.5e-3):
    """L1 error of the carried 0/1 state against its exact, translated form,
    mass-weighted over the slab, in units of the jump (1)."""
    edge = 2 * h + 20 * h + n_carry * h        # the strained half's right end after the carry
    exact = np.clip((edge - (x - 0.5 * h)) / h, 0.0, 1.0)    # each cell's strained share
    w = np.nan_to_num(mass)
    return float(np.sum(w * np.abs(np.nan_to_num(ep) - exact)) / np.sum(w) * 40)


def cells_study(print0, quick=False):
    """Every cells problem at several resolutions: rows for verify_cells.csv."""
    rows = []
    for n in ((50, 100) if quick else (50, 100, 200, 400)):
        e, wall, steps, *_ = sod(n)
        rows.append(dict(problem="sod", representation="cells", size=n, steps=steps, wall_s=wall, error=e))
        print0(f"sod      {n:5d} cells  steps {steps:5d}  wall {wall:6.2f} s  density L1 {e:.3e}")
    for h in ((100e-6, 50e-6) if quick else (100e-6, 50e-6, 25e-6)):
        e, wall, steps = impact(h)
        rows.append(dict(problem="impact", representation="markers onto cells", size=h, steps=steps, wall_s=wall, error=e))
        print0(f"impact   h {h * 1e6:5.1f} um  steps {steps:5d}  wall {wall:6.2f} s  pressure error {e:.3e}")
    for n in ((20, 40) if quick else (20, 40, 80)):
        e, wall, steps = disk(n)
        rows.append(dict(problem="disk", representation="cells", size=n, steps=steps, wall_s=wall, error=e))
        print0(f"disk     {n:5d}^2     steps {steps:5d}  wall {wall:6.2f} s  volume-fraction L1 {e:.3e}")
    for rep in ("markers", "cells"):
        for nc in ((1, 8) if quick else (1, 2, 4, 8, 16)):
            x, ep, mass, wall, steps = slab(rep, nc, load=False)
            e = state_error(x, ep, mass, nc)
            rows.append(dict(problem="carried", representation=rep, size=nc, steps=steps, wall_s=wall, error=e))
            print0(f"carried  {rep:8s} {nc:2d} cells  steps {steps:5d}  wall {wall:6.2f} s  state L1 {e:.3e} (of the jump x cell)")
    return rows


def loaded_profiles():
    """The slab carried 8 cells and loaded against a wall, on markers and in
    cells: (x, plastic strain) of each, for the picture."""
    out = {}
    for rep in ("markers", "cells"):
        x, ep, mass, wall, steps = slab(rep, 8, load=True)
        out[rep] = (x, ep)
        x0, ep0, mass0, *_ = slab(rep, 8, load=False)
        out[rep + " (carried, unloaded)"] = (x0, ep0)
    return out


def plot_cells(rows, profiles, png, png_state):
    """verify_cells.png: error against wall time per problem; cells_state.png:
    the carried and loaded slab's plastic strain, markers against cells."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(1, 4, figsize=(17, 4.2))
    titles = {"sod": "Sod in cells: density L1 / jump", "impact": "marker flyer onto cell target: |p - 9.63 GPa| / 9.63 GPa",
              "disk": "disk carried diagonally: volume-fraction L1 / area", "carried": "0/1 state carried N cells: L1 (jump x cell)"}
    for a, prob in zip(ax, ("sod", "impact", "disk", "carried")):
        reps = sorted({r["representation"] for r in rows if r["problem"] == prob})
        for rep in reps:
            rs = [r for r in rows if r["problem"] == prob and r["representation"] == rep]
            a.loglog([r["wall_s"] for r in rs], [max(r["error"], 1e-16) for r in rs], "o-", label=rep)
            for r in rs:
                a.annotate(f"{r['size']:g}" if prob != "impact" else f"{r['size'] * 1e6:g} um", (r["wall_s"], max(r["error"], 1e-16)),
                           fontsize=7, xytext=(3, 3), textcoords="offset points")
        a.set_title(titles[prob], fontsize=9)
        a.set_xlabel("wall time (s, 2 ranks)")
        a.legend(fontsize=8)
        a.grid(True, which="both", alpha=0.3)
    ax[0].set_ylabel("error")
    fig.tight_layout()
    fig.savefig(png, dpi=110)
    plt.close(fig)
    fig, ax = plt.subplots(1, 2, figsize=(12, 4))
    for rep, style in (("markers", "o-"), ("cells", "s-")):
        x, ep = profiles[rep + " (carried, unloaded)"]
        ax[0].plot(x * 1e3, ep, style, ms=3, label=rep)
        x, ep = profiles[rep]
        ax[1].plot(x * 1e3, ep, style, ms=3, label=rep)
    ax[0].set_title("carried 8 cells at 200 m/s: the 0/1 plastic strain")
    ax[1].set_title("then 4 us against a wall")
    for a in ax:
        a.set_xlabel("x (mm)")
        a.set_ylabel("plastic strain (-)")
        a.legend()
        a.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(png_state, dpi=110)
    plt.close(fig)
