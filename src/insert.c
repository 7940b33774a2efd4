/*
  insert.c - insertion of bodies and plies as markers, exact or by lattice.

  For every cell a rank owns, every body whose bounding box meets the cell,
  every sub-cell (subdivision^dim per cell) and every ply crossing it:

      piece = sub-cell ∩ ply slab ∩ laminate's lateral faces \ higher-priority bodies

  is computed exactly (geom.c), and one marker is made per non-empty piece at
  the piece's centroid, with m_p = rho V_p (Schumacher et al., the method's
  exact insertion).  Axisymmetric 2D (x = r, y = z): the piece is a section
  of a ring, whose volume is, by Pappus' second theorem, its area times the
  path of its area centroid, V_p = 2 pi r_c A = 2 pi int r dA (the piece's
  first moment about the axis: exact to round-off, slivers merged alike); the
  marker sits at the area centroid (r_c, z_c), the standard choice for a
  marker in r-z (Sulsky & Schreyer 1996; NairnMPM), and m_p = rho V_p is the
  full revolution's mass.  Sub-cells are inside the grid, so pieces are inside the
  domain by construction.

  Slivers: a piece smaller than sliver_fraction of its sub-cell is merged into
  the largest ordinary piece of the same body and ply in the same cell; mass
  and first moment are summed, so both stay exact, and the centroid stays in
  the (convex) cell ∩ ply.  With no such neighbour the sliver is kept.

  Lattice fill (insertion: lattice; as Uintah, Karamelo and NairnMPM fill a
  body): each cell is split into n^dim lattice sub-cells (n =
  points_per_cell) and the centre of each is a marker when it lies inside the
  body and in no higher-priority body (geom.c, PSBodyLocatePoint: faces
  half-open, so touching bodies and neighbouring plies never share a point);
  its ply is the one containing the point, its volume the sub-cell's and its
  mass rho times that.  It is what the exact insertion is measured against
  (plyshock verify): its ply masses and centroids are right only on average.

  Marker ids: id = ((S * nbody + body) * (maxply + 1) + ply + 1), S the linear
  index of the sub-cell (lattice point) in the body's refined grid; the same
  on any rank count.
*/
#include <math.h>
#include <string.h>
#include "geom.h"

static PetscLogEvent PS_EVENT_Insert, PS_EVENT_Fill;
static PetscBool     PSPackageInitialized = PETSC_FALSE;

