# cython: language_level=3
"""Compiled binding between the Python front end and the C solver in src/.

Only python/plyshock/core.py calls this module: it hands over a plain dict
(the scene already validated) and petsc4py DM objects.  No loop here runs over
cells or markers.
"""
from petsc4py.PETSc cimport DM, PetscDM
from petsc4py.PETSc import Error as PetscError
from libc.stdlib cimport calloc, free
from libc.string cimport memset
import numpy as np

cdef extern from "plyshock.h":
    ctypedef int PetscErrorCode
    ctypedef void *MPI_Comm
    MPI_Comm PETSC_COMM_WORLD
    ctypedef int PetscInt
    ctypedef long long PetscInt64
    ctypedef double PetscReal
    ctypedef enum PetscBool:
        PETSC_FALSE
        PETSC_TRUE
    ctypedef enum PSInsertion:
        PS_INSERT_EXACT
        PS_INSERT_LATTICE
    ctypedef enum PSBodyKind:
        PS_BODY_LAMINATE
        PS_BODY_BOX
        PS_BODY_SPHERE
        PS_BODY_CYLINDER
    ctypedef struct PSBody:
        PSBodyKind kind
        PetscInt material
        PetscInt priority
        PetscInt subdivision
        PSInsertion insertion
        PetscInt points_per_cell
        PetscReal volume_tolerance
        PetscReal sliver_fraction
        PetscReal velocity[3]
        PetscReal origin[3]
        PetscReal e[3][3]
        PetscReal size[3]
        PetscInt nply
        PetscReal *z
        PetscInt *ply_material
        PetscReal *ply_axes
        PetscReal center[3]
        PetscReal axis[3]
        PetscReal radius
        PetscReal length
        PetscInt cellmat
        PetscReal pressure
        PetscReal density
        PetscReal plastic_strain
    ctypedef struct PSScene:
        PetscInt dim
        PetscReal lower[3]
        PetscReal upper[3]
        PetscInt cells[3]
        PetscInt nmaterial
        PetscReal *density
        PetscBool anisotropic
        PetscBool need_plastic
        PetscBool need_temperature
        PetscInt ndamage
        PetscReal *T0
        PetscBool need_affine
        PetscBool need_interface
        PetscInt ncellmat
        PetscInt *cellmat
        PetscInt nbody
        PSBody *bodies
        PetscBool axisymmetric
    ctypedef struct PSInsertStats:
        PetscInt64 pieces
        PetscInt64 markers
        PetscInt64 slivers_merged
        PetscInt64 slivers_kept
    PetscErrorCode PSBodyBoundingBox(const PSScene *, PetscInt, PetscReal *, PetscReal *)
    PetscReal PSBodyVolume(const PSScene *, PetscInt)
    PetscErrorCode PSOverlapVolume(const PSScene *, PetscInt, PetscInt, PetscReal *)
    PetscErrorCode PSBodyDomainVolume(const PSScene *, PetscInt, PetscReal *)
    PetscErrorCode PSInitializePackage()
    PetscErrorCode PSCountPieces(const PSScene *, const PetscInt *, const PetscInt *, PetscInt64 *)
    PetscErrorCode PSCountSlabs(const PSScene *, PetscInt, PetscInt, PetscInt, PetscInt, PetscInt64 *)
    PetscErrorCode PSInsertMarkers(const PSScene *, PetscDM, PetscDM, PSInsertStats *)
    PetscErrorCode PSMarkersBytes(const PSScene *, PetscDM, PetscInt *)
    PetscErrorCode PSCellOwnership(PetscDM, PetscInt *, PetscInt *)
    PetscErrorCode DMSwarmGetField(PetscDM, const char *, PetscInt *, int *, void **)
    PetscErrorCode DMSwarmRestoreField(PetscDM, const char *, PetscInt *, int *, void **)
    PetscErrorCode DMSwarmGetLocalSize(PetscDM, PetscInt *)
    PetscErrorCode PSWriteMarkers(const PSScene *, PetscDM, const char *, PetscReal, PetscInt, const char **, const char **, const char **, const char **)

