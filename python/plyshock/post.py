"""Post-processing: marker pictures with orientation glyphs, rendered off screen.

Reads a marker file (HDF5) and draws each marker of a laminate as a short line
along a material axis (axis 1 = the fibre by default), coloured by ply; other
bodies are drawn as points.  With `cells`, the matching grid file's /cells
field (volume fraction of one cell material, density, pressure, ...) is drawn
under the markers as a coloured image of the cells (2D: the cell grid; 3D: the
layer of cells at one y, the --view xz cut).  pyvista renders without a display.
"""
import os
import re

import numpy as np

from .errors import DeckError

# The /cells fields `plot --cells` draws: name -> (what, unit).  velocity is
# drawn as its magnitude, velocity_x|y|z as one component.
CELL_FIELDS = {
    "volume_fraction": ("volume fraction", "-"),
    "density": ("cell density", "kg/m^3"),
    "pressure": ("cell pressure", "Pa"),
    "specific_energy": ("cell specific internal energy", "J/kg"),
    "velocity": ("cell speed", "m/s"),
    "velocity_x": ("cell velocity x", "m/s"),
    "velocity_y": ("cell velocity y", "m/s"),
    "velocity_z": ("cell velocity z", "m/s"),
}
# A cell whose cell materials fill less than this share of it holds none (a
# marker body or void): density, pressure, energy and velocity are not drawn
# there (grey), so a body's own cells do not read as a cold, empty gas.
CELL_EMPTY = 1e-6
CELL_CMAP = "magma"          # dark to light: the ply colours (tab10) stand out on it
CELL_NAN = "lightgray"



def _count(keep):
    """The caption's marker count: all of the file's markers, or how many of
    them a zoom box or a cut shows ("3,686 of 8,418 markers shown")."""
    n, shown = len(keep), int(np.count_nonzero(keep))
    return f"{n:,} markers" if shown == n else f"{shown:,} of {n:,} markers shown"

def cells_allowed(materials=None):
    """The allowed values of --cells as text (the materials' names when known)."""
    vf = "|".join(f"volume_fraction:{m}" for m in materials) if materials else "volume_fraction:MATERIAL"
    return f"{vf}, {', '.join(k for k in CELL_FIELDS if k != 'volume_fraction')}"


def parse_cells(spec):
    """(field, material or None) from a --cells value; DeckError('--cells', ...)
    naming the allowed values when it is not one."""
    field, _, mat = str(spec).partition(":")
    if field not in CELL_FIELDS:
        raise DeckError("--cells", f"{spec!r} is not a cell field; allowed: {cells_allowed()}")
    if field == "volume_fraction" and not mat:
        raise DeckError("--cells", f"volume_fraction needs a material, e.g. volume_fraction:air; allowed: {cells_allowed()}")
    if field != "volume_fraction" and _:
        raise DeckError("--cells", f"{spec!r}: only volume_fraction takes a material; allowed: {cells_allowed()}")
    return field, (mat or None)


def grid_file(markers_path):
    """The grid file written with a run's marker file: markers_NNNNN.h5 -> grid_NNNNN.h5."""
    d, b = os.path.split(markers_path)
    m = re.fullmatch(r"markers_(\d+)\.h5", b)
    return os.path.join(d, f"grid_{m.group(1)}.h5") if m else None


