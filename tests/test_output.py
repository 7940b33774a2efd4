"""Marker file schema (parallel HDF5 + .xmf), lean fields, `plyshock check`
against `plyshock init`, and the deck written by a Python scene reloading to
the same markers."""
import os

import h5py
import numpy as np
import yaml
from mpi4py import MPI

from plyshock import Body, Box, Grid, Material, Scene
from plyshock import core
from plyshock.deck import load_text
from conftest import run_cli
from helpers import random_laminate_scene

COMM = MPI.COMM_WORLD


def write(scene, path, text="deck"):
    m = core.initialize(scene)
    core.write_markers(m, path, text)
    return m


def test_schema_attributes_and_xmf(tmpdir_mpi):
    rng = np.random.default_rng(5)
    scene = random_laminate_scene(3, rng)
    scene.materials.append(Material("steel", preset="4340-steel"))
    scene.bodies.append(Body("block", box=Box([9.0, 9.0, 9.0], [9.5, 9.5, 9.5]), material="steel"))   # outside: error
    import pytest
    from plyshock import DeckError
    with pytest.raises(DeckError):
        scene.validate()
        core.check_geometry(scene, core.c_scene(scene))
    scene.bodies.pop()
    scene.materials.pop()
    path = os.path.join(tmpdir_mpi, "m.h5")
    m = write(scene, path, scene.to_yaml())
    n = m.stats["markers"]
    with h5py.File(path, "r") as f:
        g = f["markers"]
        assert g["x"].shape == (n, 3) and g["v"].shape == (n, 3)
        for k in ("id", "mass", "volume", "body", "ply", "material"):
            assert g[k].shape == (n,), k
        for k in ("axis1", "axis2", "axis3"):
            assert g[k].shape == (n, 3)
        A = np.stack([g["axis1"][...], g["axis2"][...], g["axis3"][...]], axis=1)
        assert np.allclose(np.einsum("nij,nkj->nik", A, A), np.eye(3), atol=1e-14)     # orthonormal
        assert np.allclose(np.linalg.det(A), 1.0, atol=1e-14)                          # right-handed
        assert g["id"].dtype == np.int64
        assert [s.decode() for s in g.attrs["body_names"]] == ["plate"]
        assert [s.decode() for s in g.attrs["material_names"]] == ["cfrp"]
        assert f.attrs["code_version"] and f.attrs["version"] and int(f.attrs["ranks"]) == COMM.size
        assert b"SI" in f.attrs["units"]
        # the deck recorded in the file reloads to the same scene
        again = load_text(f.attrs["deck"].decode())
        assert again.bodies[0].laminate.plies == scene.bodies[0].laminate.plies
        assert np.isclose(g["mass"][...].sum(), COMM.allreduce(core.local_fields(m, ["mass"])["mass"].sum()), rtol=1e-14)
    xmf = os.path.splitext(path)[0] + ".xmf"
    assert os.path.exists(xmf)
    text = open(xmf).read()
    assert f'NumberOfElements="{n}"' in text and "m.h5:/markers/x" in text and 'GeometryType="XYZ"' in text


def test_fields_are_lean_for_isotropic_scenes(tmpdir_mpi):
    al = Material("al", density=2700.0, elastic={"type": "isotropic", "E": 70e9, "nu": 0.33})
    iso = Scene(2, Grid([0, 0], [1, 1], [8, 8]), [al],
                [Body("block", box=Box([0.2, 0.2], [0.6, 0.5]), material="al")]).validate()
    path = os.path.join(tmpdir_mpi, "iso.h5")
    m = write(iso, path)
    rng = np.random.default_rng(9)
    lam = random_laminate_scene(2, rng)
    m2 = core.initialize(lam)
    # no axes (9 reals), ply stress (6 reals), ply damage (4 reals: IM7/8552 has Hashin failure)
    # and no ply id (one int) for a scene without anisotropy or laminates
    assert all(x.preset == "IM7/8552" for x in lam.materials)
    assert m2.bytes_per_marker - m.bytes_per_marker == (9 + 6 + 4) * 8 + 4
    assert m.bytes_per_marker == m.cs.marker_bytes(None)     # what `check` reports is what the swarm holds
    # plastic strain and temperature only with Johnson-Cook strength, damage only with failure
    steel = Scene(2, iso.grid, [Material("steel", preset="4340-steel")],
                  [Body("block", box=Box([0.2, 0.2], [0.6, 0.5]), material="steel")]).validate()
    assert core.initialize(steel).bytes_per_marker - m.bytes_per_marker == 2 * 8
    steel.materials[0].failure = {"type": "johnson-cook", "D1": 0.05, "D2": 3.44, "D3": -2.12, "D4": 0.002, "D5": 0.61}
    assert core.initialize(steel.validate()).bytes_per_marker - m.bytes_per_marker == 3 * 8
    with h5py.File(path, "r") as f:
        assert "axis1" not in f["markers"]
        assert np.all(f["markers/ply"][...] == -1)
        assert np.allclose(f["markers/v"][...], 0.0)


def test_check_predicts_init(tmpdir_mpi):
    deck = os.path.join(tmpdir_mpi, "d.yaml")
    out = os.path.join(tmpdir_mpi, "d.h5")
    rng = np.random.default_rng(11)
    scene = random_laminate_scene(3, rng)
    scene.bodies[0].velocity = [1.0, -2.0, 3.0]
    if COMM.rank == 0:
        with open(deck, "w") as f:
            f.write(scene.to_yaml())
    COMM.Barrier()
    rc, so, se = run_cli(["check", deck])
    assert rc == 0, se
    expected = int(so.split("expected markers: ")[1].split(",")[0])
    rc, so2, se = run_cli(["init", deck, "-o", out], ranks=2)
    assert rc == 0, se
    assert f"inserted {expected} markers" in so2
    assert "bytes per marker" in so2
    with h5py.File(out, "r") as f:
        assert len(f["markers/id"]) == expected
        assert np.allclose(f["markers/v"][...], [1.0, -2.0, 3.0])