cdef extern from "solver.h":
    ctypedef enum PSTransferType:
        PS_TRANSFER_MUSL
        PS_TRANSFER_APIC
    ctypedef enum PSShapeType:
        PS_SHAPE_LINEAR
        PS_SHAPE_GIMP
        PS_SHAPE_BSPLINE2
    ctypedef struct PSRunParams:
        PetscReal t_end
        PetscReal cfl
        PSShapeType shape
        PSTransferType transfer
        PetscReal output_interval
        PetscReal c_linear
        PetscReal c_quadratic
        PetscReal pic_fraction
        PetscReal dt_growth
        PetscReal mass_threshold
        PetscInt max_steps
        PetscInt history_interval
        PetscInt progress_interval
        PetscReal dt_max
        PetscBool fbar
        PetscInt lanes
        PetscBool hugepages
        PetscReal checkpoint_interval
        PetscReal checkpoint_wall_interval
        PetscReal dt_floor
    ctypedef struct PSPly:
        PetscReal C[36]
        PetscReal K_R, c2max
        PetscReal X[6]
        PetscReal Gc[4]
        PetscReal E[4]
    ctypedef struct PSZerilliArmstrong:
        PetscReal C0, C1, C2, C5, C3, C4, n
    ctypedef struct PSMTS:
        PetscReal sigma_a, mu_0, D, T_0, k_over_b3, sigma_i, g_0i, eps_dot_0i, p_i, q_i, g_0e, eps_dot_0e, p_e, q_e
        PetscReal a_0, a_1, a_2, a_3, alpha, g_0es, eps_dot_es0, sigma_es0
    ctypedef struct PSMaterial:
        PetscReal rho0, K, c0, s, gamma0, gamma, G, Y0, A, B, n, C, m, T_melt, T_room, eps_dot0, cv, chi, spall
        PSZerilliArmstrong za
        PSMTS mts
        PetscReal D[5]
        PetscBool aniso
        PSPly ply
    ctypedef struct PSTotals:
        PetscReal mass, kinetic, internal, lost_mass, lost_energy, max_pressure, friction_work, interface_energy, remap_heat, coupling_work
        PetscReal p[3]
        PetscReal lost_p[3]
        PetscInt64 markers, lost_markers
    ctypedef struct PSSolver:
        PetscReal t, dt
        PetscInt step
        PetscBool restarted
    PetscErrorCode PSSolverCreate(const PSScene *, PetscDM, PetscDM, const PSRunParams *, const PSMaterial *, const PetscInt *, PSSolver **)
    PetscErrorCode PSSolverDestroy(PSSolver **)
    PetscErrorCode PSSolverInitialState(PSSolver *)
    PetscErrorCode PSRunParamsRead(MPI_Comm, PSRunParams *)
    PetscErrorCode PSRunParamsCheck(const PSRunParams *, const char **, char *, size_t)
    PetscErrorCode PSSolverMaxSpeed(PSSolver *)
    PetscErrorCode PSSolverStep(PSSolver *, PetscReal)
    PetscErrorCode PSSolverTotals(PSSolver *, PSTotals *)
    PetscErrorCode PSSolverSetContact(PSSolver *, PetscInt, const PetscInt *, const PetscInt *, PetscInt, const PetscReal *, const PetscInt *, PetscInt, const PetscReal *)
    PetscErrorCode PSSolverCellsGet(PSSolver *, PetscInt *, PetscInt *, PetscInt *, PetscReal *)
    PetscErrorCode PSSolverCellNodesGet(PSSolver *, PetscInt *, PetscInt *, PetscReal *)
    PetscErrorCode PSSolverRun(PSSolver *, const char *, PetscInt, const char **, const char **, const char **, const char **)
    PetscErrorCode PSMaterialInit(PSMaterial *, const char *, const char *, const char *)
    PetscErrorCode PSMaterialDrive(const PSMaterial *, const PetscReal *, PetscInt, const PetscReal *, PetscReal, PetscReal, PetscReal *, PetscReal *, PetscReal *, PetscReal *)
    PetscErrorCode PSSolverCheckpoint(PSSolver *, const char *)
    PetscErrorCode PSSolverSetGauges(PSSolver *, PetscInt, const PetscInt64 *)
    PetscErrorCode PSSolverRestart(PSSolver *, const char *)
    PetscErrorCode PSCheckpointVerify(MPI_Comm, const PSScene *, const char *, char *, size_t)
    PetscErrorCode PSMarkersRegisterFields(const PSScene *, PetscDM, PetscInt *)

INSERTION = {"exact": PS_INSERT_EXACT, "lattice": PS_INSERT_LATTICE}
KIND = {"laminate": PS_BODY_LAMINATE, "box": PS_BODY_BOX, "sphere": PS_BODY_SPHERE, "cylinder": PS_BODY_CYLINDER}


cdef inline int CHK(PetscErrorCode ierr) except -1:
    if ierr != 0:
        raise PetscError(ierr)
    return 0


cdef class _Strings:
    """A NULL-free char*[] kept alive with its bytes."""
    cdef const char **ptr
    cdef list keep

    def __cinit__(self, strings):
        self.keep = [s.encode() for s in strings]
        self.ptr = <const char **>calloc(max(1, len(self.keep)), sizeof(char *))
        for i, b in enumerate(self.keep):
            self.ptr[i] = <const char *>b

    def __dealloc__(self):
        free(self.ptr)


