"""The coupled blast example's run time (issue 12, item 12): the blast on a
composite panel (examples/blast_panel_2d.py: gas charge and air in cells, the
[0/90]s panel and its supports on markers, 1 mm cells, 75 us), run with its
outputs but without pictures, against the same panel and supports alone in
vacuum (the cell bodies removed: markers only) in this same process, so the
figure is the cost the Eulerian host adds to a marker run of this scene.

    mpiexec -n 2 .venv/bin/python scripts/bench_blast.py
"""
import os
import shutil
import sys
import tempfile
import time

import petsc4py

petsc4py.init(sys.argv[:1] + [a for a in sys.argv[1:] if a.startswith("-")])
from petsc4py import PETSc  # noqa: E402

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "examples"))
import blast_panel_2d  # noqa: E402

from plyshock import core  # noqa: E402

comm = PETSc.COMM_WORLD
mpi = comm.tompi4py()


def timed(scene, outdir):
    """Whole run (insertion, steps, outputs) on every rank: its wall seconds."""
    core.run_options(scene)
    mpi.Barrier()
    t = time.perf_counter()
    m = core.initialize(scene)
    S = core.make_solver(m)
    core.run(m, outdir, scene.to_yaml(), S)
    mpi.Barrier()
    return time.perf_counter() - t


blast = blast_panel_2d.setup().validate()
alone = blast_panel_2d.setup().validate()
alone.bodies = [b for b in alone.bodies if b.representation != "cells"]
alone = alone.validate()
tmp = mpi.bcast(tempfile.mkdtemp(prefix="plyshock-bench-") if comm.getRank() == 0 else None)
tb = timed(blast, os.path.join(tmp, "blast"))
tv = timed(alone, os.path.join(tmp, "alone"))
if comm.getRank() == 0:
    print(f"blast on a panel (2D, 75 us, cells + markers), {comm.getSize()} rank(s): {tb:.2f} s; "
          f"the panel alone in vacuum (markers only): {tv:.2f} s; the cells cost {tb / tv:.2f}x the markers-only run")
    print(f"BENCH blast_seconds_{comm.getSize()} {tb:.6e}")
    print(f"BENCH blast_vacuum_seconds_{comm.getSize()} {tv:.6e}")
    shutil.rmtree(tmp, ignore_errors=True)
