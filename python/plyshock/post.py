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
    return d


def plot_markers(path, png, axis=1, bodies=None, zoom=None, color="ply", every=1, window=(1600, 1100)):
    """Render the markers of `path` to `png`; returns the png path."""
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
    key = {"ply": ply, "body": d["body"], "material": d["material"]}[color]
    labels = {"ply": None, "body": d["body_names"], "material": d["material_names"]}[color]
    # categorical colours: one per ply (body, material), fixed by id so pictures compare
    from matplotlib import colormaps
    from matplotlib.colors import ListedColormap
    ncat = int(key[lam].max()) + 1 if lam.any() else 1
    base = colormaps["tab10"].colors
    cmap = ListedColormap([base[i % 10] for i in range(ncat)])
    names = labels or [f"{i}" for i in range(ncat)]
    bar = {"title": color, "color": "black", "n_labels": 0, "n_colors": ncat}
    notes = {float(i): f"{color} {names[i]}" for i in range(ncat)}
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
        p.add_mesh(mesh, scalars=color, cmap=cmap, clim=[-0.5, ncat - 0.5], line_width=2, show_scalar_bar=True,
                   scalar_bar_args=bar, annotations=notes)
        pts = pv.PolyData(X[idx])
        pts.point_data[color] = key[idx].astype(float)
        p.add_mesh(pts, scalars=color, cmap=cmap, clim=[-0.5, ncat - 0.5], point_size=3, show_scalar_bar=False)
    elif lam.any():
        pts = pv.PolyData(X[lam])
        pts.point_data[color] = key[lam].astype(float)
        p.add_mesh(pts, scalars=color, cmap=cmap, clim=[-0.5, ncat - 0.5], point_size=4, scalar_bar_args=bar,
                   annotations=notes)
    if other.any():
        pts = pv.PolyData(X[other])
        p.add_mesh(pts, color="dimgray", point_size=6, render_points_as_spheres=True)
        # body names at the centre of each non-laminate body
        for b in np.unique(d["body"][other]):
            c = X[other & (d["body"] == b)].mean(axis=0)
            p.add_point_labels([c], [d["body_names"][b]], font_size=14, text_color="black", shape=None, show_points=False)
    title = f"{path.split('/')[-1]}: {keep.sum()} markers, glyphs = material axis {axis}, colour = {color}"
    p.add_text(title, font_size=10, color="black")
    if dim == 2:
        p.view_xy()
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