cdef class CScene:
    """The C PSScene built from the dict of core.scene_to_c()."""
    cdef PSScene s
    cdef public int maxply

    def __cinit__(self, dict spec):
        cdef PSBody *B
        cdef int i, j, k
        memset(&self.s, 0, sizeof(PSScene))
        self.s.dim = spec["dim"]
        for i in range(3):
            self.s.lower[i] = spec["lower"][i]
            self.s.upper[i] = spec["upper"][i]
            self.s.cells[i] = spec["cells"][i]
        dens = spec["density"]
        self.s.nmaterial = len(dens)
        self.s.density = <PetscReal *>calloc(max(1, len(dens)), sizeof(PetscReal))
        for i in range(len(dens)):
            self.s.density[i] = dens[i]
        self.s.anisotropic = PETSC_TRUE if spec["anisotropic"] else PETSC_FALSE
        self.s.need_plastic = PETSC_TRUE if spec.get("need_plastic") else PETSC_FALSE
        self.s.need_temperature = PETSC_TRUE if spec.get("need_temperature") else PETSC_FALSE
        self.s.ndamage = spec["ndamage"]
        self.s.need_affine = PETSC_TRUE if spec.get("need_affine") else PETSC_FALSE
        self.s.need_interface = PETSC_TRUE if spec.get("need_interface") else PETSC_FALSE
        self.s.axisymmetric = PETSC_TRUE if spec.get("axisymmetric") else PETSC_FALSE
        T0 = spec.get("T0", [294.0] * len(dens))
        self.s.T0 = <PetscReal *>calloc(max(1, len(dens)), sizeof(PetscReal))
        for i in range(len(dens)):
            self.s.T0[i] = T0[i]
        cm = spec.get("cellmat", [])
        self.s.ncellmat = len(cm)
        self.s.cellmat = <PetscInt *>calloc(max(1, len(cm)), sizeof(PetscInt))
        for i in range(len(cm)):
            self.s.cellmat[i] = cm[i]
        bodies = spec["bodies"]
        self.s.nbody = len(bodies)
        self.s.bodies = <PSBody *>calloc(max(1, len(bodies)), sizeof(PSBody))
        self.maxply = 0
        for i, b in enumerate(bodies):
            B = &self.s.bodies[i]
            B.kind = KIND[b["kind"]]
            B.material = b.get("material", -1)
            B.priority = b["priority"]
            B.subdivision = b["subdivision"]
            B.insertion = INSERTION[b.get("insertion", "exact")]
            B.points_per_cell = b.get("points_per_cell", 1)
            B.volume_tolerance = b["volume_tolerance"]
            B.sliver_fraction = b["sliver_fraction"]
            for j in range(3):
                B.velocity[j] = b["velocity"][j]
                B.origin[j] = b["origin"][j]
                B.size[j] = b["size"][j]
                B.center[j] = b["center"][j]
                B.axis[j] = b["axis"][j]
                for k in range(3):
                    B.e[j][k] = b["e"][j][k]
            B.radius = b["radius"]
            B.length = b["length"]
            B.cellmat = b.get("cellmat", -1)
            B.pressure = b.get("pressure", 0.0)
            B.density = b.get("density", 0.0)
            B.plastic_strain = b.get("plastic_strain", 0.0)
            z = b["z"]
            B.nply = max(0, len(z) - 1)
            self.maxply = max(self.maxply, B.nply)
            if B.nply:
                B.z = <PetscReal *>calloc(len(z), sizeof(PetscReal))
                B.ply_material = <PetscInt *>calloc(B.nply, sizeof(PetscInt))
                B.ply_axes = <PetscReal *>calloc(9 * B.nply, sizeof(PetscReal))
                for j in range(len(z)):
                    B.z[j] = z[j]
                for j in range(B.nply):
                    B.ply_material[j] = b["ply_material"][j]
                    for k in range(9):
                        B.ply_axes[9 * j + k] = b["ply_axes"][j][k]

    def __dealloc__(self):
        cdef int i
        if self.s.bodies != NULL:
            for i in range(self.s.nbody):
                free(self.s.bodies[i].z)
                free(self.s.bodies[i].ply_material)
                free(self.s.bodies[i].ply_axes)
        free(self.s.bodies)
        free(self.s.cellmat)
        free(self.s.density)
        free(self.s.T0)

    # geometry: no PETSc objects -------------------------------------------
    def bounding_box(self, int b):
        cdef PetscReal lo[3]
        cdef PetscReal hi[3]
        CHK(PSBodyBoundingBox(&self.s, b, lo, hi))
        return [lo[i] for i in range(3)], [hi[i] for i in range(3)]

    def body_volume(self, int b):
        return PSBodyVolume(&self.s, b)

    def domain_volume(self, int b):
        cdef PetscReal v = 0
        CHK(PSBodyDomainVolume(&self.s, b, &v))
        return v

    def overlap_volume(self, int a, int b):
        cdef PetscReal v = 0
        CHK(PSOverlapVolume(&self.s, a, b, &v))
        return v

    def count(self, cs, ce):
        """Markers per (body, ply + 1) over cells [cs, ce), without inserting."""
        cdef PetscInt c0[3]
        cdef PetscInt c1[3]
        cdef PetscInt64[:, ::1] out = np.zeros((self.s.nbody, self.maxply + 1), dtype=np.int64)
        for i in range(3):
            c0[i] = cs[i]
            c1[i] = ce[i]
        if self.s.nbody:
            CHK(PSCountPieces(&self.s, c0, c1, &out[0, 0]))
        return np.asarray(out)

    def count_slabs(self, int axis, int k0, int stride):
        """Markers per slab of cells normal to axis, for slabs k0, k0 + stride, ... (others 0)."""
        cdef PetscInt64[::1] out = np.zeros(self.s.cells[axis], dtype=np.int64)
        if self.s.nbody and k0 < self.s.cells[axis]:
            CHK(PSCountSlabs(&self.s, axis, k0, self.s.cells[axis], stride, &out[0]))
        return np.asarray(out)

    def marker_bytes(self, DM sw=None):
        cdef PetscInt nb = 0
        CHK(PSMarkersBytes(&self.s, sw.dm if sw is not None else NULL, &nb))
        return nb

    # with PETSc objects ----------------------------------------------------
    def owned_cells(self, DM da):
        cdef PetscInt cs[3]
        cdef PetscInt ce[3]
        CHK(PSCellOwnership(da.dm, cs, ce))
        return [cs[i] for i in range(3)], [ce[i] for i in range(3)]

    def register_fields(self, DM sw):
        """Register the scene's marker fields on an empty swarm (a restart fills them)."""
        cdef PetscInt nb = 0
        CHK(PSMarkersRegisterFields(&self.s, sw.dm, &nb))

    def insert(self, DM da, DM sw):
        cdef PSInsertStats st
        CHK(PSInsertMarkers(&self.s, da.dm, sw.dm, &st))
        return dict(pieces=st.pieces, markers=st.markers, slivers_merged=st.slivers_merged, slivers_kept=st.slivers_kept)

    def verify_checkpoint(self, str filename):
        """What is wrong with a checkpoint for this scene, or None when it can
        be restarted from (collective on PETSC_COMM_WORLD; HDF5 prints nothing)."""
        cdef char msg[512]
        fn = filename.encode()
        CHK(PSCheckpointVerify(PETSC_COMM_WORLD, &self.s, fn, msg, sizeof(msg)))
        return msg.decode(errors="replace") if msg[0] else None

    def write(self, DM sw, str filename, dict attrs, list body_names, list material_names):
        names = _Strings(list(attrs.keys()))
        values = _Strings([str(v) for v in attrs.values()])
        bn = _Strings(body_names)
        mn = _Strings(material_names)
        fn = filename.encode()
        CHK(PSWriteMarkers(&self.s, sw.dm, fn, 0.0, len(attrs), names.ptr, values.ptr, bn.ptr, mn.ptr))


