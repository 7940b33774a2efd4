"""Scene description: grid, materials, bodies.  SI units (m, kg, s, Pa, K).

The Python objects mirror the YAML deck (deck.py) key for key; `Scene.validate()`
checks every value and raises DeckError naming the deck key path and the
allowed range, before any PETSc object is made.
"""
from dataclasses import dataclass, field
from typing import List, Optional

import numpy as np

from . import layup as _layup
from .errors import DeckError, check_keys, number, vector
from .materials import PRESETS, preset

FACES = ("x-", "x+", "y-", "y+", "z-", "z+")
# The fastest body a deck may set moving (m/s): above the fastest natural impacts
# (meteoroids, up to about 72 km/s) and far above any gun; beyond it a time step
# would shrink toward nothing (1e20 m/s) or the kinetic energy overflow (1e300).
V_MAX = 1.0e5
BOUNDARY_KINDS = ("free", "symmetry", "fixed")
# 2D geometries: plane strain (per metre of depth) or axisymmetric (x = r >= 0,
# y = z, the x- face the axis; masses and totals of the full revolution)
GEOMETRIES = ("plane-strain", "axisymmetric")
# Relative tolerance of the transverse-isotropy test of an axisymmetric ply
TRANSVERSE_ISOTROPY_RTOL = 1e-9
# Largest ratio of a cell's longest side to its shortest: MPM's shape functions
# want near-square cells, and the exact insertion bisects a cell cut by a
# curved surface in every direction at once, so its work grows as the ratio
# to the power dim - 1 (a 1e7:1 cell never finished).
MAX_CELL_ASPECT = 10.0


@dataclass
class Grid:
    lower: List[float]
    upper: List[float]
    cells: List[int]
    boundary: dict = field(default_factory=dict)   # face -> free|symmetry|fixed

    KEYS = ("lower", "upper", "cells", "boundary")

    def validate(self, dim, path="grid"):
        self.lower = vector(self.lower, dim, f"{path}.lower")
        self.upper = vector(self.upper, dim, f"{path}.upper")
        if not isinstance(self.cells, (list, tuple)) or len(self.cells) != dim:
            raise DeckError(f"{path}.cells", f"must be a list of {dim} whole numbers, got {self.cells!r}")
        self.cells = [number(c, f"{path}.cells[{i}]", 1, 2**20, integer=True) for i, c in enumerate(self.cells)]
        for i in range(dim):
            if self.upper[i] <= self.lower[i]:
                raise DeckError(f"{path}.upper[{i}]", f"{self.upper[i]} must be > lower[{i}] = {self.lower[i]}")
        h = self.h
        if max(h) > MAX_CELL_ASPECT * min(h):
            raise DeckError(f"{path}.cells", f"cells of {' x '.join(f'{x:.4g}' for x in h)} m have an aspect ratio of "
                            f"{max(h) / min(h):.4g}; allowed at most {MAX_CELL_ASPECT:g} (choose cells so that (upper - lower) / cells "
                            f"are alike in every direction)")
        faces = FACES[: 2 * dim]
        b = self.boundary if self.boundary is not None else {}
        check_keys(b, faces, f"{path}.boundary")      # a mapping of faces
        b = dict(b)
        for f in faces:
            kind = b.setdefault(f, "free")
            if kind not in BOUNDARY_KINDS:
                raise DeckError(f"{path}.boundary.{f}", f"must be one of {'|'.join(BOUNDARY_KINDS)}, got {kind!r}")
        self.boundary = b
        return self

    @property
    def h(self):
        return [(u - l) / n for l, u, n in zip(self.lower, self.upper, self.cells)]


ELASTIC_KEYS = {"isotropic": ("type", "E", "nu"),
                "orthotropic": ("type", "E1", "E2", "E3", "G12", "G13", "G23", "nu12", "nu13", "nu23"),
                "transversely-isotropic": ("type", "E1", "E2", "G12", "nu12", "nu23")}
PLY_STRENGTHS = ("Xt", "Xc", "Yt", "Yc", "S12", "S23")
# Mechanical Threshold Stress constants (src/materials/strength_mts.c; SI: Pa, K, 1/s)
MTS_KEYS = ("sigma_a", "mu_0", "D", "T_0", "k_over_b3", "g_0e", "eps_dot_0e", "p_e", "q_e", "a_0", "a_1", "a_2", "a_3",
            "alpha", "g_0es", "eps_dot_es0", "sigma_es0", "sigma_i", "g_0i", "eps_dot_0i", "p_i", "q_i")
MTS_INTRINSIC = ("g_0i", "eps_dot_0i", "p_i", "q_i")     # needed only with sigma_i > 0
TEMPERATURE_STRENGTHS = ("johnson-cook", "zerilli-armstrong-fcc", "zerilli-armstrong-bcc", "mts")
FRACTURE_PLANE_DEG = 53.0   # IM7/8552 fracture-plane angle under transverse compression (NASA CompDam, after Camanho)
MODEL_KEYS = {
    "eos": {"mie-gruneisen": ("type", "c0", "s", "gamma0", "spall_pressure"),
            "ideal-gas": ("type", "gamma", "cv")},                   # gamma > 1; cv J/kg/K (optional: temperature)
    "strength": {"none": ("type",), "elastic-plastic": ("type", "yield_stress", "taylor_quinney"),
                 "johnson-cook": ("type", "A", "B", "n", "C", "m", "T_melt", "T_room", "eps_dot0", "taylor_quinney"),
                 "zerilli-armstrong-fcc": ("type", "C0", "C2", "C3", "C4", "T_room", "taylor_quinney"),
                 "zerilli-armstrong-bcc": ("type", "C0", "C1", "C3", "C4", "C5", "n", "T_room", "taylor_quinney"),
                 "mts": ("type",) + MTS_KEYS + ("T_room", "taylor_quinney")},
    "failure": {"johnson-cook": ("type", "D1", "D2", "D3", "D4", "D5"),
                "hashin": ("type", "G_ft", "G_fc", "G_mt", "G_mc")},   # fracture energies J/m^2
}


# Ranges of the models' parameters (lo, hi, lo excluded); None: unbounded.
# Sound speed up to V_MAX (diamond's is 18 km/s); Johnson-Cook's D1..D5 take any sign.
MODEL_RANGES = {
    ("eos", "c0"): (0, 1e5, True), ("eos", "s"): (0, 10, False), ("eos", "gamma0"): (0, 10, False),
    ("eos", "spall_pressure"): (None, 0, False),
    ("strength", "yield_stress"): (0, None, True), ("strength", "taylor_quinney"): (0, 1, False),
    ("strength", "A"): (0, None, False), ("strength", "B"): (0, None, False), ("strength", "n"): (0, None, False),
    ("strength", "C"): (0, None, False), ("strength", "m"): (0, None, True), ("strength", "T_melt"): (0, None, True),
    ("strength", "T_room"): (0, None, True), ("strength", "eps_dot0"): (0, None, True),
}


