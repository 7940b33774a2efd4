/*
  solver.c - the solver's context: creation from a scene, options (the
  deck's run: values are the defaults, -run_<key> overrides), gauges, and the
  log events of the step's phases (step.h).
*/
#include <stdio.h>
#include "step.h"
#include "cells/cells.h"
#include "contact.h"

const char *const PSShapeTypes[]    = {"linear", "gimp", "bspline2", "PSShapeType", "PS_SHAPE_", NULL};
const char *const PSTransferTypes[] = {"musl", "apic", "PSTransferType", "PS_TRANSFER_", NULL};

PetscLogEvent PS_EV_P2G, PS_EV_Grid, PS_EV_G2P, PS_EV_Reproject, PS_EV_Stress, PS_EV_Migrate, PS_EV_Dt, PS_EV_Huge;

/* A ghosted local grid vector whose array starts on a 64-byte boundary (a
   cache line), so a node of 4 or 8 reals never straddles two lines (PETSc
   3.18 aligns to 16 bytes only). */
static PetscErrorCode CreateAlignedLocal(DM dm, Vec *v, PetscReal **buf, PetscReal **array)
{
  Vec        t;
  PetscInt   n, bs;
  PetscReal *a;

  PetscFunctionBeginUser;
  PetscCall(DMGetLocalVector(dm, &t));
  PetscCall(VecGetSize(t, &n));
  PetscCall(VecGetBlockSize(t, &bs));
  PetscCall(DMRestoreLocalVector(dm, &t));
  PetscCall(PetscCalloc1(n + 8, buf)); /* 8 reals of slack to move the start to a 64-byte boundary */
  a = (PetscReal *)(((size_t)*buf + 63) & ~(size_t)63);
  PetscCall(VecCreateSeqWithArray(PETSC_COMM_SELF, bs, n, a, v));
  *array = a;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode PSSolverCreate(const PSScene *scene, DM da, DM sw, const PSRunParams *run, const PSMaterial *mats, const PetscInt bc[6], PSSolver **out)
{
  PSSolver      *S;
  PetscInt       d;
  const PetscInt *l[3];
  static PetscBool registered = PETSC_FALSE;

  PetscFunctionBeginUser;
  if (!registered) {
    PetscClassId cid;
    PetscCall(PetscClassIdRegister("plyshock solver", &cid));
    PetscCall(PetscLogEventRegister("PSP2G", cid, &PS_EV_P2G));
    PetscCall(PetscLogEventRegister("PSGridUpdate", cid, &PS_EV_Grid));
    PetscCall(PetscLogEventRegister("PSG2P", cid, &PS_EV_G2P));
    PetscCall(PetscLogEventRegister("PSReproject", cid, &PS_EV_Reproject));
    PetscCall(PetscLogEventRegister("PSStress", cid, &PS_EV_Stress));
    PetscCall(PetscLogEventRegister("PSMigrate", cid, &PS_EV_Migrate));
    PetscCall(PetscLogEventRegister("PSTimeStep", cid, &PS_EV_Dt));
    PetscCall(PetscLogEventRegister("PSHugePages", cid, &PS_EV_Huge));
    registered = PETSC_TRUE;
  }
  PetscCall(PetscNew(&S));
  S->scene = scene;
  S->run   = *run;
  S->da    = da;
  S->sw    = sw;
  S->dim   = scene->dim;
  S->pad   = PS_PAD;
  S->ndamage = scene->ndamage;
  S->axi     = scene->axisymmetric;
  PetscCheck(!S->axi || (S->dim == 2 && run->transfer == PS_TRANSFER_MUSL), PETSC_COMM_SELF, PETSC_ERR_ARG_OUTOFRANGE, "geometry axisymmetric needs dimension 2 and run.transfer musl, got dimension %" PetscInt_FMT " and transfer %s", S->dim, PSTransferTypes[run->transfer]);
  for (d = 0; d < scene->nbody; d++)
    if (scene->bodies[d].kind == PS_BODY_LAMINATE) S->has_ply = PETSC_TRUE;
  PetscCall(PetscMalloc1(scene->nmaterial, &S->mat));
  PetscCall(PetscArraycpy(S->mat, mats, scene->nmaterial));
  for (d = 0; d < 3; d++) {
    S->bc[d][0] = d < S->dim ? (PSBCType)bc[2 * d] : PS_BC_FREE;
    S->bc[d][1] = d < S->dim ? (PSBCType)bc[2 * d + 1] : PS_BC_FREE;
    S->nc[d]    = d < S->dim ? scene->cells[d] : 1;
    S->h[d]     = d < S->dim ? (scene->upper[d] - scene->lower[d]) / scene->cells[d] : 1.0;
    S->ih[d]    = 1.0 / S->h[d];
    S->Dinv[d]  = 4.0 / (S->h[d] * S->h[d]); /* MLS-MPM D_p^-1 of quadratic B-splines */
  }
  PetscCall(DMDAGetInfo(da, NULL, NULL, NULL, NULL, &S->nproc[0], &S->nproc[1], &S->nproc[2], NULL, NULL, NULL, NULL, NULL, NULL));
  PetscCall(DMDAGetOwnershipRanges(da, &l[0], &l[1], &l[2]));
  for (d = 0; d < 3; d++) {
    PetscInt r;
    PetscCall(PetscMalloc1(S->nproc[d] + 1, &S->lx[d]));
    S->lx[d][0] = 0;
    for (r = 0; r < S->nproc[d]; r++) S->lx[d][r + 1] = S->lx[d][r] + (d < S->dim ? l[d][r] : 1);
  }
  if (S->run.transfer == PS_TRANSFER_APIC) {
    PetscCheck(scene->need_affine, PetscObjectComm((PetscObject)da), PETSC_ERR_ARG_INCOMP, "run.transfer apic: the markers were made without the affine field (initialise the scene with transfer apic)");
  }
  PetscCall(DMDACreateCompatibleDMDA(da, PSGridDof(S), &S->dag));
  PetscCall(DMCreateGlobalVector(S->dag, &S->G));
  PetscCall(CreateAlignedLocal(S->dag, &S->Gl, &S->gbuf, &S->g));
  PetscCall(PSHaloCreate(S, PSGridDof(S), &S->sfg));
  if (S->run.transfer == PS_TRANSFER_MUSL) {
    PetscCall(DMDACreateCompatibleDMDA(da, PSReprojectDof(S), &S->dav));
    PetscCall(DMCreateGlobalVector(S->dav, &S->H));
    PetscCall(CreateAlignedLocal(S->dav, &S->Hl, &S->hbuf, &S->hv));
    PetscCall(PSHaloCreate(S, PSReprojectDof(S), &S->sfh));
  }
  {
    PetscReal rmin = PETSC_MAX_REAL, vc = 1.0;
    for (d = 0; d < scene->nmaterial; d++) rmin = PetscMin(rmin, mats[d].rho0);
    for (d = 0; d < S->dim; d++) vc *= S->h[d];
    S->mass_min = S->run.mass_threshold * rmin * vc;
  }
  PetscCall(PSCellOwnership(da, S->cs, S->ce));
  S->ncell = 1;
  for (d = 0; d < S->dim; d++) S->ncell *= S->ce[d] - S->cs[d];
  S->zall = PETSC_TRUE;
  if (S->run.fbar) PetscCall(PetscMalloc2(PetscMax(S->ncell, 1), &S->cell_V, PetscMax(S->ncell, 1), &S->cell_trL));
  /* Eulerian cells: their arrays only in a scene with bodies in cells */
  if (scene->ncellmat > 0) PetscCall(PSCellsCreate(S, S->mat));
  *out = S;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The initial state of a fresh run (a restart reads its own instead): the
   bodies in cells inserted, markers of bodies with an initial pressure given
   the energy e0 = (p - A)/B of their EOS p = A + B e at J = 1, and their
   initial plastic strain. */
PetscErrorCode PSSolverInitialState(PSSolver *S)
{
  const PSScene *scene = S->scene;
  PetscInt       n, p, *body, *mat;
  PetscReal     *e, *pr, *ep = NULL;
  PetscBool      any = PETSC_FALSE;

  PetscFunctionBeginUser;
  if (S->cells) {
    PetscCall(PSCellsInsert(S));
    PetscCall(PSCellsFitMarkers(S, PETSC_FALSE)); /* the markers' share of each cell; insertion is exact */
  }
  for (p = 0; p < scene->nbody; p++)
    if (scene->bodies[p].cellmat < 0 && (scene->bodies[p].pressure != 0.0 || scene->bodies[p].plastic_strain != 0.0)) any = PETSC_TRUE;
  if (!any) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(DMSwarmGetLocalSize(S->sw, &n));
  PetscCall(DMSwarmGetField(S->sw, PS_FIELD_BODY, NULL, NULL, (void **)&body));
  PetscCall(DMSwarmGetField(S->sw, PS_FIELD_MATERIAL, NULL, NULL, (void **)&mat));
  PetscCall(DMSwarmGetField(S->sw, PS_FIELD_ENERGY, NULL, NULL, (void **)&e));
  PetscCall(DMSwarmGetField(S->sw, PS_FIELD_PRESSURE, NULL, NULL, (void **)&pr));
  if (scene->need_plastic) PetscCall(DMSwarmGetField(S->sw, PS_FIELD_EPS_P, NULL, NULL, (void **)&ep));
  for (p = 0; p < n; p++) {
    const PetscReal   p0 = scene->bodies[body[p]].pressure;
    if (ep) ep[p] = scene->bodies[body[p]].plastic_strain;
    const PSMaterial *M  = &S->mat[mat[p]];
    PetscReal         A, B, c2;
    if (p0 == 0.0) continue;
    PetscCall(M->eos_fn(M, 1.0, p0, 0.0, &A, &B, &c2));
    PetscCheck(B > 0.0, PETSC_COMM_SELF, PETSC_ERR_ARG_WRONG, "body %" PetscInt_FMT ": its material's EOS has no energy term to reach the initial pressure %g Pa", body[p], (double)p0);
    e[p]  = (p0 - A) / B;
    pr[p] = p0;
  }
  if (ep) PetscCall(DMSwarmRestoreField(S->sw, PS_FIELD_EPS_P, NULL, NULL, (void **)&ep));
  PetscCall(DMSwarmRestoreField(S->sw, PS_FIELD_PRESSURE, NULL, NULL, (void **)&pr));
  PetscCall(DMSwarmRestoreField(S->sw, PS_FIELD_ENERGY, NULL, NULL, (void **)&e));
  PetscCall(DMSwarmRestoreField(S->sw, PS_FIELD_MATERIAL, NULL, NULL, (void **)&mat));
  PetscCall(DMSwarmRestoreField(S->sw, PS_FIELD_BODY, NULL, NULL, (void **)&body));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode PSSolverDestroy(PSSolver **S)
{
  PetscInt d;

  PetscFunctionBeginUser;
  if (!*S) PetscFunctionReturn(PETSC_SUCCESS);
  for (d = 0; d < 3; d++) PetscCall(PetscFree((*S)->lx[d]));
  PetscCall(VecDestroy(&(*S)->G));
  PetscCall(VecDestroy(&(*S)->Gl));
  PetscCall(VecDestroy(&(*S)->H));
  PetscCall(VecDestroy(&(*S)->Hl));
  PetscCall(PetscFree((*S)->gbuf));
  PetscCall(PetscFree((*S)->hbuf));
  PetscCall(DMDestroy(&(*S)->dav));
  PetscCall(DMDestroy(&(*S)->dag));
  PetscCall(PetscSFDestroy(&(*S)->sfg));
  PetscCall(PetscSFDestroy(&(*S)->sfh));
  PetscCall(PetscFree((*S)->mat));
  PetscCall(PetscFree((*S)->dx));
  PetscCall(PetscFree((*S)->at));
  PetscCall(PetscFree((*S)->Lp));
  if ((*S)->cell_V) PetscCall(PetscFree2((*S)->cell_V, (*S)->cell_trL));
  PetscCall(PetscFree((*S)->gauge_id));
  PetscCall(PSCellsDestroy(&(*S)->cells));
  PetscCall(PSContactDestroy(&(*S)->contact));
  PetscCall(PetscFree(*S));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Gauges follow markers by id (chosen at t = 0 as the nearest to each point). */
PetscErrorCode PSSolverSetGauges(PSSolver *S, PetscInt n, const PetscInt64 ids[])
{
  PetscFunctionBeginUser;
  PetscCall(PetscFree(S->gauge_id));
  S->ngauge = n;
  PetscCall(PetscMalloc1(PetscMax(n, 1), &S->gauge_id));
  PetscCall(PetscArraycpy(S->gauge_id, ids, n));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Run options: the deck's values are the defaults, -run_<key> overrides.  The
   one place run options are read; no checks here (PSRunParamsCheck). */
PetscErrorCode PSRunParamsRead(MPI_Comm comm, PSRunParams *r)
{
  PetscInt shape = r->shape, transfer = r->transfer;

  PetscFunctionBeginUser;
  PetscOptionsBegin(comm, "run_", "plyshock run options (SI units)", "plyshock");
  PetscCall(PetscOptionsReal("-t_end", "end time (s)", "plyshock", r->t_end, &r->t_end, NULL));
  PetscCall(PetscOptionsReal("-cfl", "Courant number", "plyshock", r->cfl, &r->cfl, NULL));
  PetscCall(PetscOptionsEList("-shape", "shape functions", "plyshock", PSShapeTypes, 3, PSShapeTypes[shape], &shape, NULL));
  PetscCall(PetscOptionsEList("-transfer", "transfer scheme", "plyshock", PSTransferTypes, 2, PSTransferTypes[transfer], &transfer, NULL));
  PetscCall(PetscOptionsReal("-output_interval", "time between outputs (s); 0: end only", "plyshock", r->output_interval, &r->output_interval, NULL));
  PetscCall(PetscOptionsReal("-c_linear", "linear artificial viscosity coefficient", "plyshock", r->c_linear, &r->c_linear, NULL));
  PetscCall(PetscOptionsReal("-c_quadratic", "quadratic artificial viscosity coefficient", "plyshock", r->c_quadratic, &r->c_quadratic, NULL));
  PetscCall(PetscOptionsReal("-pic_fraction", "PIC share of the velocity update", "plyshock", r->pic_fraction, &r->pic_fraction, NULL));
  PetscCall(PetscOptionsReal("-dt_growth", "largest dt_{n+1}/dt_n", "plyshock", r->dt_growth, &r->dt_growth, NULL));
  PetscCall(PetscOptionsReal("-dt_max", "largest time step (s); 0: none", "plyshock", r->dt_max, &r->dt_max, NULL));
  PetscCall(PetscOptionsReal("-mass_threshold", "nodes lighter than this share of a full cell carry no velocity", "plyshock", r->mass_threshold, &r->mass_threshold, NULL));
  PetscCall(PetscOptionsBool("-fbar", "average the volumetric strain rate over each cell (Delta-F-bar, against volumetric locking)", "plyshock", r->fbar, &r->fbar, NULL));
  PetscCall(PetscOptionsInt("-lanes", "markers per call of the 3D isotropic kernel: 4 (vectorised) or 1 (scalar, for checks); 1 also sends every cell through the cells' scalar loops and keeps the cells' phases in passes of their own (the results are bitwise the same)", "plyshock", r->lanes, &r->lanes, NULL));
  PetscCall(PetscOptionsInt("-max_steps", "stop after this many steps (0: none)", "plyshock", r->max_steps, &r->max_steps, NULL));
  PetscCall(PetscOptionsInt("-history_interval", "steps between history rows", "plyshock", r->history_interval, &r->history_interval, NULL));
  PetscCall(PetscOptionsInt("-progress_interval", "steps between progress lines (0: by wall time)", "plyshock", r->progress_interval, &r->progress_interval, NULL));
  PetscCall(PetscOptionsReal("-checkpoint_interval", "simulated time between checkpoints (s); 0: at every output time", "plyshock", r->checkpoint_interval, &r->checkpoint_interval, NULL));
  PetscCall(PetscOptionsReal("-checkpoint_wall_interval", "wall time between checkpoints (s); 0: none", "plyshock", r->checkpoint_wall_interval, &r->checkpoint_wall_interval, NULL));
  PetscCall(PetscOptionsBool("-hugepages", "back the large arrays with transparent huge pages (Linux; no result changes)", "plyshock", r->hugepages, &r->hugepages, NULL));
  PetscCall(PetscOptionsReal("-dt_floor", "stop when the time step falls below this share of the initial one; 0: never", "plyshock", r->dt_floor, &r->dt_floor, NULL));
  PetscOptionsEnd();
  r->shape    = (PSShapeType)shape;
  r->transfer = (PSTransferType)transfer;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The one place the run parameters' values are checked, after the command line
   has had its say (the Python front end checks the deck's structure: keys,
   types and names; see README "Input checks").  On the first value out of
   range *key names its deck key and msg says why; *key = NULL when all pass. */
PetscErrorCode PSRunParamsCheck(const PSRunParams *r, const char **key, char msg[], size_t len)
{
  PetscFunctionBeginUser;
  *key = NULL;
  msg[0] = 0;
#define RANGE(cond, k, fmt, ...) \
  if (!(cond)) { \
    *key = k; \
    snprintf(msg, len, fmt, __VA_ARGS__); /* plain %g: 5, not PETSc's 5. */ \
    PetscFunctionReturn(PETSC_SUCCESS); \
  }
  RANGE(r->t_end > 0 && r->t_end < PETSC_INFINITY, "run.t_end", "%g is out of range; allowed (0, inf) s", (double)r->t_end);
  RANGE(r->cfl > 0 && r->cfl <= 1, "run.cfl", "%g is out of range; allowed (0, 1]", (double)r->cfl);
  RANGE(r->output_interval >= 0, "run.output_interval", "%g is out of range; allowed [0, inf) s", (double)r->output_interval);
  RANGE(r->c_linear >= 0 && r->c_linear <= 100, "run.artificial_viscosity.c_linear", "%g is out of range; allowed [0, 100]", (double)r->c_linear);
  RANGE(r->c_quadratic >= 0 && r->c_quadratic <= 100, "run.artificial_viscosity.c_quadratic", "%g is out of range; allowed [0, 100]", (double)r->c_quadratic);
  RANGE(r->pic_fraction >= 0 && r->pic_fraction <= 1, "run.pic_fraction", "%g is out of range; allowed [0, 1]", (double)r->pic_fraction);
  RANGE(r->dt_growth >= 1 && r->dt_growth <= 10, "run.dt_growth", "%g is out of range; allowed [1, 10]", (double)r->dt_growth);
  RANGE(r->dt_max >= 0, "run.dt_max", "%g is out of range; allowed [0, inf) s", (double)r->dt_max);
  RANGE(r->mass_threshold >= 0 && r->mass_threshold <= 0.5, "run.mass_threshold", "%g is out of range; allowed [0, 0.5]", (double)r->mass_threshold);
  RANGE(r->max_steps >= 0, "run.max_steps", "%" PetscInt_FMT " is out of range; allowed [0, inf)", r->max_steps);
  RANGE(r->history_interval >= 1, "run.history_interval", "%" PetscInt_FMT " is out of range; allowed [1, inf)", r->history_interval);
  RANGE(r->progress_interval >= 0, "run.progress_interval", "%" PetscInt_FMT " is out of range; allowed [0, inf)", r->progress_interval);
  RANGE(r->checkpoint_interval >= 0 && r->checkpoint_interval < PETSC_INFINITY, "run.checkpoint_interval", "%g is out of range; allowed [0, inf) s (0: at every output time)", (double)r->checkpoint_interval);
  RANGE(r->checkpoint_wall_interval >= 0 && r->checkpoint_wall_interval < PETSC_INFINITY, "run.checkpoint_wall_interval", "%g is out of range; allowed [0, inf) s of wall time (0: none)", (double)r->checkpoint_wall_interval);
  RANGE(r->dt_floor >= 0 && r->dt_floor < 1, "run.dt_floor", "%g is out of range; allowed [0, 1) (a share of the initial time step; 0: no floor)", (double)r->dt_floor);
  RANGE(r->lanes == 1 || r->lanes == 4, "-run_lanes", "%" PetscInt_FMT " must be 1 or 4", r->lanes);
  /* MLS-MPM's D_p = h^2/4 I holds for quadratic B-splines only */
  RANGE(r->transfer != PS_TRANSFER_APIC || r->shape == PS_SHAPE_BSPLINE2, "run.transfer", "apic (MLS-MPM, D_p = h^2/4 I) needs run.shape bspline2, got %s", PSShapeTypes[r->shape]);
  RANGE(r->transfer != PS_TRANSFER_APIC || r->pic_fraction == 0, "run.pic_fraction", "applies to transfer musl only (apic is a PIC-type transfer): must be 0, got %g", (double)r->pic_fraction);
#undef RANGE
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Read and check: for callers of the library without the front end. */
PetscErrorCode PSRunParamsSetFromOptions(MPI_Comm comm, PSRunParams *r)
{
  const char *key;
  char        msg[256];

  PetscFunctionBeginUser;
  PetscCall(PSRunParamsRead(comm, r));
  PetscCall(PSRunParamsCheck(r, &key, msg, sizeof(msg)));
  PetscCheck(!key, comm, PETSC_ERR_ARG_OUTOFRANGE, "%s: %s", key, msg);
  PetscFunctionReturn(PETSC_SUCCESS);
}
