"""The `plyshock` command.  SI units throughout (m, kg, s, Pa, K).

    plyshock check SCENE.yaml                    validate; expected markers and memory
    plyshock init SCENE.yaml -o OUT.h5 [--png F] insert markers (under mpiexec or alone)
    plyshock run SCENE.yaml -o OUTDIR            insert and run to run.t_end (-run_<key> overrides)
    plyshock run SCENE.yaml -o OUTDIR --restart OUTDIR/checkpoint.h5   resume a killed run
    plyshock verify [-o DIR] [--levels N] [--docs DIR] [--only S,..] [--taylor [CELL ...]]
                                                 work-precision, insertion study, Taylor bar; CSV + PNG
    plyshock plot OUT.h5 --png FILE [...]        orientation glyphs coloured by ply, or --field NAME;
                                                 --cells FIELD[:MATERIAL] draws a run step's cells under them
    plyshock history OUTDIR --png FILE           energies, momentum, peak pressure against time

Decks: dimension 2 (geometry: plane-strain, the default, or axisymmetric: x = r,
y = z, masses of the full revolution) or 3. Marker bodies meet in contact
(contact: {type: friction, friction: 0.0} by default; {type: bonded} welds them);
cells (representation: cells) hold gases and flowing metals as volume fractions.
Options that start with a single dash (-log_view, -options_left, ...) go to PETSc.
Bad input exits with status 2 and a message naming the deck key; so does a run
stopped by a guard (a collapsing time step, an inverted marker) or a
checkpoint that cannot be restarted from.
"""
import argparse
import os
import re
import sys
import time


VERIFY_STUDIES = ("shock", "vibration", "insertion", "laminate", "cells", "contact")   # = verify.STUDIES (not imported: PETSc starts later)


def _rank():
    return int(os.environ.get("OMPI_COMM_WORLD_RANK", os.environ.get("PMI_RANK", "0")))


def _print0(*a):
    if _rank() == 0:
        print(*a, flush=True)


PS_ERR_RUN = 256    # = PS_ERR_RUN in src/solver.h: a run-time guard every rank raises together


def _petsc_error(e):
    """A PETSc error from the C code as one `plyshock: error:` line, exit status 2.
    A guard every rank raised together (PS_ERR_RUN) is reported once by rank 0;
    any other error may have come from one rank alone while the others wait in
    a collective call, so that rank reports it and aborts the run."""
    from mpi4py import MPI
    tb = getattr(e, "_traceback_", None) or []
    code = getattr(e, "ierr", e.args[0] if e.args else -1)
    msg = tb[-1].strip() if tb else f"PETSc error code {code}"
    comm = MPI.COMM_WORLD
    if code == PS_ERR_RUN or comm.size == 1:
        if comm.rank == 0:
            print(f"plyshock: error: {msg}", file=sys.stderr, flush=True)
        return 2
    print(f"plyshock: error: {msg} (rank {comm.rank}; stopping every rank)", file=sys.stderr, flush=True)
    comm.Abort(2)


