/*
  step.h - what the phases of the time step share (internal).

  The step (step.c) reads as named phases, each in a file of its own:
    timestep.c       dt from the CFL condition (PSTimeStep)
    grid.c           the active node box, grid reset, the grid phase: ghost sums,
                     nodal velocity with the boundary conditions (PSGridUpdate)
    transfer_musl.c  MUSL: P2G, G2P with the re-projection, L_p (PSP2G, PSG2P, PSReproject)
    transfer_apic.c  APIC/MLS-MPM: P2G, G2P (PSP2G, PSG2P)
    contact.c        bodies in contact: per-field P2G, grid update with the contact
                     law, G2P and L_p (MUSL; contact.h)
    cells/           Eulerian cell materials: their part of P2G, Lagrangian phase, remap
    stress.c         velocity gradient, F-bar, constitutive update, x_p += dx_p (PSStress)
    migrate.c        markers out of the domain booked and removed, the rest migrated (PSMigrate)
    totals.c         conserved totals with the booked losses
  Suffixes: _p marker, _i node, _c cell.  SI units.
*/
#ifndef PLYSHOCK_STEP_H
#define PLYSHOCK_STEP_H

#include <math.h>
#include <string.h>
#include "materials.h"
#include "shape.h"

/* one log event per phase (registered in solver.c) */
PETSC_INTERN PetscLogEvent PS_EV_P2G, PS_EV_Grid, PS_EV_G2P, PS_EV_Reproject, PS_EV_Stress, PS_EV_Migrate, PS_EV_Dt, PS_EV_Huge;

/* corners of a rank's ghosted local arrays and of its owned nodes (DMDA indices) */
typedef struct {
  PetscInt gs[3], gm[3]; /* ghosted corner and size */
  PetscInt os[3], om[3]; /* owned corner and size */
} PSIndex;

/* offset of node (i, j, k) in a rank's ghosted local array (in nodes) */
static inline PetscInt Lidx(const PSIndex *ix, PetscInt i, PetscInt j, PetscInt k)
{
  return ((k - ix->gs[2]) * ix->gm[1] + (j - ix->gs[1])) * ix->gm[0] + (i - ix->gs[0]);
}

/* the registered marker fields of this scene (NULL where not registered) */
typedef struct {
  PetscReal *x, *v, *mass, *vol, *V0, *F, *sig, *sdev, *p, *q, *e, *eps_p, *T, *D;
  PetscReal *axes, *smat; /* anisotropic scenes */
  PetscReal *C;           /* APIC affine velocity (transfer apic) */
  PetscReal *Di;          /* interface damage (cohesive ply interfaces) */
  PetscInt  *mat, *body, *ply;
  PetscInt64 *id;
  PetscInt   n;
} PSFields;

/* Reals per node of the step's grid array G: apic [m, mv] (1 + dim); musl 3D
   [m, mv | 0, f] (two 4-wide vectors), 2D [m, mv, f]; and of the MUSL
   re-projection H: 3D [0, mv], 2D [mv] (transfer_musl.c) */
static inline PetscInt PSGridDof(const PSSolver *S)
{
  return S->run.transfer == PS_TRANSFER_APIC ? 1 + S->dim : (S->dim == 3 ? 8 : 5);
}
static inline PetscInt PSReprojectDof(const PSSolver *S)
{
  return S->dim == 3 ? 4 : 2;
}

PETSC_INTERN PetscErrorCode PSGridIndex(DM, PSIndex *);
PETSC_INTERN PetscErrorCode PSFieldsGet(PSSolver *, PSFields *);
PETSC_INTERN PetscErrorCode PSFieldsRestore(PSSolver *, PSFields *);

/* the phases */
PETSC_INTERN PetscErrorCode PSComputeDt(PSSolver *, PetscReal t_stop);
PETSC_INTERN PetscErrorCode PSGridActiveBox(PSSolver *, const PSFields *, PetscInt box[3][2]);
PETSC_INTERN PetscErrorCode PSGridReset(PSSolver *, const PSIndex *, const PetscInt box[3][2], PetscBool whole);
PETSC_INTERN void           PSGridVelocity(const PSSolver *, const PSIndex *, const PetscReal *m, PetscInt ms, PetscReal *mv, PetscInt vs);
PETSC_INTERN void           PSGridUpdateMUSL(const PSSolver *, const PSIndex *, PetscReal dt, PetscReal *g);
PETSC_INTERN void           PSGridUpdateMUSLUnits(const PSSolver *, const PSIndex *, PetscReal dt, PetscReal *g, PetscInt u0, PetscInt u1);
PETSC_INTERN void           PSGridAddOwned(const PSSolver *, const PSIndex *, const PetscReal *b, PetscInt bs, PetscReal *a, PetscInt as);
PETSC_INTERN void           PSGridAddOwnedUnits(const PSSolver *, const PSIndex *, const PetscReal *b, PetscInt bs, PetscReal *a, PetscInt as, PetscInt u0, PetscInt u1);
PETSC_INTERN PetscErrorCode PSGridSolve(PSSolver *, const PSIndex *, PetscReal dt);
PETSC_INTERN PetscErrorCode PSMUSLP2G(PSSolver *, PSFields *, const PSIndex *);
PETSC_INTERN PetscErrorCode PSMUSLG2P(PSSolver *, PSFields *, const PSIndex *, PetscReal dt);
PETSC_INTERN PetscErrorCode PSMUSLReproject(PSSolver *, PSFields *, const PSIndex *);
PETSC_INTERN PetscErrorCode PSAPICP2G(PSSolver *, PSFields *, const PSIndex *, PetscReal dt);
PETSC_INTERN PetscErrorCode PSAPICG2P(PSSolver *, PSFields *, const PSIndex *, PetscReal dt);
PETSC_INTERN PetscErrorCode PSStressUpdate(PSSolver *, PSFields *, PetscReal dt);
PETSC_INTERN PetscErrorCode PSMemoryHugePages(PetscLogDouble *bytes);

