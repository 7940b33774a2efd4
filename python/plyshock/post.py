"""Post-processing: marker pictures with orientation glyphs, rendered off screen.

Reads a marker file (HDF5) and draws each marker of a laminate as a short line
along a material axis (axis 1 = the fibre by default), coloured by ply; other
bodies are drawn as points.  pyvista renders without a display.
"""
import numpy as np


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


def plot_field(path, png, field, bodies=None, zoom=None, window=(1600, 1100)):
    """Markers of a run step coloured by any field (stress: von Mises; vectors: magnitude)."""
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
    p.add_mesh(pts, scalars=label, cmap="viridis", point_size=5, render_points_as_spheres=True,
               scalar_bar_args={"title": label, "color": "black"})
    t = d["attrs"].get("time", 0.0)
    p.add_text(f"{path.split('/')[-1]}: t = {float(t):.4e} s, {keep.sum()} markers", font_size=10, color="black")
    if dim == 2:
        p.view_xy()
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
    ax[0].set_ylabel("energy (J; J/m in 2D)")
    for k in ("px", "py", "pz"):
        if k in H.dtype.names:
            ax[1].plot(t, H[k], label=k)
    ax[1].set_ylabel("momentum (kg m/s)")
    ax[2].plot(t, H["max_pressure"] / 1e9)
    ax[2].set_ylabel("max pressure (GPa)")
    for a in ax:
        a.set_xlabel("time (us)")
        a.grid(alpha=0.3)
        if a.get_legend_handles_labels()[0]:
            a.legend()
    drift = (H["total"][-1] - H["total"][0]) / H["total"][0] if H["total"][0] else 0.0
    fig.suptitle(f"{outdir}: {int(H['step'][-1])} steps, energy drift {100 * drift:.2f}%")
    fig.tight_layout()
    fig.savefig(png, dpi=100)
    return png


def plot_body_velocity(outdir, body, png):
    """A body's mean velocity against time from OUTDIR/bodies.csv (the
    projectile's residual velocity is its last value)."""
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
    for k in comps:
        ax.plot(t, b[k], label=k)
    speed = np.sqrt(sum(b[k] ** 2 for k in comps))
    ax.plot(t, speed, "k--", label="|v|")
    ax.set_xlabel("time (us)")
    ax.set_ylabel(f"{body} mean velocity (m/s)")
    ax.grid(alpha=0.3)
    ax.legend()
    ax.set_title(f"{body}: {speed[0]:.1f} m/s at t = 0, {speed[-1]:.1f} m/s at {t[-1]:.2f} us")
    fig.tight_layout()
    fig.savefig(png, dpi=100)
    plt.close(fig)
    return png


def plot_markers(path, png, axis=1, bodies=None, zoom=None, color="ply", every=1, window=(1600, 1100), view=None):
    """Render the markers of `path` to `png`; returns the png path.

    color: ply, body or material (categorical), or damage (a ply marker's
    largest damage variable, 0..1).  view (3D): None (oblique, default), or
    "xz" to look at a cut in the x-z plane (pair it with a thin zoom box in y)."""
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
    if color == "damage":
        if "damage" not in d:
            raise SystemExit("plyshock plot: --color damage needs a run step with a damage field")
        dm = d["damage"]
        key = dm.max(axis=1) if dm.ndim == 2 else dm
    else:
        key = {"ply": ply, "body": d["body"], "material": d["material"]}[color]
    labels = {"ply": None, "body": d["body_names"], "material": d["material_names"], "damage": None}[color]
    # categorical colours: one per ply (body, material), fixed by id so pictures compare
    from matplotlib import colormaps
    from matplotlib.colors import ListedColormap
    if color == "damage":
        # continuous: undamaged blue to failed red
        cmap, ncat, notes = "coolwarm", 2, None
        bar = {"title": "damage (max of d_ft, d_fc, d_mt, d_mc)", "color": "black"}
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
    title = (f"{path.split('/')[-1]}{f'  t = {t * 1e6:.2f} us' if t is not None else ''}: {keep.sum()} markers, "
             f"glyphs = material axis {axis}, colour = {color}")
    p.add_text(title, font_size=10, color="black")
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