def _parser():
    p = argparse.ArgumentParser(prog="plyshock", description=__doc__.split("\n\n")[0],
                                epilog="PETSc options (e.g. -log_view) may follow any command.")
    sub = p.add_subparsers(dest="cmd", required=True)
    c = sub.add_parser("check", help="validate a deck; print the expected marker count and memory without inserting")
    c.add_argument("deck")
    i = sub.add_parser("init", help="insert a scene's markers exactly and write OUT.h5 (+ .xmf)")
    i.add_argument("deck")
    i.add_argument("-o", "--output", required=True, help="marker file (HDF5)")
    i.add_argument("--png", help="also render the orientation picture to this PNG")
    i.add_argument("--axis", type=int, default=1, choices=(1, 2, 3), help="material axis drawn as glyphs (default 1, the fibre)")
    r = sub.add_parser("run", help="insert a scene and run it to run.t_end (explicit MPM); -run_<key> overrides the deck's run section")
    r.add_argument("deck")
    r.add_argument("-o", "--output", required=True, help="output directory")
    r.add_argument("--restart", help="continue from a checkpoint.h5 written by an earlier run of the same deck (checked first); "
                   "into that run's OUTDIR it resumes a killed run, appending to its .csv files")
    v = sub.add_parser("verify", help="error against run time (shock problems, a smooth vibration), exact against lattice "
                       "insertion, and with --taylor the Taylor bar")
    v.add_argument("-o", "--output", default="out/verify", help="output directory (CSVs and pictures)")
    v.add_argument("--levels", type=int, default=4, help="shock problems: grid levels from 100 um, halving (default 4)")
    v.add_argument("--only", default=",".join(VERIFY_STUDIES), help=f"comma-separated studies to run (default all: {','.join(VERIFY_STUDIES)})")
    v.add_argument("--docs", help="also copy the CSVs and pictures to this directory (scripts/verify: docs)")
    v.add_argument("--taylor", type=float, nargs="*", metavar="CELL", help="the long mode: also the copper Taylor bar at these cell "
                   "sizes (m; default 0.5e-3 0.25e-3) for each flow-stress model (Johnson-Cook, Zerilli-Armstrong, MTS), against "
                   "the same model by an axisymmetric Lagrangian reference (taylor_rz) and against the test; the verdict at the finest")
    pl = sub.add_parser("plot", help="render markers with orientation glyphs coloured by ply, off screen")
    pl.add_argument("markers", help="a marker file written by plyshock init")
    pl.add_argument("--png", required=True)
    pl.add_argument("--axis", type=int, default=1, choices=(1, 2, 3), help="material axis drawn as glyphs (default 1, the fibre)")
    pl.add_argument("--bodies", help="comma-separated body names to draw (default: all)")
    pl.add_argument("--zoom", type=float, nargs="+", metavar="X", help="zoom box: x0 y0 x1 y1 (2D) or x0 y0 z0 x1 y1 z1 (3D), metres")
    pl.add_argument("--color", default="ply", choices=("ply", "body", "material", "damage", "interface_damage"),
                    help="what colours the glyphs (default ply; damage: a run step's largest ply damage; "
                    "interface_damage: its cohesive ply interfaces' damage, delamination)")
    pl.add_argument("--view", choices=("xz",), help="3D: look at the x-z plane (a cut; pair with a thin --zoom slab in y)")
    pl.add_argument("--every", type=int, default=1, help="draw every n-th glyph (default 1)")
    pl.add_argument("--field", help="colour markers by a field of a run step instead of glyphs: pressure, stress (von Mises), "
                    "v (magnitude), energy, plastic_strain, temperature, damage, ...")
    pl.add_argument("--cells", metavar="FIELD[:MATERIAL]",
                    help="draw a run step's cell field (its grid_NNNNN.h5) under the markers: volume_fraction:MATERIAL "
                    "(a cell material's name, e.g. volume_fraction:air), density (kg/m^3), pressure (Pa), "
                    "specific_energy (J/kg), velocity (|v|, m/s), velocity_x, velocity_y, velocity_z; "
                    "2D: the cell grid; 3D: the layer of cells at the y of the --zoom box's middle (with --view xz, the cut)")
    pl.add_argument("--cells-log", action="store_true", help="logarithmic colour scale for --cells (e.g. pressure across a blast)")
    pl.add_argument("--cells-range", type=float, nargs=2, metavar=("LO", "HI"),
                    help="colour range of --cells, in the field's unit (default: the drawn cells' range; volume fraction 0 1)")
    hi = sub.add_parser("history", help="plot a run's history.csv (energies, momentum, peak pressure)")
    hi.add_argument("outdir")
    hi.add_argument("--png", required=True)
    return p


