"""Layup shorthand as composite engineers write it, and ply frames.

"[0/90/90/0]", "[0/90]s", "[0/±45/90]s" (also +-45, -+45, ∓45), "[(0/90)2]s",
"[45/-45]3", "[0_2/90]" (two 0° plies), "[0/90]2s" (repeat, then mirror).
The first angle written is ply 0, on the frame's origin; each angle is a
rotation about axis 3 in degrees.
"""
import re

import numpy as np

from .errors import DeckError

_PM = {"±": (1, -1), "+-": (1, -1), "∓": (-1, 1), "-+": (-1, 1)}


def _parse_seq(s, path, full):
    """A '/'-separated sequence of angles and (groups)n."""
    out, i = [], 0
    items = []
    depth, cur = 0, ""
    for ch in s:
        if ch == "(":
            depth += 1
        elif ch == ")":
            depth -= 1
            if depth < 0:
                raise DeckError(path, f"unbalanced ')' in layup {full!r}")
        if ch == "/" and depth == 0:
            items.append(cur)
            cur = ""
        else:
            cur += ch
    if depth != 0:
        raise DeckError(path, f"unbalanced '(' in layup {full!r}")
    items.append(cur)
    for it in items:
        it = it.strip()
        if not it:
            raise DeckError(path, f"empty ply in layup {full!r}")
        m = re.fullmatch(r"\((.*)\)(\d*)", it)
        if m:
            group = _parse_seq(m.group(1), path, full)
            out += group * int(m.group(2) or 1)
            continue
        m = re.fullmatch(r"(±|\+-|∓|-\+)?([+-]?\d+(?:\.\d*)?)(?:_(\d+))?", it)
        if not m:
            raise DeckError(path, f"cannot read ply {it!r} in layup {full!r}; write angles in degrees like 0, -45, ±45, (0/90)2, 0_2")
        a = float(m.group(2))
        n = int(m.group(3) or 1)
        if n < 1:
            raise DeckError(path, f"ply count in {it!r} must be >= 1")
        if m.group(1):
            s1, s2 = _PM[m.group(1)]
            out += [s1 * a, s2 * a] * n
        else:
            out += [a] * n
        i += 1
    return out


def parse_layup(text, path="layup"):
    """Angles (degrees, about axis 3) of a layup string, ply 0 first."""
    if not isinstance(text, str):
        raise DeckError(path, f"must be a string like '[0/90]s', got {text!r}")
    t = text.replace(" ", "")
    m = re.fullmatch(r"\[(.+)\](\d*)([sS]?)", t)
    if not m:
        raise DeckError(path, f"cannot read layup {text!r}; write it like '[0/90/90/0]', '[0/±45/90]s', '[(0/90)2]s' or '[45/-45]3'")
    angles = _parse_seq(m.group(1), path, text) * int(m.group(2) or 1)
    if m.group(3):
        angles = angles + angles[::-1]
    return angles


def frame_axes(origin, axis3, plane13, dim, path="frame"):
    """Unit axes (e1, e2, e3) of a frame given by three points.

    e3 points from origin to axis3; e1 is the part of (plane13 - origin)
    normal to e3; e2 = e3 x e1 (right-handed).  In 2D the points lie in the
    x-y plane, which is the frame's 1-3 plane.
    """
    o = np.zeros(3); a = np.zeros(3); p = np.zeros(3)
    o[:dim], a[:dim], p[:dim] = origin, axis3, plane13
    scale = max(1.0, np.abs(np.r_[o, a, p]).max())
    d3 = a - o
    if np.linalg.norm(d3) <= 1e-12 * scale:
        raise DeckError(f"{path}.axis3", f"coincides with {path}.origin {list(origin)}; it must be a distinct point on the 3-axis")
    e3 = d3 / np.linalg.norm(d3)
    d1 = (p - o) - np.dot(p - o, e3) * e3
    if np.linalg.norm(d1) <= 1e-9 * max(np.linalg.norm(p - o), 1e-300) or np.linalg.norm(p - o) <= 1e-12 * scale:
        raise DeckError(f"{path}.plane13", f"{list(plane13)} is on the 3-axis through origin and axis3 (collinear or coincident); it must be off that line")
    e1 = d1 / np.linalg.norm(d1)
    e2 = np.cross(e3, e1)
    return np.array([e1, e2, e3])


def rotate_axes(E, rotations, path="rotations"):
    """Axes E (rows e1, e2, e3) turned by up to two intrinsic rotations.

    Each rotation is [axis, degrees] about axis 1, 2 or 3 of the axes as already
    turned; right-hand rule (+θ about 3 turns axis 1 toward axis 2).
    """
    if rotations is None:
        rotations = []
    if not isinstance(rotations, (list, tuple)):
        raise DeckError(path, f"must be a list of [axis, degrees] pairs, got {rotations!r}")
    if len(rotations) > 2:
        raise DeckError(path, f"at most 2 rotations are allowed, got {len(rotations)}")
    E = np.array(E, dtype=float)
    for i, r in enumerate(rotations):
        if not isinstance(r, (list, tuple)) or len(r) != 2:
            raise DeckError(f"{path}[{i}]", f"must be [axis, degrees], got {r!r}")
        ax, ang = r
        if isinstance(ax, bool) or ax not in (1, 2, 3):
            raise DeckError(f"{path}[{i}][0]", f"rotation axis must be 1, 2 or 3, got {ax!r}")
        from .errors import number
        t = np.radians(number(ang, f"{path}[{i}][1]", -360, 360))
        c, s = np.cos(t), np.sin(t)
        j, k = {1: (1, 2), 2: (2, 0), 3: (0, 1)}[ax]
        ej, ek = E[j].copy(), E[k].copy()
        E[j] = c * ej + s * ek
        E[k] = -s * ej + c * ek
    return E
