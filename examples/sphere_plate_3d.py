"""3D quarter model: copper sphere onto a [0/90/90/0] IM7/8552 plate (SI units).

A 50 x 50 mm plate of four 0.5 mm plies, centred on the origin in x and y, its
base at z = 0 (0° fibres along x, 90° along y); a copper sphere of radius 3 mm,
0.5 mm above the plate, moving at 600 m/s in -z.  Symmetry at x = 0 and y = 0
cuts the plate and the sphere to their quarters.  The plies meet at cohesive
interfaces (INTERFACE below; --bonded: welded plies), so the plate can
delaminate.  The paper gives no sizes; these are ours.

    python examples/sphere_plate_3d.py [-o OUT.h5] [--png FILE] [--cell 0.5e-3]
    mpiexec -n 2 python examples/sphere_plate_3d.py --run [-o OUTDIR] [--cell 0.25e-3]

The first form inserts the markers and draws them (fibre glyphs by ply); the
second runs the impact and draws before.png, after.png (turned fibres),
damage.png, the same three in a cut along the symmetry plane y = 0
(*_cut.png), delamination.png and delamination_cut.png (interface damage),
and velocity.png (the sphere's) in OUTDIR.

setup(**kw) returns the Scene; tests call it at small size.
"""
import argparse
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "python"))
from plyshock import Body, Frame, Grid, Interface, Laminate, Material, Run, Scene, Sphere  # noqa: E402

# Cohesive ply interfaces of IM7/8552: the interlaminar strengths and fracture
# energies taken equal to the ply's transverse ones in its preset (Yt, S12,
# G_mt, G_mc: NASA CompDam after Camanho), an assumption: the matrix fails
# between the plies as within them.
INTERFACE = Interface("cohesive", normal_strength=62.3e6, shear_strength=92.3e6, G_I=277.0, G_II=788.0)


def setup(cell=0.5e-3, subdivision=1, layup="[0/90/90/0]", ply_thickness=0.5e-3, radius=3e-3, speed=600.0,
          t_end=8e-6, output_interval=2e-6, interface=INTERFACE):
    half, T = 25e-3, 4 * ply_thickness
    lower, upper = [0.0, 0.0, -6e-3], [half, half, 10e-3]
    cells = [max(1, round((u - l) / cell)) for l, u in zip(lower, upper)]
    frame = Frame(origin=[-half, -half, 0.0], axis3=[-half, -half, 1e-3], plane13=[0.0, -half, 0.0])
    lam = Laminate.from_layup(frame, [2 * half, 2 * half], layup, ply_thickness, "IM7/8552")
    lam.interface = interface                   # None: bonded plies
    plate = Body("plate", laminate=lam, subdivision=subdivision)
    ball = Body("sphere", sphere=Sphere([0.0, 0.0, T + 0.5e-3 + radius], radius), material="OFHC-copper",
                velocity=[0.0, 0.0, -speed], subdivision=subdivision)
    boundary = {"x-": "symmetry", "y-": "symmetry", "x+": "free", "y+": "free", "z-": "free", "z+": "free"}
    return Scene(3, Grid(lower, upper, cells, boundary),
                 [Material("IM7/8552", preset="IM7/8552"), Material("OFHC-copper", preset="OFHC-copper")],
                 [plate, ball], Run(t_end=t_end, output_interval=output_interval))


# the picture frames the impact region (m)
ZOOM = [0, 0, -1e-3, 6e-3, 6e-3, 10e-3]
# the cut: a slab along the symmetry plane y = 0 (m)
CUT = [0, 0, -2e-3, 8e-3, 0.6e-3, 8e-3]

if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("-o", "--output", help="marker file (default out/sphere_plate_3d.h5), or with --run the "
                    "output directory (default out/sphere_plate_3d)")
    ap.add_argument("--png", default="out/sphere_plate_3d.png")
    ap.add_argument("--cell", type=float, default=0.5e-3, help="cell size (m)")
    ap.add_argument("--subdivision", type=int, default=1, help="sub-cells per cell and direction")
    ap.add_argument("--run", action="store_true", help="run the impact (under mpiexec) and draw its pictures")
    ap.add_argument("--bonded", action="store_true", help="bonded plies (one velocity field for the plate) instead of cohesive interfaces")
    a, petsc = ap.parse_known_args()
    from plyshock.cli import run_impact, run_scene
    sc = setup(cell=a.cell, subdivision=a.subdivision, interface=None if a.bonded else INTERFACE)
    if a.run:
        sys.exit(run_impact(sc, a.output or "out/sphere_plate_3d", petsc, zoom=ZOOM, projectile="sphere", cut=CUT))
    sys.exit(run_scene(sc, a.output or "out/sphere_plate_3d.h5", a.png, petsc, zoom=ZOOM))
