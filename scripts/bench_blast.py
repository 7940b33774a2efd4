"""The coupled blast example's run time (issue 12, item 12): the blast on a
composite panel (examples/blast_panel_2d.py: gas charge and air in cells, the
[0/90]s panel and its supports on markers, 1 mm cells, 75 us), run with its
outputs but without pictures, against the same panel and supports alone in
vacuum (the cell bodies removed: markers only) in this same process, so the
figure is the cost the Eulerian host adds to a marker run of this scene.

    mpiexec -n 2 .venv/bin/python scripts/bench_blast.py
"""
import os
import sys

import petsc4py

petsc4py.init(sys.argv[:1] + [a for a in sys.argv[1:] if a.startswith("-")])
from petsc4py import PETSc  # noqa: E402

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "examples"))
import blast_panel_2d  # noqa: E402

from plyshock import core  # noqa: E402
from plyshock.verify import run_scratch  # noqa: E402

comm = PETSc.COMM_WORLD


def timed(scene):
    """Whole run (insertion, steps, outputs into a scratch directory) on every rank: its wall seconds."""
    core.run_options(scene)
    return run_scratch(scene, lambda d: None)[1]


blast = blast_panel_2d.setup().validate()
alone = blast_panel_2d.setup().validate()
alone.bodies = [b for b in alone.bodies if b.representation != "cells"]
alone = alone.validate()
tb = timed(blast)
tv = timed(alone)
if comm.getRank() == 0:
    print(f"blast on a panel (2D, 75 us, cells + markers), {comm.getSize()} rank(s): {tb:.2f} s; "
          f"the panel alone in vacuum (markers only): {tv:.2f} s; the cells cost {tb / tv:.2f}x the markers-only run")
    print(f"BENCH blast_seconds_{comm.getSize()} {tb:.6e}")
    print(f"BENCH blast_vacuum_seconds_{comm.getSize()} {tv:.6e}")