def orthotropic_compliance(p):
    """6x6 compliance S (Voigt 11,22,33,23,13,12, 1/Pa); the stiffness is S^-1, positive definite exactly when S is."""
    E1, E2, E3 = p["E1"], p["E2"], p["E3"]
    n12, n13, n23 = p["nu12"], p["nu13"], p["nu23"]
    S = np.zeros((6, 6))
    S[0, 0], S[1, 1], S[2, 2] = 1 / E1, 1 / E2, 1 / E3
    S[0, 1] = S[1, 0] = -n12 / E1
    S[0, 2] = S[2, 0] = -n13 / E1
    S[1, 2] = S[2, 1] = -n23 / E2
    S[3, 3], S[4, 4], S[5, 5] = 1 / p["G23"], 1 / p["G13"], 1 / p["G12"]
    return S


@dataclass
class Material:
    name: str
    preset: Optional[str] = None
    density: Optional[float] = None          # kg/m^3
    elastic: Optional[dict] = None           # {type: isotropic|orthotropic, ...} Pa
    eos: Optional[dict] = None               # {type: mie-gruneisen, c0 m/s, s, gamma0}
    shear_modulus: Optional[float] = None    # Pa
    strength: Optional[dict] = None
    failure: Optional[dict] = None
    specific_heat: Optional[float] = None    # J/kg/K
    strengths: Optional[dict] = None         # ply strengths Xt, Xc, Yt, Yc, S12, S23 (Pa)

    KEYS = ("name", "preset", "density", "elastic", "eos", "shear_modulus", "strength", "failure", "specific_heat", "strengths")

    def validate(self, path):
        if not isinstance(self.name, str) or not self.name:
            raise DeckError(f"{path}.name", f"must be a non-empty string, got {self.name!r}")
        explicit = {k: getattr(self, k) for k in self.KEYS[2:] if getattr(self, k) is not None}
        if self.preset is not None:
            if not isinstance(self.preset, str) or self.preset not in PRESETS:
                import difflib
                near = difflib.get_close_matches(str(self.preset), list(PRESETS), n=1)
                raise DeckError(f"{path}.preset", f"unknown preset {self.preset!r}{'; did you mean ' + repr(near[0]) + '?' if near else ''} (allowed: {', '.join(PRESETS)})")
            base = preset(self.preset)
            user_iso = isinstance(explicit.get("elastic"), dict) and explicit["elastic"].get("type") == "isotropic"
            if user_iso and "shear_modulus" not in explicit:
                base.pop("shear_modulus", None)      # the user's isotropic elasticity replaces the preset's G
            for k, v in base.items():
                if k not in explicit:
                    setattr(self, k, v)
                elif isinstance(v, dict) and isinstance(explicit[k], dict) and explicit[k].get("type", v.get("type")) == v.get("type"):
                    setattr(self, k, {**v, **explicit[k]})     # override single fields of a preset model
        if self.density is None:
            raise DeckError(f"{path}.density", "is required (kg/m^3, > 0) unless a preset gives it")
        self.density = number(self.density, f"{path}.density", 0, 1e5, lo_open=True)
        if self.elastic is not None:
            self._model("elastic", ELASTIC_KEYS, path)
            e = self.elastic
            if e["type"] == "transversely-isotropic":     # axis 1 the symmetry axis: 2 and 3 alike
                e = self.elastic = {"type": "orthotropic", "E1": e["E1"], "E2": e["E2"], "E3": e["E2"], "G12": e["G12"],
                                    "G13": e["G12"], "G23": e["E2"] / (2 * (1 + e["nu23"])), "nu12": e["nu12"],
                                    "nu13": e["nu12"], "nu23": e["nu23"]}
            if e["type"] == "isotropic":
                if self.shear_modulus is not None:
                    raise DeckError(f"{path}.shear_modulus", "given together with elastic: {type: isotropic}; keep one: either elastic {E, nu} or shear_modulus (with an eos)")
                number(e["E"], f"{path}.elastic.E", 0, None, lo_open=True)
                number(e["nu"], f"{path}.elastic.nu", -1, 0.5, lo_open=True)
                if e["nu"] >= 0.5:
                    raise DeckError(f"{path}.elastic.nu", f"{e['nu']} is out of range; allowed (-1, 0.5)")
            else:
                for k in ELASTIC_KEYS["orthotropic"][1:7]:
                    number(e[k], f"{path}.elastic.{k}", 0, None, lo_open=True)
                for k in ("nu12", "nu13", "nu23"):
                    number(e[k], f"{path}.elastic.{k}", -1, None, lo_open=True)
                ev = np.linalg.eigvalsh(orthotropic_compliance(e))
                if ev.min() <= 0:
                    raise DeckError(f"{path}.elastic", "orthotropic stiffness is not positive definite (check the Poisson ratios: "
                                    "need 1 - nu12 nu21 - nu23 nu32 - nu13 nu31 - 2 nu21 nu32 nu13 > 0 and nu_ij^2 < E_i/E_j)")
        for k in ("eos", "strength", "failure"):
            if getattr(self, k) is not None:
                self._model(k, MODEL_KEYS[k], path)
        if self.is_gas:
            self.eos["gamma"] = number(self.eos["gamma"], f"{path}.eos.gamma", 1, None, lo_open=True)
            if "cv" in self.eos:
                self.eos["cv"] = number(self.eos["cv"], f"{path}.eos.cv", 0, None, lo_open=True)
            for k in ("shear_modulus", "strength", "failure", "elastic"):
                if getattr(self, k) is not None:
                    raise DeckError(f"{path}.{k}", "does not apply to an ideal gas (no strength, no failure); remove it")
        if self.shear_modulus is not None:
            self.shear_modulus = number(self.shear_modulus, f"{path}.shear_modulus", 0, None, lo_open=True)
        if self.specific_heat is not None:
            self.specific_heat = number(self.specific_heat, f"{path}.specific_heat", 0, None, lo_open=True)
        if self.strengths is not None:
            check_keys(self.strengths, PLY_STRENGTHS, f"{path}.strengths")
            for k, v in list(self.strengths.items()):
                self.strengths[k] = number(v, f"{path}.strengths.{k}", 0, None, lo_open=True)
        if self.anisotropic:
            for k in ("shear_modulus", "strength"):
                if getattr(self, k) is not None and not (k == "strength" and self.strength["type"] == "none"):
                    raise DeckError(f"{path}.{k}", "does not apply to an orthotropic ply (its stiffness gives the shear "
                                    "response and plies have no plasticity); remove it")
        ftype = (self.failure or {}).get("type")
        if ftype == "hashin":
            if not self.anisotropic:
                raise DeckError(f"{path}.failure.type", "hashin is a ply failure model: it needs elastic: {type: orthotropic, ...}")
            st = dict(self.strengths or {})
            for k in PLY_STRENGTHS[:5]:
                if k not in st:
                    raise DeckError(f"{path}.strengths.{k}", "is required with failure type hashin (Pa, > 0)")
            # transverse shear strength from the fracture-plane angle unless given:
            # S23 = Yc / (2 tan 53 deg) (Puck & Schuermann; CompDam's angle for IM7/8552)
            st.setdefault("S23", st["Yc"] / (2 * np.tan(np.radians(FRACTURE_PLANE_DEG))))
            self.strengths = st
            for k in MODEL_KEYS["failure"]["hashin"][1:]:
                number(self.failure[k], f"{path}.failure.{k}", 0, None, lo_open=True)
        elif ftype == "johnson-cook" and self.anisotropic:
            raise DeckError(f"{path}.failure.type", "johnson-cook failure is for metals; an orthotropic ply takes hashin")
        return self

    def _model(self, key, table, path):
        m = getattr(self, key)
        if not isinstance(m, dict) or "type" not in m:
            raise DeckError(f"{path}.{key}", f"must be a mapping with a type from {'|'.join(table)}")
        if not isinstance(m["type"], str) or m["type"] not in table:
            raise DeckError(f"{path}.{key}.type", f"unknown {key} type {m['type']!r}; allowed: {'|'.join(table)}")
        check_keys(m, table[m["type"]], f"{path}.{key}")
        for k, v in list(m.items()):
            if k != "type":
                lo, hi, lo_open = MODEL_RANGES.get((key, k), (None, None, False))
                m[k] = number(v, f"{path}.{key}.{k}", lo, hi, lo_open=lo_open)     # YAML reads 1.0e9 (no exponent sign) as a string
        required = {"isotropic": ("E", "nu"), "orthotropic": ELASTIC_KEYS["orthotropic"][1:], "mie-gruneisen": ("c0", "s", "gamma0"),
                    "johnson-cook": ("A", "B", "n", "C", "m", "T_melt") if key == "strength" else ("D1", "D2", "D3", "D4", "D5"),
                    "transversely-isotropic": ELASTIC_KEYS["transversely-isotropic"][1:], "hashin": MODEL_KEYS["failure"]["hashin"][1:],
                    "elastic-plastic": ("yield_stress",), "none": (), "ideal-gas": ("gamma",),
                    "zerilli-armstrong-fcc": MODEL_KEYS["strength"]["zerilli-armstrong-fcc"][1:5],
                    "zerilli-armstrong-bcc": MODEL_KEYS["strength"]["zerilli-armstrong-bcc"][1:7],
                    "mts": MTS_KEYS[:17] + (MTS_INTRINSIC if m.get("sigma_i", 0) else ())}[m["type"]]
        for k in required:
            if k not in m:
                raise DeckError(f"{path}.{key}.{k}", f"is required for {key} type {m['type']}")
        if m["type"] == "johnson-cook" and key == "strength" and m.get("T_room", 294.0) >= m["T_melt"]:
            raise DeckError(f"{path}.{key}.T_melt", f"{m['T_melt']} K must be above T_room = {m.get('T_room', 294.0)} K")
        if key == "strength" and m["type"] in TEMPERATURE_STRENGTHS[1:]:
            _strength_ranges(m, f"{path}.{key}")

    @property
    def anisotropic(self):
        return isinstance(self.elastic, dict) and self.elastic.get("type") == "orthotropic"

    @property
    def is_gas(self):
        return isinstance(self.eos, dict) and self.eos.get("type") == "ideal-gas"


