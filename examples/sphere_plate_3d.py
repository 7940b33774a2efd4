"""3D quarter model: copper sphere onto a [0/90/90/0] IM7/8552 plate (SI units).

A 50 x 50 mm plate of four 0.5 mm plies, centred on the origin in x and y, its
base at z = 0 (0° fibres along x, 90° along y); a copper sphere of radius 3 mm,
0.5 mm above the plate, moving at 600 m/s in -z.  Symmetry at x = 0 and y = 0
cuts the plate and the sphere to their quarters.  The paper gives no sizes;
these are ours.

    python examples/sphere_plate_3d.py [-o OUT.h5] [--png FILE] [--cell 0.5e-3]

setup(**kw) returns the Scene; tests call it at small size.
"""
import argparse
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "python"))
from plyshock import Body, Frame, Grid, Laminate, Material, Scene, Sphere  # noqa: E402


def setup(cell=0.5e-3, subdivision=1, layup="[0/90/90/0]", ply_thickness=0.5e-3, radius=3e-3, speed=600.0):
    half, T = 25e-3, 4 * ply_thickness
    lower, upper = [0.0, 0.0, -6e-3], [half, half, 10e-3]
    cells = [max(1, round((u - l) / cell)) for l, u in zip(lower, upper)]
    frame = Frame(origin=[-half, -half, 0.0], axis3=[-half, -half, 1e-3], plane13=[0.0, -half, 0.0])
    plate = Body("plate", laminate=Laminate.from_layup(frame, [2 * half, 2 * half], layup, ply_thickness, "IM7/8552"),
                 subdivision=subdivision)
    ball = Body("sphere", sphere=Sphere([0.0, 0.0, T + 0.5e-3 + radius], radius), material="OFHC-copper",
                velocity=[0.0, 0.0, -speed], subdivision=subdivision)
    boundary = {"x-": "symmetry", "y-": "symmetry", "x+": "free", "y+": "free", "z-": "free", "z+": "free"}
    return Scene(3, Grid(lower, upper, cells, boundary),
                 [Material("IM7/8552", preset="IM7/8552"), Material("OFHC-copper", preset="OFHC-copper")],
                 [plate, ball])


# the picture frames the impact region (m)
ZOOM = [0, 0, -1e-3, 6e-3, 6e-3, 10e-3]

if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("-o", "--output", default="out/sphere_plate_3d.h5")
    ap.add_argument("--png", default="out/sphere_plate_3d.png")
    ap.add_argument("--cell", type=float, default=0.5e-3, help="cell size (m)")
    a, petsc = ap.parse_known_args()
    from plyshock.cli import run_scene
    sys.exit(run_scene(setup(cell=a.cell), a.output, a.png, petsc, zoom=ZOOM))
