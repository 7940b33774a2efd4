"""Contact between marker bodies (docs/contact.md): error against run time for
`plyshock verify --only contact`, into verify_contact.csv and
verify_contact.png.  The scenes are also those of tests/test_contact.py.

  trap     the momentum trap: a copper flyer of thickness d at V onto two
           touching copper plates of thickness d each, in uniaxial strain; the
           1D answer after the waves have passed is rear plate V, front plate
           and flyer at rest; error (|v_rear - V| + |v_front| + |v_flyer|) / V.
  coulomb  an aluminium block thrown at (20, -10) m/s onto a plate with
           friction mu = 0.3: while it slips its tangential momentum changes by
           mu times the normal impulse; error |(-dv_x / dv_y) - mu| / mu.
  mode I   a cohesive ply interface opened in mode I (spall): an aluminium
           flyer of thickness d at 20 m/s onto a two-ply laminate (plies of
           thickness d, interface: cohesive with N = 100 MPa < the 167 MPa
           the reflected pulse pulls with), in uniaxial strain; once the
           interface is open the traction-separation law has taken G_I per unit
           of area: error |interface_energy / (G_I A) - 1|.
  mode II  a lap-shear strip (lap_shear): a flyer strikes the lower of two
           5 mm aluminium plies, the shear runs a crack along the cohesive
           interface (S = 10 MPa, G_II = 20 J/m^2); once the whole strip is
           open the law has taken G_II per unit of length: error
           |interface_energy / (G_II L) - 1|.
SI units.
"""
import os

import numpy as np

from .scene import Body, Box, Contact, Frame, Grid, Interface, Laminate, Material, Ply, Run, Scene

CU = Material("cu", density=8930.0, eos={"type": "mie-gruneisen", "c0": 3940.0, "s": 1.489, "gamma0": 2.02})
AL = Material("al", density=2700.0, elastic={"type": "isotropic", "E": 70e9, "nu": 0.33})
V = 100.0          # the trap's flyer speed (m/s)
MU = 0.3           # the sliding block's friction coefficient
SPALL_V = 20.0     # the mode-I flyer's speed (m/s)
G_I = 50.0         # the mode-I interface's fracture energy (J/m^2)
G_II = 20.0        # the lap shear's mode-II fracture energy (J/m^2)
LAP_V = 50.0       # the lap shear's flyer speed (m/s)


def spall_stress(v=SPALL_V):
    """The tension (Pa) the reflected pulse pulls the interface with: rho c_L v / 2,
    c_L the aluminium's longitudinal (uniaxial strain) wave speed."""
    E, nu, rho = AL.elastic["E"], AL.elastic["nu"], AL.density
    M = E * (1 - nu) / ((1 + nu) * (1 - 2 * nu))
    return rho * (M / rho) ** 0.5 * v / 2


def spall(strength, G=G_I, h=25e-6, d=1e-3, v=SPALL_V, t_end=1.2e-6, interface="cohesive", output_interval=0.0):
    """A flyer (thickness d, at v) onto a laminate of two aluminium plies
    (thickness d each) stacked along x, in uniaxial strain (a strip of 4 cells
    between symmetry faces): the compressive pulse reflects at the free face
    as tension, which meets the ply interface at x = x0 + 2d.  interface:
    cohesive (normal and shear strength `strength`, G_I = G_II = G) or bonded."""
    W, x0 = 4 * h, 0.5e-3
    itf = Interface("cohesive", strength, strength, G, G) if interface == "cohesive" else None
    lam = Laminate(Frame([x0 + d, 0.0], [x0 + d + 1.0, 0.0], [x0 + d, 1.0]), [W], [Ply("al", d), Ply("al", d)], itf)
    bs = [Body("flyer", box=Box([x0, 0.0], [x0 + d, W]), material="al", velocity=[v, 0.0], subdivision=2),
          Body("laminate", laminate=lam, subdivision=2)]
    L = x0 + 3 * d + 2e-3
    return Scene(2, Grid([0.0, 0.0], [L, W], [round(L / h), 4], {"x-": "free", "x+": "free", "y-": "symmetry", "y+": "symmetry"}),
                 [AL], bs, Run(t_end=t_end, output_interval=output_interval, history_interval=1)).validate()