def get_int64_field(DM sw, str name):
    """A copy of an int64 swarm field (petsc4py 3.18 cannot map PETSC_INT64)."""
    cdef PetscInt n = 0, bs = 0
    cdef int dtype = 0
    cdef void *ptr = NULL
    cdef PetscInt64[::1] out
    cdef PetscInt64 *p
    cdef Py_ssize_t i
    bname = name.encode()
    CHK(DMSwarmGetLocalSize(sw.dm, &n))
    CHK(DMSwarmGetField(sw.dm, bname, &bs, &dtype, &ptr))
    out = np.empty(n * bs, dtype=np.int64)
    p = <PetscInt64 *>ptr
    for i in range(n * bs):
        out[i] = p[i]
    CHK(DMSwarmRestoreField(sw.dm, bname, &bs, &dtype, &ptr))
    return np.asarray(out).reshape(n, bs)


def initialize():
    CHK(PSInitializePackage())


SHAPES = {"linear": PS_SHAPE_LINEAR, "gimp": PS_SHAPE_GIMP, "bspline2": PS_SHAPE_BSPLINE2}
SHAPE_NAMES = {v: k for k, v in SHAPES.items()}
TRANSFERS = {"musl": PS_TRANSFER_MUSL, "apic": PS_TRANSFER_APIC}
TRANSFER_NAMES = {v: k for k, v in TRANSFERS.items()}


cdef fill_run(PSRunParams *r, dict run):
    r.t_end = run["t_end"]
    r.cfl = run["cfl"]
    r.shape = SHAPES[run["shape"]]
    r.transfer = TRANSFERS[run["transfer"]]
    r.output_interval = run["output_interval"]
    r.c_linear = run["c_linear"]
    r.c_quadratic = run["c_quadratic"]
    r.pic_fraction = run["pic_fraction"]
    r.dt_growth = run["dt_growth"]
    r.mass_threshold = run["mass_threshold"]
    r.max_steps = run["max_steps"]
    r.history_interval = run["history_interval"]
    r.progress_interval = run["progress_interval"]
    r.dt_max = run["dt_max"]
    r.fbar = <PetscBool>(1 if run.get("fbar") else 0)
    r.lanes = run.get("lanes", 4)
    r.checkpoint_interval = run.get("checkpoint_interval", 0.0)
    r.checkpoint_wall_interval = run.get("checkpoint_wall_interval", 0.0)
    r.dt_floor = run.get("dt_floor", 1e-3)
    r.hugepages = <PetscBool>(1 if run.get("hugepages", True) else 0)


cdef dict run_dict(const PSRunParams *r):
    return dict(t_end=r.t_end, cfl=r.cfl, shape=SHAPE_NAMES[r.shape], transfer=TRANSFER_NAMES[r.transfer],
                output_interval=r.output_interval, c_linear=r.c_linear, c_quadratic=r.c_quadratic,
                pic_fraction=r.pic_fraction, dt_growth=r.dt_growth, mass_threshold=r.mass_threshold,
                max_steps=r.max_steps, history_interval=r.history_interval, progress_interval=r.progress_interval,
                dt_max=r.dt_max, fbar=bool(r.fbar), lanes=r.lanes, checkpoint_interval=r.checkpoint_interval,
                checkpoint_wall_interval=r.checkpoint_wall_interval, dt_floor=r.dt_floor, hugepages=bool(r.hugepages))