def _strength_ranges(m, path):
    """Ranges of the Zerilli-Armstrong and MTS constants (the kernels' checks
    repeat them); each error names the key and the allowed range."""
    def rng(k, lo=None, hi=None, lo_open=False):
        if k in m:
            number(m[k], f"{path}.{k}", lo, hi, lo_open=lo_open)
    rng("T_room", 0, None, lo_open=True)
    rng("taylor_quinney", 0, 1)
    if m["type"].startswith("zerilli-armstrong"):
        for k in ("C0", "C1", "C2", "C5", "C3", "C4"):     # stresses (Pa) and 1/K, all >= 0
            rng(k, 0)
        rng("n", 0, 1)
        return
    for k in ("mu_0", "k_over_b3", "g_0e", "eps_dot_0e", "g_0es", "eps_dot_es0", "sigma_es0"):
        rng(k, 0, None, lo_open=True)
    for k in ("sigma_a", "D", "T_0", "sigma_i", "a_0"):
        rng(k, 0)
    # Kocks' ranges of the activation-profile exponents: 0 < p <= 1, 1 <= q <= 2
    for x in ("e", "i") if m.get("sigma_i", 0) else ("e",):
        rng(f"p_{x}", 0, 1, lo_open=True)
        rng(f"q_{x}", 1, 2)
    if m.get("sigma_i", 0):
        for k in ("g_0i", "eps_dot_0i"):
            rng(k, 0, None, lo_open=True)
    rng("alpha", 0.01, 50)
    T = float(m.get("T_room", 294.0))
    if m["D"] > 0 and m["D"] / np.expm1(m["T_0"] / T) >= m["mu_0"]:
        raise DeckError(f"{path}.D", f"{m['D']} Pa gives mu(T) = mu_0 - D/(exp(T_0/T) - 1) <= 0 at T_room = {T} K; "
                        f"allowed D < {m['mu_0'] * np.expm1(m['T_0'] / T):.6g} Pa")


@dataclass
class Frame:
    origin: List[float]
    axis3: List[float]     # a point on the 3-axis (stacking direction)
    plane13: List[float]   # a point in the 1-3 plane

    KEYS = ("origin", "axis3", "plane13")

    def axes(self, dim, path="frame"):
        o = vector(self.origin, dim, f"{path}.origin")
        a = vector(self.axis3, dim, f"{path}.axis3")
        p = vector(self.plane13, dim, f"{path}.plane13")
        return _layup.frame_axes(o, a, p, dim, path)


@dataclass
class Ply:
    material: str
    thickness: float                            # m
    rotations: list = field(default_factory=list)   # [[axis 1|2|3, degrees], ...] at most 2

    KEYS = ("material", "thickness", "rotations")


INTERFACE_TYPES = ("bonded", "cohesive")


@dataclass
class Interface:
    """A laminate's ply interfaces (docs/contact.md): bonded (one velocity
    field for the laminate) or cohesive (each ply its own field; between
    adjacent plies a traction-separation law, rigid until the strength
    ellipse, then linear softening to G_I / G_II, mixed by the linear power
    law; open, Coulomb contact with the contact section's friction)."""
    type: str = "bonded"
    normal_strength: Optional[float] = None   # Pa, > 0
    shear_strength: Optional[float] = None    # Pa, > 0
    G_I: Optional[float] = None               # J/m^2, > 0
    G_II: Optional[float] = None              # J/m^2, > 0

    KEYS = ("type", "normal_strength", "shear_strength", "G_I", "G_II")
    CONSTANTS = ("normal_strength", "shear_strength", "G_I", "G_II")

    def validate(self, path):
        if self.type not in INTERFACE_TYPES:
            raise DeckError(f"{path}.type", f"unknown interface type {self.type!r}; allowed: {'|'.join(INTERFACE_TYPES)}")
        for k in self.CONSTANTS:
            v = getattr(self, k)
            if self.type == "bonded":
                if v is not None:
                    raise DeckError(f"{path}.{k}", "applies to type cohesive only; bonded plies share one velocity field")
                continue
            if v is None:
                raise DeckError(f"{path}.{k}", f"is required for type cohesive ({'Pa' if 'strength' in k else 'J/m^2'}, > 0)")
            setattr(self, k, number(v, f"{path}.{k}", 0, None, lo_open=True))
        return self

    @property
    def cohesive(self):
        return self.type == "cohesive"