def spall_axisymmetric(strength, G=G_I, h=25e-6, d=1e-3, v=SPALL_V, t_end=1.2e-6):
    """The spall in axisymmetric 2D (x = r, y = z): the flyer and the two plies
    are disks of radius 4h stacked along the axis, a symmetry face at r = 4h
    (uniaxial strain, the plane spall's 1D problem); the interface's area is
    pi (4h)^2."""
    R, z0 = 4 * h, 0.5e-3
    itf = Interface("cohesive", strength, strength, G, G)
    lam = Laminate(Frame([0.0, z0 + d], [0.0, z0 + d + 1.0], [1.0, z0 + d]), [R], [Ply("al", d), Ply("al", d)], itf)
    bs = [Body("flyer", box=Box([0.0, z0], [R, z0 + d]), material="al", velocity=[0.0, v], subdivision=2),
          Body("laminate", laminate=lam, subdivision=2)]
    L = z0 + 3 * d + 2e-3
    return Scene(2, Grid([0.0, 0.0], [R, L], [4, round(L / h)], {"x-": "symmetry", "x+": "symmetry", "y-": "free", "y+": "free"}),
                 [AL], bs, Run(t_end=t_end, output_interval=0.0, history_interval=1), geometry="axisymmetric").validate()


def lap_shear(h=50e-6, S=10e6, G=G_II, v=LAP_V, L=5e-3, t=0.5e-3, t_end=3e-6, output_interval=0.0):
    """Mode II: a lap-shear strip.  Two aluminium plies (length L, thickness t
    each) stacked along y on a symmetry face, a cohesive interface between them
    (shear strength S, G_II = G, normal strength 1 GPa so that only shear
    opens it); an aluminium flyer (1 mm x t, at v along x) strikes the lower
    ply's end only, and the shear the lower ply's motion puts on the interface
    runs a crack along it from the struck end."""
    x0 = 2e-3
    lam = Laminate(Frame([x0, 0.0], [x0, 1.0], [x0 + 1.0, 0.0]), [L], [Ply("al", t), Ply("al", t)], Interface("cohesive", 1e9, S, 4 * G, G))
    bs = [Body("flyer", box=Box([x0 - 1e-3, 0.0], [x0, t]), material="al", velocity=[v, 0.0], subdivision=2),
          Body("laminate", laminate=lam, subdivision=2)]
    W, Ly = x0 + L + 1e-3, 2 * t + 1e-3
    return Scene(2, Grid([0.0, 0.0], [W, Ly], [round(W / h), round(Ly / h)], {"x-": "free", "x+": "free", "y-": "symmetry", "y+": "free"}),
                 [AL], bs, Run(t_end=t_end, output_interval=output_interval, history_interval=10)).validate()


def trap(contact, t_end=1.5e-6, h=50e-6, d=1e-3):
    """A copper flyer of thickness d at V onto two touching copper plates of
    thickness d each, in uniaxial strain (a strip between symmetry faces)."""
    W, L = 4 * h, 8e-3
    bs = [Body("flyer", box=Box([1e-3, 0], [1e-3 + d, W]), material="cu", velocity=[V, 0.0], subdivision=2),
          Body("front", box=Box([1e-3 + d, 0], [1e-3 + 2 * d, W]), material="cu", subdivision=2),
          Body("rear", box=Box([1e-3 + 2 * d, 0], [1e-3 + 3 * d, W]), material="cu", subdivision=2)]
    return Scene(2, Grid([0.0, 0.0], [L, W], [round(L / h), 4], {"x-": "free", "x+": "free", "y-": "symmetry", "y+": "symmetry"}),
                 [CU], bs, Run(t_end=t_end, output_interval=0.0), contact=contact).validate()


AIR = Material("air", density=1.225, eos={"type": "ideal-gas", "gamma": 1.4})    # U.S. Standard Atmosphere 1976, sea level
AIR_P = 101325.0   # its pressure (Pa)


def trap_in_air(contact, t_end=1.5e-6, h=50e-6, d=1e-3):
    """The trap with air behind the rear plate up to a wall 4 mm away
    (in_air): the bodies meet where no cell material is, so contact acts
    there; the rear plate leaves into the air, a piston whose shock does not
    reach the wall by t_end, which holds the still air at AIR_P."""
    return in_air(trap(contact, t_end=t_end, h=h, d=d), 1e-3 + 3 * d)


