"""2D oblique plate and flyer (plane strain, SI units).

The method's first scene: a 60 x 40 mm domain; an IM7/8552 [0/90/90/0] plate of
four 0.5 mm plies, 40 mm long, centred at (30, 20) mm with its axis 1 at 45° to
x (the 0° fibres run at 45°; the 90° fibres point out of the plane); an
axis-aligned 4340 steel flyer 8 x 3 mm centred on x = 30 mm, 0.5 mm clear of
the plate's upper face, moving at 400 m/s in -y.  The paper gives no sizes;
these are ours.

    python examples/oblique_plate_2d.py [-o OUT.h5] [--png FILE] [--cells 240 160]
    mpiexec -n 2 python examples/oblique_plate_2d.py --run [-o OUTDIR] [--cells 480 320] [-run_t_end 8e-6]
    mpiexec -n 2 python examples/oblique_plate_2d.py --run --air [-o OUTDIR] [--cells 96 64]

The first form inserts the markers and draws them (fibre glyphs by ply); the
second runs the impact and draws before.png, after.png (turned fibres),
damage.png and velocity.png (the flyer's) in OUTDIR.

--air runs the same scene in air (issue 12): an ambient body of air in cells
(the U.S. Standard Atmosphere 1976 at sea level: 1.225 kg/m^3, 101325 Pa, an
ideal gas with gamma = 1.4) fills the grid under the plate and the flyer (its
priority is the lowest, so the markers' bodies win their overlaps), and the
faces stay free: air, like markers, leaves there and is booked.  The flyer
squeezes the 0.5 mm of air between it and the plate (a piston at 400 m/s
drives a shock at 656 m/s, Mach 1.93, into still air: 423 kPa behind it, from
the ideal-gas shock relations) and the impact throws the air aside.  Besides the four pictures it draws
cells_pressure.png and cells_air.png (the cell pressure and the air's volume
fraction under the markers at every output time; frames/ holds each) and
history.png, in OUTDIR (default out/oblique_plate_2d_air).  Cells cost more
than markers, so --air defaults to 96 x 64 cells (0.625 mm).

setup(**kw) returns the Scene; tests call it at small size.
"""
import argparse
import math
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "python"))
from plyshock import Body, Box, Contact, Frame, Grid, Laminate, Material, Run, Scene  # noqa: E402

AIR = {"density": 1.225, "pressure": 101325.0, "gamma": 1.4}     # U.S. Standard Atmosphere 1976, sea level


def setup(cells=(240, 160), subdivision=2, layup="[0/90/90/0]", ply_thickness=0.5e-3, angle_deg=45.0,
          flyer_speed=400.0, t_end=8e-6, output_interval=2e-6, air=False):
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
    mats = [Material("IM7/8552", preset="IM7/8552"), Material("4340-steel", preset="4340-steel")]
    bodies = [plate, flyer]
    if air:             # the ambient air in cells, under everything
        mats.append(Material("air", density=AIR["density"], eos={"type": "ideal-gas", "gamma": AIR["gamma"]}))
        bodies.insert(0, Body("air", box=Box([0.0, 0.0], [60e-3, 40e-3]), material="air", representation="cells",
                              pressure=AIR["pressure"], priority=0))
        plate.priority = flyer.priority = 1
    # the flyer and the plate are in contact (the default), in air too: where they
    # meet, the air's share of the nodes is split between them (docs/contact.md)
    return Scene(2, Grid([0.0, 0.0], [60e-3, 40e-3], list(cells)), mats, bodies,
                 Run(t_end=t_end, output_interval=output_interval))


# the picture frames the impact region (m)
ZOOM = [0.022, 0.014, 0.038, 0.027]
# --air: the cells pictures (name, --cells value, log scale, range) and their frame (m)
CELLS = [("pressure", "pressure", True, (2e4, 2e6)), ("air", "volume_fraction:air", False, None)]
CELLS_ZOOM = [0.010, 0.006, 0.050, 0.034]

if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("-o", "--output", help="marker file (default out/oblique_plate_2d.h5), or with --run the "
                    "output directory (default out/oblique_plate_2d)")
    ap.add_argument("--png", help="the orientation picture (default out/oblique_plate_2d.png; with --air ..._air.png)")
    ap.add_argument("--cells", type=int, nargs=2, help="grid cells in x and y (default 240 160; with --air 96 64)")
    ap.add_argument("--run", action="store_true", help="run the impact (under mpiexec) and draw its pictures")
    ap.add_argument("--air", action="store_true", help="the scene in ambient air (cells) and pictures of cells and markers")
    a, petsc = ap.parse_known_args()
    from plyshock.cli import run_impact, run_scene
    cells = a.cells or ((96, 64) if a.air else (240, 160))
    name = "out/oblique_plate_2d_air" if a.air else "out/oblique_plate_2d"
    if a.run:
        sys.exit(run_impact(setup(cells=cells, air=a.air), a.output or name, petsc, zoom=ZOOM, projectile="flyer",
                            cells=CELLS if a.air else None, cells_zoom=CELLS_ZOOM))
    sys.exit(run_scene(setup(cells=cells, air=a.air), a.output or name + ".h5", a.png or name + ".png", petsc, zoom=ZOOM))