@dataclass
class Laminate:
    frame: Frame
    size: List[float]                # [L1] in 2D, [L1, L2] in 3D (m)
    plies: List[Ply] = field(default_factory=list)
    interface: Optional[Interface] = None   # between adjacent plies; None: bonded

    KEYS = ("frame", "size", "plies", "layup", "ply_thickness", "ply_material", "interface")

    @staticmethod
    def from_layup(frame, size, layup, ply_thickness, ply_material, path="laminate", interface=None):
        angles = _layup.parse_layup(layup, f"{path}.layup")
        return Laminate(frame, size, [Ply(ply_material, ply_thickness, [[3, a]]) for a in angles], interface)


@dataclass
class Box:
    lower: List[float]
    upper: List[float]
    KEYS = ("lower", "upper")


@dataclass
class Sphere:
    center: List[float]
    radius: float
    KEYS = ("center", "radius")


@dataclass
class Cylinder:
    base: List[float]      # centre of the base face (m)
    axis: List[float]      # direction (normalised here)
    radius: float
    length: float
    KEYS = ("base", "axis", "radius", "length")


SHAPES = {"laminate": Laminate, "box": Box, "sphere": Sphere, "cylinder": Cylinder}
REPRESENTATIONS = ("markers", "cells")
SHAPE_FUNCTIONS = ("linear", "gimp", "bspline2")
INSERTIONS = ("exact", "lattice")    # exact pieces (the method's) | a regular lattice of points per cell
MAX_POINTS_PER_CELL = 16
TRANSFERS = ("musl", "apic")


@dataclass
class Run:
    """The deck's `run:` section (SI units); each key can be overridden by -run_<key>."""
    t_end: float                          # s
    cfl: float = 0.4
    shape: str = "gimp"                   # linear | gimp | bspline2
    transfer: str = "musl"                # musl (FLIP/PIC blend) | apic (MLS-MPM; bspline2 only)
    output_interval: float = 0.0          # s; 0 = initial and final states only
    artificial_viscosity: dict = field(default_factory=lambda: {"c_linear": 0.2, "c_quadratic": 2.0})
    pic_fraction: float = 0.0             # PIC share of the velocity update (0 = FLIP)
    dt_growth: float = 1.1
    dt_max: float = 0.0                   # s; 0 = none
    mass_threshold: float = 1e-10         # of a full cell of the lightest material: lighter nodes get no velocity
    max_steps: int = 0
    history_interval: int = 10
    progress_interval: int = 0
    fbar: bool = False                    # cell-averaged volumetric rate (Delta-F-bar; against locking in plastic flow)
    checkpoint_interval: float = 0.0      # s of simulated time between checkpoints; 0 = at every output time
    checkpoint_wall_interval: float = 0.0  # s of wall time between checkpoints; 0 = none
    dt_floor: float = 1e-3                # stop when the time step falls below this share of the first one; 0 = never

    KEYS = ("t_end", "cfl", "shape", "transfer", "output_interval", "artificial_viscosity", "pic_fraction", "dt_growth",
            "dt_max", "mass_threshold", "max_steps", "history_interval", "progress_interval", "fbar",
            "checkpoint_interval", "checkpoint_wall_interval", "dt_floor")

    def validate(self, path="run"):
        """The section's structure: known names and value types.  The values'
        ranges and combinations are checked in one place, in C
        (PSRunParamsCheck, through core.run_options), after -run_<key> options
        from the command line have had their say."""
        self.t_end = number(self.t_end, f"{path}.t_end")
        self.cfl = number(self.cfl, f"{path}.cfl")
        if self.shape not in SHAPE_FUNCTIONS:
            raise DeckError(f"{path}.shape", f"must be one of {'|'.join(SHAPE_FUNCTIONS)}, got {self.shape!r}")
        if self.transfer not in TRANSFERS:
            raise DeckError(f"{path}.transfer", f"must be one of {'|'.join(TRANSFERS)}, got {self.transfer!r}")
        self.output_interval = number(self.output_interval, f"{path}.output_interval")
        av = dict(self.artificial_viscosity or {})
        check_keys(av, ("c_linear", "c_quadratic"), f"{path}.artificial_viscosity")
        av.setdefault("c_linear", 0.2)
        av.setdefault("c_quadratic", 2.0)
        for k in av:
            av[k] = number(av[k], f"{path}.artificial_viscosity.{k}")
        self.artificial_viscosity = av
        self.pic_fraction = number(self.pic_fraction, f"{path}.pic_fraction")
        self.dt_growth = number(self.dt_growth, f"{path}.dt_growth")
        self.dt_max = number(self.dt_max, f"{path}.dt_max")
        self.mass_threshold = number(self.mass_threshold, f"{path}.mass_threshold")
        self.max_steps = number(self.max_steps, f"{path}.max_steps", -2**31, 2**31 - 1, integer=True)
        self.history_interval = number(self.history_interval, f"{path}.history_interval", -2**31, 2**31 - 1, integer=True)
        self.progress_interval = number(self.progress_interval, f"{path}.progress_interval", -2**31, 2**31 - 1, integer=True)
        if not isinstance(self.fbar, bool):
            raise DeckError(f"{path}.fbar", f"must be true or false, got {self.fbar!r}")
        self.checkpoint_interval = number(self.checkpoint_interval, f"{path}.checkpoint_interval")
        self.checkpoint_wall_interval = number(self.checkpoint_wall_interval, f"{path}.checkpoint_wall_interval")
        self.dt_floor = number(self.dt_floor, f"{path}.dt_floor")
        return self


CONTACT_TYPES = ("friction", "bonded")