def in_air(s, x1):
    """Scene s with air (cells, AIR_P) from x = x1 to its x+ face, made a wall
    (symmetry): the air's pressure there is the only outside force, -AIR_P W
    in x (W the strip's width)."""
    air = Body("air", box=Box([x1, 0.0], [s.grid.upper[0], s.grid.upper[1]]), material="air", representation="cells",
               pressure=AIR_P, priority=0)
    g = Grid(s.grid.lower, s.grid.upper, s.grid.cells, dict(s.grid.boundary, **{"x+": "symmetry"}))
    return Scene(2, g, list(s.materials) + [AIR], list(s.bodies) + [air], s.run, contact=s.contact).validate()


def trap_axisymmetric(contact, t_end=1.5e-6, h=50e-6, d=1e-3, R=None):
    """The trap in axisymmetric 2D (x = r, y = z): copper disks of thickness d
    stacked along the axis, the flyer at V along +z.  R None: 4 cells wide
    with a symmetry face at r = 4h (uniaxial strain, the plane trap's 1D
    answer); else disks of radius R with a free rim in a grid 2R wide (a
    radial release)."""
    W = R or 4 * h
    bs = [Body("flyer", box=Box([0.0, 1e-3], [W, 1e-3 + d]), material="cu", velocity=[0.0, V], subdivision=2),
          Body("front", box=Box([0.0, 1e-3 + d], [W, 1e-3 + 2 * d]), material="cu", subdivision=2),
          Body("rear", box=Box([0.0, 1e-3 + 2 * d], [W, 1e-3 + 3 * d]), material="cu", subdivision=2)]
    Wg, L = (W, 8e-3) if R is None else (2 * W, 8e-3)
    return Scene(2, Grid([0.0, 0.0], [Wg, L], [round(Wg / h), round(L / h)],
                         {"x-": "symmetry", "x+": "symmetry" if R is None else "free", "y-": "free", "y+": "free"}),
                 [CU], bs, Run(t_end=t_end, output_interval=0.0), contact=contact, geometry="axisymmetric").validate()


def slide(mu, t_end=4e-6, h=0.25e-3, output_interval=0.0):
    """An aluminium block (4 x 2 mm) thrown at (20, -10) m/s onto an aluminium
    plate (20 x 2 mm) held on its lower face: it slides along the plate while
    it bounces off it."""
    bs = [Body("plate", box=Box([0.0, 0.0], [20e-3, 2e-3]), material="al", subdivision=2),
          Body("block", box=Box([4e-3, 2e-3], [8e-3, 4e-3]), material="al", velocity=[20.0, -10.0], subdivision=2)]
    return Scene(2, Grid([0.0, 0.0], [20e-3, 6e-3], [round(20e-3 / h), round(6e-3 / h)],
                         {"x-": "free", "x+": "free", "y-": "fixed", "y+": "free"}),
                 [AL], bs, Run(t_end=t_end, output_interval=output_interval, history_interval=5), contact=Contact(friction=mu)).validate()


def bodies_csv(outdir):
    """{body name: its rows of bodies.csv}"""
    B = np.genfromtxt(os.path.join(outdir, "bodies.csv"), delimiter=",", names=True, dtype=None, encoding=None)
    return {n: B[B["body"] == n] for n in set(B["body"])}


def _run(scene):
    """Run a scene (plyshock.verify.run_scratch): (its bodies.csv rows by body, wall s, steps)."""
    from .verify import run_scratch
    B, wall, _, S = run_scratch(scene, bodies_csv)
    return B, wall, S.step_count


