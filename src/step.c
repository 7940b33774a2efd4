/*
  step.c - the explicit MPM time step (MUSL, see solver.h) on DMDA + DMSwarm.

  Kernels (each a log event): PSP2G, PSGridUpdate, PSG2P, PSReproject,
  PSStress, PSMigrate.  Each kernel: get fields, reset outputs, loop over
  markers, then communicate; the communication is kept apart from the math.
*/
#include <math.h>
#include "materials.h"
#include "shape.h"

const char *const PSShapeTypes[]    = {"linear", "gimp", "bspline2", "PSShapeType", "PS_SHAPE_", NULL};
const char *const PSTransferTypes[] = {"musl", "apic", "PSTransferType", "PS_TRANSFER_", NULL};

static PetscLogEvent EV_P2G, EV_Grid, EV_G2P, EV_Reproject, EV_Stress, EV_Migrate, EV_Dt;

typedef struct {
  PetscInt gs[3], gm[3]; /* ghosted corners of the local arrays */
  PetscInt os[3], om[3]; /* owned corners */
} PSIndex;

static PetscErrorCode GetIndex(DM da, PSIndex *ix)
{
  PetscFunctionBeginUser;
  PetscCall(DMDAGetGhostCorners(da, &ix->gs[0], &ix->gs[1], &ix->gs[2], &ix->gm[0], &ix->gm[1], &ix->gm[2]));
  PetscCall(DMDAGetCorners(da, &ix->os[0], &ix->os[1], &ix->os[2], &ix->om[0], &ix->om[1], &ix->om[2]));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static inline PetscInt Lidx(const PSIndex *ix, PetscInt i, PetscInt j, PetscInt k)
{
  return ((k - ix->gs[2]) * ix->gm[1] + (j - ix->gs[1])) * ix->gm[0] + (i - ix->gs[0]);
}

/* ------------------------------------------------------------ set up -- */

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
    PetscCall(PetscLogEventRegister("PSP2G", cid, &EV_P2G));
    PetscCall(PetscLogEventRegister("PSGridUpdate", cid, &EV_Grid));
    PetscCall(PetscLogEventRegister("PSG2P", cid, &EV_G2P));
    PetscCall(PetscLogEventRegister("PSReproject", cid, &EV_Reproject));
    PetscCall(PetscLogEventRegister("PSStress", cid, &EV_Stress));
    PetscCall(PetscLogEventRegister("PSMigrate", cid, &EV_Migrate));
    PetscCall(PetscLogEventRegister("PSTimeStep", cid, &EV_Dt));
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
  for (d = 0; d < scene->nbody; d++)
    if (scene->bodies[d].kind == PS_BODY_LAMINATE) S->has_ply = PETSC_TRUE;
  PetscCall(PetscMalloc1(scene->nmaterial, &S->mat));
  PetscCall(PetscArraycpy(S->mat, mats, scene->nmaterial));
  for (d = 0; d < 3; d++) {
    S->bc[d][0] = d < S->dim ? (PSBCType)bc[2 * d] : PS_BC_FREE;
    S->bc[d][1] = d < S->dim ? (PSBCType)bc[2 * d + 1] : PS_BC_FREE;
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
    /* MLS-MPM's D_p = h^2/4 I holds for quadratic B-splines only */
    PetscCheck(S->run.shape == PS_SHAPE_BSPLINE2, PetscObjectComm((PetscObject)da), PETSC_ERR_ARG_INCOMP, "run.transfer apic needs run.shape bspline2, got %s", PSShapeTypes[S->run.shape]);
    PetscCheck(scene->need_affine, PetscObjectComm((PetscObject)da), PETSC_ERR_ARG_INCOMP, "run.transfer apic: the markers were made without the affine field (initialise the scene with transfer apic)");
    PetscCall(DMDACreateCompatibleDMDA(da, 1 + S->dim, &S->daa));
    PetscCall(DMCreateGlobalVector(S->daa, &S->G));
    PetscCall(DMCreateLocalVector(S->daa, &S->Gl));
    PetscCall(PSHaloCreate(S, 1 + S->dim, &S->sfg));
  } else {
    PetscCall(DMDACreateCompatibleDMDA(da, S->dim, &S->dav));
    PetscCall(DMCreateGlobalVector(da, &S->G));
    PetscCall(DMCreateLocalVector(da, &S->Gl));
    PetscCall(DMCreateGlobalVector(S->dav, &S->H));
    PetscCall(DMCreateLocalVector(S->dav, &S->Hl));
    PetscCall(PSHaloCreate(S, 1 + 2 * S->dim, &S->sfg));
    PetscCall(PSHaloCreate(S, S->dim, &S->sfh));
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
  *out = S;
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
  PetscCall(DMDestroy(&(*S)->dav));
  PetscCall(DMDestroy(&(*S)->daa));
  PetscCall(PetscSFDestroy(&(*S)->sfg));
  PetscCall(PetscSFDestroy(&(*S)->sfh));
  PetscCall(PetscFree((*S)->mat));
  PetscCall(PetscFree((*S)->dx));
  PetscCall(PetscFree((*S)->shape));
  PetscCall(PetscFree((*S)->Lp));
  if ((*S)->cell_V) PetscCall(PetscFree2((*S)->cell_V, (*S)->cell_trL));
  PetscCall(PetscFree((*S)->gauge_id));
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

/* Run options: the deck's values are the defaults, -run_<key> overrides. */
PetscErrorCode PSRunParamsSetFromOptions(MPI_Comm comm, PSRunParams *r)
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
  PetscCall(PetscOptionsInt("-lanes", "markers per call of the 3D isotropic kernel: 4 (vectorised) or 1 (scalar, for checks)", "plyshock", r->lanes, &r->lanes, NULL));
  PetscCall(PetscOptionsInt("-max_steps", "stop after this many steps (0: none)", "plyshock", r->max_steps, &r->max_steps, NULL));
  PetscCall(PetscOptionsInt("-history_interval", "steps between history rows", "plyshock", r->history_interval, &r->history_interval, NULL));
  PetscCall(PetscOptionsInt("-progress_interval", "steps between progress lines (0: by wall time)", "plyshock", r->progress_interval, &r->progress_interval, NULL));
  PetscOptionsEnd();
  r->shape    = (PSShapeType)shape;
  r->transfer = (PSTransferType)transfer;
  PetscCheck(r->t_end > 0, comm, PETSC_ERR_ARG_OUTOFRANGE, "run.t_end %g must be > 0 s", (double)r->t_end);
  PetscCheck(r->cfl > 0 && r->cfl <= 1, comm, PETSC_ERR_ARG_OUTOFRANGE, "run.cfl %g must be in (0, 1]", (double)r->cfl);
  PetscCheck(r->pic_fraction >= 0 && r->pic_fraction <= 1, comm, PETSC_ERR_ARG_OUTOFRANGE, "run.pic_fraction %g must be in [0, 1]", (double)r->pic_fraction);
  PetscCheck(r->transfer == PS_TRANSFER_MUSL || r->pic_fraction == 0, comm, PETSC_ERR_ARG_INCOMP, "run.pic_fraction %g applies to run.transfer musl only (apic is a PIC-type transfer); set it to 0", (double)r->pic_fraction);
  PetscCheck(r->lanes == 1 || r->lanes == 4, comm, PETSC_ERR_ARG_OUTOFRANGE, "-run_lanes %" PetscInt_FMT " must be 1 or 4", r->lanes);
  PetscCheck(r->c_linear >= 0 && r->c_quadratic >= 0, comm, PETSC_ERR_ARG_OUTOFRANGE, "artificial viscosity coefficients (%g, %g) must be >= 0", (double)r->c_linear, (double)r->c_quadratic);
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode PSRunParamsSetFromOptionsDM(DM dm, PSRunParams *r)
{
  PetscFunctionBeginUser;
  PetscCall(PSRunParamsSetFromOptions(PetscObjectComm((PetscObject)dm), r));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* ------------------------------------------------------------ helpers -- */

typedef struct {
  PetscReal *x, *v, *mass, *vol, *V0, *F, *sig, *sdev, *p, *q, *e, *eps_p, *T, *D;
  PetscReal *axes, *smat; /* anisotropic scenes */
  PetscReal *C;           /* APIC affine velocity (transfer apic) */
  PetscInt  *mat, *body, *ply;
  PetscInt64 *id;
  PetscInt   n;
} PSFields;

static PetscErrorCode FieldsGet(PSSolver *S, PSFields *f)
{
  DM sw = S->sw;

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(f, sizeof(*f)));
  PetscCall(DMSwarmGetLocalSize(sw, &f->n));
  PetscCall(DMSwarmGetField(sw, PS_FIELD_X, NULL, NULL, (void **)&f->x));
  PetscCall(DMSwarmGetField(sw, PS_FIELD_VELOCITY, NULL, NULL, (void **)&f->v));
  PetscCall(DMSwarmGetField(sw, PS_FIELD_MASS, NULL, NULL, (void **)&f->mass));
  PetscCall(DMSwarmGetField(sw, PS_FIELD_VOLUME, NULL, NULL, (void **)&f->vol));
  PetscCall(DMSwarmGetField(sw, PS_FIELD_V0, NULL, NULL, (void **)&f->V0));
  PetscCall(DMSwarmGetField(sw, PS_FIELD_F, NULL, NULL, (void **)&f->F));
  PetscCall(DMSwarmGetField(sw, PS_FIELD_STRESS, NULL, NULL, (void **)&f->sig));
  PetscCall(DMSwarmGetField(sw, PS_FIELD_SDEV, NULL, NULL, (void **)&f->sdev));
  PetscCall(DMSwarmGetField(sw, PS_FIELD_PRESSURE, NULL, NULL, (void **)&f->p));
  PetscCall(DMSwarmGetField(sw, PS_FIELD_Q, NULL, NULL, (void **)&f->q));
  PetscCall(DMSwarmGetField(sw, PS_FIELD_ENERGY, NULL, NULL, (void **)&f->e));
  PetscCall(DMSwarmGetField(sw, PS_FIELD_MATERIAL, NULL, NULL, (void **)&f->mat));
  PetscCall(DMSwarmGetField(sw, PS_FIELD_ID, NULL, NULL, (void **)&f->id));
  if (S->scene->need_plastic) PetscCall(DMSwarmGetField(sw, PS_FIELD_EPS_P, NULL, NULL, (void **)&f->eps_p));
  if (S->scene->need_temperature) PetscCall(DMSwarmGetField(sw, PS_FIELD_TEMP, NULL, NULL, (void **)&f->T));
  if (S->scene->ndamage) PetscCall(DMSwarmGetField(sw, PS_FIELD_DAMAGE, NULL, NULL, (void **)&f->D));
  if (S->scene->need_affine) PetscCall(DMSwarmGetField(sw, PS_FIELD_AFFINE, NULL, NULL, (void **)&f->C));
  if (S->scene->anisotropic) {
    PetscCall(DMSwarmGetField(sw, PS_FIELD_AXES, NULL, NULL, (void **)&f->axes));
    PetscCall(DMSwarmGetField(sw, PS_FIELD_SMAT, NULL, NULL, (void **)&f->smat));
    PetscCall(DMSwarmGetField(sw, PS_FIELD_BODY, NULL, NULL, (void **)&f->body));
    if (S->has_ply) PetscCall(DMSwarmGetField(sw, PS_FIELD_PLY, NULL, NULL, (void **)&f->ply));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode FieldsRestore(PSSolver *S, PSFields *f)
{
  DM sw = S->sw;

  PetscFunctionBeginUser;
  if (f->C) PetscCall(DMSwarmRestoreField(sw, PS_FIELD_AFFINE, NULL, NULL, (void **)&f->C));
  if (f->ply) PetscCall(DMSwarmRestoreField(sw, PS_FIELD_PLY, NULL, NULL, (void **)&f->ply));
  if (f->body) PetscCall(DMSwarmRestoreField(sw, PS_FIELD_BODY, NULL, NULL, (void **)&f->body));
  if (f->smat) PetscCall(DMSwarmRestoreField(sw, PS_FIELD_SMAT, NULL, NULL, (void **)&f->smat));
  if (f->axes) PetscCall(DMSwarmRestoreField(sw, PS_FIELD_AXES, NULL, NULL, (void **)&f->axes));
  if (f->D) PetscCall(DMSwarmRestoreField(sw, PS_FIELD_DAMAGE, NULL, NULL, (void **)&f->D));
  if (f->T) PetscCall(DMSwarmRestoreField(sw, PS_FIELD_TEMP, NULL, NULL, (void **)&f->T));
  if (f->eps_p) PetscCall(DMSwarmRestoreField(sw, PS_FIELD_EPS_P, NULL, NULL, (void **)&f->eps_p));
  PetscCall(DMSwarmRestoreField(sw, PS_FIELD_ID, NULL, NULL, (void **)&f->id));
  PetscCall(DMSwarmRestoreField(sw, PS_FIELD_MATERIAL, NULL, NULL, (void **)&f->mat));
  PetscCall(DMSwarmRestoreField(sw, PS_FIELD_ENERGY, NULL, NULL, (void **)&f->e));
  PetscCall(DMSwarmRestoreField(sw, PS_FIELD_Q, NULL, NULL, (void **)&f->q));
  PetscCall(DMSwarmRestoreField(sw, PS_FIELD_PRESSURE, NULL, NULL, (void **)&f->p));
  PetscCall(DMSwarmRestoreField(sw, PS_FIELD_SDEV, NULL, NULL, (void **)&f->sdev));
  PetscCall(DMSwarmRestoreField(sw, PS_FIELD_STRESS, NULL, NULL, (void **)&f->sig));
  PetscCall(DMSwarmRestoreField(sw, PS_FIELD_F, NULL, NULL, (void **)&f->F));
  PetscCall(DMSwarmRestoreField(sw, PS_FIELD_V0, NULL, NULL, (void **)&f->V0));
  PetscCall(DMSwarmRestoreField(sw, PS_FIELD_VOLUME, NULL, NULL, (void **)&f->vol));
  PetscCall(DMSwarmRestoreField(sw, PS_FIELD_MASS, NULL, NULL, (void **)&f->mass));
  PetscCall(DMSwarmRestoreField(sw, PS_FIELD_VELOCITY, NULL, NULL, (void **)&f->v));
  PetscCall(DMSwarmRestoreField(sw, PS_FIELD_X, NULL, NULL, (void **)&f->x));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* GIMP half size of a marker: half its initial size */
static inline PetscReal HalfSize(PetscInt dim, PetscReal V0)
{
  return 0.5 * (dim == 3 ? cbrt(V0) : sqrt(V0));
}

/* Cauchy stress minus q (the force's stress) as a 3x3 */
static inline void ForceStress(PetscInt dim, const PetscReal *sg, PetscReal q, PetscReal s[3][3])
{
  s[0][0] = sg[0] - q;
  s[1][1] = sg[1] - q;
  s[2][2] = sg[2] - q;
  if (dim == 3) {
    s[1][2] = s[2][1] = sg[3];
    s[0][2] = s[2][0] = sg[4];
    s[0][1] = s[1][0] = sg[5];
  } else {
    s[0][1] = s[1][0] = sg[3];
    s[0][2] = s[2][0] = s[1][2] = s[2][1] = 0.0;
  }
}

/* boundary conditions on a node's velocity: physical node index ip[d] */
static inline void NodeBC(const PSSolver *S, const PetscInt ip[3], PetscReal *v)
{
  PetscInt d, e;
  for (d = 0; d < S->dim; d++) {
    PSBCType bc = ip[d] <= 0 ? S->bc[d][0] : ip[d] >= S->scene->cells[d] ? S->bc[d][1] : PS_BC_FREE;
    if (bc == PS_BC_SYMMETRY) v[d] = 0.0;
    else if (bc == PS_BC_FIXED)
      for (e = 0; e < S->dim; e++) v[e] = 0.0;
  }
}

/* L = sum_i v_i (x) grad N_ip at a marker from the ghosted nodal velocities,
   accumulated in registers */
static inline void VelocityGradient(PetscInt dim, const PSIndex *ix, const PetscReal *hv, const PSShape *sh, PetscReal L[3][3])
{
  const PetscInt n3[3] = {sh->n, sh->n, dim == 3 ? sh->n : 1};
  PetscReal      l00 = 0, l01 = 0, l02 = 0, l10 = 0, l11 = 0, l12 = 0, l20 = 0, l21 = 0, l22 = 0;
  PetscInt       a, b, c;

  for (c = 0; c < n3[2]; c++)
    for (b = 0; b < n3[1]; b++) {
      const PetscReal  wyz = sh->w[1][b] * sh->w[2][c], dyz = sh->dw[1][b] * sh->w[2][c], wydz = sh->w[1][b] * sh->dw[2][c];
      const PetscReal *hr  = &hv[dim * Lidx(ix, sh->i0[0], sh->i0[1] + b, sh->i0[2] + c)];
      if (dim == 3)
        for (a = 0; a < n3[0]; a++) {
          const PetscReal  g0 = sh->dw[0][a] * wyz, g1 = sh->w[0][a] * dyz, g2 = sh->w[0][a] * wydz;
          const PetscReal *vn = hr + 3 * a;
          l00 += vn[0] * g0;
          l01 += vn[0] * g1;
          l02 += vn[0] * g2;
          l10 += vn[1] * g0;
          l11 += vn[1] * g1;
          l12 += vn[1] * g2;
          l20 += vn[2] * g0;
          l21 += vn[2] * g1;
          l22 += vn[2] * g2;
        }
      else
        for (a = 0; a < n3[0]; a++) {
          const PetscReal  g0 = sh->dw[0][a] * wyz, g1 = sh->w[0][a] * dyz;
          const PetscReal *vn = hr + 2 * a;
          l00 += vn[0] * g0;
          l01 += vn[0] * g1;
          l10 += vn[1] * g0;
          l11 += vn[1] * g1;
        }
    }
  L[0][0] = l00;
  L[0][1] = l01;
  L[0][2] = l02;
  L[1][0] = l10;
  L[1][1] = l11;
  L[1][2] = l12;
  L[2][0] = l20;
  L[2][1] = l21;
  L[2][2] = l22;
}

/* this rank's local index of the cell holding x (a marker's cell is owned here) */
static inline PetscInt LocalCell(const PSSolver *S, const PetscReal *x)
{
  PetscInt d, k = 0;
  for (d = S->dim - 1; d >= 0; d--) {
    PetscInt c = (PetscInt)PetscFloorReal((x[d] - S->scene->lower[d]) * S->ih[d]);
    c = PetscMin(PetscMax(c, S->cs[d]), S->ce[d] - 1);
    k = k * (S->ce[d] - S->cs[d]) + (c - S->cs[d]);
  }
  return k;
}


/* The nodes this step's transfers can touch, over all ranks: from each
   marker's cell c the nodes c-1 .. c+2 in every direction (every shape
   function), as DMDA indices [lo, hi).  Markers fill a small part of a
   typical domain, so zeroing and the grid loops run on this box only. */
static PetscErrorCode ActiveBox(PSSolver *S, const PSFields *f, PetscInt box[3][2])
{
  const PetscInt dim = S->dim;
  PetscReal      buf[6], gbuf[6];
  PetscInt       p, d;

  PetscFunctionBeginUser;
  for (d = 0; d < 6; d++) buf[d] = -PETSC_MAX_REAL;
  for (p = 0; p < f->n; p++)
    for (d = 0; d < dim; d++) {
      buf[d]     = PetscMax(buf[d], -f->x[p * dim + d]);
      buf[3 + d] = PetscMax(buf[3 + d], f->x[p * dim + d]);
    }
  PetscCallMPI(MPI_Allreduce(buf, gbuf, 6, MPIU_REAL, MPI_MAX, PetscObjectComm((PetscObject)S->sw)));
  for (d = 0; d < 3; d++) {
    if (d >= dim) {
      box[d][0] = 0;
      box[d][1] = 1;
    } else if (-gbuf[d] > gbuf[3 + d]) { /* no markers */
      box[d][0] = box[d][1] = 0;
    } else {
      const PetscInt n  = S->scene->cells[d];
      PetscInt       cl = (PetscInt)PetscFloorReal((-gbuf[d] - S->scene->lower[d]) / S->h[d]);
      PetscInt       ch = (PetscInt)PetscFloorReal((gbuf[3 + d] - S->scene->lower[d]) / S->h[d]);
      cl        = PetscMin(PetscMax(cl, 0), n - 1);
      ch        = PetscMin(PetscMax(ch, 0), n - 1);
      box[d][0] = PetscMax(cl - 1 + S->pad, 0);
      box[d][1] = PetscMin(ch + 3 + S->pad, n + 1 + 2 * S->pad);
    }
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* box clipped to the array's corner s and size m (lo >= hi: empty) */
static inline void Clip(const PetscInt box[3][2], const PetscInt s[3], const PetscInt m[3], PetscInt lo[3], PetscInt hi[3])
{
  PetscInt d;
  for (d = 0; d < 3; d++) {
    lo[d] = PetscMax(box[d][0], s[d]);
    hi[d] = PetscMin(box[d][1], s[d] + m[d]);
  }
}

/* zero the nodes of box in a dof-per-node array with corner s and size m */
static PetscErrorCode ZeroBox(Vec v, PetscInt dof, const PetscInt s[3], const PetscInt m[3], const PetscInt box[3][2])
{
  PetscReal *a;
  PetscInt   lo[3], hi[3], j, k;

  PetscFunctionBeginUser;
  if (!v) PetscFunctionReturn(PETSC_SUCCESS);
  Clip(box, s, m, lo, hi);
  if (hi[0] <= lo[0] || hi[1] <= lo[1] || hi[2] <= lo[2]) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(VecGetArray(v, &a));
  for (k = lo[2]; k < hi[2]; k++)
    for (j = lo[1]; j < hi[1]; j++) PetscCall(PetscArrayzero(&a[dof * (((k - s[2]) * m[1] + (j - s[1])) * m[0] + (lo[0] - s[0]))], dof * (hi[0] - lo[0])));
  PetscCall(VecRestoreArray(v, &a));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Start of a step: zero what the last step wrote in the local grid arrays
   (they are zero elsewhere), then note this step's box.  The step works on
   the local arrays alone (halo.c); the global vectors serve output. */
static PetscErrorCode GridReset(PSSolver *S, const PSIndex *ix, const PetscInt box[3][2])
{
  const PetscInt dim = S->dim, dofg = S->run.transfer == PS_TRANSFER_APIC ? 1 + dim : 1 + 2 * dim;

  PetscFunctionBeginUser;
  if (S->zall) {
    PetscCall(VecZeroEntries(S->Gl));
    if (S->Hl) PetscCall(VecZeroEntries(S->Hl));
  } else {
    PetscCall(ZeroBox(S->Gl, dofg, ix->gs, ix->gm, S->zbox));
    PetscCall(ZeroBox(S->Hl, dim, ix->gs, ix->gm, S->zbox));
  }
  S->zall = PETSC_FALSE;
  PetscCall(PetscArraycpy(&S->zbox[0][0], &box[0][0], 6));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* ---------------------------------------------------------- the step -- */

/* wave speed + |v| over all markers (for the first dt and after restarts) */
PetscErrorCode PSSolverMaxSpeed(PSSolver *S)
{
  PSFields  f;
  PetscInt  p, d, dim = S->dim;
  PetscReal smax = 0.0;

  PetscFunctionBeginUser;
  PetscCall(FieldsGet(S, &f));
  for (p = 0; p < f.n; p++) {
    PetscReal c, v2 = 0.0, J = f.vol[p] / f.V0[p];
    PetscCall(PSMarkerSoundSpeed(&S->mat[f.mat[p]], J, f.e[p], f.p[p], &c));
    for (d = 0; d < dim; d++) v2 += f.v[p * dim + d] * f.v[p * dim + d];
    smax = PetscMax(smax, c + PetscSqrtReal(v2));
  }
  PetscCall(FieldsRestore(S, &f));
  PetscCallMPI(MPI_Allreduce(&smax, &S->smax, 1, MPIU_REAL, MPI_MAX, PetscObjectComm((PetscObject)S->sw)));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* dt = cfl h_min / max(c + |v|), capped in growth, by dt_max and the next stop */
static PetscErrorCode ComputeDt(PSSolver *S, PetscReal t_stop)
{
  PetscReal hmin = PETSC_MAX_REAL, dt;
  PetscInt  d;

  PetscFunctionBeginUser;
  PetscCall(PetscLogEventBegin(EV_Dt, 0, 0, 0, 0));
  for (d = 0; d < S->dim; d++) hmin = PetscMin(hmin, S->h[d]);
  dt = S->run.cfl * hmin / PetscMax(S->smax, 1e-300);
  if (S->dt > 0) dt = PetscMin(dt, S->run.dt_growth * S->dt);
  if (S->run.dt_max > 0) dt = PetscMin(dt, S->run.dt_max);
  if (S->t + dt > t_stop) dt = t_stop - S->t;
  else if (S->t + 1.5 * dt > t_stop) dt = 0.5 * (t_stop - S->t); /* no sliver step before a stop */
  S->dt = dt;
  PetscCall(PetscLogEventEnd(EV_Dt, 0, 0, 0, 0));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* MUSL transfers (solver.h, steps 1-4): leaves the re-projected nodal
   velocity in S->Hl and each marker's shape functions in S->shape */
static PetscErrorCode TransferMUSL(PSSolver *S, PSFields *fp, const PSIndex *ixp, PetscReal dt)
{
  const PetscInt  dim = S->dim, dof = 1 + 2 * dim;
  const PetscReal *lower = S->scene->lower;
  const PSIndex   ix = *ixp;
  PSFields        f  = *fp;
  PSShape         sh;
  PetscReal      *g, *hv;
  PetscInt        p, d, e, a, b, c, n3[3], lo[3], hi[3];

  PetscFunctionBeginUser;
  /* 1. P2G: mass, momentum, internal force -(sigma - q I) grad N V */
  PetscCall(PetscLogEventBegin(EV_P2G, 0, 0, 0, 0));
  PetscCall(VecGetArray(S->Gl, &g));
  for (p = 0; p < f.n; p++) {
    const PetscReal *x = &f.x[p * dim], *v = &f.v[p * dim], m = f.mass[p], V = f.vol[p];
    PetscReal        s[3][3];
    ForceStress(dim, &f.sig[p * PSStressComponents(dim)], f.q[p], s);
    PSShapeEval(S->run.shape, dim, lower, S->h, x, S->run.shape == PS_SHAPE_GIMP ? HalfSize(dim, f.V0[p]) : 0.0, &S->shape[p]);
    sh    = S->shape[p]; /* the step's transfers all use N_ip at x_p^n (MUSL) */
    n3[0] = n3[1] = sh.n;
    n3[2] = dim == 3 ? sh.n : 1;
    {
      /* per marker: m v and the stress rows, then 27 (9) nodes of w, grad w */
      PetscReal mv[3], Vs[3][3];
      for (d = 0; d < dim; d++) {
        mv[d] = m * v[d];
        for (e = 0; e < dim; e++) Vs[d][e] = V * s[d][e];
      }
      for (c = 0; c < n3[2]; c++)
        for (b = 0; b < n3[1]; b++) {
          const PetscReal wyz = sh.w[1][b] * sh.w[2][c], dyz = sh.dw[1][b] * sh.w[2][c], wydz = sh.w[1][b] * sh.dw[2][c];
          PetscReal      *gr  = &g[dof * Lidx(&ix, sh.i0[0], sh.i0[1] + b, sh.i0[2] + c)];
          for (a = 0; a < n3[0]; a++) {
            const PetscReal w     = sh.w[0][a] * wyz;
            const PetscReal gw[3] = {sh.dw[0][a] * wyz, sh.w[0][a] * dyz, sh.w[0][a] * wydz};
            PetscReal      *gn    = gr + dof * a;
            gn[0] += w * m;
            for (d = 0; d < dim; d++) {
              PetscReal fd = 0.0;
              for (e = 0; e < dim; e++) fd += Vs[d][e] * gw[e];
              gn[1 + d] += w * mv[d];
              gn[1 + dim + d] -= fd;
            }
          }
        }
    }
  }
  PetscCall(PetscLogEventEnd(EV_P2G, 0, 0, 0, 0));
  PetscCall(PSHaloReduce(S->sfg, g));

  /* 2. grid: v_old = mv/m, v_new = v_old + dt f/m, boundary conditions;
        the node keeps [m, v_new, v_new - v_old] */
  PetscCall(PetscLogEventBegin(EV_Grid, 0, 0, 0, 0));
  Clip(S->zbox, ix.os, ix.om, lo, hi); /* owned nodes of the active box: no mass elsewhere */
  for (c = lo[2] - ix.os[2]; c < hi[2] - ix.os[2]; c++)
    for (b = lo[1] - ix.os[1]; b < hi[1] - ix.os[1]; b++)
      for (a = lo[0] - ix.os[0]; a < hi[0] - ix.os[0]; a++) {
        const PetscInt ip[3] = {ix.os[0] + a - S->pad, ix.os[1] + b - S->pad, dim == 3 ? ix.os[2] + c - S->pad : 0};
        PetscReal     *gn    = &g[dof * Lidx(&ix, ix.os[0] + a, ix.os[1] + b, ix.os[2] + c)], vo[3] = {0, 0, 0}, vn[3] = {0, 0, 0};
        if (gn[0] > S->mass_min) {
          for (d = 0; d < dim; d++) {
            vo[d] = gn[1 + d] / gn[0];
            vn[d] = vo[d] + dt * gn[1 + dim + d] / gn[0];
          }
          NodeBC(S, ip, vn);
        }
        for (d = 0; d < dim; d++) {
          gn[1 + d]       = vn[d];
          gn[1 + dim + d] = vn[d] - vo[d];
        }
      }
  PetscCall(PetscLogEventEnd(EV_Grid, 0, 0, 0, 0));
  PetscCall(PSHaloBcast(S->sfg, g));

  /* 3. G2P: v_p = (1 - a)(v_p + sum N dv) + a sum N v_new; dx_p = dt sum N v_new;
     4. and in the same pass the re-projection (mv)_i = sum_p N_ip m_p v_p^{n+1} */
  PetscCall(PetscLogEventBegin(EV_G2P, 0, 0, 0, 0));
  PetscCall(VecGetArray(S->Hl, &hv));
  for (p = 0; p < f.n; p++) {
    PetscReal      vpic[3] = {0, 0, 0}, dv[3] = {0, 0, 0}, mv[3];
    const PSShape *sp      = &S->shape[p];
    n3[0] = n3[1] = sp->n;
    n3[2] = dim == 3 ? sp->n : 1;
    {
      /* accumulate in registers: v_pic = sum N v_new, dv = sum N (v_new - v_old) */
      PetscReal a0 = 0, a1 = 0, a2 = 0, b0 = 0, b1 = 0, b2 = 0;
      for (c = 0; c < n3[2]; c++)
        for (b = 0; b < n3[1]; b++) {
          const PetscReal  wyz = sp->w[1][b] * sp->w[2][c];
          const PetscReal *gr  = &g[dof * Lidx(&ix, sp->i0[0], sp->i0[1] + b, sp->i0[2] + c)];
          if (dim == 3)
            for (a = 0; a < n3[0]; a++) {
              const PetscReal  w  = sp->w[0][a] * wyz;
              const PetscReal *gn = gr + 7 * a;
              a0 += w * gn[1];
              a1 += w * gn[2];
              a2 += w * gn[3];
              b0 += w * gn[4];
              b1 += w * gn[5];
              b2 += w * gn[6];
            }
          else
            for (a = 0; a < n3[0]; a++) {
              const PetscReal  w  = sp->w[0][a] * wyz;
              const PetscReal *gn = gr + 5 * a;
              a0 += w * gn[1];
              a1 += w * gn[2];
              b0 += w * gn[3];
              b1 += w * gn[4];
            }
        }
      vpic[0] = a0;
      vpic[1] = a1;
      vpic[2] = a2;
      dv[0]   = b0;
      dv[1]   = b1;
      dv[2]   = b2;
    }
    for (d = 0; d < dim; d++) {
      f.v[p * dim + d]   = (1.0 - S->run.pic_fraction) * (f.v[p * dim + d] + dv[d]) + S->run.pic_fraction * vpic[d];
      S->dx[p * dim + d] = dt * vpic[d];
      mv[d]              = f.mass[p] * f.v[p * dim + d];
    }
    for (c = 0; c < n3[2]; c++)
      for (b = 0; b < n3[1]; b++) {
        const PetscReal wyz = sp->w[1][b] * sp->w[2][c];
        PetscReal      *hr  = &hv[dim * Lidx(&ix, sp->i0[0], sp->i0[1] + b, sp->i0[2] + c)];
        for (a = 0; a < n3[0]; a++) {
          const PetscReal w  = sp->w[0][a] * wyz;
          PetscReal      *hn = hr + dim * a;
          for (d = 0; d < dim; d++) hn[d] += w * mv[d];
        }
      }
  }
  PetscCall(PetscLogEventEnd(EV_G2P, 0, 0, 0, 0));

  PetscCall(PetscLogEventBegin(EV_Reproject, 0, 0, 0, 0));
  PetscCall(PSHaloReduce(S->sfh, hv));
  Clip(S->zbox, ix.os, ix.om, lo, hi); /* owned nodes of the active box: no mass elsewhere */
  for (c = lo[2] - ix.os[2]; c < hi[2] - ix.os[2]; c++)
    for (b = lo[1] - ix.os[1]; b < hi[1] - ix.os[1]; b++)
      for (a = lo[0] - ix.os[0]; a < hi[0] - ix.os[0]; a++) {
        const PetscInt  o     = Lidx(&ix, ix.os[0] + a, ix.os[1] + b, ix.os[2] + c);
        const PetscInt  ip[3] = {ix.os[0] + a - S->pad, ix.os[1] + b - S->pad, dim == 3 ? ix.os[2] + c - S->pad : 0};
        const PetscReal m     = g[dof * o];
        PetscReal       vn[3] = {0, 0, 0};
        if (m > S->mass_min) {
          for (d = 0; d < dim; d++) vn[d] = hv[dim * o + d] / m;
          NodeBC(S, ip, vn);
        }
        for (d = 0; d < dim; d++) hv[dim * o + d] = vn[d];
      }
  PetscCall(PetscLogEventEnd(EV_Reproject, 0, 0, 0, 0));
  PetscCall(PSHaloBcast(S->sfh, hv));
  PetscCall(VecRestoreArray(S->Hl, &hv));
  PetscCall(VecRestoreArray(S->Gl, &g));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* quadratic B-spline weights w and offsets r = x_i - x_p (m) per direction,
   first node i0 (DMDA index); unused directions get w = (1, 0, 0), r = 0 */
typedef struct {
  PetscInt  i0[3];
  PetscReal w[3][3], r[3][3];
} PSBspline;

static inline void BsplineEval(PetscInt dim, const PetscReal lower[], const PetscReal h[], const PetscReal ih[], const PetscReal x[], PSBspline *B)
{
  PetscInt d, a;
  for (d = 0; d < 3; d++) {
    if (d < dim) {
      const PetscReal xi = (x[d] - lower[d]) * ih[d], b = PetscFloorReal(xi - 0.5), fx = xi - b;
      B->i0[d]   = (PetscInt)b + PS_PAD;
      B->w[d][0] = 0.5 * (1.5 - fx) * (1.5 - fx);
      B->w[d][1] = 0.75 - (fx - 1.0) * (fx - 1.0);
      B->w[d][2] = 0.5 * (fx - 0.5) * (fx - 0.5);
      for (a = 0; a < 3; a++) B->r[d][a] = (a - fx) * h[d];
    } else {
      B->i0[d]   = 0;
      B->w[d][0] = 1.0;
      B->w[d][1] = B->w[d][2] = 0.0;
      for (a = 0; a < 3; a++) B->r[d][a] = 0.0;
    }
  }
}

/* 3D APIC nodes hold 4 reals (m, m v): one 4-wide vector (PSv4, solver.h) */
static inline PSv4 Load4(const PetscReal *p)
{
  PSv4 v;
  memcpy(&v, p, sizeof(v));
  return v;
}
static inline void Store4(PetscReal *p, PSv4 v)
{
  memcpy(p, &v, sizeof(v));
}

/* APIC P2G in the MLS-MPM form (solver.h): per marker the affine matrix
   Q = m_p C_p - dt V_p (sigma_p - q_p I) D_p^-1, D_p^-1 = diag(4/h^2), then per
   node (m, m v + Q (x_i - x_p)) weighted by N_ip.  dim is a constant at each
   call (always inlined: a 2D and a 3D kernel). */
static inline __attribute__((always_inline)) void P2GAPIC(const PSSolver *S, const PSFields *f, const PSIndex *ix, PetscReal dt, const PetscInt dim, PetscReal *g)
{
  /* row and plane strides of the local array, read once (the extension is
     built with -fno-strict-aliasing: an index read per row is re-read after
     every store into g) */
  const PetscInt dof = 1 + dim, nz = dim == 3 ? 3 : 1, ns = PSStressComponents(dim), sy = dof * ix->gm[0], sz = sy * ix->gm[1];
  const PetscReal *Dinv = S->Dinv, *ih = S->ih;
  PetscInt        p, d, e, a, b, c;

  for (p = 0; p < f->n; p++) {
    const PetscReal m = f->mass[p], V = f->vol[p], *Cp = &f->C[p * dim * dim];
    PetscReal       s[3][3], Q[3][3], mv[3], *g0;
    PSBspline       B;
    BsplineEval(dim, S->scene->lower, S->h, ih, &f->x[p * dim], &B);
    ForceStress(dim, &f->sig[p * ns], f->q[p], s);
    for (d = 0; d < dim; d++) {
      mv[d] = m * f->v[p * dim + d];
      for (e = 0; e < dim; e++) Q[d][e] = m * Cp[d * dim + e] - dt * V * s[d][e] * Dinv[e];
    }
    /* per row of 3 nodes along x: T = (m, m v + Q_.1 r_y + Q_.2 r_z), node a
       adds w_a (T + r_x,a Qx) with Qx = (0, Q_.0): dof-wide multiply-adds */
    g0 = &g[dof * Lidx(ix, B.i0[0], B.i0[1], B.i0[2])]; /* first node; rows sy, planes sz apart */
    if (dim == 3) {
      /* the same, 4-wide */
      const PSv4 Qx = {0.0, Q[0][0], Q[1][0], Q[2][0]}, Qy = {0.0, Q[0][1], Q[1][1], Q[2][1]}, Qz = {0.0, Q[0][2], Q[1][2], Q[2][2]};
      const PSv4 T0 = {m, mv[0], mv[1], mv[2]};
      for (c = 0; c < 3; c++) {
        const PSv4 Tz = T0 + B.r[2][c] * Qz;
        for (b = 0; b < 3; b++) {
          const PetscReal wyz = B.w[1][b] * B.w[2][c];
          const PSv4      T   = Tz + B.r[1][b] * Qy;
          PetscReal      *gr  = g0 + c * sz + b * sy;
          for (a = 0; a < 3; a++) Store4(gr + 4 * a, Load4(gr + 4 * a) + (B.w[0][a] * wyz) * (T + B.r[0][a] * Qx));
        }
      }
      continue;
    }
    for (c = 0; c < nz; c++)
      for (b = 0; b < 3; b++) {
        const PetscReal wyz = B.w[1][b] * B.w[2][c];
        PetscReal       T[4], Qx[4], *gr = g0 + c * sz + b * sy;
        T[0]  = m;
        Qx[0] = 0.0;
        for (d = 0; d < dim; d++) {
          T[1 + d]  = mv[d] + Q[d][1] * B.r[1][b] + (dim == 3 ? Q[d][2] * B.r[2][c] : 0.0);
          Qx[1 + d] = Q[d][0];
        }
        for (a = 0; a < 3; a++) {
          const PetscReal w = B.w[0][a] * wyz, ra = B.r[0][a];
          PetscReal      *gn = gr + dof * a;
          for (e = 0; e < dof; e++) gn[e] += w * (T[e] + ra * Qx[e]);
        }
      }
  }
}

/* APIC G2P: v_p = sum N v_i, C_p = sum N v_i (x_i - x_p)^T D^-1 (sums over a
   row of nodes first: per node 2 dim multiply-adds), displacement dt v_p */
static inline __attribute__((always_inline)) void G2PAPIC(PSSolver *S, PSFields *f, const PSIndex *ix, PetscReal dt, const PetscInt dim, const PetscReal *g)
{
  const PetscInt   dof = 1 + dim, nz = dim == 3 ? 3 : 1, sy = dof * ix->gm[0], sz = sy * ix->gm[1];
  const PetscReal *Dinv = S->Dinv, *ih = S->ih, *gb;
  PetscInt         p, d, e, a, b, c;

  for (p = 0; p < f->n; p++) {
    PetscReal v[4] = {0, 0, 0, 0}, Bm[3][4] = {{0}}; /* lane 1 + d: velocity component d; Bm[e][1 + d] = sum N v_d r_e */
    PSBspline B;
    BsplineEval(dim, S->scene->lower, S->h, ih, &f->x[p * dim], &B);
    gb = &g[dof * Lidx(ix, B.i0[0], B.i0[1], B.i0[2])]; /* first node; rows sy, planes sz apart */
    if (dim == 3) {
      /* the same, 4-wide */
      PSv4 vv = {0, 0, 0, 0}, B0 = {0, 0, 0, 0}, B1 = {0, 0, 0, 0}, B2 = {0, 0, 0, 0};
      for (c = 0; c < 3; c++)
        for (b = 0; b < 3; b++) {
          const PetscReal  wyz = B.w[1][b] * B.w[2][c];
          const PetscReal *gr  = gb + c * sz + b * sy;
          const PSv4       g0 = Load4(gr), g1 = Load4(gr + 4), g2 = Load4(gr + 8);
          const PSv4       sw = B.w[0][0] * g0 + B.w[0][1] * g1 + B.w[0][2] * g2;
          const PSv4       sx = (B.w[0][0] * B.r[0][0]) * g0 + (B.w[0][1] * B.r[0][1]) * g1 + (B.w[0][2] * B.r[0][2]) * g2;
          vv += wyz * sw;
          B0 += wyz * sx;
          B1 += (wyz * B.r[1][b]) * sw;
          B2 += (wyz * B.r[2][c]) * sw;
        }
      for (d = 0; d < 4; d++) {
        v[d]     = vv[d];
        Bm[0][d] = B0[d];
        Bm[1][d] = B1[d];
        Bm[2][d] = B2[d];
      }
    } else
    for (c = 0; c < nz; c++)
      for (b = 0; b < 3; b++) {
        /* a row of 3 nodes: sw = sum_a w_a g_a, sx = sum_a w_a r_x,a g_a (dof wide, lane 0 the mass) */
        const PetscReal  wyz = B.w[1][b] * B.w[2][c], ry = B.r[1][b], rz = B.r[2][c];
        const PetscReal *gr  = gb + c * sz + b * sy;
        PetscReal        sw[4] = {0, 0, 0, 0}, sx[4] = {0, 0, 0, 0};
        for (a = 0; a < 3; a++) {
          const PetscReal  w = B.w[0][a] * wyz, wr = w * B.r[0][a];
          const PetscReal *gn = gr + dof * a;
          for (e = 0; e < dof; e++) {
            sw[e] += w * gn[e];
            sx[e] += wr * gn[e];
          }
        }
        for (e = 0; e < dof; e++) {
          v[e] += sw[e];
          Bm[0][e] += sx[e];
          Bm[1][e] += ry * sw[e];
          Bm[2][e] += rz * sw[e];
        }
      }
    for (d = 0; d < dim; d++) {
      f->v[p * dim + d]  = v[1 + d];
      S->dx[p * dim + d] = dt * v[1 + d];
      for (e = 0; e < dim; e++) f->C[p * dim * dim + d * dim + e] = Bm[e][1 + d] * Dinv[e];
    }
  }
}

/* APIC transfers (solver.h): leaves each marker's v_p, C_p and displacement */
static PetscErrorCode TransferAPIC(PSSolver *S, PSFields *f, const PSIndex *ix, PetscReal dt)
{
  const PetscInt dim = S->dim, dof = 1 + dim;
  PetscReal     *g;
  PetscInt       a, b, c, d, lo[3], hi[3];

  PetscFunctionBeginUser;
  /* 1. P2G: mass and momentum with the affine and force terms */
  PetscCall(PetscLogEventBegin(EV_P2G, 0, 0, 0, 0));
  PetscCall(VecGetArray(S->Gl, &g));
  if (dim == 3) P2GAPIC(S, f, ix, dt, 3, g);
  else P2GAPIC(S, f, ix, dt, 2, g);
  PetscCall(PetscLogEventEnd(EV_P2G, 0, 0, 0, 0));
  PetscCall(PSHaloReduce(S->sfg, g));

  /* 2. grid: v_i = (mv)_i / m_i with the boundary conditions */
  PetscCall(PetscLogEventBegin(EV_Grid, 0, 0, 0, 0));
  Clip(S->zbox, ix->os, ix->om, lo, hi); /* owned nodes of the active box: no mass elsewhere */
  for (c = lo[2] - ix->os[2]; c < hi[2] - ix->os[2]; c++)
    for (b = lo[1] - ix->os[1]; b < hi[1] - ix->os[1]; b++)
      for (a = lo[0] - ix->os[0]; a < hi[0] - ix->os[0]; a++) {
        const PetscInt ip[3] = {ix->os[0] + a - S->pad, ix->os[1] + b - S->pad, dim == 3 ? ix->os[2] + c - S->pad : 0};
        PetscReal     *gn    = &g[dof * Lidx(ix, ix->os[0] + a, ix->os[1] + b, ix->os[2] + c)], vn[3] = {0, 0, 0};
        if (gn[0] > S->mass_min) {
          for (d = 0; d < dim; d++) vn[d] = gn[1 + d] / gn[0];
          NodeBC(S, ip, vn);
        }
        for (d = 0; d < dim; d++) gn[1 + d] = vn[d];
      }
  PetscCall(PetscLogEventEnd(EV_Grid, 0, 0, 0, 0));
  PetscCall(PSHaloBcast(S->sfg, g));

  /* 3. G2P: velocity, affine velocity, displacement */
  PetscCall(PetscLogEventBegin(EV_G2P, 0, 0, 0, 0));
  if (dim == 3) G2PAPIC(S, f, ix, dt, 3, g);
  else G2PAPIC(S, f, ix, dt, 2, g);
  PetscCall(VecRestoreArray(S->Gl, &g));
  PetscCall(PetscLogEventEnd(EV_G2P, 0, 0, 0, 0));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* L_p: the MUSL gradient of the re-projected velocity, or APIC's C_p */
static inline void MarkerL(const PSSolver *S, const PSFields *f, const PSIndex *ix, const PetscReal *hv, PetscInt p, PetscReal L[3][3])
{
  const PetscInt dim = S->dim;
  PetscInt       d, e;
  if (f->C) {
    for (d = 0; d < 3; d++)
      for (e = 0; e < 3; e++) L[d][e] = (d < dim && e < dim) ? f->C[p * dim * dim + d * dim + e] : 0.0;
  } else VelocityGradient(dim, ix, hv, &S->shape[p], L);
}

/* pointers to marker p's state for the constitutive kernels */
static inline void MarkerState(const PSSolver *S, const PSFields *f, PetscInt p, PSMarkerState *st)
{
  const PetscInt dim = S->dim, ns = PSStressComponents(dim);
  memset(st, 0, sizeof(*st));
  st->F     = &f->F[p * dim * dim];
  st->V0    = f->V0[p];
  st->vol   = &f->vol[p];
  st->sdev  = &f->sdev[p * ns];
  st->sig   = &f->sig[p * ns];
  st->p     = &f->p[p];
  st->q     = &f->q[p];
  st->e     = &f->e[p];
  st->eps_p = f->eps_p ? &f->eps_p[p] : NULL;
  st->T     = f->T ? &f->T[p] : NULL;
  st->D     = f->D ? &f->D[p * S->scene->ndamage] : NULL;
  if (f->axes) {
    /* a ply's axes at t = 0 from its body and ply (identity outside laminates) */
    static const PetscReal I9[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    const PetscInt         k     = f->ply ? f->ply[p] : -1;
    st->axes0 = k >= 0 ? &S->scene->bodies[f->body[p]].ply_axes[9 * k] : I9;
    st->axes  = &f->axes[9 * p];
    st->smat  = &f->smat[6 * p];
  }
}

PetscErrorCode PSSolverStep(PSSolver *S, PetscReal t_stop)
{
  const PetscInt  dim = S->dim;
  PSIndex         ix;
  PSFields        f;
  const PetscReal *hv = NULL;
  PetscReal       smax = 0.0, dt, hm = 0.0;
  PetscInt        p, d;
  MPI_Comm        comm = PetscObjectComm((PetscObject)S->sw);

  PetscFunctionBeginUser;
  PetscCall(ComputeDt(S, t_stop));
  dt = S->dt;
  PetscCall(GetIndex(S->da, &ix));
  PetscCall(FieldsGet(S, &f));
  if (f.n > S->ncache) {
    PetscCall(PetscFree(S->dx));
    PetscCall(PetscFree(S->shape));
    PetscCall(PetscFree(S->Lp));
    S->ncache = (PetscInt)(1.2 * f.n) + 16;
    PetscCall(PetscMalloc1(S->ncache * dim, &S->dx));
    if (S->run.transfer == PS_TRANSFER_MUSL) PetscCall(PetscMalloc1(S->ncache, &S->shape));
    if (S->run.fbar) PetscCall(PetscMalloc1(9 * S->ncache, &S->Lp));
  }

  {
    PetscInt box[3][2];
    PetscCall(ActiveBox(S, &f, box));
    PetscCall(GridReset(S, &ix, box));
  }
  if (S->run.transfer == PS_TRANSFER_APIC) PetscCall(TransferAPIC(S, &f, &ix, dt));
  else PetscCall(TransferMUSL(S, &f, &ix, dt));

  /* 5. velocity gradient, stress update; then move the markers */
  PetscCall(PetscLogEventBegin(EV_Stress, 0, 0, 0, 0));
  if (S->Hl) PetscCall(VecGetArrayRead(S->Hl, &hv));
  if (S->run.fbar) {
    /* Delta-F-bar (Coombs, Augarde et al. 2018; Uintah's pressure
       stabilisation): each marker's volumetric rate is replaced by its cell's
       volume-weighted mean, which removes the volumetric locking of
       near-incompressible (plastic) flow.  A marker's cell at x^n is owned by
       this rank (migration), so the means need no communication. */
    PetscCall(PetscArrayzero(S->cell_V, S->ncell));
    PetscCall(PetscArrayzero(S->cell_trL, S->ncell));
    for (p = 0; p < f.n; p++) {
      PetscReal     *Lp = &S->Lp[9 * p];
      const PetscInt c  = LocalCell(S, &f.x[p * dim]);
      MarkerL(S, &f, &ix, hv, p, (PetscReal(*)[3])Lp);
      S->cell_V[c] += f.vol[p];
      S->cell_trL[c] += f.vol[p] * (Lp[0] + Lp[4] + Lp[8]);
    }
    for (p = 0; p < f.n; p++) {
      PetscReal     *Lp = &S->Lp[9 * p];
      const PetscInt c  = LocalCell(S, &f.x[p * dim]);
      const PetscReal shift = (S->cell_trL[c] / S->cell_V[c] - (Lp[0] + Lp[4] + Lp[8])) / dim;
      for (d = 0; d < dim; d++) Lp[4 * d] += shift;
    }
  }
  for (d = 0; d < dim; d++) hm = PetscMax(hm, S->h[d]);
  for (p = 0; p < f.n;) {
    const PSMaterial *M = &S->mat[f.mat[p]];
    PetscReal         L[4][3][3], J[4], cs[4];
    PSMarkerState     st[4];
    PetscInt          k, nb = 1;

    /* four 3D markers of one material in a row go through the 4-lane kernel */
    if (dim == 3 && S->run.lanes == 4 && M->update4_fn && p + 4 <= f.n && f.mat[p + 1] == f.mat[p] && f.mat[p + 2] == f.mat[p] && f.mat[p + 3] == f.mat[p]) nb = 4;
    for (k = 0; k < nb; k++) {
      if (S->run.fbar) PetscCall(PetscArraycpy(&L[k][0][0], &S->Lp[9 * (p + k)], 9));
      else {
        PetscCall(PetscArrayzero(&L[k][0][0], 9));
        MarkerL(S, &f, &ix, hv, p + k, L[k]);
      }
      MarkerState(S, &f, p + k, &st[k]);
    }
    if (nb == 4) PetscCall(M->update4_fn(M, (const PetscReal(*)[3][3])L, dt, hm, S->run.c_linear, S->run.c_quadratic, st, J, cs));
    else PetscCall(M->update_fn(M, dim, L[0], dt, hm, S->run.c_linear, S->run.c_quadratic, &st[0], &J[0], &cs[0]));
    for (k = 0; k < nb; k++, p++) {
      PetscReal v2 = 0.0;
      if (PetscUnlikely(J[k] <= 0.0)) PetscCall(PSMarkerCheckJ(J[k], f.id[p], f.mat[p], S->step + 1, S->t));
      for (d = 0; d < dim; d++) {
        f.x[p * dim + d] += S->dx[p * dim + d];
        v2 += f.v[p * dim + d] * f.v[p * dim + d];
      }
      /* the viscous term tightens the CFL limit in compression (q / (rho c)) */
      smax = PetscMax(smax, cs[k] + PetscSqrtReal(v2) + (f.q[p] > 0.0 ? f.q[p] * f.vol[p] / (f.mass[p] * PetscMax(cs[k], 1e-300)) : 0.0));
    }
  }
  if (S->Hl) PetscCall(VecRestoreArrayRead(S->Hl, &hv));
  PetscCall(PetscLogEventEnd(EV_Stress, 0, 0, 0, 0));
  PetscCall(FieldsRestore(S, &f));
  PetscCallMPI(MPI_Allreduce(&smax, &S->smax, 1, MPIU_REAL, MPI_MAX, comm));

  /* 6. markers out of the domain are booked and removed; the rest migrate */
  PetscCall(PSSolverMigrate(S));
  S->t += dt;
  S->step++;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Remove markers outside the domain (booking mass, momentum, energy), then send
   every marker to the rank that owns its cell. */
PetscErrorCode PSSolverMigrate(PSSolver *S)
{
  const PetscInt dim = S->dim;
  PSFields       f;
  PetscInt       p, d, *rank, nmove = 0, gmove;
  PetscMPIInt    me;
  PetscInt       nrm = 0, *rm = NULL;

  PetscFunctionBeginUser;
  PetscCall(PetscLogEventBegin(EV_Migrate, 0, 0, 0, 0));
  PetscCall(FieldsGet(S, &f));
  PetscCall(PetscMalloc1(PetscMax(1, f.n), &rm));
  for (p = 0; p < f.n; p++) {
    PetscBool out = PETSC_FALSE;
    for (d = 0; d < dim; d++)
      if (!(f.x[p * dim + d] >= S->scene->lower[d] && f.x[p * dim + d] < S->scene->upper[d])) out = PETSC_TRUE; /* NaN too */
    if (!out) continue;
    {
      PetscReal v2 = 0.0;
      for (d = 0; d < dim; d++) {
        S->lost_local.p[d] += f.mass[p] * f.v[p * dim + d];
        v2 += f.v[p * dim + d] * f.v[p * dim + d];
      }
      S->lost_local.mass += f.mass[p];
      S->lost_local.kinetic += 0.5 * f.mass[p] * v2;
      S->lost_local.internal += f.mass[p] * f.e[p];
      S->lost_local.markers++;
    }
    rm[nrm++] = p;
  }
  PetscCall(FieldsRestore(S, &f));
  /* from the back: DMSwarm moves the last marker into the hole */
  for (p = nrm - 1; p >= 0; p--) PetscCall(DMSwarmRemovePointAtIndex(S->sw, rm[p]));
  PetscCall(PetscFree(rm));

  if (S->nproc[0] * S->nproc[1] * S->nproc[2] == 1) { /* one rank: nowhere to send a marker */
    PetscCall(PetscLogEventEnd(EV_Migrate, 0, 0, 0, 0));
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  PetscCallMPI(MPI_Comm_rank(PetscObjectComm((PetscObject)S->sw), &me));
  PetscCall(DMSwarmGetLocalSize(S->sw, &f.n));
  PetscCall(DMSwarmGetField(S->sw, PS_FIELD_X, NULL, NULL, (void **)&f.x));
  PetscCall(DMSwarmGetField(S->sw, DMSwarmField_rank, NULL, NULL, (void **)&rank));
  for (p = 0; p < f.n; p++) {
    PetscInt r[3] = {0, 0, 0};
    for (d = 0; d < dim; d++) {
      PetscInt cell = (PetscInt)floor((f.x[p * dim + d] - S->scene->lower[d]) * S->ih[d]), node, k = 0;
      cell = PetscMin(PetscMax(cell, 0), S->scene->cells[d] - 1);
      node = cell + S->pad;
      while (k + 1 < S->nproc[d] && node >= S->lx[d][k + 1]) k++;
      r[d] = k;
    }
    rank[p] = r[0] + S->nproc[0] * (r[1] + S->nproc[1] * r[2]);
    if (rank[p] != me) nmove++;
  }
  PetscCall(DMSwarmRestoreField(S->sw, DMSwarmField_rank, NULL, NULL, (void **)&rank));
  PetscCall(DMSwarmRestoreField(S->sw, PS_FIELD_X, NULL, NULL, (void **)&f.x));
  /* most steps move no marker across a rank boundary (a marker moves less
     than a cell per step): then the swarm's exchange, with its collective
     set-up, is skipped */
  PetscCallMPI(MPI_Allreduce(&nmove, &gmove, 1, MPIU_INT, MPI_SUM, PetscObjectComm((PetscObject)S->sw)));
  if (gmove > 0) PetscCall(DMSwarmMigrate(S->sw, PETSC_TRUE));
  PetscCall(PetscLogEventEnd(EV_Migrate, 0, 0, 0, 0));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Global totals now, with the booked losses. */
PetscErrorCode PSSolverTotals(PSSolver *S, PSTotals *T)
{
  const PetscInt dim = S->dim;
  PSFields       f;
  PetscInt       p, d;
  PetscReal      loc[12] = {0}, glob[12], pmax = -PETSC_MAX_REAL, lost[8], glost[8];
  PetscInt64     nl[2], ng[2];
  MPI_Comm       comm = PetscObjectComm((PetscObject)S->sw);

  PetscFunctionBeginUser;
  PetscCall(FieldsGet(S, &f));
  for (p = 0; p < f.n; p++) {
    PetscReal v2 = 0.0;
    loc[0] += f.mass[p];
    for (d = 0; d < dim; d++) {
      loc[1 + d] += f.mass[p] * f.v[p * dim + d];
      v2 += f.v[p * dim + d] * f.v[p * dim + d];
    }
    loc[4] += 0.5 * f.mass[p] * v2;
    loc[5] += f.mass[p] * f.e[p];
    pmax = PetscMax(pmax, f.p[p]);
  }
  PetscCall(FieldsRestore(S, &f));
  PetscCallMPI(MPI_Allreduce(loc, glob, 6, MPIU_REAL, MPI_SUM, comm));
  PetscCallMPI(MPI_Allreduce(&pmax, &T->max_pressure, 1, MPIU_REAL, MPI_MAX, comm));
  lost[0] = S->lost_local.mass;
  lost[1] = S->lost_local.p[0];
  lost[2] = S->lost_local.p[1];
  lost[3] = S->lost_local.p[2];
  lost[4] = S->lost_local.kinetic + S->lost_local.internal;
  PetscCallMPI(MPI_Allreduce(lost, glost, 5, MPIU_REAL, MPI_SUM, comm));
  nl[0] = f.n;
  nl[1] = S->lost_local.markers;
  PetscCallMPI(MPI_Allreduce(nl, ng, 2, MPIU_INT64, MPI_SUM, comm));
  T->mass     = glob[0];
  T->p[0]     = glob[1];
  T->p[1]     = glob[2];
  T->p[2]     = glob[3];
  T->kinetic  = glob[4];
  T->internal = glob[5];
  T->lost_mass = glost[0];
  T->lost_p[0] = glost[1];
  T->lost_p[1] = glost[2];
  T->lost_p[2] = glost[3];
  T->lost_energy = glost[4];
  T->markers      = ng[0];
  T->lost_markers = ng[1];
  PetscFunctionReturn(PETSC_SUCCESS);
}
