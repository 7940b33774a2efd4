/*
  grid.c - the grid phase of the step: the box of nodes the markers reach,
  zeroing what the last step wrote, and the nodal velocity with the boundary
  conditions of each face (PSGridUpdate):
    free      nothing imposed (markers leave and are booked, migrate.c)
    symmetry  zero normal velocity
    fixed     zero velocity
*/
#include "step.h"
#include "cells/cells.h"

PetscErrorCode PSGridActiveBox(PSSolver *S, const PSFields *f, PetscInt box[3][2])
{
  const PetscInt dim = S->dim;
  PetscReal      buf[6], gbuf[6];
  PetscInt       p, d;

  PetscFunctionBeginUser;
  if (S->cells) { /* cell materials fill the grid: every node */
    PetscInt N[3];
    PetscCall(DMDAGetInfo(S->da, NULL, &N[0], &N[1], &N[2], NULL, NULL, NULL, NULL, NULL, NULL, NULL, NULL, NULL));
    for (d = 0; d < 3; d++) {
      box[d][0] = 0;
      box[d][1] = d < dim ? N[d] : 1;
    }
    PetscFunctionReturn(PETSC_SUCCESS);
  }
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
   the local arrays alone (halo.c); the global vectors serve output.  With
   whole (the cells' P2G comes next and writes every value of every local
   node of G, a unit at a time, from sums of its own: lagrange.c), G is
   not zeroed: its values are written once a step, not zeroed in a pass of
   their own and then added to (the 256^2 quadrants' G, 2.6 MB, lies past
   this machine's L2) */
PetscErrorCode PSGridReset(PSSolver *S, const PSIndex *ix, const PetscInt box[3][2], PetscBool whole)
{
  PetscFunctionBeginUser;
  if (S->zall) {
    PetscCall(VecZeroEntries(S->Gl));
    if (S->Hl) PetscCall(VecZeroEntries(S->Hl));
  } else {
    if (!whole) PetscCall(ZeroBox(S->Gl, PSGridDof(S), ix->gs, ix->gm, S->zbox));
    if (PSSolverReprojects(S)) PetscCall(ZeroBox(S->Hl, PSReprojectDof(S), ix->gs, ix->gm, S->zbox)); /* (else nothing writes it) */
  }
  S->zall = PETSC_FALSE;
  PetscCall(PetscArraycpy(&S->zbox[0][0], &box[0][0], 6));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* v_i = (mv)_i / m_i with the boundary conditions on the owned nodes of the
   active box (no mass elsewhere); nodes lighter than mass_min get v = 0.  The
   mass of node o is m[ms o], its momentum mv[vs o + d], overwritten by v. */
void PSGridVelocity(const PSSolver *S, const PSIndex *ix, const PetscReal *m, PetscInt ms, PetscReal *mv, PetscInt vs)
{
  const PetscInt dim = S->dim;
  PetscInt       a, b, c, d, lo[3], hi[3];

  Clip(S->zbox, ix->os, ix->om, lo, hi);
  for (c = lo[2]; c < hi[2]; c++)
    for (b = lo[1]; b < hi[1]; b++)
      for (a = lo[0]; a < hi[0]; a++) {
        const PetscInt  o     = Lidx(ix, a, b, c);
        const PetscInt  ip[3] = {a - S->pad, b - S->pad, dim == 3 ? c - S->pad : 0};
        const PetscReal mi    = m[ms * o];
        PetscReal       vn[3] = {0, 0, 0};
        if (mi > S->mass_min) {
          for (d = 0; d < dim; d++) vn[d] = mv[vs * o + d] / mi;
          PSNodeBC(S, ip, vn);
        }
        for (d = 0; d < dim; d++) mv[vs * o + d] = vn[d];
      }
}

/* MUSL's grid update on nodes holding [m, mv, .., f] (PSGridDof; f in the
   last dim reals): v_old = mv/m, v_new = v_old + dt f/m with the boundary
   conditions; the node keeps [m, v_new, .., v_new - v_old] for G2P. */
static inline __attribute__((always_inline)) void GridUpdateMUSLNode(const PSSolver *S, PetscReal dt, PetscReal *gn, const PetscInt dim, const PetscInt dof, const PetscBool bc, const PetscInt ip[3])
{
  const PetscInt fo = dof - dim;
  PetscReal      vo[3] = {0, 0, 0}, vn[3] = {0, 0, 0};
  PetscInt       d;
  if (gn[0] > S->mass_min) {
    const PetscReal im = 1.0 / gn[0];
    for (d = 0; d < dim; d++) {
      vo[d] = gn[1 + d] * im;
      vn[d] = vo[d] + dt * gn[fo + d] * im;
    }
    if (bc) PSNodeBCDim(S, dim, ip, vn);
  }
  for (d = 0; d < dim; d++) {
    gn[1 + d]  = vn[d];
    gn[fo + d] = vn[d] - vo[d];
  }
}

/* (a row inside the domain takes the boundary conditions at its ends alone:
   PSNodeBCDim leaves the others, and its test per node was 0.6% of the
   cells' quadrants' instructions) */
static inline void GridUpdateMUSLDim(const PSSolver *S, const PSIndex *ix, PetscReal dt, PetscReal *g, const PetscInt dim, PetscInt u0, PetscInt u1)
{
  const PetscInt dof = PSGridDof(S), pad = S->pad;
  PetscInt       a, b, c, lo[3], hi[3];

  Clip(S->zbox, ix->os, ix->om, lo, hi);
  lo[dim - 1] = PetscMax(lo[dim - 1], u0);
  hi[dim - 1] = PetscMin(hi[dim - 1], u1);
  for (c = lo[2]; c < hi[2]; c++)
    for (b = lo[1]; b < hi[1]; b++) {
      PetscInt xa, xb, ip[3] = {0, b - pad, dim == 3 ? c - pad : 0};
      PSNodeRowInside(S, dim, lo[0], hi[0], b, c, &xa, &xb);
      for (a = lo[0]; a < xa; a++) {
        ip[0] = a - pad;
        GridUpdateMUSLNode(S, dt, &g[dof * Lidx(ix, a, b, c)], dim, dof, PETSC_TRUE, ip);
      }
      for (a = xa; a < xb; a++) GridUpdateMUSLNode(S, dt, &g[dof * Lidx(ix, a, b, c)], dim, dof, PETSC_FALSE, ip);
      for (a = xb; a < hi[0]; a++) {
        ip[0] = a - pad;
        GridUpdateMUSLNode(S, dt, &g[dof * Lidx(ix, a, b, c)], dim, dof, PETSC_TRUE, ip);
      }
    }
}

/* (dim a constant in the node loop, so it unrolls) */
void PSGridUpdateMUSL(const PSSolver *S, const PSIndex *ix, PetscReal dt, PetscReal *g)
{
  PSGridUpdateMUSLUnits(S, ix, dt, g, PETSC_MIN_INT, PETSC_MAX_INT);
}

/* PSGridUpdateMUSL on the nodes of grid index [u0, u1) along y (2D) or z
   (3D) alone (the cells' Lagrangian pipeline, a unit at a time) */
void PSGridUpdateMUSLUnits(const PSSolver *S, const PSIndex *ix, PetscReal dt, PetscReal *g, PetscInt u0, PetscInt u1)
{
  if (S->dim == 2) GridUpdateMUSLDim(S, ix, dt, g, 2, u0, u1);
  else GridUpdateMUSLDim(S, ix, dt, g, 3, u0, u1);
}

/* a[a_s o + d] += b[b_s o + d] on the owned nodes of the active box */
void PSGridAddOwned(const PSSolver *S, const PSIndex *ix, const PetscReal *b, PetscInt bs, PetscReal *a, PetscInt as)
{
  PSGridAddOwnedUnits(S, ix, b, bs, a, as, PETSC_MIN_INT, PETSC_MAX_INT);
}

/* PSGridAddOwned on the nodes of grid index [u0, u1) along y (2D) or z (3D)
   alone (a caller that adds to the nodes a row or plane at a time) */
void PSGridAddOwnedUnits(const PSSolver *S, const PSIndex *ix, const PetscReal *b, PetscInt bs, PetscReal *a, PetscInt as, PetscInt u0, PetscInt u1)
{
  const PetscInt dim = S->dim;
  PetscInt       i, j, k, lo[3], hi[3];

  Clip(S->zbox, ix->os, ix->om, lo, hi);
  lo[dim - 1] = PetscMax(lo[dim - 1], u0);
  hi[dim - 1] = PetscMin(hi[dim - 1], u1);
  for (k = lo[2]; k < hi[2]; k++)
    for (j = lo[1]; j < hi[1]; j++) {
      const PetscInt orow = Lidx(ix, 0, j, k); /* (node (i, j, k) is orow + i) */
      for (i = lo[0]; i < hi[0]; i++) {
        const PetscInt o = orow + i;
        /* (the components written out: a loop of run-time length cost five
           times these adds) */
        a[as * o] += b[bs * o];
        a[as * o + 1] += b[bs * o + 1];
        if (dim == 3) a[as * o + 2] += b[bs * o + 2];
      }
    }
}

/* 2. The grid phase: the ghosts' P2G sums to their owners, the nodal velocity
   with the boundary conditions (musl: v_new and v_new - v_old; apic: v), and
   the owners' values back to the ghosts. */
PetscErrorCode PSGridSolve(PSSolver *S, const PSIndex *ix, PetscReal dt)
{
  PetscFunctionBeginUser;
  PetscCall(PSHaloReduce(S->sfg, S->g));
  PetscCall(PetscLogEventBegin(PS_EV_Grid, 0, 0, 0, 0));
  if (S->run.transfer == PS_TRANSFER_MUSL) PSGridUpdateMUSL(S, ix, dt, S->g);
  else PSGridVelocity(S, ix, S->g, PSGridDof(S), S->g + 1, PSGridDof(S));
  PetscCall(PetscLogEventEnd(PS_EV_Grid, 0, 0, 0, 0));
  PetscCall(PSHaloBcast(S->sfg, S->g));
  PetscFunctionReturn(PETSC_SUCCESS);
}
