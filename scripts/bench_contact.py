"""Contact's overhead (issue 13, item 5): the 2D oblique plate example
(examples/oblique_plate_2d.py at its default 240 x 160 cells; the flyer and
the plate) run with its default contact (each body its own velocity field
where they meet, friction 0) and with `contact: {type: bonded}` (one field),
in this same process: marker-steps per second per core, best of three runs
of 100 steps after the flyer has reached the plate (the first 300 steps are
not timed), no output; and the plate's plies with cohesive interfaces
(interface: cohesive with the 3D example's constants: each ply its own field,
the traction-separation law where plies meet) against bonded plies.

    mpiexec -n 1 .venv/bin/python scripts/bench_contact.py
"""
import os
import sys

import petsc4py

petsc4py.init(sys.argv[:1] + [a for a in sys.argv[1:] if a.startswith("-")])
from petsc4py import PETSc  # noqa: E402

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "examples"))
import oblique_plate_2d  # noqa: E402

from plyshock import Contact, core  # noqa: E402
from benchlib import timed_steps  # noqa: E402  (scripts/benchlib.py)

comm = PETSc.COMM_WORLD
mpi = comm.tompi4py()
STEPS, WARM = 100, 300


def bench(contact, interface=None):
    scene = oblique_plate_2d.setup()
    scene.contact = contact
    next(b for b in scene.bodies if b.name == "plate").laminate.interface = interface
    scene = scene.validate()
    core.run_options(scene)
    m = core.initialize(scene)
    S = core.make_solver(m)
    for _ in range(WARM):
        S.step()
    ts = []
    for _ in range(3):
        ts.append(timed_steps(S, STEPS, mpi))
    n = m.stats["markers"]
    return n * STEPS / min(ts) / comm.getSize(), n


from sphere_plate_3d import INTERFACE  # noqa: E402

multi, n = bench(None)                                 # the default: friction 0 between flyer and plate
bonded, _ = bench(Contact(type="bonded"))
cohesive, _ = bench(None, INTERFACE)                   # and each ply its own field with cohesive interfaces
r = comm.getSize()
if comm.getRank() == 0:
    print(f"contact benchmark (oblique plate 2D, 240 x 160 cells, {n} markers, {STEPS} steps after {WARM}): {r} rank(s)")
    print(f"  contact (two fields where flyer and plate meet): {multi / 1e6:.3f} M marker-steps/s/core; "
          f"bonded (one field): {bonded / 1e6:.3f} M/s/core; contact runs {multi / bonded:.2f}x bonded")
    print(f"  plate's plies with cohesive interfaces (a field per ply, 5 in all): {cohesive / 1e6:.3f} M/s/core; "
          f"{cohesive / bonded:.2f}x bonded")
    print(f"BENCH contact_multi_{r} {multi:.6e}")
    print(f"BENCH contact_cohesive_{r} {cohesive:.6e}")
    print(f"BENCH contact_bonded_{r} {bonded:.6e}")
