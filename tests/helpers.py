"""Shared helpers of the tests: random oblique scenes and gathered marker views."""
import numpy as np
from mpi4py import MPI

from plyshock import Body, Frame, Grid, Laminate, Material, Scene
from plyshock import core

LAYUPS = ["[0/90/90/0]", "[0/±45/90]s", "[45/-45]3", "[(0/90)2]s", "[30/-60/15]"]


def random_laminate_scene(dim, rng, boundary_kind="free", subdivision=None, cells_range=(5, 12)):
    """A random oblique laminate that may cross the grid's faces (clipped)."""
    lo = rng.uniform(-1, 0.5, dim)
    hi = lo + rng.uniform(0.6, 1.4, dim)
    cells = rng.integers(*cells_range, dim).tolist()
    o = lo + rng.uniform(0.15, 0.6, dim) * (hi - lo)
    a3 = o + rng.normal(size=dim)
    p13 = o + rng.normal(size=dim)
    layup = str(rng.choice(LAYUPS))
    size = rng.uniform(0.3, 1.2, dim - 1).tolist()
    t = float(rng.uniform(0.02, 0.1))
    lam = Laminate.from_layup(Frame(o.tolist(), a3.tolist(), p13.tolist()), size, layup, t, "cfrp")
    s = int(rng.integers(1, 3)) if subdivision is None else subdivision
    faces = ["x-", "x+", "y-", "y+", "z-", "z+"][: 2 * dim]
    if boundary_kind == "mixed":
        boundary = {f: str(rng.choice(["symmetry", "free"])) for f in faces}
    else:
        boundary = {f: boundary_kind for f in faces}
    body = Body("plate", laminate=lam, subdivision=s, clip=True)
    return Scene(dim, Grid(lo.tolist(), hi.tolist(), cells, boundary), [Material("cfrp", preset="IM7/8552")], [body]).validate()


def gather(m, names):
    """All ranks' marker fields concatenated on every rank (tests only, small)."""
    f = core.local_fields(m, names)
    comm = m.sw.getComm().tompi4py()
    return {k: np.concatenate(comm.allgather(v)) for k, v in f.items()}


def laminate_frame(body, dim):
    """(origin, in-plane axes in dim components) of a laminate: axes 1(,2),3."""
    E = np.asarray(body._axes)
    axes = [E[0], E[2]] if dim == 2 else [E[0], E[1], E[2]]
    return np.array(body.laminate.frame.origin, float), np.array([a[:dim] for a in axes])


def ply_bounds(body, k, dim):
    """Frame-coordinate bounds (lo, hi) of ply k (k = -1: the whole laminate)."""
    z0, z1 = (body._z[k], body._z[k + 1]) if k >= 0 else (0.0, body._z[-1])
    return [0.0] * (dim - 1) + [z0], list(body.laminate.size) + [z1]


def allreduce_sum(x):
    return MPI.COMM_WORLD.allreduce(x, op=MPI.SUM)