def read_cells(markers_path, spec):
    """One /cells field of the grid file that goes with a run's marker file:
    {values: (ny, nx) or (nz, ny, nx) array (NaN where no cell material is),
    field, material, title (with the unit), lower, upper, h, cells, time,
    materials, path}.  Bad input is DeckError('--cells', ...)."""
    import h5py
    import yaml
    field, mat = parse_cells(spec)
    gpath = grid_file(markers_path)
    if gpath is None or not os.path.exists(gpath):
        raise DeckError("--cells", f"needs the grid file of a run's step beside {markers_path} "
                        f"(markers_NNNNN.h5 with grid_NNNNN.h5, written by plyshock run); "
                        f"{'found none' if gpath is None else gpath + ' does not exist'}")
    with h5py.File(markers_path, "r") as f:
        deck = f.attrs.get("deck")
        tm = float(np.asarray(f.attrs["time"]).reshape(-1)[0]) if "time" in f.attrs else None
    if isinstance(deck, bytes):
        deck = deck.decode()
    g = (yaml.safe_load(deck) or {}).get("grid") if deck else None
    if not g:
        raise DeckError("--cells", f"{markers_path} records no deck, so the grid's position is unknown")
    with h5py.File(gpath, "r") as f:
        if "cells" not in f:
            raise DeckError("--cells", f"{gpath} has no /cells: the run has no body in cells (representation: cells)")
        tg = float(np.asarray(f.attrs["time"]).reshape(-1)[0]) if "time" in f.attrs else None
        vfd = f["cells/volume_fraction"]
        names = [s.decode() if isinstance(s, bytes) else str(s) for s in vfd.attrs["materials"]]
        vf = vfd[...]
        if field == "volume_fraction":
            if mat not in names:
                raise DeckError("--cells", f"no cell material {mat!r} in {gpath}; allowed: {cells_allowed(names)}")
            a = vf[..., names.index(mat)]
        elif field.startswith("velocity"):
            v = f["cells/velocity"][...]
            dim = v.shape[-1]
            if field == "velocity":
                a = np.linalg.norm(v, axis=-1)
            else:
                k = "xyz".index(field[-1])
                if k >= dim:
                    raise DeckError("--cells", f"{field} in a {dim}D run; allowed: {cells_allowed(names).replace(', velocity_z', '')}")
                a = v[..., k]
        else:
            a = f[f"cells/{field}"][...]
    if tm is not None and tg is not None and not np.isclose(tm, tg, rtol=1e-12, atol=0):
        raise DeckError("--cells", f"{gpath} is at t = {tg:.6e} s, {markers_path} at {tm:.6e} s: not the same step")
    dim = a.ndim
    lower, upper = np.asarray(g["lower"], float), np.asarray(g["upper"], float)
    cells = np.array(a.shape[::-1])                      # nx, ny(, nz)
    if len(lower) != dim or list(cells) != list(g["cells"]):
        raise DeckError("--cells", f"{gpath}'s cells {list(cells)} are not the recorded deck's grid {g['cells']}")
    a = np.asarray(a, dtype=float)
    if field != "volume_fraction":
        a = np.where(vf.sum(axis=-1) >= CELL_EMPTY, a, np.nan)
    what, unit = CELL_FIELDS[field]
    title = f"{what} of {mat} ({unit})" if mat else f"{what} ({unit})"
    bar = f"{mat} {what} ({unit})" if mat else f"{what.replace('cell ', '')} ({unit})"
    return dict(values=a, field=field, material=mat, title=title, bar=bar, lower=lower, upper=upper,
                h=(upper - lower) / cells, cells=cells, time=tg, materials=names, path=gpath)


