"""The one place where scene objects become C calls (through _core).

    cs = c_scene(scene)                 # a C PSScene, no PETSc objects
    report = check_geometry(scene, cs)  # bodies vs domain, overlaps: DeckError
    m = initialize(scene, cs)           # DMDA + DMSwarm with exact markers
    write_markers(m, "out.h5", deck_text)
"""
import os
import sys
from dataclasses import dataclass

import numpy as np

from .errors import DeckError
from .scene import MTS_KEYS, TEMPERATURE_STRENGTHS

_FACE = {0: ("x-", "x+"), 1: ("y-", "y+"), 2: ("z-", "z+")}
PAD = 1   # = PS_PAD in src/plyshock.h


def scene_to_c(scene):
    """The plain dict _core.CScene reads (SI units, 3-vectors)."""
    dim = scene.dimension
    pad = lambda v: list(v) + [0.0] * (3 - len(v))
    cellmat = scene.cell_materials
    bodies = []
    for b in scene.bodies:
        lattice = b.insertion == "lattice"
        d = dict(kind=b.kind, priority=b.priority or 0, subdivision=1 if lattice else b.subdivision,
                 insertion=b.insertion, points_per_cell=b.points_per_cell if lattice else 1,
                 volume_tolerance=b.volume_tolerance or 1e-6, sliver_fraction=b.sliver_fraction or 0.0,
                 velocity=pad(b.velocity), origin=[0.0] * 3, e=np.eye(3).tolist(), size=[0.0] * 3,
                 center=[0.0] * 3, axis=[0.0] * 3, radius=0.0, length=0.0, z=[],
                 cellmat=cellmat.index(b._mat) if b.representation == "cells" else -1, pressure=b.pressure or 0.0,
                 density=b.density or 0.0, plastic_strain=b.plastic_strain or 0.0)
        if b.kind == "laminate":
            lam = b.laminate
            size = list(lam.size) + ([0.0] if dim == 2 else [])
            d.update(origin=pad(lam.frame.origin), e=np.asarray(b._axes).tolist(),
                     size=[size[0], size[1], b._z[-1]], z=list(b._z), ply_material=list(b._ply_mat),
                     ply_axes=[np.asarray(E).reshape(9).tolist() for E in b._ply_axes])
        else:
            d["material"] = b._mat
            if b.kind == "box":
                d.update(origin=pad(b.box.lower), size=pad(np.subtract(b.box.upper, b.box.lower).tolist()))
                if dim == 2:   # a 2D box spans axes 1 and 3 of its frame (x and y)
                    d.update(e=[[1, 0, 0], [0, 0, 1], [0, 1, 0]], size=[d["size"][0], 0.0, d["size"][1]])
            elif b.kind == "sphere":
                d.update(center=pad(b.sphere.center), radius=b.sphere.radius)
            else:
                c = b.cylinder
                d.update(center=pad(c.base), axis=pad(c.axis), radius=c.radius, length=c.length)
        bodies.append(d)
    return dict(dim=dim, lower=pad(scene.grid.lower), upper=pad(scene.grid.upper),
                cells=list(scene.grid.cells) + [1] * (3 - dim),
                density=[m.density for m in scene.materials], anisotropic=scene.anisotropic, bodies=bodies,
                need_plastic=any(m.strength is not None and m.strength.get("type") != "none" for m in scene.materials),
                need_temperature=any((m.strength or {}).get("type") in TEMPERATURE_STRENGTHS for m in scene.materials),
                ndamage=4 if any((m.failure or {}).get("type") == "hashin" for m in scene.materials)
                else 1 if any(m.failure is not None for m in scene.materials) else 0,
                T0=[float((m.strength or {}).get("T_room", 294.0)) for m in scene.materials],
                need_affine=transfer(scene) == "apic", cellmat=cellmat, axisymmetric=scene.axisymmetric,
                need_interface=any(b.kind == "laminate" and b.representation == "markers" and b.laminate.interface is not None
                                   and b.laminate.interface.cohesive for b in scene.bodies))


def run_options(scene):
    """The run parameters in force: the deck's run: section with the
    -run_<key> options of the command line over it, checked in one place
    (C's PSRunParamsCheck).  Raises DeckError naming the key before any work."""
    from petsc4py import PETSc
    from . import _core
    from .scene import SHAPE_FUNCTIONS, TRANSFERS
    opts = PETSc.Options()
    for key, names in (("shape", SHAPE_FUNCTIONS), ("transfer", TRANSFERS)):
        v = opts.getString(f"run_{key}") if opts.hasName(f"run_{key}") else None
        if v is not None and v not in names:
            raise DeckError(f"-run_{key}", f"must be one of {'|'.join(names)}, got {v!r}")
    if scene.run is None:
        raise DeckError("run", "a run needs a run: section with at least t_end (s)")
    try:
        params, key, msg = _core.run_params(run_to_c(scene.run))
    except PETSc.Error as e:          # an option PETSc cannot read (-run_cfl abc): every rank reads it alike
        tb = getattr(e, "_traceback_", None) or ["?"]
        raise DeckError("-run_<key>", f"{tb[-1].strip()} (a -run_<key> option on the command line)") from None
    if key is not None:
        opt = "-run_lanes" if key == "-run_lanes" else "-run_" + key.split(".")[-1]
        raise DeckError(key, f"{msg} (the deck's {key} or the option {opt})" if key != "-run_lanes" else msg)
    if scene.axisymmetric and params["transfer"] != "musl":
        raise DeckError("run.transfer", f"{params['transfer']} is not available with geometry: axisymmetric; allowed: musl "
                        "(the deck's run.transfer or the option -run_transfer)")
    lay = scene.contact.layout(scene) if scene.contact is not None else None
    if params["transfer"] != "musl" and lay is not None and lay["nfield"] >= 2:
        split = [i for i, sp in enumerate(lay["split"]) if sp]
        if split:      # a field per ply: the laminate's interfaces ask for it, not (only) the contact section
            raise DeckError(f"bodies[{split[0]}].laminate.interface", f"cohesive ply interfaces need run.transfer: musl "
                            f"(got {params['transfer']}; the fields are implemented for MUSL only); set run.transfer: musl, "
                            "or interface: {type: bonded}")
        raise DeckError("contact", f"friction needs run.transfer: musl (got {params['transfer']}; multi-field contact "
                        "is implemented for MUSL only); set run.transfer: musl, or contact: {type: bonded}")
    return params


