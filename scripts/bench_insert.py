"""Insertion benchmark (issue: exact layered-composite marker insertion).

Standard case: the unit cube with 64^3 cells, subdivision 1, one laminate
through the centre covering the cube, 8 plies each 0.37 cell thick, stacking
direction (0.3, 0.5, 0.81) normalised.  Prints cut pieces (non-empty sub-cell ∩
ply pieces) per second per core for
  - the geometry kernel alone (counting mode: clip, moments, sliver merging),
  - full insertion (kernel + marker list + DMSwarm fill),
and, as a reference in the same run, a solid box insertion making about as many
uncut markers (no clipping).  The r3d figure quoted for comparison (1.4 M cut
cells/s/core, box clipped by such a slab with first moments) was measured on
the project's 2-core machines and is not re-run here.
"""
import sys
import time

import numpy as np
import petsc4py

petsc4py.init(sys.argv[:1] + [a for a in sys.argv[1:] if a.startswith("-")])
from petsc4py import PETSc  # noqa: E402
from mpi4py import MPI  # noqa: E402

from plyshock import Body, Box, Frame, Grid, Laminate, Material, Ply, Scene  # noqa: E402
from plyshock import core  # noqa: E402

R3D = 1.4e6
N = 64
comm = PETSc.COMM_WORLD
mpi = comm.tompi4py()
size = comm.getSize()


def laminate_scene():
    n3 = np.array([0.3, 0.5, 0.81]) / np.linalg.norm([0.3, 0.5, 0.81])
    t1 = np.cross(n3, [1.0, 0, 0]); t1 /= np.linalg.norm(t1)
    t2 = np.cross(n3, t1)
    T = 8 * 0.37 / N
    o = np.full(3, 0.5) - 2.0 * t1 - 2.0 * t2 - 0.5 * T * n3        # laminate centred, 4 x 4 wide
    frame = Frame(o.tolist(), (o + n3).tolist(), (o + t1).tolist())
    plies = [Ply("cfrp", 0.37 / N, [[3, a]]) for a in (0, 45, -45, 90, 90, -45, 45, 0)]
    lam = Body("lam", laminate=Laminate(frame, [4.0, 4.0], plies), clip=True)
    return Scene(3, Grid([0, 0, 0], [1, 1, 1], [N] * 3), [Material("cfrp", preset="IM7/8552")], [lam]).validate()


def best_of(fn, repeat=3):
    ts = []
    for _ in range(repeat):
        mpi.Barrier()
        t = time.perf_counter()
        out = fn()
        mpi.Barrier()
        ts.append(time.perf_counter() - t)
    return min(ts), out


def main():
    scene = laminate_scene()
    cs = core.c_scene(scene)
    # geometry kernel alone, one rank's worth of the cells (split in z like the DMDA would)
    t_kernel, counts = best_of(lambda: cs.count([0, 0, 0], [N, N, N]), repeat=10)
    pieces = int(counts.sum())
    # insertion into a DMSwarm (C: kernel, marker list, field fill) on this communicator
    from plyshock import _core
    _core.initialize()
    m0 = core.initialize(scene, cs)          # the grid, made once

    def insert(c=cs, da=m0.da):
        sw = PETSc.DMSwarm().create(comm=comm)
        sw.setDimension(3)
        sw.setType(PETSc.DMSwarm.Type.BASIC)
        mpi.Barrier()
        t = time.perf_counter()
        st = c.insert(da, sw)
        t = time.perf_counter() - t
        sw.destroy()
        return mpi.allreduce(t, op=MPI.MAX), mpi.allreduce(st["pieces"]), mpi.allreduce(st["markers"])

    t_ins, npieces, _ = min(insert() for _ in range(5))
    # reference: a solid box with about as many uncut markers
    nb = max(1, round((pieces / N**2)))
    box = Scene(3, Grid([0, 0, 0], [1, 1, 1], [N] * 3), [Material("steel", preset="4340-steel")],
                [Body("block", box=Box([0, 0, 0.25], [1, 1, 0.25 + nb / N]), material="steel")]).validate()
    csb = core.c_scene(box)

    t_box, _, nbox = min(insert(csb, core.initialize(box, csb).da) for _ in range(5))
    if comm.getRank() == 0:
        k_rate = pieces / t_kernel
        i_rate = npieces / t_ins / size
        b_rate = nbox / t_box / size
        print(f"insertion benchmark: unit cube {N}^3 cells, 8 plies 0.37 cell thick, normal (0.3,0.5,0.81); {size} rank(s)")
        print(f"  cut pieces: {npieces}")
        print(f"  geometry kernel (1 core, serial count): {k_rate / 1e6:.2f} M pieces/s/core = {k_rate / R3D:.2f} x r3d's 1.4 M/s")
        print(f"  insertion into the DMSwarm (PSInsertMarkers, all ranks): {i_rate / 1e6:.2f} M pieces/s/core = {i_rate / R3D:.2f} x r3d's 1.4 M/s")
        print(f"  reference in this run, solid box of {nbox} uncut markers: {b_rate / 1e6:.2f} M markers/s/core; "
              f"exact cut pieces cost {b_rate / i_rate:.2f} x an uncut marker")
        print(f"  bytes per marker: {cs.marker_bytes(None)}")
        print(f"BENCH insert_kernel_{size} {k_rate:.6e}")
        print(f"BENCH insert_{size} {i_rate:.6e}")
        print(f"BENCH insert_box_{size} {b_rate:.6e}")


main()