/* boundary conditions on a node's velocity (or momentum): physical node ip */
static inline void PSNodeBCDim(const PSSolver *S, const PetscInt dim, const PetscInt ip[3], PetscReal *v)
{
  PetscInt d, e;
  for (d = 0; d < dim; d++) {
    PSBCType bc;
    if (ip[d] > 0 && ip[d] < S->nc[d]) continue; /* not on a face of the domain (nearly every node) */
    bc = ip[d] <= 0 ? S->bc[d][0] : S->bc[d][1];
    if (bc == PS_BC_SYMMETRY) v[d] = 0.0;
    else if (bc == PS_BC_FIXED)
      for (e = 0; e < dim; e++) v[e] = 0.0;
  }
}

/* the nodes [xa, xb) of [x0, x1) in the row (j, k) (padded indices) that lie
   inside the domain, on none of its faces: PSNodeBCDim leaves them as they
   are.  None (xa = xb = x1) where the row itself is on a face across x */
static inline void PSNodeRowInside(const PSSolver *S, const PetscInt dim, PetscInt x0, PetscInt x1, PetscInt j, PetscInt k, PetscInt *xa, PetscInt *xb)
{
  const PetscBool inside = j - PS_PAD > 0 && j - PS_PAD < S->nc[1] && (dim < 3 || (k - PS_PAD > 0 && k - PS_PAD < S->nc[2]));
  *xa = inside ? PetscMin(PetscMax(x0, 1 + PS_PAD), x1) : x1;
  *xb = inside ? PetscMax(PetscMin(x1, S->nc[0] + PS_PAD), *xa) : x1;
}

/* PSNodeBCDim on the nodes [x0, x1) of the row (j, k) of the local node
   arrays (padded indices; node x's dim values at v[dim (orow + x)]), but for
   those it leaves as they are (PSNodeRowInside), so a row's loop without it
   can run in SIMD lanes */
static inline void PSNodeBCRow(const PSSolver *S, const PetscInt dim, PetscInt orow, PetscInt x0, PetscInt x1, PetscInt j, PetscInt k, PetscReal *v)
{
  PetscInt xa, xb, x;
  PSNodeRowInside(S, dim, x0, x1, j, k, &xa, &xb);
  for (x = x0; x < x1; x++) {
    if (x == xa) x = xb; /* (past the inside ones) */
    if (x < x1) {
      const PetscInt ip[3] = {x - PS_PAD, j - PS_PAD, dim == 3 ? k - PS_PAD : 0};
      PSNodeBCDim(S, dim, ip, &v[dim * (orow + x)]);
    }
  }
}

/* (dim a constant in the cells' loops, which call PSNodeBCDim) */
static inline void PSNodeBC(const PSSolver *S, const PetscInt ip[3], PetscReal *v)
{
  PSNodeBCDim(S, S->dim, ip, v);
}

/* GIMP half size of a marker: half its initial size (m) */
static inline PetscReal HalfSize(PetscInt dim, PetscReal V0)
{
  return 0.5 * (dim == 3 ? cbrt(V0) : sqrt(V0));
}

/* marker p's weights where MUSL's P2G located it this step (S->at) */
static inline void PSMarkerWeights(const PSSolver *S, PetscInt p, PetscInt dim, PSShape *sh)
{
  PSShapeWeights(S->run.shape, dim, S->ih, &S->at[p], sh);
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

/* box clipped to the array's corner s and size m (lo >= hi: empty) */
static inline void Clip(const PetscInt box[3][2], const PetscInt s[3], const PetscInt m[3], PetscInt lo[3], PetscInt hi[3])
{
  PetscInt d;
  for (d = 0; d < 3; d++) {
    lo[d] = PetscMax(box[d][0], s[d]);
    hi[d] = PetscMin(box[d][1], s[d] + m[d]);
  }
}

/* 4-wide loads and stores (PSv4, solver.h) */
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
static inline PSv8 Load8(const PetscReal *p)
{
  PSv8 v;
  memcpy(&v, p, sizeof(v));
  return v;
}
static inline void Store8(PetscReal *p, PSv8 v)
{
  memcpy(p, &v, sizeof(v));
}

#endif