def contact_fields(scene):
    """(field of each body, nfield, friction matrix) of the scene's contact
    section (scene.Contact.fields); one field without a section (not validated)."""
    if scene.contact is None:
        return [0] * len(scene.bodies), 1, np.zeros((1, 1))
    return scene.contact.fields(scene)


def transfer(scene):
    """The run's transfer scheme (it decides which marker fields exist, so it
    is known before the markers are made); musl for a deck without a run."""
    return run_options(scene)["transfer"] if scene.run is not None else "musl"


def c_scene(scene):
    from . import _core
    return _core.CScene(scene_to_c(scene))


def check_geometry(scene, cs):
    """Bodies against the domain and each other; raises DeckError.

    Returns {body name: clipped-away volume} for bodies cut by a face (symmetry
    faces always, other faces only with clip: true).  Runs in C on the plain
    scene struct, before any PETSc object is made.
    """
    g, dim = scene.grid, scene.dimension
    clipped = {}
    size = max(u - l for l, u in zip(g.lower, g.upper))
    tol = 1e-12 * size
    for i, b in enumerate(scene.bodies):
        lo, hi = cs.bounding_box(i)
        for a in range(dim):
            if hi[a] <= g.lower[a] + tol or lo[a] >= g.upper[a] - tol:
                raise DeckError(f"bodies[{i}]", f"body '{b.name}' lies wholly outside the grid "
                                f"(its extent along {'xyz'[a]} is [{lo[a]:.6g}, {hi[a]:.6g}] m, the grid's [{g.lower[a]:.6g}, {g.upper[a]:.6g}] m)")
        crossed = []
        for a in range(dim):
            if lo[a] < g.lower[a] - tol:
                crossed.append(_FACE[a][0])
            if hi[a] > g.upper[a] + tol:
                crossed.append(_FACE[a][1])
        for f in crossed:
            if g.boundary[f] != "symmetry" and not b.clip:
                raise DeckError(f"bodies[{i}].clip", f"body '{b.name}' crosses the {g.boundary[f]} face {f} of the grid; "
                                f"move it inside, or set clip: true to cut it there (the clipped-away volume is reported)")
        if crossed:
            inside = cs.domain_volume(i)
            if inside <= 0.0:
                raise DeckError(f"bodies[{i}]", f"body '{b.name}' lies wholly outside the grid")
            clipped[b.name] = cs.body_volume(i) - inside
    # overlaps: positive common volume; touching bodies do not overlap
    for i in range(len(scene.bodies)):
        for j in range(i + 1, len(scene.bodies)):
            lo1, hi1 = cs.bounding_box(i)
            lo2, hi2 = cs.bounding_box(j)
            if any(min(hi1[a], hi2[a]) <= max(lo1[a], lo2[a]) + tol for a in range(dim)):
                continue
            v = cs.overlap_volume(i, j)
            bi, bj = scene.bodies[i], scene.bodies[j]
            if v > 1e-9 * min(cs.body_volume(i), cs.body_volume(j)) and (bi.priority or 0) == (bj.priority or 0):
                raise DeckError(f"bodies[{j}]", f"bodies '{bi.name}' and '{bj.name}' overlap ({v:.6g} m^{dim} in common); "
                                f"move them apart, or give them different priority (the higher wins the overlap)")
    return clipped


# bytes per grid node: the DMDA vectors the solver keeps (global and ghosted
# local of m, mv, f; of the re-projected v; one output vector; coordinates),
# reals, plus about two indices of maps and halo (an estimate, not a count)
def _grid_bytes_per_node(dim):
    return 8 * (3 + 8 * dim) + 16


# per marker besides its fields: the step's scratch (displacement; under musl
# where the marker sits, PSShapeAt of src/shape.h, 88 bytes, and L_p, 9 reals)
# and a quarter of spare swarm buffer
def _marker_bytes(dim, field_bytes):
    return int(1.25 * field_bytes) + 8 * dim + 88 + 9 * 8


def machine_memory():
    """This machine's physical memory (bytes)."""
    try:
        with open("/proc/meminfo") as f:
            for line in f:
                if line.startswith("MemTotal:"):
                    return int(line.split()[1]) * 1024
    except OSError:
        pass
    return os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES")


def PSC(dim):
    """Stress components per marker or cell material: 6 in 3D, 4 in 2D (xx, yy, zz, xy)."""
    return 6 if dim == 3 else 4