def _add_cells(p, cf, dim, zoom=None, view=None, log=False, clim=None, bar_x=0.86):
    """Draw a read_cells() field as an unlit image of cells, behind the markers
    (2D: at z slightly below 0; 3D: the layer of cells at the y of the zoom
    box's middle, or the grid's, placed at the box's far side for --view xz);
    a vertical colour bar with the unit at the right.  Returns the (lo, hi)
    range drawn; sets cf["caption"], a line saying what is drawn."""
    import pyvista as pv
    a, lo, h, n = cf["values"], cf["lower"], cf["h"], cf["cells"]
    # cells overlapping the zoom box, in each in-plane direction
    rng = [(0, int(n[k])) for k in range(dim)]
    if zoom:
        zl, zh = np.asarray(zoom[:dim], float), np.asarray(zoom[dim:], float)
        rng = [(int(np.clip(np.floor((zl[k] - lo[k]) / h[k]), 0, n[k] - 1)),
                int(np.clip(np.ceil((zh[k] - lo[k]) / h[k]), 1, n[k]))) for k in range(dim)]
    extent = float(np.max(cf["upper"] - lo))
    if dim == 2:
        (i0, i1), (j0, j1) = rng
        img = pv.ImageData(dimensions=(i1 - i0 + 1, j1 - j0 + 1, 1),
                           origin=(lo[0] + i0 * h[0], lo[1] + j0 * h[1], -1e-3 * extent), spacing=(h[0], h[1], 1.0))
        vals = a[j0:j1, i0:i1]
    else:
        # the cut: the cells of one layer in y, drawn in the x-z plane
        yc = 0.5 * (zoom[1] + zoom[4]) if zoom else 0.5 * (lo[1] + cf["upper"][1])
        j = int(np.clip(np.floor((yc - lo[1]) / h[1]), 0, n[1] - 1))
        if view == "xz":       # the camera looks along +y: behind the markers of the slab
            yp = (zoom[4] if zoom else lo[1] + (j + 1) * h[1]) + 1e-3 * extent
        else:
            yp = lo[1] + (j + 0.5) * h[1]
        (i0, i1), _, (k0, k1) = rng
        img = pv.ImageData(dimensions=(i1 - i0 + 1, 1, k1 - k0 + 1),
                           origin=(lo[0] + i0 * h[0], yp, lo[2] + k0 * h[2]), spacing=(h[0], 1.0, h[2]))
        vals = a[k0:k1, j, i0:i1]                         # (nz, nx), x fastest as ImageData's cells
        cf["layer_y"] = lo[1] + (j + 0.5) * h[1]
    finite = vals[np.isfinite(vals)]
    if clim is None:
        if cf["field"] == "volume_fraction":
            clim = (0.0, 1.0)
        elif finite.size:
            clim = (float(finite.min()), float(finite.max()))
            if log:
                pos = finite[finite > 0]
                clim = (float(pos.min()), float(pos.max())) if pos.size else (1.0, 10.0)
        else:
            clim = (0.0, 1.0)
        if clim[1] <= clim[0]:
            clim = (clim[0] - 0.5 * abs(clim[0]) - 1e-30, clim[1] + 0.5 * abs(clim[1]) + 1e-30)
    name = cf["bar"]
    img.cell_data[name] = np.ascontiguousarray(vals).ravel()
    bar = {"title": name, "color": "black", "vertical": True, "position_x": bar_x, "position_y": 0.12, "height": 0.7,
           "width": 0.05, "fmt": "%.3g", "title_font_size": 16, "label_font_size": 14}
    p.add_mesh(img, scalars=name, cmap=CELL_CMAP, clim=list(clim), log_scale=bool(log), lighting=False,
               nan_color=CELL_NAN, scalar_bar_args=bar)
    cf["caption"] = ("cells: " + cf["title"] + (f", the layer at y = {cf['layer_y'] * 1e3:.3g} mm" if dim == 3 else "")
                     + ("; grey: no cell material" if cf["field"] != "volume_fraction" else ""))
    return tuple(clim)


def read_markers(path):
    """The /markers datasets and attributes of a marker file, as numpy arrays."""
    import h5py
    with h5py.File(path, "r") as f:
        g = f["markers"]
        d = {k: g[k][...] for k in g.keys()}
        d["body_names"] = [s.decode() if isinstance(s, bytes) else str(s) for s in g.attrs["body_names"]]
        d["material_names"] = [s.decode() if isinstance(s, bytes) else str(s) for s in g.attrs["material_names"]]
        d["attrs"] = {k: (v.decode() if isinstance(v, bytes) else v) for k, v in f.attrs.items()}
        if "time" in d["attrs"]:
            d["attrs"]["time"] = float(np.asarray(d["attrs"]["time"]).reshape(-1)[0])
    return d


def marker_scalar(d, field):
    """A scalar per marker from a dataset: vectors by magnitude, stress by von Mises."""
    if field not in d:
        names = sorted(k for k, v in d.items() if isinstance(v, np.ndarray) and v.ndim >= 1 and len(v) == len(d["x"]))
        raise SystemExit(f"plyshock plot: no field {field!r} in the file; it has {', '.join(names)}")
    a = np.asarray(d[field], dtype=float)
    if field == "stress":
        s = a - np.einsum("nii->n", a)[:, None, None] / 3 * np.eye(3)
        return np.sqrt(1.5 * np.einsum("nij,nij->n", s, s))
    if a.ndim == 2:
        return np.linalg.norm(a, axis=1)
    return a