@dataclass
class Contact:
    """The deck's `contact:` section: how marker bodies meet (docs/contact.md).
    Default: friction 0 between every two bodies (each body its own velocity
    field: bodies separate and slide); type bonded joins them in one field.
    pairs: [{bodies: [a, b], type: bonded|friction, friction: mu}] set single
    pairs; bonded is transitive (a field is a group of bodies joined by bonded
    pairs)."""
    type: str = "friction"               # friction | bonded: between bodies no pair names
    friction: float = 0.0                # Coulomb coefficient (-), [0, inf)
    pairs: Optional[list] = None

    KEYS = ("type", "friction", "pairs")
    PAIR_KEYS = ("bodies", "type", "friction")

    def validate(self, bodies, path="contact"):
        """bodies: {name: deck index} of the scene's bodies."""
        if self.type not in CONTACT_TYPES:
            raise DeckError(f"{path}.type", f"unknown contact type {self.type!r}; allowed: {'|'.join(CONTACT_TYPES)}")
        self.friction = number(self.friction, f"{path}.friction", 0.0)
        if self.pairs is None:
            return self
        if not isinstance(self.pairs, list):
            raise DeckError(f"{path}.pairs", "must be a list of {bodies: [a, b], type: bonded|friction, friction: mu}")
        seen = {}
        for i, pr in enumerate(self.pairs):
            pp = f"{path}.pairs[{i}]"
            check_keys(pr, self.PAIR_KEYS, pp)
            names = pr.get("bodies")
            if not isinstance(names, list) or len(names) != 2:
                raise DeckError(f"{pp}.bodies", f"must be a list of two body names, got {names!r}")
            for j, nm in enumerate(names):
                if nm not in bodies:
                    import difflib
                    near = difflib.get_close_matches(str(nm), list(bodies), n=1)
                    raise DeckError(f"{pp}.bodies[{j}]", f"unknown body {nm!r}{'; did you mean ' + repr(near[0]) + '?' if near else ''} "
                                    f"(defined: {', '.join(bodies)})")
            if names[0] == names[1]:
                raise DeckError(f"{pp}.bodies", f"names {names[0]!r} twice; a pair is two different bodies")
            key = frozenset(names)
            if key in seen:
                raise DeckError(f"{pp}.bodies", f"the pair {names[0]!r}, {names[1]!r} is already {path}.pairs[{seen[key]}]")
            seen[key] = i
            pr.setdefault("type", "friction")
            if pr["type"] not in CONTACT_TYPES:
                raise DeckError(f"{pp}.type", f"unknown contact type {pr['type']!r}; allowed: {'|'.join(CONTACT_TYPES)}")
            if pr["type"] == "bonded" and "friction" in pr:
                raise DeckError(f"{pp}.friction", "applies to type friction only; a bonded pair shares one velocity field")
            if pr["type"] == "friction":
                pr["friction"] = number(pr.get("friction", self.friction), f"{pp}.friction", 0.0)
        return self

    def fields(self, scene):
        """(field of each body, -1 for bodies in cells; nfield; nfield x nfield
        friction coefficients): layout() without the cohesive plies' part."""
        lay = self.layout(scene)
        return lay["field"], lay["nfield"], lay["mu"]

    def layout(self, scene):
        """The velocity fields: {field: of each body (-1 for bodies in cells;
        a laminate with cohesive interfaces: of its first ply), split: 1 for
        such a laminate (ply j is field field + j), nfield, mu: nfield x nfield
        friction coefficients, coh: nfield x nfield cohesive law of a pair of
        fields (-1 none), cohp: the laws (N, S, G_I, G_II)}.  Fields are the
        groups of marker bodies joined by bonded pairs (the section's type for
        pairs not listed); a laminate with cohesive interfaces is a group of
        its own and takes a field per ply."""
        idx = {b.name: i for i, b in enumerate(scene.bodies)}
        marker = [i for i, b in enumerate(scene.bodies) if b.representation == "markers"]
        listed = {}
        for i, pr in enumerate(self.pairs or []):
            a, b = (idx[n] for n in pr["bodies"])
            listed[frozenset((a, b))] = (i, pr["type"], pr.get("friction", 0.0))
        parent = {i: i for i in marker}

        def root(i):
            while parent[i] != i:
                i = parent[i]
            return i
        for x in marker:
            for y in marker:
                if x < y and listed.get(frozenset((x, y)), (None, self.type))[1] == "bonded":
                    parent[root(y)] = root(x)
        field, roots = [-1] * len(scene.bodies), []
        for i in marker:
            r = root(i)
            if r not in roots:
                roots.append(r)
            field[i] = roots.index(r)
        coh_body = [i for i in marker if scene.bodies[i].kind == "laminate" and scene.bodies[i].laminate.interface is not None
                    and scene.bodies[i].laminate.interface.cohesive]
        for i in coh_body:
            other = [j for j in marker if j != i and field[j] == field[i]]
            if other:
                raise DeckError(f"bodies[{i}].laminate.interface", f"a laminate with cohesive ply interfaces cannot be bonded to other bodies "
                                f"({scene.bodies[other[0]].name!r} through the contact section); list their pairs as type friction")
        nf = len(roots)
        mu = np.full((nf, nf), -1.0)
        # listed pairs first, then the section's friction between groups no listed pair joins
        for listed_pass in (True, False):
            for x in marker:
                for y in marker:
                    if x >= y or (frozenset((x, y)) in listed) != listed_pass:
                        continue
                    i, kind, f = listed.get(frozenset((x, y)), (None, self.type, self.friction))
                    a, b = field[x], field[y]
                    pp = f"contact.pairs[{i}]" if i is not None else "contact"
                    if a == b:
                        if kind == "friction":
                            raise DeckError(f"{pp}.type", f"bodies {scene.bodies[x].name!r} and {scene.bodies[y].name!r} are bonded "
                                            "through other pairs (bonded is transitive: list the pairs of the group as friction)")
                        continue
                    if not listed_pass:
                        if mu[a, b] < 0:
                            mu[a, b] = mu[b, a] = f
                        continue
                    if mu[a, b] >= 0 and mu[a, b] != f:
                        raise DeckError(f"{pp}.friction", f"{f} differs from {mu[a, b]} between the same two groups of bonded bodies "
                                        f"({scene.bodies[x].name!r} and {scene.bodies[y].name!r}); one coefficient per pair of groups")
                    mu[a, b] = mu[b, a] = f
        mu[mu < 0] = 0.0
        # a cohesive laminate: its group's field becomes one per ply, in ply order
        split = [0] * len(scene.bodies)
        grp_first = list(range(nf))         # group g -> its first field
        nply = {field[i]: len(scene.bodies[i].laminate.plies) for i in coh_body}
        total = 0
        for g in range(nf):
            grp_first[g] = total
            total += nply.get(g, 1)
        expand = [g for g in range(nf) for _ in range(nply.get(g, 1))]
        mu2 = mu[np.ix_(expand, expand)] if nf else mu
        coh = np.full((total, total), -1, dtype=int)
        cohp = []
        for i in coh_body:
            g, itf = field[i], scene.bodies[i].laminate.interface
            f0 = grp_first[g]
            for j in range(nply[g]):
                for k in range(nply[g]):
                    if j != k:
                        mu2[f0 + j, f0 + k] = self.friction   # plies once open: Coulomb contact
            for j in range(nply[g] - 1):
                coh[f0 + j, f0 + j + 1] = coh[f0 + j + 1, f0 + j] = len(cohp)
            cohp.append([itf.normal_strength, itf.shear_strength, itf.G_I, itf.G_II])
            split[i] = 1
        field = [grp_first[f] if f >= 0 else -1 for f in field]
        return dict(field=field, split=split, nfield=total, mu=mu2, coh=coh, cohp=np.asarray(cohp, dtype=float).reshape(-1, 4))


@dataclass
class Body:
    name: str
    laminate: Optional[Laminate] = None
    box: Optional[Box] = None
    sphere: Optional[Sphere] = None
    cylinder: Optional[Cylinder] = None
    material: Optional[str] = None       # for box, sphere, cylinder
    velocity: Optional[List[float]] = None   # m/s
    subdivision: Optional[int] = None        # exact: sub-cells per cell and direction (default 1)
    volume_tolerance: Optional[float] = None  # exact, curved bodies: relative (default 1e-6)
    sliver_fraction: Optional[float] = None  # exact: of a sub-cell (default 1e-6)
    priority: Optional[int] = None
    clip: bool = False
    representation: str = "markers"      # markers | cells (Eulerian volume fractions, remapped every step)
    pressure: Optional[float] = None     # Pa: initial pressure (sets e0 through the EOS at the initial density)
    density: Optional[float] = None      # kg/m^3: a body in cells: its initial density (default: its material's)
    plastic_strain: Optional[float] = None   # -: initial equivalent plastic strain (a material with strength)
    insertion: str = "exact"                 # exact | lattice
    points_per_cell: Optional[int] = None    # lattice: points per cell and direction (default 2; n^dim per cell)

    KEYS = ("name", "laminate", "box", "sphere", "cylinder", "material", "velocity", "subdivision",
            "volume_tolerance", "sliver_fraction", "priority", "clip", "representation", "pressure", "density", "plastic_strain", "insertion", "points_per_cell")

    @property
    def kind(self):
        return next(k for k in SHAPES if getattr(self, k) is not None)