def resources(scene, cs, markers=None, hosts=1, ranks=1):
    """What a scene needs before anything is made: grid nodes, the entries of
    the largest grid vector against PETSc's index size, and memory (bytes) for
    the grid and the markers (markers: an exact count, else an estimate from
    the bodies' volumes) against the memory of the machines (hosts of this
    machine's size).  No PETSc object is made."""
    from petsc4py import PETSc
    g, dim = scene.grid, scene.dimension
    nodes = int(np.prod([n + 1 + 2 * PAD for n in g.cells]))
    cells = int(np.prod(g.cells))
    estimated = markers is None
    if markers is None:        # each body's volume in cells, times its sub-cells: a floor for the count
        vcell = float(np.prod(g.h))
        vgrid = float(np.prod(np.subtract(g.upper, g.lower)))
        per_cell = lambda b: (0 if b.representation == "cells" else
                              (b.points_per_cell or 2) ** dim if b.insertion == "lattice" else (b.subdivision or 1) ** dim)
        markers = round(sum(min(cs.body_volume(i), vgrid) / vcell * per_cell(b) for i, b in enumerate(scene.bodies)))
    per_marker = _marker_bytes(dim, cs.marker_bytes(None))
    # Eulerian cells: per cell and cell material V, M, E (and the strength state), 4 more per cell; per node
    # the cells' momentum, its scratch, velocity and mass
    ncm = len(scene.cell_materials)
    strength = any((scene.materials[i].strength or {}).get("type", "none") != "none" for i in scene.cell_materials)
    cell_dof = ncm * (3 + (PSC(dim) + 2 if strength else 0)) + 4 if ncm else 0
    # the state and its scratch per cell, the predictor's half-step values (cells.h PSCellsHalfSize), its mass;
    # per node P, Pn, vh, v^n, the force change (dim each) and m^C
    cell_half = ncm * (1 + PSC(dim)) + 13
    cell_bytes = 8 * (cells * (cell_dof + cell_half + 1) + nodes * (5 * dim + 1)) if ncm else 0
    # velocity fields of bodies in contact (and plies with cohesive interfaces): per node and field
    # the P2G/grid block (4 + 4 dim reals, contact.h), the re-projection (dim) and the mass pass (1),
    # plus a flag
    nfield = scene.contact.layout(scene)["nfield"] if scene.contact is not None else 1
    field_bytes = nodes * (8 * nfield * (5 + 5 * dim) + 1) if nfield >= 2 else 0
    return dict(cells=cells, nodes=nodes, entries=nodes * (1 + 2 * dim), index_max=int(np.iinfo(PETSc.IntType).max),
                index_bits=8 * np.dtype(PETSc.IntType).itemsize, markers=markers, markers_estimated=estimated,
                grid_bytes=nodes * _grid_bytes_per_node(dim) + cell_bytes + field_bytes, marker_bytes=markers * per_marker,
                velocity_fields=nfield,
                machine_bytes=machine_memory() * hosts, hosts=hosts, ranks=ranks)


def describe_resources(r):
    mib = 2.0 ** 20
    tot = r["grid_bytes"] + r["marker_bytes"]
    where = "this machine's" if r["hosts"] == 1 else f"{r['hosts']} machines'"
    fields = f", {r['velocity_fields']} velocity fields" if r.get("velocity_fields", 1) >= 2 else ""
    return (f"about {tot / mib:.1f} MiB (grid of {r['nodes']} nodes{fields} {r['grid_bytes'] / mib:.1f} MiB, "
            f"{'at least ' if r['markers_estimated'] else ''}{r['markers']} markers {r['marker_bytes'] / mib:.1f} MiB) "
            f"of {where} {r['machine_bytes'] / mib:.0f} MiB")


def check_resources(r, scene):
    """DeckError (grid.cells) when the grid overflows PETSc's index or the
    run would not fit in memory; r from resources()."""
    cells = " x ".join(map(str, scene.grid.cells))
    if r["entries"] > r["index_max"] or r["cells"] > r["index_max"]:
        raise DeckError("grid.cells", f"{cells} = {r['cells']:.4g} cells: the grid vectors would hold {r['entries']:.4g} entries, "
                        f"beyond PETSc's {r['index_bits']}-bit index limit {r['index_max']}; use fewer cells")
    if r["markers"] / max(r["ranks"], 1) > r["index_max"]:
        raise DeckError("grid.cells", f"{r['markers']:.4g} markers on {r['ranks']} rank(s) exceed PETSc's "
                        f"{r['index_bits']}-bit index limit {r['index_max']} per rank; use fewer cells or more ranks")
    if r["grid_bytes"] + r["marker_bytes"] > r["machine_bytes"]:
        raise DeckError("grid.cells", f"{cells} cells need more memory than there is: {describe_resources(r)}; "
                        f"use fewer cells or sub-cells, or more machines")


def verify_checkpoint(scene, path, cs=None):
    """A checkpoint fit to restart this scene from, or DeckError(--restart) saying
    what is wrong with it (missing, not HDF5, truncated, incomplete, damaged,
    another grid or deck), the same on every rank, before any work."""
    if not os.path.exists(path):
        raise DeckError("--restart", f"checkpoint {path} does not exist")
    if os.path.isdir(path):
        raise DeckError("--restart", f"{path} is a directory; give the checkpoint file (OUTDIR/checkpoint.h5)")
    msg = (cs or c_scene(scene)).verify_checkpoint(path)
    if msg:
        raise DeckError("--restart", f"checkpoint {path} {msg}")