def plot_field(path, png, field, bodies=None, zoom=None, window=(1600, 1100), cells=None, cells_log=False,
               cells_range=None, view=None, field_range=None):
    """Markers of a run step coloured by any field (stress: von Mises; vectors:
    magnitude); with cells (a --cells value) over that cell field (read_cells).
    field_range (lo, hi): a fixed colour range (default the data's)."""
    cf = read_cells(path, cells) if cells else None      # bad input first, before pyvista starts
    import pyvista as pv
    pv.OFF_SCREEN = True
    d = read_markers(path)
    x = d["x"]
    dim = x.shape[1]
    X = np.zeros((len(x), 3))
    X[:, :dim] = x
    keep = np.ones(len(x), bool)
    if bodies:
        keep &= np.isin(d["body"], [d["body_names"].index(b) for b in bodies])
    if zoom:
        lo, hi = np.array(zoom[:dim]), np.array(zoom[dim:])
        keep &= np.all((x >= lo) & (x <= hi), axis=1)
    val = marker_scalar(d, field)
    pts = pv.PolyData(X[keep])
    label = {"stress": "von Mises stress (Pa)", "v": "|v| (m/s)", "pressure": "pressure (Pa)", "energy": "energy (J/kg)",
             "temperature": "temperature (K)"}.get(field, field)
    pts.point_data[label] = val[keep]
    p = pv.Plotter(off_screen=True, window_size=window)
    p.set_background("white")
    if cf is not None:
        _add_cells(p, cf, dim, zoom, view, cells_log, cells_range)
    p.add_mesh(pts, scalars=label, cmap="viridis", point_size=5, render_points_as_spheres=True,
               scalar_bar_args={"title": label, "color": "black"}, clim=list(field_range) if field_range else None)
    t = d["attrs"].get("time", 0.0)
    p.add_text(f"{path.split('/')[-1]}: t = {float(t) * 1e6:.2f} us, {_count(keep)}"
               + (f"\n{cf['caption']}" if cf is not None else ""), font_size=10, color="black")
    if dim == 2:
        p.view_xy()
    elif view == "xz":
        p.view_xz()
    else:
        c = X[keep].mean(axis=0)
        p.camera_position = [tuple(c + np.array([1.0, 0.75, 0.6])), tuple(c), (0, 0, 1)]
        p.reset_camera()
    p.screenshot(png)
    p.close()
    return png