@dataclass
class Scene:
    dimension: int
    grid: Grid
    materials: List[Material]
    bodies: List[Body]
    run: Optional[Run] = None
    gauges: Optional[list] = None        # [{name, point: [x, y(, z)]}]: each follows the marker nearest at t = 0
    geometry: Optional[str] = None       # plane-strain (None: the default) | axisymmetric (2D: x = r, y = z)
    contact: Optional[Contact] = None    # how marker bodies meet; None: friction 0 between different bodies

    KEYS = ("dimension", "grid", "materials", "bodies", "run", "gauges", "geometry", "contact")

    @property
    def axisymmetric(self):
        return self.geometry == "axisymmetric"

    # ------------------------------------------------------------ checks --
    def validate(self):
        """Check every value; fills defaults and derived geometry.  Returns self."""
        if self.dimension not in (2, 3) or isinstance(self.dimension, bool):
            raise DeckError("dimension", f"must be 2 (plane strain) or 3, got {self.dimension!r}")
        dim = self.dimension
        self._validate_geometry(grid=False)
        self.grid.validate(dim)
        self._validate_geometry(grid=True)
        if not self.materials:
            raise DeckError("materials", "at least one material is required")
        names = {}
        for i, m in enumerate(self.materials):
            m.validate(f"materials[{i}]")
            if m.name in names:
                raise DeckError(f"materials[{i}].name", f"{m.name!r} is already materials[{names[m.name]}]")
            names[m.name] = i
        if not self.bodies:
            raise DeckError("bodies", "at least one body is required")
        bnames = {}
        for i, b in enumerate(self.bodies):
            self._validate_body(b, f"bodies[{i}]", names)
            self._validate_representation(b, f"bodies[{i}]")
            if b.name in bnames:
                raise DeckError(f"bodies[{i}].name", f"{b.name!r} is already bodies[{bnames[b.name]}]")
            bnames[b.name] = i
        if self.axisymmetric:
            for i, b in enumerate(self.bodies):
                self._validate_axisymmetric_body(b, f"bodies[{i}]")
        if self.run is not None:
            self.run.validate()
        if self.contact is None:
            self.contact = Contact()
        elif not isinstance(self.contact, Contact):
            raise DeckError("contact", "must be a mapping {type: friction|bonded, friction: mu, pairs: [...]}")
        self.contact.validate(bnames)
        lay = self.contact.layout(self)
        for i, b in enumerate(self.bodies):
            if lay["split"][i] and lay["nfield"] > 16:
                raise DeckError(f"bodies[{i}].laminate.interface", f"cohesive ply interfaces give each of its {len(b.laminate.plies)} plies a velocity "
                                f"field: {lay['nfield']} fields in the scene; allowed at most 16")
        if self.gauges is not None:
            if not isinstance(self.gauges, list):
                raise DeckError("gauges", "must be a list of {name, point}")
            for i, g in enumerate(self.gauges):
                check_keys(g, ("name", "point"), f"gauges[{i}]")
                if "point" not in g:
                    raise DeckError(f"gauges[{i}].point", f"is required: {dim} coordinates (m)")
                g["point"] = vector(g["point"], dim, f"gauges[{i}].point")
                g.setdefault("name", f"gauge{i}")
                for a in range(dim):
                    if not self.grid.lower[a] <= g["point"][a] <= self.grid.upper[a]:
                        raise DeckError(f"gauges[{i}].point[{a}]", f"{g['point'][a]} is outside the grid [{self.grid.lower[a]}, {self.grid.upper[a]}]")
        return self

    def _validate_geometry(self, grid):
        """geometry: plane-strain (default) | axisymmetric: 2D only (checked
        before the grid), the grid in r >= 0 and its x- face (the axis) a
        symmetry face (checked after it)."""
        g = self.geometry if self.geometry is not None else "plane-strain"
        if not isinstance(g, str) or g not in GEOMETRIES:
            raise DeckError("geometry", f"must be one of {'|'.join(GEOMETRIES)}, got {g!r}")
        if g != "axisymmetric":
            return
        if self.dimension != 2:
            raise DeckError("geometry", f"axisymmetric needs dimension 2 (x = r, y = z), got dimension {self.dimension}; "
                            f"allowed: {'|'.join(GEOMETRIES)} in 2D, plane-strain only in 3D")
        if not grid:
            return
        if self.grid.lower[0] < 0:
            raise DeckError("grid.lower[0]", f"{self.grid.lower[0]} is out of range with geometry: axisymmetric "
                            "(x is the radius r); allowed [0, inf]")
        if self.grid.boundary["x-"] != "symmetry":
            raise DeckError("grid.boundary.x-", f"must be symmetry with geometry: axisymmetric (the x- face is the axis r = 0 "
                            f"or an inner radius, v_r = 0 there), got {self.grid.boundary['x-']!r}; allowed: symmetry")

    def _validate_axisymmetric_body(self, b, path):
        """Axisymmetric bodies: markers only; a laminate stacked along z (y) whose
        plies are isotropic or transversely isotropic about the stacking axis
        (a body of revolution's material must not depend on the angle)."""
        if b.representation == "cells":
            raise DeckError(f"{path}.representation", "cells are not available with geometry: axisymmetric; allowed: markers")
        if b.kind != "laminate":
            return
        ax = np.asarray(b._axes, dtype=float)
        a3 = ax[2]     # the frame's stacking axis (axis 3) in x, y, z
        if abs(abs(a3[1]) - 1.0) > TRANSVERSE_ISOTROPY_RTOL:
            raise DeckError(f"{path}.laminate.frame.axis3", f"the stacking axis {np.round(a3[:2], 6).tolist()} must be the z axis "
                            "(y, the axis of revolution) with geometry: axisymmetric; allowed: axis3 - origin along +-y")
        for j, p in enumerate(b.laminate.plies):
            m = self.materials[b._ply_mat[j]]
            if not m.anisotropic:
                continue
            e = m.elastic
            pp = f"{path}.laminate.plies[{j}]"
            close = lambda a, c: abs(a - c) <= TRANSVERSE_ISOTROPY_RTOL * max(abs(a), abs(c))
            # transversely isotropic about material axis 3: the 1-2 plane isotropic
            ti = (close(e["E1"], e["E2"]) and close(e["nu13"], e["nu23"]) and close(e["G13"], e["G23"])
                  and close(e["G12"], e["E1"] / (2.0 * (1.0 + e["nu12"]))))
            if not ti:
                raise DeckError(f"{pp}.material", f"material {m.name!r} is not transversely isotropic about the stacking axis "
                                "(needs E1 = E2, nu13 = nu23, G13 = G23, G12 = E1/(2(1+nu12))); with geometry: axisymmetric "
                                "allowed: isotropic plies or plies transversely isotropic about the stacking axis")
            a3p = np.asarray(b._ply_axes[j], dtype=float).reshape(3, 3)[2]
            if abs(abs(a3p[1]) - 1.0) > TRANSVERSE_ISOTROPY_RTOL:
                raise DeckError(f"{pp}.rotations", f"turn the ply's axis 3 to {np.round(a3p, 6).tolist()}, off the stacking (z) axis; "
                                "with geometry: axisymmetric allowed: rotations about axis 3 only")

    def _material_id(self, name, path, names):
        if not isinstance(name, str):
            raise DeckError(path, f"must be a material's name, got {name!r} (defined: {', '.join(names)})")
        if name not in names:
            import difflib
            near = difflib.get_close_matches(str(name), list(names), n=1)
            raise DeckError(path, f"unknown material {name!r}{'; did you mean ' + repr(near[0]) + '?' if near else ''} (defined: {', '.join(names)})")
        return names[name]

    def _validate_body(self, b, path, names):
        dim = self.dimension
        if not isinstance(b.name, str) or not b.name:
            raise DeckError(f"{path}.name", f"must be a non-empty string, got {b.name!r}")
        shapes = [k for k in SHAPES if getattr(b, k) is not None]
        if len(shapes) != 1:
            raise DeckError(path, f"needs exactly one shape of {', '.join(SHAPES)}; got {shapes or 'none'}")
        if b.insertion not in INSERTIONS:
            raise DeckError(f"{path}.insertion", f"must be one of {'|'.join(INSERTIONS)}, got {b.insertion!r}")
        if b.insertion == "lattice":
            # the lattice fill has its own resolution; the exact insertion's keys do not apply
            for k in ("subdivision", "volume_tolerance", "sliver_fraction"):
                if getattr(b, k) is not None:
                    raise DeckError(f"{path}.{k}", f"applies to insertion exact only; insertion lattice takes points_per_cell "
                                    f"(points per cell and direction, 1 to {MAX_POINTS_PER_CELL})")
            b.points_per_cell = number(2 if b.points_per_cell is None else b.points_per_cell, f"{path}.points_per_cell",
                                       1, MAX_POINTS_PER_CELL, integer=True)
        else:
            if b.points_per_cell is not None:
                raise DeckError(f"{path}.points_per_cell", "applies to insertion: lattice only (the exact insertion "
                                "refines with subdivision); set insertion: lattice or remove it")
            b.subdivision = number(1 if b.subdivision is None else b.subdivision, f"{path}.subdivision", 1, 64, integer=True)
            b.volume_tolerance = number(1e-6 if b.volume_tolerance is None else b.volume_tolerance, f"{path}.volume_tolerance", 1e-12, 0.1)
            b.sliver_fraction = number(1e-6 if b.sliver_fraction is None else b.sliver_fraction, f"{path}.sliver_fraction", 0, 0.5)
        if b.priority is not None:
            b.priority = number(b.priority, f"{path}.priority", -10**6, 10**6, integer=True)
        if not isinstance(b.clip, bool):
            raise DeckError(f"{path}.clip", f"must be true or false, got {b.clip!r}")
        b.velocity = vector(b.velocity if b.velocity is not None else [0.0] * dim, dim, f"{path}.velocity")
        speed = float(np.sqrt(sum(v * v for v in b.velocity))) if all(abs(v) < 1e150 for v in b.velocity) else float("inf")
        if speed > V_MAX:
            raise DeckError(f"{path}.velocity", f"speed {speed:.6g} m/s is out of range; allowed |v| <= {V_MAX:g} m/s "
                            f"(100 km/s, beyond the fastest natural impacts)")
        if b.representation not in REPRESENTATIONS:
            raise DeckError(f"{path}.representation", f"unknown representation {b.representation!r}; allowed: {'|'.join(REPRESENTATIONS)}")
        if b.pressure is not None:
            b.pressure = number(b.pressure, f"{path}.pressure")
        if b.density is not None:
            b.density = number(b.density, f"{path}.density", 0, 1e5, lo_open=True)
        L = self.grid.upper[0] - self.grid.lower[0]
        k = b.kind
        if k == "laminate":
            if b.material is not None:
                raise DeckError(f"{path}.material", "a laminate takes its materials from its plies; remove this key")
            lam = b.laminate
            lp = f"{path}.laminate"
            b._axes = lam.frame.axes(dim, f"{lp}.frame")
            if not isinstance(lam.size, (list, tuple)) or len(lam.size) != dim - 1:
                raise DeckError(f"{lp}.size", f"must be a list of {dim - 1} lengths (extent along axis 1{' and axis 2' if dim == 3 else ''}), got {lam.size!r}")
            lam.size = [number(s, f"{lp}.size[{i}]", 0, None, lo_open=True) for i, s in enumerate(lam.size)]
            if not lam.plies:
                raise DeckError(f"{lp}.plies", "a laminate needs at least one ply")
            b._ply_axes, b._ply_mat, z = [], [], [0.0]
            for j, p in enumerate(lam.plies):
                pp = f"{lp}.plies[{j}]"
                t = number(p.thickness, f"{pp}.thickness", 0, None, lo_open=True)
                z.append(z[-1] + t)
                b._ply_mat.append(self._material_id(p.material, f"{pp}.material", names))
                b._ply_axes.append(_layup.rotate_axes(b._axes, p.rotations, f"{pp}.rotations"))
            b._z = z
            if lam.interface is not None:          # None: bonded
                if not isinstance(lam.interface, Interface):
                    raise DeckError(f"{lp}.interface", "must be a mapping {type: bonded|cohesive, normal_strength, shear_strength, G_I, G_II}")
                lam.interface.validate(f"{lp}.interface")
        else:
            if b.material is None:
                raise DeckError(f"{path}.material", f"is required for a {k} body")
            b._mat = self._material_id(b.material, f"{path}.material", names)
            sp = f"{path}.{k}"
            if k == "box":
                lo = vector(b.box.lower, dim, f"{sp}.lower")
                hi = vector(b.box.upper, dim, f"{sp}.upper")
                for i in range(dim):
                    if hi[i] <= lo[i]:
                        raise DeckError(f"{sp}.upper[{i}]", f"{hi[i]} must be > lower[{i}] = {lo[i]}")
                b.box.lower, b.box.upper = lo, hi
            elif k == "sphere":
                b.sphere.center = vector(b.sphere.center, dim, f"{sp}.center")
                b.sphere.radius = number(b.sphere.radius, f"{sp}.radius", 0, None, lo_open=True)
            else:
                c = b.cylinder
                c.base = vector(c.base, dim, f"{sp}.base")
                a = np.array(vector(c.axis, dim, f"{sp}.axis"))
                if np.linalg.norm(a) == 0:
                    raise DeckError(f"{sp}.axis", "must be a non-zero direction")
                c.axis = list(a / np.linalg.norm(a))
                c.radius = number(c.radius, f"{sp}.radius", 0, None, lo_open=True)
                c.length = number(c.length, f"{sp}.length", 0, None, lo_open=True)

    def _validate_representation(self, b, path):
        """A body in cells: a material with a state EOS, no laminate; an ideal
        gas needs its initial pressure (any representation)."""
        mats = [self.materials[i] for i in ([b._mat] if b.kind != "laminate" else b._ply_mat)]
        if b.representation == "cells":
            if b.kind == "laminate":
                raise DeckError(f"{path}.representation", "a laminate's plies ride on markers (they keep their fibre axes); use markers")
            m = mats[0]
            if m.eos is None:
                raise DeckError(f"{path}.representation", f"material {m.name!r} has no eos: a material in cells needs one "
                                "(mie-gruneisen or ideal-gas; its state is density and energy)")
            if m.anisotropic:
                raise DeckError(f"{path}.representation", f"material {m.name!r} is orthotropic: plies ride on markers")
            if b.subdivision != 1:
                raise DeckError(f"{path}.subdivision", "applies to markers only; a body in cells is inserted as exact volume fractions")
            if b.insertion != "exact":
                raise DeckError(f"{path}.insertion", "applies to markers only; a body in cells is inserted as exact volume fractions")
        elif b.density is not None:
            raise DeckError(f"{path}.density", "applies to a body in cells (representation: cells) only; "
                            "a body on markers takes its material's density")
        if b.plastic_strain is not None:
            b.plastic_strain = number(b.plastic_strain, f"{path}.plastic_strain", 0, 100)
            if any((m.strength or {}).get("type", "none") == "none" for m in mats):
                raise DeckError(f"{path}.plastic_strain", "needs a material with a strength model (it is that model's state)")
        for m in mats:
            if m.is_gas and b.pressure is None:
                raise DeckError(f"{path}.pressure", f"is required for a body of ideal-gas material {m.name!r} (Pa, > 0): "
                                "it sets the gas's initial energy")
            if m.is_gas and b.pressure <= 0:
                raise DeckError(f"{path}.pressure", f"{b.pressure} is out of range for an ideal gas; allowed (0, inf)")

    @property
    def cell_materials(self):
        """Ids of the materials of bodies in cells, in deck order."""
        used = {b._mat for b in self.bodies if b.representation == "cells"}
        return [i for i in range(len(self.materials)) if i in used]

    @property
    def anisotropic(self):
        return any(m.anisotropic for m in self.materials)

    # ------------------------------------------------------------- decks --
    def to_yaml(self):
        """The scene as deck text (SI units), loadable by deck.load_text()."""
        import dataclasses
        import yaml

        def clean(o):
            if dataclasses.is_dataclass(o):
                return {k: clean(v) for k, v in dataclasses.asdict(o).items() if v is not None and v != {}}
            if isinstance(o, dict):
                return {k: clean(v) for k, v in o.items() if v is not None}
            if isinstance(o, (list, tuple)):
                return [clean(v) for v in o]
            if isinstance(o, np.generic):
                return o.item()
            return o
        d = clean(self)
        return "# plyshock deck; SI units (m, kg, s, Pa, K)\n" + yaml.safe_dump(d, sort_keys=False, default_flow_style=None)

    @staticmethod
    def from_dict(d):
        """A scene from a parsed deck (unknown keys are errors)."""
        check_keys(d, Scene.KEYS, "")
        for k in ("dimension", "grid", "materials", "bodies"):
            if k not in d:
                raise DeckError(k, "is required")
        g = d["grid"]
        check_keys(g, Grid.KEYS, "grid")
        for k in ("lower", "upper", "cells"):
            if k not in g:
                raise DeckError(f"grid.{k}", "is required")
        grid = Grid(**g)
        if not isinstance(d["materials"], list):
            raise DeckError("materials", "must be a list of materials")
        mats = []
        for i, m in enumerate(d["materials"]):
            check_keys(m, Material.KEYS, f"materials[{i}]")
            if "name" not in m:
                raise DeckError(f"materials[{i}].name", "is required")
            mats.append(Material(**m))
        if not isinstance(d["bodies"], list):
            raise DeckError("bodies", "must be a list of bodies")
        bodies = []
        for i, b in enumerate(d["bodies"]):
            path = f"bodies[{i}]"
            check_keys(b, Body.KEYS, path)
            if "name" not in b:
                raise DeckError(f"{path}.name", "is required")
            kw = dict(b)
            for k, cls in SHAPES.items():
                if k not in kw:
                    continue
                sp = f"{path}.{k}"
                check_keys(kw[k], cls.KEYS, sp)
                if k == "laminate":
                    kw[k] = _laminate_from_dict(kw[k], sp)
                else:
                    for key in cls.KEYS:
                        if key not in kw[k]:
                            raise DeckError(f"{sp}.{key}", "is required")
                    kw[k] = cls(**kw[k])
            bodies.append(Body(**kw))
        run = None
        if d.get("run") is not None:
            check_keys(d["run"], Run.KEYS, "run")
            if "t_end" not in d["run"]:
                raise DeckError("run.t_end", "is required (s, > 0)")
            run = Run(**d["run"])
        contact = None
        if d.get("contact") is not None:
            check_keys(d["contact"], Contact.KEYS, "contact")
            contact = Contact(**d["contact"])
        return Scene(d["dimension"], grid, mats, bodies, run, d.get("gauges"), d.get("geometry"), contact)


