"""2D oblique plate and flyer (plane strain, SI units).

The method's first scene: a 60 x 40 mm domain; an IM7/8552 [0/90/90/0] plate of
four 0.5 mm plies, 40 mm long, centred at (30, 20) mm with its axis 1 at 45° to
x (the 0° fibres run at 45°; the 90° fibres point out of the plane); an
axis-aligned 4340 steel flyer 8 x 3 mm centred on x = 30 mm, 0.5 mm clear of
the plate's upper face, moving at 400 m/s in -y.  The paper gives no sizes;
these are ours.

    python examples/oblique_plate_2d.py [-o OUT.h5] [--png FILE] [--cells 240 160]
    mpiexec -n 2 python examples/oblique_plate_2d.py --run [-o OUTDIR] [--cells 480 320] [-run_t_end 8e-6]

The first form inserts the markers and draws them (fibre glyphs by ply); the
second runs the impact and draws before.png, after.png (turned fibres),
damage.png and velocity.png (the flyer's) in OUTDIR.

setup(**kw) returns the Scene; tests call it at small size.
"""
import argparse
import math
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "python"))
from plyshock import Body, Box, Frame, Grid, Laminate, Material, Run, Scene  # noqa: E402


def setup(cells=(240, 160), subdivision=2, layup="[0/90/90/0]", ply_thickness=0.5e-3, angle_deg=45.0,
          flyer_speed=400.0, t_end=8e-6, output_interval=2e-6):
    L, c = 40e-3, (30e-3, 20e-3)
    T = ply_thickness * 4
    e1 = (math.cos(math.radians(angle_deg)), math.sin(math.radians(angle_deg)))
    e3 = (-e1[1], e1[0])
    # the origin is the corner of the plate's base: centre - L/2 e1 - T/2 e3
    o = (c[0] - L / 2 * e1[0] - T / 2 * e3[0], c[1] - L / 2 * e1[1] - T / 2 * e3[1])
    frame = Frame(origin=list(o), axis3=[o[0] + e3[0] * 0.01, o[1] + e3[1] * 0.01],
                  plane13=[o[0] + e1[0] * 0.01, o[1] + e1[1] * 0.01])
    plate = Body("plate", laminate=Laminate.from_layup(frame, [L], layup, ply_thickness, "IM7/8552"),
                 subdivision=subdivision)
    # highest point of the plate's upper face under the flyer (|x - 30 mm| <= 4 mm)
    top = c[1] + T / 2 / e1[0] + 4e-3 * math.tan(math.radians(angle_deg))
    flyer = Body("flyer", box=Box([26e-3, top + 0.5e-3], [34e-3, top + 3.5e-3]), material="4340-steel",
                 velocity=[0.0, -flyer_speed], subdivision=subdivision)
    return Scene(2, Grid([0.0, 0.0], [60e-3, 40e-3], list(cells)),
                 [Material("IM7/8552", preset="IM7/8552"), Material("4340-steel", preset="4340-steel")],
                 [plate, flyer], Run(t_end=t_end, output_interval=output_interval))


# the picture frames the impact region (m)
ZOOM = [0.022, 0.014, 0.038, 0.027]

if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("-o", "--output", help="marker file (default out/oblique_plate_2d.h5), or with --run the "
                    "output directory (default out/oblique_plate_2d)")
    ap.add_argument("--png", default="out/oblique_plate_2d.png")
    ap.add_argument("--cells", type=int, nargs=2, default=(240, 160))
    ap.add_argument("--run", action="store_true", help="run the impact (under mpiexec) and draw its pictures")
    a, petsc = ap.parse_known_args()
    from plyshock.cli import run_impact, run_scene
    if a.run:
        sys.exit(run_impact(setup(cells=a.cells), a.output or "out/oblique_plate_2d", petsc, zoom=ZOOM, projectile="flyer"))
    sys.exit(run_scene(setup(cells=a.cells), a.output or "out/oblique_plate_2d.h5", a.png, petsc, zoom=ZOOM))