def plot_history(outdir, png):
    """Energies, momentum and peak pressure of a run against time (history.csv)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    H = np.genfromtxt(f"{outdir}/history.csv", delimiter=",", names=True)
    fig, ax = plt.subplots(1, 3, figsize=(15, 4.2))
    t = H["time"] * 1e6
    for k in ("kinetic", "internal", "lost_energy", "total"):
        ax[0].plot(t, H[k], label=k)
    for k in ("remap_heat", "coupling_work"):       # with cells: booked in internal (see docs/cells.md)
        if k in H.dtype.names:
            ax[0].plot(t, H[k], "--", label=k)
    for k in ("friction_work", "interface_energy"):   # contact and cohesive ply interfaces (docs/contact.md): in total
        if k in H.dtype.names and np.any(H[k] != 0):
            ax[0].plot(t, H[k], ":", label=k)
    ax[0].set_ylabel("energy (J; J/m in 2D)")
    for k in ("px", "py", "pz"):
        if k in H.dtype.names:
            ax[1].plot(t, H[k], label=k)
    ax[1].set_ylabel("momentum (kg m/s)")
    ax[2].plot(t, H["max_pressure"] / 1e9)
    ax[2].set_ylabel("max pressure (GPa)")
    if "coupling_work" in H.dtype.names and np.all(H["max_pressure"] > 0):
        ax[2].set_yscale("log")
    for a in ax:
        a.set_xlabel("time (us)")
        a.grid(alpha=0.3)
        if a.get_legend_handles_labels()[0]:
            a.legend()
    drift = (H["total"][-1] - H["total"][0]) / H["total"][0] if H["total"][0] else 0.0
    fig.suptitle(f"{outdir}: {int(H['step'][-1])} steps, energy drift {100 * drift:.2f}%")
    fig.tight_layout()
    fig.savefig(png, dpi=100)
    plt.close(fig)
    return png


def montage(pngs, png, columns=3, width=2400):
    """Pictures side by side, `columns` to a row, in one PNG about `width`
    pixels wide (each keeps its own title and colour bars)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.image as mpimg
    import matplotlib.pyplot as plt
    imgs = [mpimg.imread(f) for f in pngs]
    cols = min(columns, len(imgs))
    rows = -(-len(imgs) // cols)
    h, w = imgs[0].shape[:2]
    dpi = 100
    fig = plt.figure(figsize=(width / dpi, width / dpi * rows * h / (cols * w)), dpi=dpi)
    for k, im in enumerate(imgs):
        ax = fig.add_axes([(k % cols) / cols, 1 - (k // cols + 1) / rows, 1 / cols, 1 / rows])
        ax.imshow(im)
        ax.set_axis_off()
    fig.savefig(png, dpi=dpi)
    plt.close(fig)
    return png


def plot_body_velocity(outdir, body, png, gauges=None, axisymmetric=False):
    """A body's mean velocity against time from OUTDIR/bodies.csv (the
    projectile's residual velocity is its last value); with gauges (names of
    the run's gauges, gauges.csv), the last velocity component (vy in 2D, vz
    in 3D) of the marker each follows too.  axisymmetric: vx is the mass
    mean of v_r (the body's spreading, not a component of its velocity), so
    the speed in the title is |v_z|."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    B = np.genfromtxt(f"{outdir}/bodies.csv", delimiter=",", names=True, dtype=None, encoding=None)
    b = B[B["body"] == body]
    if not len(b):
        raise SystemExit(f"plyshock: no body {body!r} in {outdir}/bodies.csv")
    comps = [k for k in ("vx", "vy", "vz") if k in B.dtype.names]
    fig, ax = plt.subplots(figsize=(7, 4.2))
    t = b["time"] * 1e6
    names = {"vx": "v_r (mass mean: spreading)", "vy": "v_z (mean)"} if axisymmetric else {}
    for k in comps:
        ax.plot(t, b[k], label=names.get(k, f"{k} (mean)"))
    speed = np.abs(b["vy"]) if axisymmetric else np.sqrt(sum(b[k] ** 2 for k in comps))
    ax.plot(t, speed, "k--", label="|v_z| (mean)" if axisymmetric else "|v| (mean)")
    if gauges:
        G = np.genfromtxt(f"{outdir}/gauges.csv", delimiter=",", names=True, dtype=None, encoding=None)
        for k, name in enumerate(gauges):
            g = G[G["gauge"] == k]
            ax.plot(g["time"] * 1e6, g[comps[-1]], ":", lw=2, label=f"{comps[-1]} at gauge {name}")
    ax.set_xlabel("time (us)")
    ax.set_ylabel(f"{body} velocity (m/s)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    ax.set_title(f"{body}: mean {speed[0]:.1f} m/s at t = 0, {speed[-1]:.1f} m/s at {t[-1]:.2f} us")
    fig.tight_layout()
    fig.savefig(png, dpi=100)
    plt.close(fig)
    return png


def plot_markers(path, png, axis=1, bodies=None, zoom=None, color="ply", every=1, window=(1600, 1100), view=None,
                 cells=None, cells_log=False, cells_range=None, title=None, font_size=10):
    """Render the markers of `path` to `png`; returns the png path.

    color: ply, body or material (categorical), damage (a ply marker's
    largest damage variable, 0..1) or interface_damage (the damage of the
    cohesive ply interface next to the marker, 0..1: delamination).  view (3D): None (oblique, default), or
    "xz" to look at a cut in the x-z plane (pair it with a thin zoom box in y).
    cells: a --cells value (e.g. "pressure", "volume_fraction:air"): that cell
    field of the step's grid file drawn under the markers (read_cells), with
    cells_log a logarithmic colour scale and cells_range (lo, hi) its range.
    title: a line of text in place of the file name; font_size: its size."""
    cf = read_cells(path, cells) if cells else None      # bad input first, before pyvista starts
    import pyvista as pv
    pv.OFF_SCREEN = True
    d = read_markers(path)
    x = d["x"]
    dim = x.shape[1]
    X = np.zeros((len(x), 3))
    X[:, :dim] = x
    keep = np.ones(len(x), bool)
    if bodies:
        unknown = [b for b in bodies if b not in d["body_names"]]
        if unknown:
            raise SystemExit(f"plyshock plot: unknown body {unknown[0]!r}; the file has {', '.join(d['body_names'])}")
        keep &= np.isin(d["body"], [d["body_names"].index(b) for b in bodies])
    if zoom:
        if len(zoom) != 2 * dim:
            raise SystemExit(f"plyshock plot: --zoom takes {2 * dim} numbers for a {dim}D file, got {len(zoom)}")
        lo, hi = np.array(zoom[:dim]), np.array(zoom[dim:])
        keep &= np.all((x >= lo) & (x <= hi), axis=1)
    ply = d["ply"]
    lam = keep & (ply >= 0)
    other = keep & (ply < 0)
    # glyph length: the typical marker spacing
    vol = d["volume"][keep]
    h = float(np.median(vol) ** (1.0 / dim)) if len(vol) else 1.0
    p = pv.Plotter(off_screen=True, window_size=window)
    p.set_background("white")
    if cf is not None:
        _add_cells(p, cf, dim, zoom, view, cells_log, cells_range)
    if color in ("damage", "interface_damage"):
        if color not in d:
            raise SystemExit(f"plyshock plot: --color {color} needs a run step with a {color} field"
                             + (" (a laminate with interface: {type: cohesive})" if color == "interface_damage" else ""))
        dm = d[color]
        key = dm.max(axis=1) if dm.ndim == 2 else dm
    else:
        key = {"ply": ply, "body": d["body"], "material": d["material"]}[color]
    labels = {"ply": None, "body": d["body_names"], "material": d["material_names"], "damage": None, "interface_damage": None}[color]
    # categorical colours: one per ply (body, material), fixed by id so pictures compare
    from matplotlib import colormaps
    from matplotlib.colors import ListedColormap
    if color in ("damage", "interface_damage"):
        # continuous: undamaged blue to failed red
        cmap, ncat, notes = "coolwarm", 2, None
        bar = {"title": "damage (max of d_ft, d_fc, d_mt, d_mc)" if color == "damage" else
               "interface damage (0 bonded, 1 delaminated)", "color": "black"}
        clim = [0.0, 1.0]
    else:
        ncat = int(key[lam].max()) + 1 if lam.any() else 1
        base = colormaps["tab10"].colors
        cmap = ListedColormap([base[i % 10] for i in range(ncat)])
        names = labels or [f"{i}" for i in range(ncat)]
        bar = {"title": color, "color": "black", "n_labels": 0, "n_colors": ncat}
        notes = {float(i): f"{color} {names[i]}" for i in range(ncat)}
        clim = [-0.5, ncat - 0.5]
    if lam.any() and f"axis{axis}" in d:
        idx = np.flatnonzero(lam)[::max(1, every)]
        a = d[f"axis{axis}"][idx]
        # a line along the axis through each marker; an axis out of the 2D plane
        # (90° plies in a cross-section) projects to a dot
        lines = np.empty((2 * len(idx), 3))
        lines[0::2] = X[idx] - 0.45 * h * a
        lines[1::2] = X[idx] + 0.45 * h * a
        mesh = pv.line_segments_from_points(lines)
        mesh.cell_data[color] = key[idx].astype(float)
        p.add_mesh(mesh, scalars=color, cmap=cmap, clim=clim, line_width=2, show_scalar_bar=True,
                   scalar_bar_args=bar, annotations=notes)
        pts = pv.PolyData(X[idx])
        pts.point_data[color] = key[idx].astype(float)
        p.add_mesh(pts, scalars=color, cmap=cmap, clim=clim, point_size=3, show_scalar_bar=False)
    elif lam.any():
        pts = pv.PolyData(X[lam])
        pts.point_data[color] = key[lam].astype(float)
        p.add_mesh(pts, scalars=color, cmap=cmap, clim=clim, point_size=4, scalar_bar_args=bar,
                   annotations=notes)
    if other.any():
        pts = pv.PolyData(X[other])
        p.add_mesh(pts, color="dimgray", point_size=6, render_points_as_spheres=True)
        # body names at the centre of each non-laminate body
        for b in np.unique(d["body"][other]):
            c = X[other & (d["body"] == b)].mean(axis=0)
            p.add_point_labels([c], [d["body_names"][b]], font_size=14, text_color="black", shape=None, show_points=False)
    t = d["attrs"].get("time")
    head = title or path.split('/')[-1]
    text = (f"{head}{f'  t = {t * 1e6:.2f} us' if t is not None else ''}: {_count(keep)}, "
            f"glyphs = material axis {axis}, colour = {color}")
    if cf is not None:
        text += f"\n{cf['caption']}"
    p.add_text(text, font_size=font_size, color="black")
    if dim == 2:
        p.view_xy()
    elif view == "xz":
        p.view_xz()                     # x to the right, z up
    else:
        # look at the low-x, low-y faces: in a quarter model these are the
        # symmetry cuts, which show the plies in section
        c = X[keep].mean(axis=0) if keep.any() else np.zeros(3)
        p.camera_position = [tuple(c + np.array([1.0, 0.75, 0.6])), tuple(c), (0, 0, 1)]
        p.reset_camera()
    p.show_axes()
    p.screenshot(png)
    p.close()
    return png