def run_params(dict run):
    """The deck's run values merged with the -run_<key> options (C reads them),
    and the one check of their ranges: (params, key, message); key is None
    when every value is in range."""
    cdef PSRunParams r
    cdef const char *key = NULL
    cdef char msg[256]
    fill_run(&r, run)
    CHK(PSRunParamsRead(PETSC_COMM_WORLD, &r))
    CHK(PSRunParamsCheck(&r, &key, msg, sizeof(msg)))
    if key == NULL:
        return run_dict(&r), None, None
    return run_dict(&r), key.decode(), msg.decode()


cdef class Solver:
    """The C solver on a scene's grid and markers (keeps them alive)."""
    cdef PSSolver *S
    cdef PSRunParams r
    cdef object keep

    def __cinit__(self, CScene scene, DM da, DM sw, dict run, list materials, list bc):
        cdef PSMaterial *mats
        cdef PetscInt cbc[6]
        cdef int i, k
        self.S = NULL
        self.keep = (scene, da, sw)
        fill_run(&self.r, run)
        mats = <PSMaterial *>calloc(max(1, len(materials)), sizeof(PSMaterial))
        try:
            for i, md in enumerate(materials):
                fill_material(&mats[i], md)
            for i in range(6):
                cbc[i] = bc[i]
            CHK(PSSolverCreate(&scene.s, da.dm, sw.dm, &self.r, mats, cbc, &self.S))
        finally:
            free(mats)

    def __dealloc__(self):
        if self.S != NULL:
            PSSolverDestroy(&self.S)

    @property
    def run_params(self):
        return run_dict(&self.r)

    @property
    def time(self):
        return self.S.t

    @property
    def step_count(self):
        return self.S.step

    @property
    def restarted(self):
        return bool(self.S.restarted)

    def step(self, t_stop=None):
        if self.S.step == 0 and self.S.dt == 0:
            CHK(PSSolverMaxSpeed(self.S))
        CHK(PSSolverStep(self.S, self.r.t_end if t_stop is None else t_stop))

    def initial_state(self):
        """A fresh run's state: bodies in cells, markers' initial pressures."""
        CHK(PSSolverInitialState(self.S))

    def set_gauges(self, ids):
        cdef PetscInt64[::1] a = np.ascontiguousarray(ids, dtype=np.int64)
        if len(a):
            CHK(PSSolverSetGauges(self.S, len(a), &a[0]))

    def checkpoint(self, str filename):
        CHK(PSSolverCheckpoint(self.S, filename.encode()))

    def restart(self, str filename):
        CHK(PSSolverRestart(self.S, filename.encode()))

    def totals(self):
        cdef PSTotals T
        CHK(PSSolverTotals(self.S, &T))
        return dict(mass=T.mass, p=[T.p[0], T.p[1], T.p[2]], kinetic=T.kinetic, internal=T.internal,
                    lost_mass=T.lost_mass, lost_p=[T.lost_p[0], T.lost_p[1], T.lost_p[2]], lost_energy=T.lost_energy,
                    max_pressure=T.max_pressure, markers=T.markers, lost_markers=T.lost_markers,
                    friction_work=T.friction_work, interface_energy=T.interface_energy,
                    remap_heat=T.remap_heat, coupling_work=T.coupling_work)

    def set_contact(self, fields, split, nfield, mu, coh, cohp):
        """Velocity fields of the bodies (field of each body, -1 for bodies in
        cells; split: a laminate whose ply j is field fields[b] + j; nfield < 2:
        the single field), the nfield x nfield friction coefficients, the
        nfield x nfield cohesive law of a pair of fields (-1 none) and the laws'
        constants (n x 4: N, S in Pa; G_I, G_II in J/m^2)."""
        itype = np.int32 if sizeof(PetscInt) == 4 else np.int64
        cdef PetscInt[::1] f = np.ascontiguousarray(fields, dtype=itype)
        cdef PetscInt[::1] sp = np.ascontiguousarray(split, dtype=itype)
        cdef double[::1] m = np.ascontiguousarray(np.asarray(mu, dtype=float).reshape(-1) if nfield > 0 else np.zeros(1))
        cdef PetscInt[::1] c = np.ascontiguousarray(np.asarray(coh).reshape(-1) if nfield > 0 else np.full(1, -1), dtype=itype)
        cp_ = np.asarray(cohp, dtype=float).reshape(-1)
        ncoh = len(cp_) // 4
        cdef double[::1] cp = np.ascontiguousarray(cp_ if ncoh else np.zeros(4))
        if len(f) == 0:
            return
        CHK(PSSolverSetContact(self.S, len(f), &f[0], &sp[0], nfield, &m[0], &c[0], ncoh, &cp[0]))

    def cells(self):
        """This rank's owned cells: {start (3), state (nz, ny, nx, dof) with
        per material (V, M, E, ...) blocks of ms reals, nmat, ms}; None
        without cell materials."""
        cdef PetscInt cs[3]
        cdef PetscInt cm[3]
        cdef PetscInt lay[3]
        cdef double[::1] buf
        CHK(PSSolverCellsGet(self.S, cs, cm, lay, NULL))
        if lay[2] == 0:
            return None
        a = np.zeros(max(1, cm[0] * cm[1] * cm[2] * lay[2]))
        buf = a
        CHK(PSSolverCellsGet(self.S, cs, cm, lay, &buf[0]))
        return dict(start=[cs[0], cs[1], cs[2]], state=a[:cm[0] * cm[1] * cm[2] * lay[2]].reshape(cm[2], cm[1], cm[0], lay[2]),
                    nmat=lay[0], ms=lay[1])

    def cell_nodes(self):
        """This rank's owned nodes (physical indices from start): (nz, ny, nx, 1 + dim)
        of the cell materials' nodal mass m^C and momentum P^C."""
        cdef PetscInt ns[3]
        cdef PetscInt nm[3]
        cdef double[::1] buf
        CHK(PSSolverCellNodesGet(self.S, ns, nm, NULL))
        dim = 3 if nm[2] > 1 else 2
        a = np.zeros(max(1, nm[0] * nm[1] * nm[2] * (1 + dim)))
        buf = a
        CHK(PSSolverCellNodesGet(self.S, ns, nm, &buf[0]))
        return dict(start=[ns[0], ns[1], ns[2]], nodes=a[:nm[0] * nm[1] * nm[2] * (1 + dim)].reshape(nm[2], nm[1], nm[0], 1 + dim))

    def run(self, str outdir, dict attrs, list body_names, list material_names):
        names = _Strings(list(attrs.keys()))
        values = _Strings([str(v) for v in attrs.values()])
        bn = _Strings(body_names)
        mn = _Strings(material_names)
        od = outdir.encode()
        CHK(PSSolverRun(self.S, od, len(attrs), names.ptr, values.ptr, bn.ptr, mn.ptr))