def main(argv=None):
    argv = sys.argv[1:] if argv is None else argv
    # single-dash options go to PETSc, with the value that follows when it is not an option
    ours, petsc = [], []
    k = 0
    while k < len(argv):
        a = argv[k]
        if re.match(r"^-[A-Za-z_]\w+", a):
            petsc.append(a)
            if k + 1 < len(argv) and not re.match(r"^-[A-Za-z_]", argv[k + 1]):
                petsc.append(argv[k + 1])
                k += 1
        else:
            ours.append(a)
        k += 1
    args = _parser().parse_args(ours)
    from .errors import DeckError
    try:
        if args.cmd == "history":
            from .post import plot_history
            plot_history(args.outdir, args.png)
            print(f"wrote {args.png}")
            return 0
        if args.cmd == "plot":
            _check_cells_options(args)
            cells = dict(cells=args.cells, cells_log=args.cells_log, cells_range=args.cells_range)
        if args.cmd == "plot" and args.field:
            from .post import plot_field
            plot_field(args.markers, args.png, args.field, bodies=args.bodies.split(",") if args.bodies else None, zoom=args.zoom,
                       view=args.view, **cells)
            print(f"wrote {args.png}")
            return 0
        if args.cmd == "plot":
            from .post import plot_markers
            plot_markers(args.markers, args.png, axis=args.axis, bodies=args.bodies.split(",") if args.bodies else None,
                         zoom=args.zoom, color=args.color, every=args.every, view=args.view, **cells)
            print(f"wrote {args.png}")
            return 0
        if args.cmd == "verify":
            import petsc4py
            petsc4py.init([sys.argv[0]] + petsc)
            from .verify import main as verify
            only = [x for x in args.only.split(",") if x]
            bad = [x for x in only if x not in VERIFY_STUDIES]
            if bad:
                raise DeckError("--only", f"unknown study {bad[0]!r}; allowed: {', '.join(VERIFY_STUDIES)}")
            taylor = None if args.taylor is None else (args.taylor or [0.5e-3, 0.25e-3])
            if taylor and any(not 0.05e-3 <= c <= 2e-3 for c in taylor):
                raise DeckError("--taylor", f"cell sizes {taylor} m: allowed [5e-05, 0.002]")
            verify(args.output, args.levels, taylor_cells=taylor, docs=args.docs, only=only)
            return 0
        from .deck import load
        scene, text = load(args.deck)
        import petsc4py
        petsc4py.init([sys.argv[0]] + petsc)
        if args.cmd == "check":
            return _check(scene)
        if args.cmd == "run":
            return _run(scene, text, args.output, args.restart)
        return _init(scene, text, args.output, args.png, args.axis)
    except DeckError as e:
        if _rank() == 0:
            print(f"plyshock: error: {e}", file=sys.stderr, flush=True)
        return 2
    except Exception as e:
        petsc = sys.modules.get("petsc4py.PETSc")
        if petsc is not None and isinstance(e, petsc.Error):
            return _petsc_error(e)
        raise


def _check_cells_options(args):
    """plot's --cells, --cells-log and --cells-range before any file is read:
    DeckError naming the option and the allowed values."""
    import math
    from .errors import DeckError
    from .post import parse_cells
    if args.cells is None:
        for k in ("cells_log", "cells_range"):
            if getattr(args, k):
                raise DeckError(f"--{k.replace('_', '-')}", "applies to --cells only; give --cells FIELD[:MATERIAL] too")
        return
    field, _ = parse_cells(args.cells)
    r = args.cells_range
    if r is not None:
        if not all(math.isfinite(v) for v in r) or r[1] <= r[0]:
            raise DeckError("--cells-range", f"{r[0]:g} {r[1]:g}: allowed two finite numbers LO < HI")
        if args.cells_log and r[0] <= 0:
            raise DeckError("--cells-range", f"{r[0]:g} {r[1]:g}: with --cells-log allowed 0 < LO < HI")
    if args.cells_log and field.startswith("velocity_"):
        raise DeckError("--cells-log", f"a logarithmic scale of {field}, which takes either sign; allowed with "
                        "volume_fraction, density, pressure, specific_energy, velocity")


def _table(scene, counts, masses=None):
    rows = []
    for b, body in enumerate(scene.bodies):
        plies = range(len(body.laminate.plies)) if body.kind == "laminate" else [-1]
        for p in plies:
            n = counts.get((b, p), 0)
            what = f"ply {p} ({body.laminate.plies[p].material})" if p >= 0 else body.material
            m = f"  mass {masses[(b, p)]:.9g} kg{'/m' if scene.dimension == 2 and not scene.axisymmetric else ''}" if masses else ""
            rows.append(f"  {body.name:<12s} {what:<24s} {n:>10d} markers{m}")
    return "\n".join(rows)


def _check(scene):
    from . import core
    from .errors import DeckError
    cs = core.c_scene(scene)
    clipped = core.check_geometry(scene, cs)
    # the grid's size and memory before the count, which takes as long as the grid is large
    r = core.resources(scene, cs)
    try:
        core.check_resources(r, scene)
    except DeckError:
        _print0(f"memory: {core.describe_resources(r)} (estimate)")
        raise
    counts, nbytes = core.count_markers(scene, cs)
    P = cs.maxply + 1
    d = {(b, p - 1): int(counts[b, p]) for b in range(counts.shape[0]) for p in range(P) if counts[b, p]}
    total = sum(d.values())
    r = core.resources(scene, cs, markers=total)
    _print0(f"deck {'OK' if r['grid_bytes'] + r['marker_bytes'] <= r['machine_bytes'] else 'too large'}: "
            f"dimension {scene.dimension}{' axisymmetric' if scene.axisymmetric else ''}, grid {' x '.join(map(str, scene.grid.cells))} cells, "
            f"{len(scene.materials)} materials, {len(scene.bodies)} bodies (SI units)")
    for name, v in clipped.items():
        _print0(f"  body {name}: {v:.6g} m^{scene.dimension} clipped away by the grid's faces{' (of the r-z section)' if scene.axisymmetric else ''}")
    _print0(_table(scene, d))
    _print0(f"expected markers: {total}, {nbytes} bytes per marker, {total * nbytes / 2**20:.3f} MiB")
    _print0(f"memory: {core.describe_resources(r)} (estimate)")
    core.check_resources(r, scene)
    for w in core.damage_warnings(scene):
        _print0(f"warning: {w}")
    return 0


