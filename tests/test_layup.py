"""Layup shorthand, frames and ply rotations (pure geometry)."""
import numpy as np
import pytest

from plyshock import DeckError, parse_layup
from plyshock.layup import frame_axes, rotate_axes


@pytest.mark.parametrize("text,angles", [
    ("[0/90/90/0]", [0, 90, 90, 0]),
    ("[0/90]s", [0, 90, 90, 0]),
    ("[0/±45/90]s", [0, 45, -45, 90, 90, -45, 45, 0]),
    ("[0/+-45/90]s", [0, 45, -45, 90, 90, -45, 45, 0]),
    ("[(0/90)2]s", [0, 90, 0, 90, 90, 0, 90, 0]),
    ("[45/-45]3", [45, -45] * 3),
    ("[0_2/90]", [0, 0, 90]),
    ("[0/90]2s", [0, 90, 0, 90, 90, 0, 90, 0]),
    ("[ 30 / -60 ]", [30, -60]),
])
def test_layup_shorthand(text, angles):
    assert parse_layup(text) == angles


@pytest.mark.parametrize("bad", ["0/90", "[0/90", "[0//90]", "[0/abc]", "[(0/90]s", "[]", "[0/90]x"])
def test_bad_layup_names_the_key(bad):
    with pytest.raises(DeckError) as e:
        parse_layup(bad, "bodies[0].laminate.layup")
    assert e.value.path == "bodies[0].laminate.layup"


def test_frame_is_orthonormal_right_handed_from_points():
    rng = np.random.default_rng(3)
    for _ in range(20):
        o, a, p = rng.normal(size=(3, 3))
        E = frame_axes(o, a, p, 3)
        assert np.allclose(E @ E.T, np.eye(3), atol=1e-14)
        assert np.allclose(np.cross(E[2], E[0]), E[1], atol=1e-14)        # axis 2 = axis 3 x axis 1
        assert np.allclose(E[2], (a - o) / np.linalg.norm(a - o), atol=1e-14)
        assert np.dot(p - o, E[0]) > 0 and abs(np.dot(p - o, E[1])) < 1e-12  # plane13 in the 1-3 plane


def test_2d_frame_axis2_out_of_plane_and_90_ply_fibres_out_of_plane():
    E = frame_axes([0.02, 0.005], [0.0, 0.025], [0.04, 0.025], 2)
    assert np.allclose(E[0], [2**-0.5, 2**-0.5, 0])
    assert np.allclose(E[1], [0, 0, -1])                     # e3 x e1 for e3 = (-1,1)/sqrt2
    F = rotate_axes(E, [[3, 90]])
    assert np.allclose(F[0], E[1], atol=1e-15)               # +90 about 3 turns axis 1 onto axis 2
    assert np.allclose(F[1], -E[0], atol=1e-15)


def test_rotations_are_intrinsic_and_right_handed():
    I = np.eye(3)
    # +30 about 3, then +90 about the turned axis 1
    F = rotate_axes(I, [[3, 30], [1, 90]])
    c, s = np.cos(np.radians(30)), np.sin(np.radians(30))
    assert np.allclose(F[0], [c, s, 0], atol=1e-15)
    assert np.allclose(F[1], [0, 0, 1], atol=1e-15)          # turned axis 2 goes to axis 3
    assert np.allclose(F[2], [s, -c, 0], atol=1e-15)
    # +90 about 2 turns axis 3 toward axis 1
    G = rotate_axes(I, [[2, 90]])
    assert np.allclose(G[2], [1, 0, 0], atol=1e-15)
    assert np.allclose(G @ G.T, I, atol=1e-15)


@pytest.mark.parametrize("rot,path", [([[4, 10]], "r[0][0]"), ([[3, 1], [1, 2], [2, 3]], "r"), ([[3]], "r[0]")])
def test_bad_rotations(rot, path):
    with pytest.raises(DeckError) as e:
        rotate_axes(np.eye(3), rot, "r")
    assert e.value.path == path


@pytest.mark.parametrize("o,a,p,key", [([0, 0], [0, 0], [1, 0], "f.axis3"), ([0, 0], [0, 1], [0, 2], "f.plane13"),
                                       ([0, 0], [0, 1], [0, 0], "f.plane13")])
def test_degenerate_frames(o, a, p, key):
    with pytest.raises(DeckError) as e:
        frame_axes(o, a, p, 2, "f")
    assert e.value.path == key