def contact_study(print0, quick=False):
    """The trap, the sliding block and the cohesive modes I and II at several resolutions: rows for verify_contact.csv."""
    rows = []
    _run(trap(None, h=100e-6))          # a warm-up run, not timed (the first run pays for the solver's setup)
    for h in ((100e-6, 50e-6) if quick else (100e-6, 50e-6, 25e-6)):
        B, wall, steps = _run(trap(None, h=h))
        v = {n: B[n]["vx"][-1] for n in B}
        e = (abs(v["rear"] - V) + abs(v["front"]) + abs(v["flyer"])) / V
        rows.append(dict(problem="trap", size=h, steps=steps, wall_s=wall, error=e))
        print0(f"trap     h {h * 1e6:5.1f} um  steps {steps:5d}  wall {wall:6.2f} s  rear {v['rear']:.2f}, front {v['front']:.2f}, "
               f"flyer {v['flyer']:.2f} m/s  error {e:.3e}")
    from .verify import run_scratch
    for h in ((0.5e-3, 0.25e-3) if quick else (0.5e-3, 0.25e-3, 0.125e-3)):
        (B, H), wall, _, S = run_scratch(slide(MU, h=h), lambda d: (bodies_csv(d), _history(d)))
        steps, b = S.step_count, B["block"]
        dvx, dvy = b["vx"][-1] - b["vx"][0], b["vy"][-1] - b["vy"][0]
        e = abs(-dvx / dvy - MU) / MU
        rows.append(dict(problem="coulomb", size=h, steps=steps, wall_s=wall, error=e))
        print0(f"coulomb  h {h * 1e3:5.3f} mm  steps {steps:5d}  wall {wall:6.2f} s  -dv_x/dv_y {-dvx / dvy:.4f} (mu {MU})  error {e:.3e}  "
               f"total drift {100 * (H['total'][-1] / H['total'][0] - 1):+.2f}% (friction work {H['friction_work'][-1]:.3f} J/m)")
    # the cohesive laws: the energy taken against G times the interface opened
    cohesive = (("mode I", "G_I A", (50e-6, 25e-6, 12.5e-6), lambda h: spall(100e6, h=h), lambda h: G_I * 4 * h),
                ("mode II", "G_II L", (100e-6, 50e-6, 25e-6), lambda h: lap_shear(h=h), lambda h: G_II * 5e-3))
    for prob, ref, sizes, scene, taken in cohesive:
        for h in (sizes[:2] if quick else sizes):
            H, wall, _, S = run_scratch(scene(h), _history)
            took = H["interface_energy"][-1] / taken(h)
            e = abs(took - 1)
            rows.append(dict(problem=prob, size=h, steps=S.step_count, wall_s=wall, error=e))
            print0(f"{prob:8s} h {h * 1e6:5.1f} um  steps {S.step_count:5d}  wall {wall:6.2f} s  interface energy {took:.4f} {ref}  "
                   f"total drift {100 * (H['total'][-1] / H['total'][0] - 1):+.2f}%  error {e:.3e}")
    return rows


def _history(outdir):
    return np.genfromtxt(os.path.join(outdir, "history.csv"), delimiter=",", names=True)


def plot_contact(rows, png):
    """verify_contact.png: error against wall time for the trap, the block and the cohesive modes I and II."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(1, 4, figsize=(19, 4.2))
    titles = {"trap": "momentum trap: (|v_rear - V| + |v_front| + |v_flyer|) / V",
              "coulomb": f"sliding block: |(-dv_t / dv_n) - mu| / mu, mu = {MU}",
              "mode I": "cohesive mode I (spall): |interface energy / (G_I A) - 1|",
              "mode II": "cohesive mode II (lap shear): |interface energy / (G_II L) - 1|"}
    for a, prob in zip(ax, ("trap", "coulomb", "mode I", "mode II")):
        rs = [r for r in rows if r["problem"] == prob]
        a.loglog([r["wall_s"] for r in rs], [max(r["error"], 1e-16) for r in rs], "o-")
        for r in rs:
            lab = f"{r['size'] * 1e3:g} mm" if prob == "coulomb" else f"{r['size'] * 1e6:g} um"
            a.annotate(lab, (r["wall_s"], max(r["error"], 1e-16)), textcoords="offset points", xytext=(4, 4), fontsize=8)
        a.set_title(titles[prob], fontsize=9)
        a.set_xlabel("wall time (s, 2 ranks)")
        a.grid(True, which="both", alpha=0.3)
    ax[0].set_ylabel("error")
    fig.tight_layout()
    fig.savefig(png, dpi=110)
    plt.close(fig)