cdef int fill_material(PSMaterial *M, dict md) except -1:
    """A PSMaterial from core.material_to_c's dict (missing numbers are 0)."""
    cdef int k
    g = lambda key: float(md.get(key, 0.0))
    memset(M, 0, sizeof(PSMaterial))
    M.rho0, M.K, M.c0, M.s, M.gamma0, M.G = g("rho0"), g("K"), g("c0"), g("s"), g("gamma0"), g("G")
    M.gamma = g("gamma")
    M.Y0, M.A, M.B, M.n, M.C, M.m = g("Y0"), g("A"), g("B"), g("n"), g("C"), g("m")
    M.T_melt, M.T_room, M.eps_dot0, M.cv, M.chi, M.spall = g("T_melt"), g("T_room"), g("eps_dot0"), g("cv"), g("chi"), g("spall")
    for k in range(5):
        M.D[k] = md.get("D", [0.0] * 5)[k]
    za = md.get("za", {})
    z = lambda key: float(za.get(key, 0.0))
    M.za.C0, M.za.C1, M.za.C2, M.za.C3, M.za.C4, M.za.C5, M.za.n = z("C0"), z("C1"), z("C2"), z("C3"), z("C4"), z("C5"), z("n")
    mts = md.get("mts", {})
    t = lambda key: float(mts.get(key, 0.0))
    M.mts.sigma_a, M.mts.mu_0, M.mts.D, M.mts.T_0, M.mts.k_over_b3 = t("sigma_a"), t("mu_0"), t("D"), t("T_0"), t("k_over_b3")
    M.mts.sigma_i, M.mts.g_0i, M.mts.eps_dot_0i, M.mts.p_i, M.mts.q_i = t("sigma_i"), t("g_0i"), t("eps_dot_0i"), t("p_i"), t("q_i")
    M.mts.g_0e, M.mts.eps_dot_0e, M.mts.p_e, M.mts.q_e = t("g_0e"), t("eps_dot_0e"), t("p_e"), t("q_e")
    M.mts.a_0, M.mts.a_1, M.mts.a_2, M.mts.a_3, M.mts.alpha = t("a_0"), t("a_1"), t("a_2"), t("a_3"), t("alpha")
    M.mts.g_0es, M.mts.eps_dot_es0, M.mts.sigma_es0 = t("g_0es"), t("eps_dot_es0"), t("sigma_es0")
    if md.get("aniso"):
        M.aniso = <PetscBool>1
        for k in range(36):
            M.ply.C[k] = md["ply_C"][k]
        for k in range(6):
            M.ply.X[k] = md["ply_X"][k]
        for k in range(4):
            M.ply.Gc[k] = md["ply_Gc"][k]
            M.ply.E[k] = md["ply_E"][k]
        M.ply.K_R, M.ply.c2max = g("K_R"), g("c2max")
    CHK(PSMaterialInit(M, md["eos"].encode(), md["strength"].encode(), md["failure"].encode()))
    return 0