def run_scene(scene, output, png=None, petsc_args=(), axis=1, zoom=None):
    """`plyshock init` for a Scene built in Python (the examples); zoom frames the picture."""
    from .errors import DeckError
    try:
        scene.validate()
        import petsc4py
        petsc4py.init([sys.argv[0]] + list(petsc_args))
        return _init(scene, scene.to_yaml(), output, png, axis, zoom)
    except DeckError as e:
        if _rank() == 0:
            print(f"plyshock: error: {e}", file=sys.stderr, flush=True)
        return 2


def run_impact(scene, outdir, petsc_args=(), zoom=None, projectile=None, cut=None, cells=None, cells_zoom=None):
    """The examples' --run: validate, start PETSc, then impact(); exit status."""
    from .errors import DeckError
    try:
        scene.validate()
        import petsc4py
        petsc4py.init([sys.argv[0]] + list(petsc_args))
        out = impact(scene, outdir, zoom, projectile, cut, cells, cells_zoom)
    except DeckError as e:
        if _rank() == 0:
            print(f"plyshock: error: {e}", file=sys.stderr, flush=True)
        return 2
    _print0(f"{os.path.basename(outdir)}: {out['ranks']} rank(s), {out['wall']:.1f} s wall for the run")
    return 0


def impact(scene, outdir, zoom=None, projectile=None, cut=None, cells=None, cells_zoom=None):
    """An impact example from layup to pictures (the method's figures): run the
    scene to run.t_end in OUTDIR, then on rank 0 draw before.png (fibre glyphs
    coloured by ply at t = 0), after.png (the turned fibre glyphs at the end),
    damage.png (the same glyphs coloured by ply damage, when a ply can fail),
    delamination.png (coloured by interface damage, when a laminate has
    cohesive ply interfaces) and velocity.png (the projectile's mean velocity against time).  With cut
    (a zoom box of a slab in y, 3D) the first three also in the cut, looked at
    in the x-z plane (*_cut.png).  With cells, a list of (name, --cells value,
    log scale, range or None), a scene with bodies in cells also gets
    cells_<name>.png: that cell field under the markers at every output time,
    one frame each (framed by cells_zoom, default the grid; the frames are
    kept in OUTDIR/frames/), and history.png.  Returns {pngs, wall, ranks}."""
    from petsc4py import PETSc
    comm = PETSc.COMM_WORLD
    t0 = time.perf_counter()
    _run(scene, scene.to_yaml(), outdir)
    wall = time.perf_counter() - t0
    pngs, err, frames = [], None, {}
    if cells:               # every rank draws a share of the frames
        import glob
        try:
            frames = cells_frames(outdir, sorted(glob.glob(os.path.join(outdir, "markers_*.h5"))), cells, cells_zoom,
                                  comm.getRank(), comm.getSize())
        except Exception as e:
            err = f"{type(e).__name__}: {e}"
        errs = [e for e in comm.tompi4py().allgather(err) if e]
        if errs:
            raise RuntimeError(f"cells pictures failed: {errs[0]}")
    if comm.getRank() == 0:
        try:
            import glob
            from .post import plot_body_velocity, plot_markers
            steps = sorted(glob.glob(os.path.join(outdir, "markers_*.h5")))
            can_fail = any((m.failure or {}).get("type") == "hashin" for m in scene.materials)
            pics = [("before", steps[0], "ply", zoom, None), ("after", steps[-1], "ply", zoom, None)]
            pics += [("damage", steps[-1], "damage", zoom, None)] if can_fail else []
            cohesive = any(b.kind == "laminate" and b.laminate.interface is not None and b.laminate.interface.cohesive
                           for b in scene.bodies)
            pics += [("delamination", steps[-1], "interface_damage", zoom, None)] if cohesive else []
            if cut:
                pics += [(f"{name}_cut", f, c, cut, "xz") for name, f, c, _, _ in pics]
            for name, f, color, box, view in pics:
                pngs.append(plot_markers(f, os.path.join(outdir, name + ".png"), zoom=box, color=color, view=view))
            if projectile:
                pngs.append(plot_body_velocity(outdir, projectile, os.path.join(outdir, "velocity.png"),
                                               gauges=[g["name"] for g in scene.gauges or []], axisymmetric=scene.axisymmetric))
            if cells:
                pngs += cells_montages(outdir, frames)
            for png in pngs:
                print(f"wrote {png}", flush=True)
        except Exception as e:      # every rank raises, none waits for rank 0
            err = f"{type(e).__name__}: {e}"
    err = comm.tompi4py().bcast(err, root=0)
    if err:
        raise RuntimeError(f"impact pictures failed on rank 0: {err}")
    return {"pngs": comm.tompi4py().bcast(pngs, root=0), "wall": wall, "ranks": comm.getSize()}