def resume_outputs(outdir, step, time):
    """Before a restart into OUTDIR (rank 0): cut history.csv back to the rows
    before the checkpoint's step, bodies.csv and gauges.csv to those before its
    time, dropping a row a killed run left half written; the restarted run
    appends from there."""
    for name, col, limit in (("history.csv", 0, step), ("bodies.csv", 0, float(f"{time:.10e}")), ("gauges.csv", 0, float(f"{time:.10e}"))):
        fn = os.path.join(outdir, name)
        if not os.path.exists(fn):
            continue
        with open(fn, errors="replace") as f:
            lines = f.read().split("\n")
        keep = lines[:1]
        ncol = len(lines[0].split(","))
        for line in lines[1:]:
            cells = line.split(",")
            try:
                if len(cells) == ncol and float(cells[col]) < limit:
                    keep.append(line)
            except ValueError:
                pass
        with open(fn, "w") as f:
            f.write("\n".join(keep) + "\n")


def count_markers(scene, cs):
    """Markers per (body, ply+1) that insertion will make, counted serially, and
    bytes per marker; nothing is inserted and no PETSc object is made."""
    cells = list(scene.grid.cells) + [1] * (3 - scene.dimension)
    return cs.count([0, 0, 0], cells), cs.marker_bytes(None)


@dataclass
class Markers:
    scene: object
    cs: object
    da: object
    sw: object
    stats: dict
    bytes_per_marker: int
    clipped: dict


def initialize(scene, cs=None, comm=None, restart=False):
    """DMDA grid + DMSwarm markers with exact insertion, on any rank count
    (restart=True: an empty swarm with the scene's fields, for Solver.restart)."""
    from petsc4py import PETSc
    from . import _core
    if cs is None:
        cs = c_scene(scene)
    clipped = check_geometry(scene, cs)
    comm = comm or PETSc.COMM_WORLD
    from mpi4py import MPI
    hosts = len(set(comm.tompi4py().allgather(MPI.Get_processor_name())))
    check_resources(resources(scene, cs, hosts=hosts, ranks=comm.getSize()), scene)
    _core.initialize()
    g, dim = scene.grid, scene.dimension
    # nodes: cells + 1 plus PAD outside the domain on each side (shape functions
    # reach one cell out); dof = mass, momentum, force; stencil 2 for GIMP/B-splines
    dof = 1 + 2 * dim
    sizes = tuple(n + 1 + 2 * PAD for n in g.cells)
    da = PETSc.DMDA().create(dim=dim, dof=dof, sizes=sizes, stencil_width=2,
                             stencil_type=PETSc.DMDA.StencilType.BOX, comm=comm)
    # cell materials fill the grid: there a cell weighs like a few markers
    ranges = balanced_ranges(cs, g.cells, da.getProcSizes()[:dim], comm.tompi4py(),
                             grid_weight=4.0 if scene.cell_materials else 0.1)
    if ranges is not None:
        # the same process grid, its cuts moved so each rank holds a like share of markers
        da.destroy()
        da = PETSc.DMDA().create(dim=dim, dof=dof, sizes=sizes, proc_sizes=tuple(len(r) for r in ranges),
                                 ownership_ranges=ranges, stencil_width=2,
                                 stencil_type=PETSc.DMDA.StencilType.BOX, comm=comm)
    h = g.h
    da.setUniformCoordinates(*[v for a in range(dim) for v in (g.lower[a] - PAD * h[a], g.upper[a] + PAD * h[a])])
    sw = PETSc.DMSwarm().create(comm=comm)
    sw.setDimension(dim)
    sw.setType(PETSc.DMSwarm.Type.BASIC)
    mpi = comm.tompi4py()
    if restart:
        # fields only: the solver fills them from the checkpoint (restart())
        cs.register_fields(sw)
        m = Markers(scene, cs, da, sw, {}, 0, clipped)
        return m
    stats = cs.insert(da, sw)
    stats = {k: mpi.allreduce(v) for k, v in stats.items()}
    return Markers(scene, cs, da, sw, stats, cs.marker_bytes(sw), clipped)


def balanced_ranges(cs, cells, procs, mpi, grid_weight=0.1, min_cells=3):
    """DMDA node ownership ranges that balance the markers: along each split
    direction, contiguous cell ranges of about equal weight, a cell slab
    weighing its markers plus grid_weight per cell (the grid's share of a
    step).  Slab counts are shared among the ranks (each counts every size-th
    slab, exactly, in C) and summed; no rank counts the whole scene.  None
    when nothing is split or the scene is too small to move the cuts."""
    if all(P == 1 for P in procs):
        return None
    ranges = []
    for a, (n, P) in enumerate(zip(cells, procs)):
        if P == 1:
            ranges.append((n + 1 + 2 * PAD,))
            continue
        if n < P * min_cells:
            return None
        counts = cs.count_slabs(a, mpi.rank, mpi.size)
        from mpi4py import MPI
        mpi.Allreduce(MPI.IN_PLACE, counts, op=MPI.SUM)
        cross = int(np.prod([c for b, c in enumerate(cells) if b != a]))
        w = np.cumsum(counts + grid_weight * cross)
        # cut k after the slab where the cumulative weight passes k/P of the total
        cuts = [0]
        for k in range(1, P):
            c = int(np.searchsorted(w, k * w[-1] / P)) + 1
            c = min(max(c, cuts[-1] + min_cells), n - (P - k) * min_cells)
            cuts.append(c)
        cuts.append(n)
        # cell c is node c + PAD; the first rank also holds the PAD nodes before
        # the domain, the last the node after the last cell and the PAD after it
        nodes = [cuts[k + 1] - cuts[k] for k in range(P)]
        nodes[0] += PAD
        nodes[-1] += 1 + PAD
        ranges.append(tuple(nodes))
    return tuple(ranges)


