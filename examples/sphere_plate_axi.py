"""Axisymmetric 2D: a copper sphere normally impacting a steel plate (SI units).

geometry: axisymmetric (x = r, y = z; the x- face is the axis). A 4340 steel
plate 3 mm thick and 25 mm in radius (Johnson-Cook strength, Mie-Grueneisen
EOS), its upper face at z = 0; an OFHC copper sphere of radius 3 mm (a disk on
the axis in r-z), 0.5 mm above it, moving at 600 m/s in -z. Every marker's mass
is that of its ring (the full revolution): the sphere weighs 4/3 pi R^3 rho.
The 3D example (sphere_plate_3d.py) strikes a laminate of UD plies instead; UD
plies are not bodies of revolution, so axisymmetric decks refuse them.

    python examples/sphere_plate_axi.py [-o OUT.h5] [--png FILE] [--cell 0.25e-3]
    mpiexec -n 2 python examples/sphere_plate_axi.py --run [-o OUTDIR] [--cell 0.125e-3]

The first form inserts the markers and draws them; the second runs the impact
to 8 us and draws before.png, after.png (the markers), pressure.png (at 2 us),
plastic.png (plastic strain at the end) and velocity.png (the sphere's mean
velocity against time) in OUTDIR.

The run is MUSL with quadratic B-splines, F-bar and a 1% PIC share (as the
axisymmetric Taylor bar); the PIC share removes kinetic energy without heating:
at 0.5 mm cells the total energy falls by 9% to 4 us (plane strain, the same
scene: 7%; with no PIC share 2% and 0%, but a noisier field).

setup(**kw) returns the Scene; tests call it at small size.
"""
import argparse
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "python"))
from plyshock import Body, Box, Grid, Material, Run, Scene, Sphere  # noqa: E402


def setup(cell=0.25e-3, subdivision=2, radius=3e-3, speed=600.0, thickness=3e-3, t_end=8e-6, output_interval=2e-6):
    lower, upper = [0.0, -thickness - 3e-3], [25e-3, 10e-3]
    cells = [max(1, round((u - l) / cell)) for l, u in zip(lower, upper)]
    plate = Body("plate", box=Box([0.0, -thickness], [25e-3, 0.0]), material="4340-steel", subdivision=subdivision)
    ball = Body("sphere", sphere=Sphere([0.0, 0.5e-3 + radius], radius), material="OFHC-copper",
                velocity=[0.0, -speed], subdivision=subdivision)
    boundary = {"x-": "symmetry", "x+": "free", "y-": "free", "y+": "free"}
    return Scene(2, Grid(lower, upper, cells, boundary),
                 [Material("4340-steel", preset="4340-steel"), Material("OFHC-copper", preset="OFHC-copper")],
                 [plate, ball], Run(t_end=t_end, output_interval=output_interval, shape="bspline2", fbar=True,
                                    pic_fraction=0.01),
                 geometry="axisymmetric")   # sphere and plate in contact (the default): each its own velocity field


# the pictures frame the impact region (m): r from the axis, z across the plate
ZOOM = [0.0, -6.5e-3, 12e-3, 7e-3]

# fields drawn by the post-processing: (picture, output number (-1: the last), field, colour range); the
# pressure at the first output (2 us: the shock in the plate), on a fixed scale (a marker where the sphere
# meets the plate reaches 10.9 GPa, which would otherwise set it; 40 GPa when the two were bonded)
FIELDS = [("pressure", 1, "pressure", (-2e9, 8e9)), ("plastic", -1, "plastic_strain", (0.0, 1.0))]


def draw_fields(outdir):
    """pressure.png and plastic.png (FIELDS) of the run in OUTDIR (rank 0); exit status."""
    import glob
    from mpi4py import MPI
    if MPI.COMM_WORLD.rank == 0:
        from plyshock.post import plot_field
        steps = sorted(glob.glob(os.path.join(outdir, "markers_*.h5")))
        for name, k, field, rng in FIELDS:
            png = plot_field(steps[k], os.path.join(outdir, name + ".png"), field, zoom=ZOOM, field_range=rng)
            print(f"wrote {png}", flush=True)
    return 0


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("-o", "--output", help="marker file (default out/sphere_plate_axi.h5), or with --run the "
                    "output directory (default out/sphere_plate_axi)")
    ap.add_argument("--png", default="out/sphere_plate_axi.png")
    ap.add_argument("--cell", type=float, default=0.25e-3, help="cell size (m)")
    ap.add_argument("--run", action="store_true", help="run the impact (under mpiexec) and draw its pictures")
    a, petsc = ap.parse_known_args()
    from plyshock.cli import run_impact, run_scene
    sc = setup(cell=a.cell)
    if a.run:
        out = a.output or "out/sphere_plate_axi"
        rc = run_impact(sc, out, petsc, zoom=ZOOM, projectile="sphere")
        if rc == 0:
            sys.exit(draw_fields(out))
        sys.exit(rc)
    sys.exit(run_scene(sc, a.output or "out/sphere_plate_axi.h5", a.png, petsc, zoom=ZOOM))