def drive(dict md, axes0, L, double dt, double h):
    """The solver's kernel on one 3D marker under the velocity gradients L
    (n x 3 x 3, 1/s) with time step dt (s) and regularisation length h (m).
    Returns stress (n x 3 x 3, Pa), axes (n x 3 x 3, rows a_k), damage (n x 4),
    pressure (Pa), energy (J/kg) and J after each step."""
    cdef PSMaterial M
    cdef double[::1] a0 = np.ascontiguousarray(axes0, dtype=float).reshape(9)
    cdef double[::1] Lh = np.ascontiguousarray(L, dtype=float).reshape(-1)
    cdef PetscInt n = Lh.shape[0] // 9
    sig = np.zeros((max(n, 1), 3, 3))
    ax = np.zeros((max(n, 1), 3, 3))
    dmg = np.zeros((max(n, 1), 4))
    pe = np.zeros((max(n, 1), 3))
    cdef double[:, :, ::1] vs = sig
    cdef double[:, :, ::1] va = ax
    cdef double[:, ::1] vd = dmg
    cdef double[:, ::1] vp = pe
    fill_material(&M, md)
    if n > 0:
        CHK(PSMaterialDrive(&M, &a0[0], n, &Lh[0], dt, h, &vs[0, 0, 0], &va[0, 0, 0], &vd[0, 0], &vp[0, 0]))
    return dict(stress=sig[:n], axes=ax[:n], damage=dmg[:n], pressure=pe[:n, 0], energy=pe[:n, 1], J=pe[:n, 2])


# ===========================================================================
# Eulerian cells: PLIC interface geometry (src/cells/plic.h).  Thin batch
# wrappers for the tests and scripts/bench_plic.py, called directly (the
# solver's C code calls plic.h itself, so core.py has nothing to add): one C
# call per item, the loop typed; arrays carry dim in their last axis (2 or 3).
# Kept in one block at the end of the file so merges stay simple.
# ===========================================================================
from libc.stddef cimport ptrdiff_t

cdef extern from "cells/plic.h":
    enum: PS_PLIC_MAXMAT
    ctypedef struct PSPlicCell:
        int dim
        int nmat
        double h[3]
        double n[7][3]
        double d[7]
    int PSPlicYoungsNormal(int, const double *, ptrdiff_t, ptrdiff_t, ptrdiff_t, const double *, double *)
    double PSPlicVolume(int, const double *, double, const double *)
    double PSPlicOffset(int, const double *, double, const double *)
    # n is const double[][3] in C; void * converts to it implicitly
    int PSPlicReconstruct(int, const double *, int, const double *, const void *, PSPlicCell *)
    int PSPlicSlabVolumes(const PSPlicCell *, int, int, double, double *)

PLIC_MAXMAT = PS_PLIC_MAXMAT


def _plic_rows(x, N, dim):
    """x broadcast to a C-contiguous (N, dim) float array."""
    return np.array(np.broadcast_to(np.asarray(x, dtype=float), (N, dim)), order="C")


def plic_youngs(a, h):
    """Youngs' unit normals (out of the material) at every interior cell of a
    field of volume fractions a[ix, iy(, iz)] (2D or 3D, at least 3 cells a
    side, any strides), cell sizes h (m).  Returns (n (nx-2, ny-2[, nz-2], 3),
    flat (same shape without the 3)): flat marks flat blocks, where n is the
    fallback (1, 0, 0)."""
    arr = np.asarray(a, dtype=float)
    cdef int dim = arr.ndim
    if dim not in (2, 3) or any(s < 3 for s in arr.shape):
        raise ValueError("a must be 2D or 3D with at least 3 cells a side")
    cdef double hh[3]
    cdef double[:, :] v2
    cdef double[:, :, :] v3
    cdef double[:, ::1] vn
    cdef signed char[::1] vf
    cdef Py_ssize_t i, j, k, m = 0, sx, sy, sz
    hv = np.zeros(3)
    hv[:dim] = np.asarray(h, dtype=float)[:dim]
    for i in range(3):
        hh[i] = hv[i]
    inner = tuple(s - 2 for s in arr.shape)
    out = np.zeros((int(np.prod(inner)), 3))
    flat = np.zeros(out.shape[0], dtype=np.int8)
    vn, vf = out, flat
    if dim == 2:
        v2 = arr
        sx, sy = v2.strides[0] // 8, v2.strides[1] // 8
        for i in range(1, v2.shape[0] - 1):
            for j in range(1, v2.shape[1] - 1):
                vf[m] = PSPlicYoungsNormal(2, &v2[i, j], sx, sy, 0, hh, &vn[m, 0])
                m += 1
    else:
        v3 = arr
        sx, sy, sz = v3.strides[0] // 8, v3.strides[1] // 8, v3.strides[2] // 8
        for i in range(1, v3.shape[0] - 1):
            for j in range(1, v3.shape[1] - 1):
                for k in range(1, v3.shape[2] - 1):
                    vf[m] = PSPlicYoungsNormal(3, &v3[i, j, k], sx, sy, sz, hh, &vn[m, 0])
                    m += 1
    return out.reshape(inner + (3,)), flat.reshape(inner).astype(bool)


def plic_offset(n, alpha, h):
    """Offsets d (N,) with |{x in the cell : n.x <= d}| = alpha |cell|; n (N, dim),
    alpha (N,), h (dim,) or (N, dim) in m; the cell centred at 0."""
    nn = np.atleast_2d(np.asarray(n, dtype=float))
    cdef Py_ssize_t N = nn.shape[0], i
    cdef int dim = nn.shape[1], j
    cdef double[:, ::1] vn = _plic_rows(nn, N, dim)
    cdef double[:, ::1] vh = _plic_rows(h, N, dim)
    cdef double[::1] va = np.array(np.broadcast_to(np.asarray(alpha, dtype=float), (N,)))
    out = np.empty(N)
    cdef double[::1] vo = out
    cdef double n3[3]
    cdef double h3[3]
    for i in range(N):
        n3[2] = 0.0
        h3[2] = 0.0
        for j in range(dim):
            n3[j] = vn[i, j]
            h3[j] = vh[i, j]
        vo[i] = PSPlicOffset(dim, n3, va[i], h3)
    return out