def local_fields(m, names):
    """Copies of this rank's marker fields, shaped (n, block size)."""
    from . import _core
    bs = {"x": m.scene.dimension, "v": m.scene.dimension, "axes": 9}
    n = m.sw.getLocalSize()
    out = {}
    for name in names:
        if name == "id":
            out[name] = _core.get_int64_field(m.sw, name)
            continue
        f = m.sw.getField(name)
        a = np.array(f)
        out[name] = a.reshape(n, a.size // n if n else bs.get(name, 1))
        m.sw.restoreField(name)
    return out


def summary(m):
    """Global marker count and mass per (body, ply): {(body, ply): (count, mass)}."""
    has_ply = any(b.kind == "laminate" for b in m.scene.bodies)
    f = local_fields(m, ["body", "mass"] + (["ply"] if has_ply else []))
    body = f["body"][:, 0].astype(np.int64)
    ply = f["ply"][:, 0].astype(np.int64) if has_ply else -np.ones_like(body)
    P = m.cs.maxply + 1
    key = body * P + ply + 1
    nk = len(m.scene.bodies) * P
    count = np.bincount(key, minlength=nk).astype(np.int64)
    mass = np.bincount(key, weights=f["mass"][:, 0], minlength=nk)
    mpi = m.sw.getComm().tompi4py()
    from mpi4py import MPI
    mpi.Allreduce(MPI.IN_PLACE, count, op=MPI.SUM)
    mpi.Allreduce(MPI.IN_PLACE, mass, op=MPI.SUM)
    return {(int(k // P), int(k % P) - 1): (int(count[k]), float(mass[k])) for k in range(nk) if count[k]}


def write_markers(m, filename, deck_text):
    """The marker file (parallel HDF5) and its ParaView .xmf (rank 0)."""
    from petsc4py import PETSc
    from . import __version__
    comm = m.sw.getComm()
    opts = " ".join(f"-{k} {v}".strip() for k, v in PETSc.Options().getAll().items())
    attrs = {"deck": deck_text, "code_version": __version__, "petsc_options": opts,
             "ranks": str(comm.getSize()), "command": " ".join(sys.argv), "dimension": str(m.scene.dimension)}
    # HDF5 writes attributes collectively: every rank must pass the same values
    attrs = comm.tompi4py().bcast(attrs, root=0)
    m.cs.write(m.sw, filename, attrs, [b.name for b in m.scene.bodies], [x.name for x in m.scene.materials])
    if comm.getRank() == 0:
        write_xmf(filename, m.stats["markers"], m.scene.dimension, m.scene.anisotropic)
    comm.barrier()


def write_xmf(filename, n, dim, anisotropic):
    """An XDMF description of the marker file so ParaView opens it."""
    h5 = os.path.basename(filename)

    def item(path, dims, kind="Float", prec=8):
        return f'<DataItem Dimensions="{dims}" NumberType="{kind}" Precision="{prec}" Format="HDF">{h5}:{path}</DataItem>'

    attrs = [("mass", "Scalar", str(n), "Float", 8), ("volume", "Scalar", str(n), "Float", 8),
             ("id", "Scalar", str(n), "Int", 8), ("body", "Scalar", str(n), "Int", 4),
             ("ply", "Scalar", str(n), "Int", 4), ("material", "Scalar", str(n), "Int", 4)]
    if anisotropic:
        attrs += [(a, "Vector", f"{n} 3", "Float", 8) for a in ("axis1", "axis2", "axis3")]
    body = "\n".join(f'   <Attribute Name="{a}" AttributeType="{t}" Center="Node">{item("/markers/" + a, d, k, p)}</Attribute>'
                     for a, t, d, k, p in attrs)
    text = f"""<?xml version="1.0" ?>
<Xdmf Version="2.0">
 <Domain>
  <Grid Name="markers" GridType="Uniform">
   <Topology TopologyType="Polyvertex" NumberOfElements="{n}" NodesPerElement="1"/>
   <Geometry GeometryType="{'XY' if dim == 2 else 'XYZ'}">{item('/markers/x', f'{n} {dim}')}</Geometry>
{body}
  </Grid>
 </Domain>
</Xdmf>
"""
    with open(os.path.splitext(filename)[0] + ".xmf", "w") as f:
        f.write(text)


# ------------------------------------------------------------------ solver --
BC_CODE = {"free": 0, "symmetry": 1, "fixed": 2}


def material_to_c(m, path):
    """A material's constitutive data for the C solver (SI units); models by name."""
    d = {"rho0": m.density, "eos": "none", "strength": "none", "failure": "none", "chi": 0.9,
         "T_room": 294.0, "eps_dot0": 1.0, "T_melt": 1e30}
    el = m.elastic or {}
    if el.get("type") == "orthotropic":
        d.update(ply_data(m))
    if m.is_gas:
        d.update(eos="ideal-gas", gamma=m.eos["gamma"], G=0.0, cv=float(m.eos.get("cv", 0.0)))
        return d
    if m.eos is not None:
        d.update(eos="mie-gruneisen", c0=m.eos["c0"], s=m.eos["s"], gamma0=m.eos["gamma0"],
                 spall=float(m.eos.get("spall_pressure", 0.0)))
        if d["spall"] > 0:
            raise DeckError(f"{path}.eos.spall_pressure", f"{d['spall']} must be a negative pressure (Pa, tension)")
        d["G"] = m.shear_modulus or 0.0
    elif d.get("aniso"):
        d["K"] = d["K_R"]       # no EOS: linear volumetric response, sigma = C : eps exactly (orthotropic.c)
    elif el.get("type") == "isotropic":
        E, nu = el["E"], el["nu"]
        d.update(K=E / (3 * (1 - 2 * nu)), G=E / (2 * (1 + nu)))
    else:
        raise DeckError(path, "needs an eos (with shear_modulus for strength) or elastic: {type: isotropic, E, nu} to run")
    if m.strength is not None and m.strength["type"] != "none":
        st = m.strength
        if d["G"] <= 0:
            raise DeckError(f"{path}.shear_modulus", f"is required with strength type {st['type']} (Pa, > 0)")
        d["strength"] = st["type"]
        d["chi"] = float(st.get("taylor_quinney", 0.9))
        if st["type"] == "elastic-plastic":
            d["Y0"] = st["yield_stress"]
        else:
            d["T_room"] = float(st.get("T_room", 294.0))
            if st["type"] == "johnson-cook":
                d.update(A=st["A"], B=st["B"], n=st["n"], C=st["C"], m=st["m"], T_melt=st["T_melt"],
                         eps_dot0=float(st.get("eps_dot0", 1.0)))
            elif st["type"] == "mts":
                d["mts"] = {k: float(st.get(k, 0.0)) for k in MTS_KEYS}
            else:   # zerilli-armstrong-fcc | -bcc
                d["za"] = {k: float(st.get(k, 0.0)) for k in ("C0", "C1", "C2", "C3", "C4", "C5", "n")}
            if m.specific_heat is None:
                raise DeckError(f"{path}.specific_heat", f"is required with {st['type']} strength (J/kg/K; temperature from plastic work)")
    d["cv"] = m.specific_heat or 0.0
    if d.get("aniso"):
        if m.failure is not None:
            d["failure"] = m.failure["type"]
        return d
    if m.failure is not None:
        if d["strength"] == "none":
            raise DeckError(f"{path}.failure", "Johnson-Cook failure needs a strength model (it accumulates plastic strain)")
        d["failure"] = "johnson-cook"
        d["D"] = [m.failure[k] for k in ("D1", "D2", "D3", "D4", "D5")]
    return d


def ply_data(m):
    """An orthotropic ply's data for the C kernel (orthotropic.c): stiffness C in
    material axes (Voigt 11,22,33,23,13,12, engineering shears), the Reuss bulk
    modulus, the bound c2max on every wave speed^2, strengths, fracture energies."""
    from .scene import orthotropic_compliance
    el = m.elastic
    S = orthotropic_compliance(el)
    C = np.linalg.inv(S)
    C = 0.5 * (C + C.T)
    # Mandel form (shears times sqrt 2): its largest eigenvalue bounds the
    # acoustic tensor's for every direction and rotation (2D: conservative)
    w = np.array([1, 1, 1, np.sqrt(2), np.sqrt(2), np.sqrt(2)])
    lam = np.linalg.eigvalsh(C * np.outer(w, w)).max()
    st = m.strengths or {}
    f = m.failure or {}
    return dict(aniso=1, ply_C=C.reshape(36).tolist(), K_R=1.0 / S[:3, :3].sum(), c2max=lam / m.density,
                ply_X=[st.get(k, 0.0) for k in ("Xt", "Xc", "Yt", "Yc", "S12", "S23")],
                ply_Gc=[f.get(k, 0.0) for k in ("G_ft", "G_fc", "G_mt", "G_mc")],
                ply_E=[el["E1"], el["E1"], el["E2"], el["E2"]])


def drive_material(material, L, dt, axes=None, h=1.0e-3):
    """The solver's constitutive kernel on one 3D marker, no grid: apply the
    velocity gradients L (n x 3 x 3, 1/s), time step dt (s); axes: the ply's
    material axes at t = 0 (rows a_1, a_2, a_3; default x, y, z); h: the cell
    size that regularises damage (m).  Returns dict of arrays per step: stress
    (n x 3 x 3 Pa), axes, damage (n x 4), pressure, energy, J."""
    from . import _core
    return _core.drive(material_to_c(material, "material"), np.eye(3) if axes is None else axes, L, dt, h)


def damage_warnings(scene):
    """Ply failure modes whose fracture energy cannot be spread over a cell of
    this grid (2 G_c E / (X^2 h) <= 1: the mode then fails at once, dissipating
    less than G_c).  One line per material and mode."""
    h = max(scene.grid.h)
    out = []
    for m in scene.materials:
        if (m.failure or {}).get("type") != "hashin":
            continue
        d = ply_data(m)
        for k, mode in enumerate(("fiber tension", "fiber compression", "matrix tension", "matrix compression")):
            lmax = 2 * d["ply_Gc"][k] * d["ply_E"][k] / d["ply_X"][k] ** 2
            if h >= lmax:
                out.append(f"material {m.name}: {mode} fails at once on cells of {h:.3g} m (its fracture energy "
                           f"spreads over at most {lmax:.3g} m); refine to honour G_c")
    return out


def run_to_c(run):
    av = run.artificial_viscosity
    return dict(t_end=run.t_end, cfl=run.cfl, shape=run.shape, transfer=run.transfer, output_interval=run.output_interval,
                c_linear=av["c_linear"], c_quadratic=av["c_quadratic"], pic_fraction=run.pic_fraction,
                dt_growth=run.dt_growth, mass_threshold=run.mass_threshold, max_steps=run.max_steps,
                history_interval=run.history_interval, progress_interval=run.progress_interval, dt_max=run.dt_max,
                fbar=run.fbar, checkpoint_interval=run.checkpoint_interval,
                checkpoint_wall_interval=run.checkpoint_wall_interval, dt_floor=run.dt_floor)


def make_solver(m, restart=None, verified=False):
    """The C solver on initialised markers m (from initialize); reads -run_<key> options.
    restart: a checkpoint.h5 to continue from (m from initialize(restart=True)),
    checked first unless verified (by verify_checkpoint, before any work)."""
    from . import _core
    scene = m.scene
    params = run_options(scene)
    mats = [material_to_c(x, f"materials[{i}]") for i, x in enumerate(scene.materials)]
    faces = ["x-", "x+", "y-", "y+", "z-", "z+"][: 2 * scene.dimension]
    bc = [BC_CODE[scene.grid.boundary[f]] for f in faces] + [0] * (6 - len(faces))
    S = _core.Solver(m.cs, m.da, m.sw, params, mats, bc)
    lay = scene.contact.layout(scene) if scene.contact is not None else None
    if lay is not None and lay["nfield"] >= 2:
        # each group of bonded bodies its own velocity field, each ply of a laminate with cohesive interfaces its own (contact.c)
        S.set_contact(lay["field"], lay["split"], lay["nfield"], lay["mu"], lay["coh"], lay["cohp"])
    if not restart:
        S.initial_state()      # bodies in cells; markers' initial pressures
    if scene.gauges and not restart:
        S.set_gauges(gauge_markers(m, [g["point"] for g in scene.gauges]))
    if restart:
        if not verified:
            verify_checkpoint(scene, restart, m.cs)
        S.restart(restart)
        m.stats = {"markers": m.sw.getComm().tompi4py().allreduce(m.sw.getLocalSize())}
        m.bytes_per_marker = m.cs.marker_bytes(m.sw)
    return S


def gauge_markers(m, points):
    """Id of the marker nearest to each point (ties: the smaller id), over all ranks."""
    from mpi4py import MPI
    f = local_fields(m, ["x", "id"])
    comm = m.sw.getComm().tompi4py()
    ids = []
    for pt in points:
        d2 = np.sum((f["x"] - np.asarray(pt)) ** 2, axis=1) if len(f["x"]) else np.array([np.inf])
        k = int(np.argmin(d2))
        best = (float(d2[k]), int(f["id"][k, 0]) if len(f["x"]) else -1)
        ids.append(comm.allreduce(best, op=MPI.MIN)[1])
    return ids


def run(m, outdir, deck_text, solver=None):
    """Run to run.t_end writing OUTDIR/markers_*.h5, grid_*.h5, history.csv, bodies.csv, markers.xdmf."""
    from petsc4py import PETSc
    from . import __version__
    comm = m.sw.getComm()
    err = None
    if comm.getRank() == 0:
        try:
            os.makedirs(outdir, exist_ok=True)
        except OSError as e:
            err = f"cannot make the output directory {outdir}: {e.strerror}"
    err = comm.tompi4py().bcast(err, root=0)
    if err:
        raise DeckError("-o", err)
    S = solver or make_solver(m)
    if S.restarted and comm.getRank() == 0:
        resume_outputs(outdir, S.step_count, S.time)
    comm.barrier()
    opts = " ".join(f"-{k} {v}".strip() for k, v in PETSc.Options().getAll().items())
    attrs = {"deck": deck_text, "code_version": __version__, "petsc_options": opts, "ranks": str(comm.getSize()),
             "command": " ".join(sys.argv), "dimension": str(m.scene.dimension), "run": repr(S.run_params)}
    attrs = comm.tompi4py().bcast(attrs, root=0)
    S.run(outdir, attrs, [b.name for b in m.scene.bodies], [x.name for x in m.scene.materials])
    if comm.getRank() == 0:
        write_xdmf_series(outdir, m.scene.dimension, m.scene)
    comm.barrier()
    return S


def write_xdmf_series(outdir, dim, scene):
    """markers.xdmf: the time series of marker files, for ParaView."""
    import glob
    import h5py
    steps = []
    for fn in sorted(glob.glob(os.path.join(outdir, "markers_*.h5"))):
        with h5py.File(fn, "r") as f:
            steps.append((os.path.basename(fn), float(f.attrs["time"]), len(f["markers/id"]),
                          {k: f["markers"][k].shape for k in f["markers"].keys()}))
    grids = []
    for name, t, n, keys in steps:
        def item(path, dims, kind="Float", prec=8):
            return f'<DataItem Dimensions="{dims}" NumberType="{kind}" Precision="{prec}" Format="HDF">{name}:{path}</DataItem>'
        attrs = []
        for k in keys:
            if k in ("x",):
                continue
            if k == "damage" and len(keys[k]) == 2:      # a ply's four damage variables
                attrs.append(f'<Attribute Name="{k}" AttributeType="Matrix" Center="Node">{item("/markers/" + k, f"{n} {keys[k][1]}")}</Attribute>')
            elif k in ("mass", "volume", "pressure", "energy", "plastic_strain", "temperature", "damage", "interface_damage"):
                attrs.append(f'<Attribute Name="{k}" AttributeType="Scalar" Center="Node">{item("/markers/" + k, n)}</Attribute>')
            elif k in ("id",):
                attrs.append(f'<Attribute Name="{k}" AttributeType="Scalar" Center="Node">{item("/markers/" + k, n, "Int", 8)}</Attribute>')
            elif k in ("body", "ply", "material"):
                attrs.append(f'<Attribute Name="{k}" AttributeType="Scalar" Center="Node">{item("/markers/" + k, n, "Int", 4)}</Attribute>')
            elif k in ("axis1", "axis2", "axis3"):
                attrs.append(f'<Attribute Name="{k}" AttributeType="Vector" Center="Node">{item("/markers/" + k, f"{n} 3")}</Attribute>')
            elif k == "stress":
                attrs.append(f'<Attribute Name="stress" AttributeType="Tensor" Center="Node">{item("/markers/stress", f"{n} 3 3")}</Attribute>')
        grids.append(f'''   <Grid Name="markers" GridType="Uniform">
    <Time Value="{t!r}"/>
    <Topology TopologyType="Polyvertex" NumberOfElements="{n}" NodesPerElement="1"/>
    <Geometry GeometryType="{'XY' if dim == 2 else 'XYZ'}">{item('/markers/x', f'{n} {dim}')}</Geometry>
    {chr(10).join('    ' + a for a in attrs)}
   </Grid>''')
    text = ('<?xml version="1.0" ?>\n<Xdmf Version="2.0">\n <Domain>\n  <Grid Name="series" GridType="Collection" CollectionType="Temporal">\n'
            + "\n".join(grids) + "\n  </Grid>\n </Domain>\n</Xdmf>\n")
    with open(os.path.join(outdir, "markers.xdmf"), "w") as f:
        f.write(text)
    if scene.cell_materials:
        write_cells_xdmf(outdir, scene)


def write_cells_xdmf(outdir, scene):
    """cells.xdmf: the time series of the grid files' /cells fields, cell-centred
    on the grid (a CoRectMesh), one scalar per material's volume fraction and
    per velocity component, for ParaView."""
    import glob
    import h5py
    g, dim = scene.grid, scene.dimension
    shape = list(reversed(g.cells))                      # nz ny nx, slowest first
    nodes = " ".join(str(n + 1) for n in shape)
    origin = " ".join(repr(float(v)) for v in reversed(g.lower))
    spacing = " ".join(repr(float(v)) for v in reversed(g.h))
    mats = [scene.materials[i].name for i in scene.cell_materials]
    cdims = " ".join(map(str, shape))

    def slab(name, path, k, n):
        start = " ".join(["0"] * dim + [str(k)])
        stride = " ".join(["1"] * (dim + 1))
        count = " ".join(map(str, shape + [1]))
        return (f'<DataItem ItemType="HyperSlab" Dimensions="{cdims}" Type="HyperSlab">'
                f'<DataItem Dimensions="3 {dim + 1}" Format="XML">{start} {stride} {count}</DataItem>'
                f'<DataItem Dimensions="{cdims} {n}" NumberType="Float" Precision="8" Format="HDF">{name}:{path}</DataItem></DataItem>')

    grids = []
    for fn in sorted(glob.glob(os.path.join(outdir, "grid_*.h5"))):
        name = os.path.basename(fn)
        with h5py.File(fn, "r") as f:
            if "cells" not in f:
                continue
            t = float(f.attrs["time"])
        attrs = [f'<Attribute Name="volume_fraction_{m}" AttributeType="Scalar" Center="Cell">{slab(name, "/cells/volume_fraction", k, len(mats))}</Attribute>'
                 for k, m in enumerate(mats)]
        for q in ("density", "pressure", "specific_energy"):
            attrs.append(f'<Attribute Name="{q}" AttributeType="Scalar" Center="Cell"><DataItem Dimensions="{cdims}" NumberType="Float" '
                         f'Precision="8" Format="HDF">{name}:/cells/{q}</DataItem></Attribute>')
        attrs += [f'<Attribute Name="velocity_{"xyz"[k]}" AttributeType="Scalar" Center="Cell">{slab(name, "/cells/velocity", k, dim)}</Attribute>'
                  for k in range(dim)]
        grids.append(f'''   <Grid Name="cells" GridType="Uniform">
    <Time Value="{t!r}"/>
    <Topology TopologyType="{dim}DCoRectMesh" Dimensions="{nodes}"/>
    <Geometry GeometryType="{'ORIGIN_DXDY' if dim == 2 else 'ORIGIN_DXDYDZ'}">
     <DataItem Dimensions="{dim}" Format="XML">{origin}</DataItem>
     <DataItem Dimensions="{dim}" Format="XML">{spacing}</DataItem>
    </Geometry>
    {chr(10).join('    ' + a for a in attrs)}
   </Grid>''')
    text = ('<?xml version="1.0" ?>\n<Xdmf Version="2.0">\n <Domain>\n  <Grid Name="series" GridType="Collection" CollectionType="Temporal">\n'
            + "\n".join(grids) + "\n  </Grid>\n </Domain>\n</Xdmf>\n")
    with open(os.path.join(outdir, "cells.xdmf"), "w") as f:
        f.write(text)