PetscErrorCode PSInitializePackage(void)
{
  PetscClassId cid;

  PetscFunctionBeginUser;
  if (PSPackageInitialized) PetscFunctionReturn(PETSC_SUCCESS);
  PSPackageInitialized = PETSC_TRUE;
  PetscCall(PetscClassIdRegister("plyshock", &cid));
  PetscCall(PetscLogEventRegister("PSInsertPieces", cid, &PS_EVENT_Insert));
  PetscCall(PetscLogEventRegister("PSInsertFill", cid, &PS_EVENT_Fill));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* One piece, before sliver merging. */
typedef struct {
  PetscInt q;     /* sub-cell within the cell */
  PetscInt ply;   /* -1 outside laminates */
  double   m[4];  /* volume, first moments */
} PSPiece;

/* A growable list of markers (struct of arrays); NULL in count-only mode. */
typedef struct {
  PetscInt    n, cap, dim;
  PetscBool   axi;  /* axisymmetric: volumes of the full revolution (Pappus) */
  PetscReal  *x, *vol, *mass;
  PetscInt64 *id;
  PetscInt   *body, *ply, *mat;
} PSMarkerList;

static PetscErrorCode ListPush(PSMarkerList *L, const double m[4], PetscReal rho, PetscInt64 id, PetscInt b, PetscInt ply, PetscInt mat)
{
  PetscInt d;

  PetscFunctionBeginUser;
  if (L->n == L->cap) {
    PetscInt cap = PetscMax(1024, 2 * L->cap);
    PetscCall(PetscRealloc(sizeof(PetscReal) * 3 * cap, &L->x));
    PetscCall(PetscRealloc(sizeof(PetscReal) * cap, &L->vol));
    PetscCall(PetscRealloc(sizeof(PetscReal) * cap, &L->mass));
    PetscCall(PetscRealloc(sizeof(PetscInt64) * cap, &L->id));
    PetscCall(PetscRealloc(sizeof(PetscInt) * cap, &L->body));
    PetscCall(PetscRealloc(sizeof(PetscInt) * cap, &L->ply));
    PetscCall(PetscRealloc(sizeof(PetscInt) * cap, &L->mat));
    L->cap = cap;
  }
  /* x_p = first moment / volume (area in 2D); m_p = rho V_p; axisymmetric:
     V_p = 2 pi int r dA = 2 pi m[1] (Pappus), x_p the area centroid */
  for (d = 0; d < 3; d++) L->x[3 * L->n + d] = d < L->dim ? m[1 + d] / m[0] : 0.0;
  L->vol[L->n]  = L->axi ? 2.0 * PETSC_PI * m[1] : m[0];
  L->mass[L->n] = rho * L->vol[L->n];
  L->id[L->n]   = id;
  L->body[L->n] = b;
  L->ply[L->n]  = ply;
  L->mat[L->n]  = mat;
  L->n++;
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode ListDestroy(PSMarkerList *L)
{
  PetscFunctionBeginUser;
  PetscCall(PetscFree(L->x));
  PetscCall(PetscFree(L->vol));
  PetscCall(PetscFree(L->mass));
  PetscCall(PetscFree(L->id));
  PetscCall(PetscFree(L->body));
  PetscCall(PetscFree(L->ply));
  PetscCall(PetscFree(L->mat));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Narrow the cells [i0, i1) of row (j, k) to those a flat hull can touch: each
   face n.x <= d bounds x on the row, since the cell centre's n.x is linear in
   i.  Conservative by one cell; the exact test per cell follows. */
static void RowRange(const PSScene *scene, const PSRegion *hull, PetscInt j, PetscInt k, const double h[3], PetscInt *i0, PetscInt *i1)
{
  const PetscInt dim = scene->dim;
  int            f;
  for (f = 0; f < hull->nflat; f++) {
    const double *n = hull->flat[f].n;
    double        rest = hull->flat[f].d, ext = 0.0, x;
    int           d;
    for (d = 0; d < dim; d++) ext += 0.5 * fabs(n[d]) * h[d];
    rest += ext - n[1] * (scene->lower[1] + (j + 0.5) * h[1]) - (dim == 3 ? n[2] * (scene->lower[2] + (k + 0.5) * h[2]) : 0.0);
    /* cells whose centre x satisfies n_x x <= rest can meet the half-space */
    if (n[0] == 0.0) {
      if (rest < 0.0) *i1 = *i0;
      continue;
    }
    x = (rest / n[0] - scene->lower[0]) / h[0] - 0.5;
    if (n[0] > 0.0) *i1 = PetscMin(*i1, (PetscInt)PetscMax(-1.0, PetscMin(floor(x) + 2.0, 1e9)));
    else *i0 = PetscMax(*i0, (PetscInt)PetscMin(1e9, PetscMax(ceil(x) - 1.0, -1.0)));
  }
  if (*i1 < *i0) *i1 = *i0;
}

/* A marker at a point (the lattice fill): its position exactly x; vol the
   lattice sub-cell's (area in 2D; axisymmetric: its ring, 2 pi x_r area) */
static PetscErrorCode ListPushPoint(PSMarkerList *L, const double x[3], double vol, PetscReal rho, PetscInt64 id, PetscInt b, PetscInt ply, PetscInt mat)
{
  const double m[4] = {vol, L->axi ? vol * x[0] : 0.0, 0.0, 0.0};
  PetscInt     d;

  PetscFunctionBeginUser;
  PetscCall(ListPush(L, m, rho, id, b, ply, mat));
  for (d = 0; d < L->dim; d++) L->x[3 * (L->n - 1) + d] = x[d];
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Global id of the marker of (sub-cell qi of cell idx refined s times, body b, ply). */
static inline PetscInt64 MarkerId(const PSScene *scene, const PetscInt idx[3], PetscInt s, const PetscInt qi[3], PetscInt b, PetscInt maxply, PetscInt ply)
{
  const PetscInt64 nx = (PetscInt64)scene->cells[0] * s, ny = (PetscInt64)scene->cells[1] * s;
  const PetscInt64 S  = (PetscInt64)(idx[0] * s + qi[0]) + nx * ((PetscInt64)(idx[1] * s + qi[1]) + (scene->dim == 3 ? ny * (PetscInt64)(idx[2] * s + qi[2]) : 0));
  return (S * scene->nbody + b) * (maxply + 1) + ply + 1;
}

/* Work space of one body's insertion. */
typedef struct {
  const PSBody *B;
  PetscInt      b, maxply, nreg, nsub;
  PSRegion     *reg;              /* the plies, or the body */
  PSRegion      sub[PS_MAX_SUB];  /* higher-priority bodies that may overlap it */
  PSPiece      *pc;               /* the pieces of one cell (exact) */
} PSBodyWork;

/* Exact insertion of one cell: every (sub-cell, ply) piece, slivers merged. */
static PetscErrorCode ExactCell(const PSScene *scene, PSBodyWork *w, const PetscInt idx[3], PSMarkerList *L, PetscInt64 *count_bp, PSInsertStats *st)
{
  const PSBody  *B   = w->B;
  const PetscInt dim = scene->dim, s = B->subdivision, nsc = dim == 3 ? s * s * s : s * s;
  PSPiece       *pc  = w->pc;
  PetscInt       npc = 0, q, p, pp, d;
  double         vsub = 1.0;

  PetscFunctionBeginUser;
  for (q = 0; q < nsc; q++) {
    PetscInt qi[3] = {q % s, (q / s) % s, q / (s * s)}, k0 = 0, k1 = w->nreg;
    double   lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
    PSSubCellBounds(scene, idx, s, qi, lo, hi);
    vsub = 1.0;
    for (d = 0; d < dim; d++) vsub *= hi[d] - lo[d];
    if (B->kind == PS_BODY_LAMINATE) {
      /* plies that can cross the sub-cell: its extent along axis 3 */
      const double *e3 = B->e[2];
      double        zc = 0.0, ze = 0.0;
      for (d = 0; d < dim; d++) {
        zc += e3[d] * (0.5 * (lo[d] + hi[d]) - B->origin[d]);
        ze += fabs(e3[d]) * 0.5 * (hi[d] - lo[d]);
      }
      while (k0 < w->nreg && B->z[k0 + 1] <= zc - ze) k0++;
      k1 = k0;
      while (k1 < w->nreg && B->z[k1] < zc + ze) k1++;
    }
    for (p = k0; p < k1; p++) {
      PSPiece *P = &pc[npc];
      P->m[0] = P->m[1] = P->m[2] = P->m[3] = 0.0;
      PSPieceMoments(dim, lo, hi, 1, &w->reg[p], w->nsub, w->sub, P->m);
      /* a piece of round-off volume is no piece (planes touching a face) */
      if (P->m[0] <= 1e-14 * vsub) continue;
      P->q   = q;
      P->ply = w->reg[p].ply;
      npc++;
    }
  }
  st->pieces += npc;
  /* slivers: merge into the largest ordinary piece of the same ply in the cell */
  for (p = 0; p < npc; p++) {
    PetscInt best = -1;
    if (pc[p].m[0] >= B->sliver_fraction * vsub) continue;
    for (pp = 0; pp < npc; pp++)
      if (pc[pp].ply == pc[p].ply && pc[pp].m[0] >= B->sliver_fraction * vsub && (best < 0 || pc[pp].m[0] > pc[best].m[0])) best = pp;
    if (best < 0) {
      st->slivers_kept++;
      continue;
    }
    for (d = 0; d < 4; d++) {
      pc[best].m[d] += pc[p].m[d];
      pc[p].m[d] = 0.0;
    }
    st->slivers_merged++;
  }
  for (p = 0; p < npc; p++) {
    const PetscInt ply = pc[p].ply, mat = ply >= 0 ? B->ply_material[ply] : B->material;
    if (pc[p].m[0] == 0.0) continue; /* merged away */
    st->markers++;
    if (count_bp) count_bp[w->b * (w->maxply + 1) + ply + 1]++;
    if (!L) continue;
    {
      const PetscInt qi[3] = {pc[p].q % s, (pc[p].q / s) % s, pc[p].q / (s * s)};
      PetscCall(ListPush(L, pc[p].m, scene->density[mat], MarkerId(scene, idx, s, qi, w->b, w->maxply, ply), w->b, ply, mat));
    }
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Lattice fill of one cell: the centre of each of its n^dim lattice sub-cells
   is a marker with the sub-cell's volume when it lies inside the body (in the
   ply containing it) and in no higher-priority body. */
static PetscErrorCode LatticeCell(const PSScene *scene, PSBodyWork *w, const PetscInt idx[3], PSMarkerList *L, PetscInt64 *count_bp, PSInsertStats *st)
{
  const PSBody  *B   = w->B;
  const PetscInt dim = scene->dim, n = B->points_per_cell, npt = dim == 3 ? n * n * n : n * n;
  PetscInt       q, d, k;

  PetscFunctionBeginUser;
  for (q = 0; q < npt; q++) {
    const PetscInt qi[3] = {q % n, (q / n) % n, q / (n * n)};
    double         lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0}, x[3] = {0, 0, 0}, vol = 1.0;
    PetscInt       ply, mat;
    PetscBool      covered = PETSC_FALSE;
    PSSubCellBounds(scene, idx, n, qi, lo, hi);
    for (d = 0; d < dim; d++) {
      x[d] = 0.5 * (lo[d] + hi[d]);
      vol *= hi[d] - lo[d];
    }
    ply = PSBodyLocatePoint(dim, B, x);
    if (ply < -1) continue;
    for (k = 0; k < w->nsub && !covered; k++)
      if (PSBodyLocatePoint(dim, w->sub[k].body, x) >= -1) covered = PETSC_TRUE;
    if (covered) continue;
    mat = ply >= 0 ? B->ply_material[ply] : B->material;
    st->pieces++;
    st->markers++;
    if (count_bp) count_bp[w->b * (w->maxply + 1) + ply + 1]++;
    if (L) PetscCall(ListPushPoint(L, x, vol, scene->density[mat], MarkerId(scene, idx, n, qi, w->b, w->maxply, ply), w->b, ply, mat));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The insertion kernel over cells [cs, ce).  L may be NULL (count only); counts
   per (body, ply) go to count_bp[b * (maxply + 1) + ply + 1] when given. */
static PetscErrorCode InsertKernel(const PSScene *scene, const PetscInt cs[3], const PetscInt ce[3], PSMarkerList *L, PetscInt64 *count_bp, PSInsertStats *st)
{
  PetscInt dim = scene->dim, b, d, maxply = 0;
  double   h[3] = {0, 0, 0}, hmax = 0.0;

  PetscFunctionBeginUser;
  for (b = 0; b < scene->nbody; b++) maxply = PetscMax(maxply, scene->bodies[b].nply);
  for (d = 0; d < dim; d++) {
    h[d] = (scene->upper[d] - scene->lower[d]) / scene->cells[d];
    hmax = PetscMax(hmax, h[d]);
  }
  for (b = 0; b < scene->nbody; b++) {
    const PSBody  *B       = &scene->bodies[b];
    const PetscBool lattice = B->insertion == PS_INSERT_LATTICE ? PETSC_TRUE : PETSC_FALSE;
    const PetscInt  s       = lattice ? 1 : B->subdivision, nsc = dim == 3 ? s * s * s : s * s;
    PetscReal       blo[3], bhi[3];
    PetscInt        bcs[3], bce[3], i, j, k;
    PSRegion        hull;
    PSBodyWork      w;

    if (B->cellmat >= 0) continue; /* a body in cells puts no markers (cells/cells.c) */
    PetscCall(PSBodyBoundingBox(scene, b, blo, bhi));
    PSCellRange(scene, blo, bhi, bcs, bce);
    for (d = 0; d < 3; d++) {
      bcs[d] = PetscMax(bcs[d], cs[d]);
      bce[d] = PetscMin(bce[d], ce[d]);
    }
    if (bcs[0] >= bce[0] || bcs[1] >= bce[1] || bcs[2] >= bce[2]) continue;
    /* regions: the plies (or the body), the hull, and higher-priority bodies */
    w.B      = B;
    w.b      = b;
    w.maxply = maxply;
    w.nreg   = B->kind == PS_BODY_LAMINATE ? B->nply : 1;
    w.nsub   = 0;
    PetscCall(PetscMalloc1(w.nreg, &w.reg));
    for (i = 0; i < w.nreg; i++) PSRegionSetup(scene, B, B->kind == PS_BODY_LAMINATE ? i : -1, hmax / s, &w.reg[i]);
    PSRegionSetup(scene, B, -1, hmax / s, &hull);
    for (i = 0; i < scene->nbody; i++) {
      PetscReal olo[3], ohi[3];
      PetscBool meet = PETSC_TRUE;
      if (i == b || scene->bodies[i].priority <= B->priority) continue;
      PetscCall(PSBodyBoundingBox(scene, i, olo, ohi));
      for (d = 0; d < dim; d++)
        if (ohi[d] <= blo[d] || olo[d] >= bhi[d]) meet = PETSC_FALSE;
      if (!meet) continue;
      PetscCheck(w.nsub < PS_MAX_SUB, PETSC_COMM_SELF, PETSC_ERR_SUP, "body %" PetscInt_FMT " lies under more than %d higher-priority bodies", b, PS_MAX_SUB);
      PSRegionSetup(scene, &scene->bodies[i], -1, hmax / s, &w.sub[w.nsub++]);
    }
    PetscCall(PetscMalloc1(lattice ? 1 : nsc * w.nreg, &w.pc));
    for (k = bcs[2]; k < bce[2]; k++)
      for (j = bcs[1]; j < bce[1]; j++) {
        PetscInt i0 = bcs[0], i1 = bce[0];
        RowRange(scene, &hull, j, k, h, &i0, &i1);
        for (i = i0; i < i1; i++) {
          PetscInt idx[3] = {i, j, k}, q0[3] = {0, 0, 0};
          double   clo[3] = {0, 0, 0}, chi[3] = {0, 0, 0};

          /* whole cell against the body's hull first: most cells are far away */
          PSSubCellBounds(scene, idx, 1, q0, clo, chi);
          if (PSRegionClassify(dim, &hull, clo, chi) == PS_OUT) continue;
          if (lattice) PetscCall(LatticeCell(scene, &w, idx, L, count_bp, st));
          else PetscCall(ExactCell(scene, &w, idx, L, count_bp, st));
        }
      }
    PetscCall(PetscFree(w.pc));
    PetscCall(PetscFree(w.reg));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Count markers per (body, ply) over cells [cs, ce) without making any:
   n_body_ply[b * (maxply + 1) + ply + 1].  No PETSc objects. */
PetscErrorCode PSCountPieces(const PSScene *scene, const PetscInt cs[3], const PetscInt ce[3], PetscInt64 *n_body_ply)
{
  PSInsertStats st;

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(&st, sizeof(st)));
  PetscCall(InsertKernel(scene, cs, ce, NULL, n_body_ply, &st));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Markers in each slab k = k0, k0 + stride, ... < k1 of cells normal to axis
   (counts[k] set, other entries untouched): the marker distribution the grid
   partition balances (core.py), shared among ranks by the stride. */
PetscErrorCode PSCountSlabs(const PSScene *scene, PetscInt axis, PetscInt k0, PetscInt k1, PetscInt stride, PetscInt64 counts[])
{
  PetscInt      k, b, maxply = 0, cs[3] = {0, 0, 0}, ce[3] = {1, 1, 1};
  PetscInt64   *bp;
  PSInsertStats st;

  PetscFunctionBeginUser;
  for (b = 0; b < scene->nbody; b++) maxply = PetscMax(maxply, scene->bodies[b].nply);
  for (b = 0; b < scene->dim; b++) ce[b] = scene->cells[b];
  PetscCall(PetscMalloc1(scene->nbody * (maxply + 1), &bp));
  for (k = k0; k < k1; k += stride) {
    PetscCall(PetscArrayzero(bp, scene->nbody * (maxply + 1)));
    PetscCall(PetscMemzero(&st, sizeof(st)));
    cs[axis] = k;
    ce[axis] = k + 1;
    PetscCall(InsertKernel(scene, cs, ce, NULL, bp, &st));
    counts[k] = 0;
    for (b = 0; b < scene->nbody * (maxply + 1); b++) counts[k] += bp[b];
  }
  PetscCall(PetscFree(bp));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Insert the scene's markers into the swarm (fields registered here), each on
   the rank that owns its cell. */
PetscErrorCode PSInsertMarkers(const PSScene *scene, DM da, DM sw, PSInsertStats *st)
{
  PSMarkerList L;
  PetscInt     cs[3], ce[3], bytes, n, p, d, dim = scene->dim, b;
  PetscReal   *x, *mass, *vol, *v, *axes = NULL;
  PetscInt64  *id;
  PetscInt    *body, *ply = NULL, *mat;
  PetscBool    laminates = PETSC_FALSE;

  PetscFunctionBeginUser;
  PetscCall(PSInitializePackage());
  PetscCall(PetscMemzero(st, sizeof(*st)));
  PetscCall(PetscMemzero(&L, sizeof(L)));
  L.dim = dim;
  L.axi = scene->axisymmetric;
  PetscCheck(!scene->axisymmetric || (dim == 2 && scene->lower[0] >= 0.0), PETSC_COMM_SELF, PETSC_ERR_ARG_OUTOFRANGE, "axisymmetric insertion needs dimension 2 and r >= 0: dimension %" PetscInt_FMT ", lower r %g", dim, (double)scene->lower[0]);
  for (b = 0; b < scene->nbody; b++)
    if (scene->bodies[b].kind == PS_BODY_LAMINATE) laminates = PETSC_TRUE;
  PetscCall(PSCellOwnership(da, cs, ce));
  PetscCall(PetscLogEventBegin(PS_EVENT_Insert, 0, 0, 0, 0));
  PetscCall(InsertKernel(scene, cs, ce, &L, NULL, st));
  PetscCall(PetscLogEventEnd(PS_EVENT_Insert, 0, 0, 0, 0));

  PetscCall(PetscLogEventBegin(PS_EVENT_Fill, 0, 0, 0, 0));
  PetscCall(PSMarkersRegisterFields(scene, sw, &bytes));
  /* a small spare buffer: 3.18 zeroes all of it on every removal */
  PetscCall(DMSwarmSetLocalSizes(sw, L.n, PetscMax(16, L.n / 16)));
  PetscCall(DMSwarmGetLocalSize(sw, &n));
  PetscCall(DMSwarmGetField(sw, PS_FIELD_X, NULL, NULL, (void **)&x));
  PetscCall(DMSwarmGetField(sw, PS_FIELD_MASS, NULL, NULL, (void **)&mass));
  PetscCall(DMSwarmGetField(sw, PS_FIELD_VOLUME, NULL, NULL, (void **)&vol));
  PetscCall(DMSwarmGetField(sw, PS_FIELD_VELOCITY, NULL, NULL, (void **)&v));
  PetscCall(DMSwarmGetField(sw, PS_FIELD_ID, NULL, NULL, (void **)&id));
  PetscCall(DMSwarmGetField(sw, PS_FIELD_BODY, NULL, NULL, (void **)&body));
  PetscCall(DMSwarmGetField(sw, PS_FIELD_MATERIAL, NULL, NULL, (void **)&mat));
  if (laminates) PetscCall(DMSwarmGetField(sw, PS_FIELD_PLY, NULL, NULL, (void **)&ply));
  if (scene->anisotropic) PetscCall(DMSwarmGetField(sw, PS_FIELD_AXES, NULL, NULL, (void **)&axes));
  for (p = 0; p < n; p++) {
    const PSBody *B = &scene->bodies[L.body[p]];
    for (d = 0; d < dim; d++) {
      x[p * dim + d] = L.x[3 * p + d];
      v[p * dim + d] = B->velocity[d];
    }
    mass[p] = L.mass[p];
    vol[p]  = L.vol[p];
    id[p]   = L.id[p];
    body[p] = L.body[p];
    mat[p]  = L.mat[p];
    if (ply) ply[p] = L.ply[p];
    if (axes) {
      /* a ply's axes; other bodies carry the global axes x, y, z */
      static const PetscReal I9[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
      const PetscReal       *A     = L.ply[p] >= 0 ? &B->ply_axes[9 * L.ply[p]] : I9;
      for (d = 0; d < 9; d++) axes[9 * p + d] = A[d];
    }
  }
  if (axes) PetscCall(DMSwarmRestoreField(sw, PS_FIELD_AXES, NULL, NULL, (void **)&axes));
  /* solver state at rest: F = I, V0 = V, no stress, no energy, T = T0 */
  {
    const PetscInt ns = PSStressComponents(dim);
    PetscReal     *F, *V0, *sig, *sdev, *pr, *q, *e, *T = NULL, *ep = NULL, *D = NULL, *Sm = NULL;
    PetscCall(DMSwarmGetField(sw, PS_FIELD_F, NULL, NULL, (void **)&F));
    PetscCall(DMSwarmGetField(sw, PS_FIELD_V0, NULL, NULL, (void **)&V0));
    PetscCall(DMSwarmGetField(sw, PS_FIELD_STRESS, NULL, NULL, (void **)&sig));
    PetscCall(DMSwarmGetField(sw, PS_FIELD_SDEV, NULL, NULL, (void **)&sdev));
    PetscCall(DMSwarmGetField(sw, PS_FIELD_PRESSURE, NULL, NULL, (void **)&pr));
    PetscCall(DMSwarmGetField(sw, PS_FIELD_Q, NULL, NULL, (void **)&q));
    PetscCall(DMSwarmGetField(sw, PS_FIELD_ENERGY, NULL, NULL, (void **)&e));
    if (scene->need_temperature) PetscCall(DMSwarmGetField(sw, PS_FIELD_TEMP, NULL, NULL, (void **)&T));
    if (scene->need_plastic) PetscCall(DMSwarmGetField(sw, PS_FIELD_EPS_P, NULL, NULL, (void **)&ep));
    if (scene->ndamage) PetscCall(DMSwarmGetField(sw, PS_FIELD_DAMAGE, NULL, NULL, (void **)&D));
    if (scene->anisotropic) PetscCall(DMSwarmGetField(sw, PS_FIELD_SMAT, NULL, NULL, (void **)&Sm));
    for (p = 0; p < n; p++) {
      for (d = 0; d < dim * dim; d++) F[p * dim * dim + d] = (d % (dim + 1) == 0) ? 1.0 : 0.0;
      for (d = 0; d < ns; d++) sig[p * ns + d] = sdev[p * ns + d] = 0.0;
      V0[p] = L.vol[p];
      pr[p] = q[p] = e[p] = 0.0;
      if (T) T[p] = scene->T0[L.mat[p]];
      if (ep) ep[p] = 0.0;
      for (d = 0; D && d < scene->ndamage; d++) D[p * scene->ndamage + d] = 0.0;
      for (d = 0; Sm && d < 6; d++) Sm[6 * p + d] = 0.0;
    }
    if (Sm) PetscCall(DMSwarmRestoreField(sw, PS_FIELD_SMAT, NULL, NULL, (void **)&Sm));
    if (D) PetscCall(DMSwarmRestoreField(sw, PS_FIELD_DAMAGE, NULL, NULL, (void **)&D));
    if (ep) PetscCall(DMSwarmRestoreField(sw, PS_FIELD_EPS_P, NULL, NULL, (void **)&ep));
    if (T) PetscCall(DMSwarmRestoreField(sw, PS_FIELD_TEMP, NULL, NULL, (void **)&T));
    PetscCall(DMSwarmRestoreField(sw, PS_FIELD_ENERGY, NULL, NULL, (void **)&e));
    PetscCall(DMSwarmRestoreField(sw, PS_FIELD_Q, NULL, NULL, (void **)&q));
    PetscCall(DMSwarmRestoreField(sw, PS_FIELD_PRESSURE, NULL, NULL, (void **)&pr));
    PetscCall(DMSwarmRestoreField(sw, PS_FIELD_SDEV, NULL, NULL, (void **)&sdev));
    PetscCall(DMSwarmRestoreField(sw, PS_FIELD_STRESS, NULL, NULL, (void **)&sig));
    PetscCall(DMSwarmRestoreField(sw, PS_FIELD_V0, NULL, NULL, (void **)&V0));
    PetscCall(DMSwarmRestoreField(sw, PS_FIELD_F, NULL, NULL, (void **)&F));
  }
  if (ply) PetscCall(DMSwarmRestoreField(sw, PS_FIELD_PLY, NULL, NULL, (void **)&ply));
  PetscCall(DMSwarmRestoreField(sw, PS_FIELD_MATERIAL, NULL, NULL, (void **)&mat));
  PetscCall(DMSwarmRestoreField(sw, PS_FIELD_BODY, NULL, NULL, (void **)&body));
  PetscCall(DMSwarmRestoreField(sw, PS_FIELD_ID, NULL, NULL, (void **)&id));
  PetscCall(DMSwarmRestoreField(sw, PS_FIELD_VELOCITY, NULL, NULL, (void **)&v));
  PetscCall(DMSwarmRestoreField(sw, PS_FIELD_VOLUME, NULL, NULL, (void **)&vol));
  PetscCall(DMSwarmRestoreField(sw, PS_FIELD_MASS, NULL, NULL, (void **)&mass));
  PetscCall(DMSwarmRestoreField(sw, PS_FIELD_X, NULL, NULL, (void **)&x));
  PetscCall(PetscLogEventEnd(PS_EVENT_Fill, 0, 0, 0, 0));
  PetscCall(ListDestroy(&L));
  PetscFunctionReturn(PETSC_SUCCESS);
}