def _laminate_from_dict(d, path):
    for k in ("frame", "size"):
        if k not in d:
            raise DeckError(f"{path}.{k}", "is required")
    check_keys(d["frame"], Frame.KEYS, f"{path}.frame")
    for k in Frame.KEYS:
        if k not in d["frame"]:
            raise DeckError(f"{path}.frame.{k}", "is required (a point)")
    frame = Frame(**d["frame"])
    interface = None
    if d.get("interface") is not None:
        if not isinstance(d["interface"], dict):
            raise DeckError(f"{path}.interface", "must be a mapping {type: bonded|cohesive, normal_strength, shear_strength, G_I, G_II}")
        check_keys(d["interface"], Interface.KEYS, f"{path}.interface")
        interface = Interface(**d["interface"])
    short = [k for k in ("layup", "ply_thickness", "ply_material") if k in d]
    if short and "plies" in d:
        raise DeckError(f"{path}.layup", "give either plies or layup/ply_thickness/ply_material, not both")
    if short:
        for k in ("layup", "ply_thickness", "ply_material"):
            if k not in d:
                raise DeckError(f"{path}.{k}", "is required with layup")
        return Laminate.from_layup(frame, d["size"], d["layup"], d["ply_thickness"], d["ply_material"], path, interface)
    if "plies" not in d or not isinstance(d["plies"], list):
        raise DeckError(f"{path}.plies", "is required: a list of {material, thickness, rotations}, or use layup")
    plies = []
    for j, p in enumerate(d["plies"]):
        check_keys(p, Ply.KEYS, f"{path}.plies[{j}]")
        for k in ("material", "thickness"):
            if k not in p:
                raise DeckError(f"{path}.plies[{j}].{k}", "is required")
        plies.append(Ply(**p))
    return Laminate(frame, d["size"], plies, interface)