def plic_volume(n, d, h):
    """Volumes (N,) of {x in the cell : n.x <= d} (m^3; m^2 in 2D); n (N, dim),
    d (N,), h (dim,) or (N, dim)."""
    nn = np.atleast_2d(np.asarray(n, dtype=float))
    cdef Py_ssize_t N = nn.shape[0], i
    cdef int dim = nn.shape[1], j
    cdef double[:, ::1] vn = _plic_rows(nn, N, dim)
    cdef double[:, ::1] vh = _plic_rows(h, N, dim)
    cdef double[::1] vd = np.array(np.broadcast_to(np.asarray(d, dtype=float), (N,)))
    out = np.empty(N)
    cdef double[::1] vo = out
    cdef double n3[3]
    cdef double h3[3]
    for i in range(N):
        n3[2] = 0.0
        h3[2] = 0.0
        for j in range(dim):
            n3[j] = vn[i, j]
            h3[j] = vh[i, j]
        vo[i] = PSPlicVolume(dim, n3, vd[i], h3)
    return out


def plic_reconstruct(alpha, n, h):
    """Nested dissection of N cells: alpha (N, K) volume fractions in dissection
    order, n (N, K-1, dim) normals out of each material, h (dim,) or (N, dim).
    Returns the offsets d (N, K-1)."""
    al = np.array(np.atleast_2d(np.asarray(alpha, dtype=float)), order="C")
    cdef Py_ssize_t N = al.shape[0], i
    cdef int K = al.shape[1], dim, j, k
    if K < 1 or K > PS_PLIC_MAXMAT:
        raise ValueError(f"need 1..{PS_PLIC_MAXMAT} materials, not {K}")
    nn = np.asarray(n, dtype=float).reshape(N, K - 1, -1) if K > 1 else None
    dim = nn.shape[2] if K > 1 else np.asarray(h).shape[-1]
    if dim not in (2, 3):
        raise ValueError("dim must be 2 or 3")
    cdef double[:, ::1] va = al
    cdef double[:, ::1] vn = np.array(nn.reshape(N, -1), order="C") if K > 1 else np.zeros((N, 1))
    cdef double[:, ::1] vh = _plic_rows(h, N, dim)
    out = np.zeros((N, max(K - 1, 1)))
    cdef double[:, ::1] vo = out
    cdef PSPlicCell c
    cdef double n3[7][3]
    cdef double h3[3]
    for i in range(N):
        h3[2] = 0.0
        for j in range(dim):
            h3[j] = vh[i, j]
        for k in range(K - 1):
            n3[k][2] = 0.0
            for j in range(dim):
                n3[k][j] = vn[i, k * dim + j]
        if PSPlicReconstruct(dim, h3, K, &va[i, 0], n3, &c):
            raise RuntimeError(f"PSPlicReconstruct failed on item {i}")
        for k in range(K - 1):
            vo[i, k] = c.d[k]
    return out[:, :K - 1]


def plic_slab(n, d, h, int axis, int side, w):
    """Volume of each material (N, K) in the slab within w (N,) of the face
    (axis, side = -1|+1) of N reconstructed cells: n (N, K-1, dim), d (N, K-1),
    h (dim,) or (N, dim)."""
    dd = np.array(np.atleast_2d(np.asarray(d, dtype=float)), order="C")
    cdef Py_ssize_t N = dd.shape[0], i
    cdef int K = dd.shape[1] + 1, dim, j, k
    if K > PS_PLIC_MAXMAT:
        raise ValueError(f"need 1..{PS_PLIC_MAXMAT} materials, not {K}")
    nn = np.asarray(n, dtype=float).reshape(N, K - 1, -1) if K > 1 else None
    dim = nn.shape[2] if K > 1 else np.asarray(h).shape[-1]
    if dim not in (2, 3):
        raise ValueError("dim must be 2 or 3")
    cdef double[:, ::1] vd = dd if K > 1 else np.zeros((N, 1))
    cdef double[:, ::1] vn = np.array(nn.reshape(N, -1), order="C") if K > 1 else np.zeros((N, 1))
    cdef double[:, ::1] vh = _plic_rows(h, N, dim)
    cdef double[::1] vw = np.array(np.broadcast_to(np.asarray(w, dtype=float), (N,)))
    out = np.empty((N, K))
    cdef double[:, ::1] vo = out
    cdef PSPlicCell c
    c.dim = dim
    c.nmat = K
    for i in range(N):
        c.h[2] = 0.0
        for j in range(dim):
            c.h[j] = vh[i, j]
        for k in range(K - 1):
            c.n[k][2] = 0.0
            for j in range(dim):
                c.n[k][j] = vn[i, k * dim + j]
            c.d[k] = vd[i, k]
        if PSPlicSlabVolumes(&c, axis, side, vw[i], &vo[i, 0]):
            raise ValueError(f"PSPlicSlabVolumes: bad input on item {i} (axis {axis}, side {side})")
    return out