def cells_frames(outdir, steps, cells, zoom=None, rank=0, size=1):
    """OUTDIR/frames/<name>_NNNNN.png for each (name, --cells value, log,
    range) of cells and each marker file of steps: the cell field under the
    markers (fibre glyphs by ply).  Rank r of size draws every size-th frame
    from the r-th; returns {name: every frame's path, in time order}."""
    from .post import plot_markers
    os.makedirs(os.path.join(outdir, "frames"), exist_ok=True)
    out, k = {}, 0
    for name, spec, log, rng in cells:
        out[name] = []
        for f in steps:
            n = os.path.basename(f)[len("markers_"):-len(".h5")]
            png = os.path.join(outdir, "frames", f"{name}_{n}.png")
            if k % size == rank:
                plot_markers(f, png, zoom=zoom, cells=spec, cells_log=log, cells_range=rng, window=(1100, 900),
                             title=os.path.basename(os.path.normpath(outdir)), font_size=14)
            out[name].append(png)
            k += 1
    return out


def cells_montages(outdir, frames, columns=3):
    """cells_<name>.png (the frames side by side) and history.png in OUTDIR; their paths."""
    from .post import montage, plot_history
    out = [montage(f, os.path.join(outdir, f"cells_{name}.png"), columns=columns) for name, f in frames.items()]
    return out + [plot_history(outdir, os.path.join(outdir, "history.png"))]


def _run(scene, text, outdir, restart=None):
    from petsc4py import PETSc
    from . import core
    core.run_options(scene)                 # run errors before any work
    if restart:
        core.verify_checkpoint(scene, restart)   # a damaged checkpoint too
    m = core.initialize(scene, restart=bool(restart))
    S = core.make_solver(m, restart, verified=True)      # material and run errors before any step
    for w in core.damage_warnings(scene):
        _print0(f"warning: {w}")
    _print0(f"running {m.stats['markers']} markers on {PETSc.COMM_WORLD.getSize()} rank(s), {m.bytes_per_marker} bytes per marker; "
            f"{S.run_params}")
    core.run(m, outdir, text, S)
    return 0


def _init(scene, text, output, png=None, axis=1, zoom=None):
    from petsc4py import PETSc
    from . import core
    t0 = time.perf_counter()
    m = core.initialize(scene)
    t1 = time.perf_counter()
    s = core.summary(m)
    how = {"exact": "exact pieces", "lattice": "lattice points"}
    kinds = sorted({b.insertion for b in scene.bodies})
    _print0(f"inserted {m.stats['markers']} markers from {m.stats['pieces']} {' and '.join(how[k] for k in kinds)} on "
            f"{PETSc.COMM_WORLD.getSize()} rank(s) in {t1 - t0:.3f} s; slivers merged {m.stats['slivers_merged']}, "
            f"kept {m.stats['slivers_kept']}")
    for name, v in m.clipped.items():
        _print0(f"  body {name}: {v:.6g} m^{scene.dimension} clipped away by the grid's faces{' (of the r-z section)' if scene.axisymmetric else ''}")
    _print0(_table(scene, {k: v[0] for k, v in s.items()}, {k: v[1] for k, v in s.items()}))
    _print0(f"{m.bytes_per_marker} bytes per marker, {m.stats['markers'] * m.bytes_per_marker / 2**20:.3f} MiB in all")
    d = os.path.dirname(os.path.abspath(output))
    if PETSc.COMM_WORLD.getRank() == 0:
        os.makedirs(d, exist_ok=True)
    PETSc.COMM_WORLD.barrier()
    core.write_markers(m, output, text)
    _print0(f"wrote {output} and {os.path.splitext(output)[0]}.xmf")
    if png and PETSc.COMM_WORLD.getRank() == 0:
        from .post import plot_markers
        plot_markers(output, png, axis=axis, zoom=zoom)
        print(f"wrote {png}", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
