/*
  cells.c - the Eulerian cells' arrays, their exact insertion, totals, output
  and checkpoint (cells.h describes the state).

  Insertion: for every owned cell and every body in cells, the body's part of
  the cell, less the bodies of higher priority, is computed exactly by the
  piece kernel that inserts the plies (geom.c; curved surfaces to the body's
  volume tolerance); its volume gives V_k, rho_k0 V_k the mass, and the body's
  initial pressure the specific energy e0 = (p - A)/B of the EOS p = A + B e at
  the initial density.  The body's velocity gives the nodal momentum: each
  cell sends M_c v / 2^dim to each of its corners.
*/
#include <petscviewerhdf5.h>
#include "cells.h"
#include "../geom.h"

/* the corners of a cell (cells.h PSCorners) for the node DMDA's local layout ix */
static void CornersBuild(const PSSolver *S, const PSCells *C, const PSIndex *ix, PSCorners *K)
{
  const PetscInt dim = S->dim;
  PetscInt       a, d;

  K->dim = dim;
  K->nco = 1 << dim;
  for (a = 0; a < K->nco; a++) {
    PetscReal s[3];
    PetscInt  o[3];
    for (d = 0; d < 3; d++) {
      o[d] = d < dim ? (a >> d) & 1 : 0;
      s[d] = o[d] ? 1.0 : -1.0;
      K->gN[a][d] = d < dim ? s[d] / S->h[d] / (dim == 3 ? 4.0 : 2.0) : 0.0;
    }
    K->off[a] = (o[2] * ix->gm[1] + o[1]) * ix->gm[0] + o[0];
  }
  K->khg = C->hourglass / PetscMin(S->h[0], S->h[1]) / K->nco;
}

/* cells [lc[k], lc[k+1]) of rank k along one direction, from its nodes (markers.c's rule) */
static PetscErrorCode CellRanges(const PSSolver *S, PetscInt d, PetscInt nc, PetscInt **lc)
{
  PetscInt r, P = S->nproc[d];

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc1(P + 1, lc));
  for (r = 0; r <= P; r++) (*lc)[r] = d < S->dim ? PetscMin(PetscMax(S->lx[d][r] - PS_PAD, 0), nc) : (r ? 1 : 0);
  (*lc)[P] = d < S->dim ? nc : 1;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode PSCellsCreate(PSSolver *S, const PSMaterial *mats)
{
  const PSScene *scene = S->scene;
  PSCells       *C;
  PetscInt       d, k, *lc[3] = {NULL, NULL, NULL}, nn = 1, sizes[3];
  PetscBool      strength = PETSC_FALSE;
  MPI_Comm       comm = PetscObjectComm((PetscObject)S->da);
  PSIndex        ix;

  PetscFunctionBeginUser;
  PetscCheck(scene->ncellmat <= PS_MAX_CELLMAT, comm, PETSC_ERR_SUP, "%" PetscInt_FMT " cell materials; at most %d", scene->ncellmat, PS_MAX_CELLMAT);
  PetscCall(PetscNew(&C));
  C->dim  = S->dim;
  C->nmat = scene->ncellmat;
  for (k = 0; k < scene->nbody; k++)
    if (scene->bodies[k].cellmat < 0) C->markers = PETSC_TRUE;
  for (k = 0; k < C->nmat; k++) {
    C->mat[k] = scene->cellmat[k];
    C->rho_min[k] = PS_RHO_MIN * mats[C->mat[k]].rho0;
    if (mats[C->mat[k]].G > 0.0) strength = PETSC_TRUE;
  }
  C->ns        = PSStressComponents(S->dim);
  C->nq        = strength ? C->ns + 2 : 0;
  C->ms        = 3 + C->nq;
  /* the materials whose one-material cells the Lagrangian phases take in
     SIMD lanes (lagrange.c): an ideal gas (the predictor's own update for
     it) without a deviator */
  for (k = 0; k < C->nmat; k++) {
    const PSMaterial *M = &mats[C->mat[k]];
    C->gasf[k]          = M->eos_fn == PSEOSIdealGas && M->spall >= 0.0 && M->gamma > 0.0 && !(C->nq > 0 && M->G > 0.0);
    C->gam[k]           = M->gamma;
  }
  C->dof       = C->nmat * C->ms + PS_CX_N;
  C->over      = -1; /* (not counted: the fit tests every cell) */
  C->hourglass = 0.1;
  PetscCall(PetscMalloc1(scene->nmaterial, &C->Kmat));
  for (k = 0; k < scene->nmaterial; k++) {
    PetscReal A, B, c2;
    PetscCall(mats[k].eos_fn(&mats[k], 1.0, 0.0, 0.0, &A, &B, &c2));
    C->Kmat[k] = mats[k].aniso ? mats[k].ply.K_R : mats[k].rho0 * c2;
  }
  C->Vc        = 1.0;
  for (d = 0; d < 3; d++) {
    C->nc[d] = d < S->dim ? scene->cells[d] : 1;
    if (d < S->dim) C->Vc *= S->h[d];
  }
  /* owned cells and the ghosted box */
  PetscCall(PSCellOwnership(S->da, C->cs, C->ce));
  C->ncl = 1;
  for (d = 0; d < 3; d++) {
    C->gs[d] = d < S->dim ? PetscMax(C->cs[d] - PS_CELL_GHOST, 0) : 0;
    C->gm[d] = (d < S->dim ? PetscMin(C->ce[d] + PS_CELL_GHOST, C->nc[d]) : 1) - C->gs[d];
    C->ncl *= C->gm[d];
    C->xs[d] = d < S->dim ? PetscMax(C->cs[d] - 1, 0) : 0; /* (PSCellsXIdx) */
    C->xm[d] = C->ce[d] - C->xs[d];
    PetscCall(CellRanges(S, d, C->nc[d], &lc[d]));
  }
  C->cst[0] = 1; /* (PSCellIdx) */
  C->cst[1] = C->gm[0];
  C->cst[2] = C->gm[0] * C->gm[1];
  C->coff   = C->gs[0] + C->gs[1] * C->cst[1] + C->gs[2] * C->cst[2];
  PetscCall(PetscCalloc1(C->ncl * C->dof, &C->u));
  C->mst = C->ncl * C->ms;
  C->ux  = C->u + C->nmat * C->mst;
  PetscCall(PSHaloCreateBox(comm, S->dim, C->nc, S->nproc, lc, PS_CELL_GHOST, C->nmat, C->ms, PS_CX_N, &C->sfu));
  PetscCall(PSHaloCreateBox(comm, S->dim, C->nc, S->nproc, lc, PS_CELL_GHOST, 1, 2, 0, &C->sfd));
  PetscCall(PetscCalloc1(2 * C->ncl, &C->dep));
  /* the cells without ghosts: the same ownership, for HDF5 output and checkpoints */
  for (d = 0; d < 3; d++) {
    PetscInt r;
    for (r = 0; r < S->nproc[d]; r++) lc[d][r] = lc[d][r + 1] - lc[d][r];
    sizes[d] = C->nc[d];
  }
  if (S->dim == 2) PetscCall(DMDACreate2d(comm, DM_BOUNDARY_NONE, DM_BOUNDARY_NONE, DMDA_STENCIL_BOX, sizes[0], sizes[1], S->nproc[0], S->nproc[1], C->dof, 0, lc[0], lc[1], &C->dac));
  else PetscCall(DMDACreate3d(comm, DM_BOUNDARY_NONE, DM_BOUNDARY_NONE, DM_BOUNDARY_NONE, DMDA_STENCIL_BOX, sizes[0], sizes[1], sizes[2], S->nproc[0], S->nproc[1], S->nproc[2], C->dof, 0, lc[0], lc[1], lc[2], &C->dac));
  PetscCall(DMSetUp(C->dac));
  for (d = 0; d < 3; d++) PetscCall(PetscFree(lc[d]));
  /* nodal arrays in the node DMDA's local layout */
  PetscCall(PSGridIndex(S->da, &ix));
  for (d = 0; d < 3; d++) nn *= ix.gm[d];
  C->nnl = nn;
  PetscCall(PetscCalloc1(nn * S->dim, &C->P));
  PetscCall(PetscMalloc4(nn, &C->sK, nn * S->dim, &C->sVL, ix.gm[0] * S->dim, &C->sdP, PSCellsPlaneLen(C, &ix) * PetscMax((S->dim + 1) * (S->dim == 3 ? 4 : 2) + 1, 15 + (1 << S->dim) * S->dim + (S->dim == 3 ? 4 : 1) * S->dim), &C->sW)); /* the remap's scratch; sVL is the cells' P2G's too (sW's planes the longer of a ghosted row of nodes and of cells, FractionsRun's, padded: PSCellsPlaneLen) */
  PetscCall(PetscCalloc1(nn, &C->mcn)); /* mcn and mco apart: the remap's sweeps swap them */
  PetscCall(PetscCalloc1(nn, &C->mco));
  PetscCall(PetscCalloc1(nn * S->dim, &C->vh));
  PetscCall(PetscCalloc1(C->ncl, &C->Mcell));
  PetscCall(PetscMalloc1(C->ncl, &C->sole));
  CornersBuild(S, C, &ix, &C->K);
  PetscCall(PetscMalloc3(PetscMax(1, PSCellsSlots(C) * PSCellsHalfSize(C)), &C->hs, nn * S->dim, &C->vo, nn * S->dim, &C->df)); /* the predictor's (lagrange.c; with the pipeline's edge units: PSCellsSlots) */
  PetscCall(PSHaloCreate(S, S->dim, &C->sfp));
  PetscCall(PSHaloCreate(S, 1, &C->sfk));
  S->cells = C;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode PSCellsDestroy(PSCells **C)
{
  PetscFunctionBeginUser;
  if (!*C) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(PetscFree((*C)->u));
  PetscCall(PetscFree((*C)->P));
  PetscCall(PetscFree((*C)->mcn));
  PetscCall(PetscFree((*C)->mco));
  PetscCall(PetscFree((*C)->vh));
  PetscCall(PetscFree((*C)->Mcell));
  PetscCall(PetscFree((*C)->sole));
  PSCellsWindowEnd(*C); /* (the whole arrays, where a step stopped inside the pipeline) */
  PetscCall(PetscFree((*C)->win.buf));
  PetscCall(PetscFree3((*C)->hs, (*C)->vo, (*C)->df));
  PetscCall(PetscSFDestroy(&(*C)->sfu));
  PetscCall(PetscSFDestroy(&(*C)->sfd));
  PetscCall(PetscFree((*C)->dep));
  PetscCall(PetscFree2((*C)->sF, (*C)->sR));
  PetscCall(PetscFree((*C)->sA));
  PetscCall(PetscFree3((*C)->sS, (*C)->sP, (*C)->sM));
  PetscCall(PetscFree((*C)->ec));
  PetscCall(PetscFree((*C)->eco));
  PetscCall(PetscFree((*C)->hm));
  PetscCall(PetscFree4((*C)->sK, (*C)->sVL, (*C)->sdP, (*C)->sW));
  PetscCall(PetscFree((*C)->sVR));
  PetscCall(PetscFree((*C)->acc));
  PetscCall(PetscFree((*C)->rsp));
  PetscCall(PetscFree((*C)->sD));
  PetscCall(PetscFree((*C)->sDR));
  PetscCall(PetscSFDestroy(&(*C)->sfk));
  PetscCall(PetscSFDestroy(&(*C)->sfp));
  PetscCall(DMDestroy(&(*C)->dac));
  PetscCall(PetscFree((*C)->Kmat));
  PetscCall(PetscFree(*C));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* owners' cells to the ghosts (the whole state) */
PetscErrorCode PSCellsExchange(PSCells *C)
{
  PetscFunctionBeginUser;
  PetscCall(PSHaloBcast(C->sfu, C->u));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* m^C_i = sum_c M_c / 2^dim over the cells around each local node (ghost
   nodes included where their cells are in the ghosted box), from C->Mcell:
   each node sums its cells in the order of the cell array (z, y, x) (a cell
   without mass adds nothing), into mcn; the nodes whose index along y (2D)
   or z (3D) lies in [n0, n1) alone (PSCellsNodalMassUnits, the remap's
   KEBehind); dim a constant where it is called (PSCellsNodalMassGather
   picks 2D or 3D), so the loop over a node's cells unrolls */
static inline PetscErrorCode NodalMassGatherDim(PSSolver *S, const PSIndex *ix, PetscReal *mcn, PetscInt n0, PetscInt n1, const PetscInt dim)
{
  PSCells        *C   = S->cells;
  const PetscInt  nco = 1 << dim;
  const PetscReal w   = dim == 3 ? 0.125 : 0.25;
  PetscInt        n[3], c[3], lo[3], hi[3], e, a, off[8];

  PetscFunctionBeginUser;
  /* a node's cells from its lower-left one, in the loop order below (x fastest) */
  for (a = 0; a < nco; a++) off[a] = (a & 1) + ((a >> 1) & 1) * C->gm[0] + ((a >> 2) & 1) * C->gm[0] * C->gm[1];
  for (n[2] = dim == 3 ? PetscMax(n0, ix->gs[2]) : 0; n[2] < (dim == 3 ? PetscMin(n1, ix->gs[2] + ix->gm[2]) : 1); n[2]++)
    for (n[1] = dim == 2 ? PetscMax(n0, ix->gs[1]) : ix->gs[1]; n[1] < (dim == 2 ? PetscMin(n1, ix->gs[1] + ix->gm[1]) : ix->gs[1] + ix->gm[1]); n[1]++) {
      /* the nodes of this row whose 2^dim cells are all in the ghosted cell
         box (nearly all): the same sum without the clipping.  Physical node
         n - PS_PAD has cells n - PS_PAD - 1 and n - PS_PAD along each direction */
      PetscBool full = PETSC_TRUE;
      PetscInt  x0, x1;
      for (e = 1; e < dim; e++)
        if (n[e] - PS_PAD - 1 < C->gs[e] || n[e] - PS_PAD > C->gs[e] + C->gm[e] - 1) full = PETSC_FALSE;
      x0 = full ? PetscMax(C->gs[0] + PS_PAD + 1, ix->gs[0]) : ix->gs[0] + ix->gm[0];
      x1 = full ? PetscMin(C->gs[0] + C->gm[0] - 1 + PS_PAD + 1, ix->gs[0] + ix->gm[0]) : ix->gs[0] + ix->gm[0];
      for (n[0] = ix->gs[0]; n[0] < ix->gs[0] + ix->gm[0]; n[0]++) {
        PetscReal mc = 0.0;
        if (n[0] == x0 && x0 < x1) {
          /* the run [x0, x1) at once, each node's cells at fixed offsets
             from a pointer along the row (a loop the compiler can take in
             SIMD lanes, each node's sum in the same order); a cell without
             mass adds w 0 = 0, which changes no sum: no test */
          const PetscReal *Mr = &C->Mcell[PSCellIdx(C, x0 - PS_PAD - 1, n[1] - PS_PAD - 1, dim == 3 ? n[2] - PS_PAD - 1 : 0)];
          PetscReal       *mr = &mcn[Lidx(ix, x0, n[1], n[2])];
          PetscInt         x;
          for (x = 0; x < x1 - x0; x++) {
            PetscReal sm = 0.0;
            for (a = 0; a < nco; a++) sm += w * Mr[x + off[a]];
            mr[x] = sm;
          }
          n[0] = x1 - 1;
          continue;
        }
        /* the cells with node n as a corner, clipped to the ghosted cell box */
        for (e = 0; e < 3; e++) {
          lo[e] = e < dim ? PetscMax(n[e] - PS_PAD - 1, C->gs[e]) : 0;
          hi[e] = e < dim ? PetscMin(n[e] - PS_PAD, C->gs[e] + C->gm[e] - 1) : 0;
        }
        for (c[2] = lo[2]; c[2] <= hi[2]; c[2]++)
          for (c[1] = lo[1]; c[1] <= hi[1]; c[1]++)
            for (c[0] = lo[0]; c[0] <= hi[0]; c[0]++) {
              const PetscReal Mc = C->Mcell[PSCellIdx(C, c[0], c[1], c[2])];
              if (Mc != 0.0) mc += w * Mc;
            }
        mcn[Lidx(ix, n[0], n[1], n[2])] = mc;
      }
    }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode PSCellsNodalMassGather(PSSolver *S, const PSIndex *ix, PetscReal *mcn, PetscInt n0, PetscInt n1)
{
  PetscFunctionBeginUser;
  if (S->dim == 2) PetscCall(NodalMassGatherDim(S, ix, mcn, n0, n1, 2));
  else PetscCall(NodalMassGatherDim(S, ix, mcn, n0, n1, 3));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* the nodal masses m^C_i, with each ghosted cell's M_c and materials with
   mass (C->Mcell, C->sole: PSCellsCellMass) for the remap and the
   Lagrangian phases; every change of the cells' masses ends here (the fit,
   insertion, restart, the remap's sweeps).  owned_set: the owned cells' M_c
   are already set (the remap's cell update), so only the ghost cells' (just
   exchanged) are taken; the nodes' sums over the units [n0, n1) of nodes
   along y (2D) or z (3D) alone (grid indices: the remap's sweep has summed
   the others behind its cells' update) */
PetscErrorCode PSCellsNodalMassUnits(PSSolver *S, const PSIndex *ix, PetscBool owned_set, PetscInt n0, PetscInt n1)
{
  PSCells *C = S->cells;
  PetscInt i, j, k;

  PetscFunctionBeginUser;
  for (k = C->gs[2]; k < C->gs[2] + C->gm[2]; k++)
    for (j = C->gs[1]; j < C->gs[1] + C->gm[1]; j++) {
      /* a row through the owned cells skips them (one test per row) */
      const PetscBool skip = owned_set && j >= C->cs[1] && j < C->ce[1] && k >= C->cs[2] && k < C->ce[2];
      for (i = C->gs[0]; i < C->gs[0] + C->gm[0]; i++) {
        if (skip && i == C->cs[0]) i = C->ce[0];
        if (i >= C->gs[0] + C->gm[0]) break;
        PSCellsCellMass(C, PSCellIdx(C, i, j, k));
      }
    }
  PetscCall(PSCellsNodalMassGather(S, ix, C->mcn, n0, n1));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode PSCellsNodalMass(PSSolver *S, const PSIndex *ix, PetscBool owned_set)
{
  PetscFunctionBeginUser;
  PetscCall(PSCellsNodalMassUnits(S, ix, owned_set, PETSC_MIN_INT, PETSC_MAX_INT));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Exact insertion of the bodies in cells (see the top of the file), then
   the ghosts and nodal masses. */
PetscErrorCode PSCellsInsert(PSSolver *S)
{
  const PSScene *scene = S->scene;
  PSCells       *C     = S->cells;
  const PetscInt dim   = S->dim, nz = dim == 3 ? 2 : 1;
  PetscReal      hmax  = 0.0;
  PetscInt       b, d, i, j, k, a, bb, c;
  PSIndex        ix;

  PetscFunctionBeginUser;
  PetscCall(PSGridIndex(S->da, &ix));
  PetscCall(PetscArrayzero(C->u, C->ncl * C->dof));
  PetscCall(PetscArrayzero(C->P, C->nnl * dim));
  for (d = 0; d < dim; d++) hmax = PetscMax(hmax, S->h[d]);
  for (b = 0; b < scene->nbody; b++) {
    const PSBody     *B = &scene->bodies[b];
    const PSMaterial *M;
    PSRegion          reg, sub[PS_MAX_SUB];
    PetscReal         blo[3], bhi[3], A, Bc, c2, e0, rho;
    PetscInt          bcs[3], bce[3], nsub = 0, o, own;
    if (B->cellmat < 0) continue;
    M = &S->mat[C->mat[B->cellmat]];
    /* the initial density: the body's (a region of the same material at
       another state, as a CTH insertion's density), else the material's */
    rho = B->density > 0.0 ? B->density : M->rho0;
    /* e0 from the initial pressure at the initial density (J = rho0 / rho) */
    PetscCall(M->eos_fn(M, M->rho0 / rho, B->pressure, 0.0, &A, &Bc, &c2));
    PetscCheck(Bc > 0.0 || B->pressure == A, PETSC_COMM_SELF, PETSC_ERR_ARG_WRONG, "body %" PetscInt_FMT ": its EOS cannot reach the initial pressure %g Pa at its density %g kg/m^3", b, (double)B->pressure, (double)rho);
    e0 = Bc > 0.0 ? (B->pressure - A) / Bc : 0.0;
    PetscCall(PSBodyBoundingBox(scene, b, blo, bhi));
    PSCellRange(scene, blo, bhi, bcs, bce);
    /* the cells around the owned nodes: the owned ones take their part of
       the body, the owned nodes the momentum of all of theirs (in the order
       one rank takes it: PSCellsXIdx) */
    for (d = 0; d < 3; d++) {
      bcs[d] = PetscMax(bcs[d], C->xs[d]);
      bce[d] = PetscMin(bce[d], C->ce[d]);
    }
    if (bcs[0] >= bce[0] || bcs[1] >= bce[1] || bcs[2] >= bce[2]) continue;
    PSRegionSetup(scene, B, -1, hmax, &reg);
    for (o = 0; o < scene->nbody; o++) {
      if (o == b || scene->bodies[o].priority <= B->priority) continue;
      PetscCheck(nsub < PS_MAX_SUB, PETSC_COMM_SELF, PETSC_ERR_SUP, "body %" PetscInt_FMT " lies under more than %d higher-priority bodies", b, PS_MAX_SUB);
      PSRegionSetup(scene, &scene->bodies[o], -1, hmax, &sub[nsub++]);
    }
    for (k = bcs[2]; k < bce[2]; k++)
      for (j = bcs[1]; j < bce[1]; j++)
        for (i = bcs[0]; i < bce[0]; i++) {
          const PetscInt idx[3] = {i, j, k}, q0[3] = {0, 0, 0};
          double         lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0}, m[4] = {0, 0, 0, 0};
          PetscReal     *blk, dm;
          PSSubCellBounds(scene, idx, 1, q0, lo, hi);
          if (PSRegionClassify(dim, &reg, lo, hi) == PS_OUT) continue;
          PSPieceMoments(dim, lo, hi, 1, &reg, nsub, sub, m);
          if (m[0] <= 1e-14 * C->Vc) continue;
          dm = rho * m[0];
          if (i >= C->cs[0] && j >= C->cs[1] && k >= C->cs[2]) {
            blk = PSCellsBlk(C, PSCellIdx(C, i, j, k), B->cellmat);
            blk[PS_CV] += m[0];
            blk[PS_CM] += dm;
            blk[PS_CE] += dm * e0;
            if (C->nq) {
              blk[PS_CQ + C->ns] += dm * B->plastic_strain; /* M eps_p */
              blk[PS_CQ + C->ns + 1] += dm * M->T_room;     /* M T; no deviator */
            }
          }
          /* the body's velocity: M v / 2^dim to each owned corner */
          own = PSCellsOwnedCorners(&ix, dim, i, j, k);
          for (c = 0; c < nz; c++)
            for (bb = 0; bb < 2; bb++)
              for (a = 0; a < 2; a++) {
                const PetscInt o2 = Lidx(&ix, i + PS_PAD + a, j + PS_PAD + bb, dim == 3 ? k + PS_PAD + c : 0);
                if (!((own >> (a + 2 * bb + 4 * c)) & 1)) continue;
                for (d = 0; d < dim; d++) C->P[dim * o2 + d] += dm * B->velocity[d] / (dim == 3 ? 8.0 : 4.0);
              }
        }
  }
  /* the owners' sums to the ghosts */
  PetscCall(PSHaloBcast(C->sfp, C->P));
  PetscCall(PSCellsExchange(C));
  PetscCall(PSCellsNodalMass(S, &ix, PETSC_FALSE));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* an owned node of the node DMDA (its local index o) */
static inline PetscBool OwnedNode(const PSIndex *ix, PetscInt i, PetscInt j, PetscInt k)
{
  return i >= ix->os[0] && i < ix->os[0] + ix->om[0] && j >= ix->os[1] && j < ix->os[1] + ix->om[1] && k >= ix->os[2] && k < ix->os[2] + ix->om[2];
}

/* this rank's share of the totals: loc = mass, momentum (3), kinetic,
   internal energy of the cell materials; the largest cell pressure */
PetscErrorCode PSCellsTotals(PSSolver *S, PetscReal loc[6], PetscReal *pmax)
{
  PSCells       *C   = S->cells;
  const PetscInt dim = S->dim;
  PetscInt       i, j, k, m, d;
  PSIndex        ix;

  PetscFunctionBeginUser;
  PetscCall(PSGridIndex(S->da, &ix));
  for (k = C->cs[2]; k < C->ce[2]; k++)
    for (j = C->cs[1]; j < C->ce[1]; j++)
      for (i = C->cs[0]; i < C->ce[0]; i++) {
        const PetscInt ci = PSCellIdx(C, i, j, k);
        for (m = 0; m < C->nmat; m++) {
          const PetscReal *blk = PSCellsBlk(C, ci, m);
          PetscReal        p = 0.0, c = 0.0; /* (set by PSCellsPressure; GCC cannot see it on its error path) */
          if (blk[PS_CM] <= 0.0) continue;
          loc[0] += blk[PS_CM];
          loc[5] += blk[PS_CE];
          PetscCall(PSCellsPressure(S, m, blk, &p, &c));
          *pmax = PetscMax(*pmax, p);
        }
      }
  for (k = ix.os[2]; k < ix.os[2] + ix.om[2]; k++)
    for (j = ix.os[1]; j < ix.os[1] + ix.om[1]; j++)
      for (i = ix.os[0]; i < ix.os[0] + ix.om[0]; i++) {
        const PetscInt   o = Lidx(&ix, i, j, k);
        const PetscReal *P = &C->P[dim * o];
        PetscReal        p2 = 0.0;
        for (d = 0; d < dim; d++) {
          loc[1 + d] += P[d];
          p2 += P[d] * P[d];
        }
        if (C->mcn[o] > 0.0) loc[4] += 0.5 * p2 / C->mcn[o];
      }
  (void)OwnedNode;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* This rank's owned cells copied out (ny x nx x dof or nz x ny x nx x dof,
   x fastest), their corner cs and size cm, and the layout (nmat, ms, dof);
   out may be NULL to ask for the sizes.  For tests and post-processing. */
PetscErrorCode PSSolverCellsGet(PSSolver *S, PetscInt cs[3], PetscInt cm[3], PetscInt layout[3], PetscReal *out)
{
  PSCells *C = S->cells;
  PetscInt i, j, k, d, n = 0;

  PetscFunctionBeginUser;
  if (!C) {
    for (d = 0; d < 3; d++) cs[d] = cm[d] = layout[d] = 0;
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  for (d = 0; d < 3; d++) {
    cs[d] = C->cs[d];
    cm[d] = C->ce[d] - C->cs[d];
  }
  layout[0] = C->nmat;
  layout[1] = C->ms;
  layout[2] = C->dof;
  if (!out) PetscFunctionReturn(PETSC_SUCCESS);
  for (k = C->cs[2]; k < C->ce[2]; k++)
    for (j = C->cs[1]; j < C->ce[1]; j++)
      for (i = C->cs[0]; i < C->ce[0]; i++, n++) PSCellsCopyOut(C, PSCellIdx(C, i, j, k), &out[n * C->dof]);
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The cell materials' nodal mass and momentum of this rank's owned nodes
   (physical node indices ns, sizes nm; per node m^C then P^C, dim reals). */
PetscErrorCode PSSolverCellNodesGet(PSSolver *S, PetscInt ns[3], PetscInt nm[3], PetscReal *out)
{
  PSCells *C = S->cells;
  PSIndex  ix;
  PetscInt i, j, k, d, n = 0;

  PetscFunctionBeginUser;
  PetscCall(PSGridIndex(S->da, &ix));
  for (d = 0; d < 3; d++) {
    ns[d] = d < S->dim ? ix.os[d] - PS_PAD : 0;
    nm[d] = ix.om[d];
  }
  if (!out || !C) PetscFunctionReturn(PETSC_SUCCESS);
  for (k = ix.os[2]; k < ix.os[2] + ix.om[2]; k++)
    for (j = ix.os[1]; j < ix.os[1] + ix.om[1]; j++)
      for (i = ix.os[0]; i < ix.os[0] + ix.om[0]; i++, n++) {
        const PetscInt o = Lidx(&ix, i, j, k);
        out[n * (1 + S->dim)] = C->mcn[o];
        for (d = 0; d < S->dim; d++) out[n * (1 + S->dim) + 1 + d] = C->P[S->dim * o + d];
      }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* /cells in a grid file (the viewer is open on it): volume_fraction (ny, nx,
   nmat) with the attribute materials (their names, deck order), density
   (kg/m^3: cell-material mass / cell volume), pressure (Pa, weighted by
   volume fraction), velocity (ny, nx, dim; the mean of the corners' cell
   velocity P^C / m^C), specific_energy (J/kg); 3D with nz first. */
PetscErrorCode PSCellsWrite(PSSolver *S, PetscViewer v, const char *const material_names[])
{
  PSCells       *C = S->cells;
  const PetscInt dim = S->dim, nco = 1 << dim;
  DM             dm[3];
  Vec            X[5];
  PetscReal     *a[5];
  const char    *names[5] = {"volume_fraction", "density", "pressure", "velocity", "specific_energy"};
  const PetscInt dofs[5]  = {C->nmat, 1, 1, dim, 1};
  PetscInt       i, j, k, m, d, c, n = 0, f;
  PSIndex        ix;

  PetscFunctionBeginUser;
  PetscCall(PSGridIndex(S->da, &ix));
  PetscCall(DMDACreateCompatibleDMDA(C->dac, C->nmat, &dm[0]));
  PetscCall(DMDACreateCompatibleDMDA(C->dac, 1, &dm[1]));
  PetscCall(DMDACreateCompatibleDMDA(C->dac, dim, &dm[2]));
  for (f = 0; f < 5; f++) {
    PetscCall(DMCreateGlobalVector(dofs[f] == C->nmat && f == 0 ? dm[0] : dofs[f] == dim && f == 3 ? dm[2] : dm[1], &X[f]));
    PetscCall(PetscObjectSetName((PetscObject)X[f], names[f]));
    PetscCall(VecGetArray(X[f], &a[f]));
  }
  for (k = C->cs[2]; k < C->ce[2]; k++)
    for (j = C->cs[1]; j < C->ce[1]; j++)
      for (i = C->cs[0]; i < C->ce[0]; i++, n++) {
        const PetscInt ci = PSCellIdx(C, i, j, k);
        PetscReal      Mc = 0.0, Ec = 0.0, pc = 0.0;
        for (m = 0; m < C->nmat; m++) {
          const PetscReal *blk = PSCellsBlk(C, ci, m);
          PetscReal        p = 0.0, cs = 0.0; /* (set by PSCellsPressure; GCC cannot see it on its error path) */
          a[0][n * C->nmat + m] = blk[PS_CV] / C->Vc;
          Mc += blk[PS_CM];
          Ec += blk[PS_CE];
          PetscCall(PSCellsPressure(S, m, blk, &p, &cs));
          pc += blk[PS_CV] / C->Vc * p;
        }
        a[1][n] = Mc / C->Vc;
        a[2][n] = pc;
        a[4][n] = Mc > 0.0 ? Ec / Mc : 0.0;
        for (d = 0; d < dim; d++) a[3][n * dim + d] = 0.0;
        for (c = 0; c < nco; c++) {
          const PetscInt o = Lidx(&ix, i + PS_PAD + (c & 1), j + PS_PAD + ((c >> 1) & 1), dim == 3 ? k + PS_PAD + ((c >> 2) & 1) : 0);
          for (d = 0; d < dim; d++) a[3][n * dim + d] += C->mcn[o] > 0.0 ? C->P[dim * o + d] / C->mcn[o] / nco : 0.0;
        }
      }
  PetscCall(PetscViewerHDF5PushGroup(v, "/cells"));
  for (f = 0; f < 5; f++) {
    PetscCall(VecRestoreArray(X[f], &a[f]));
    /* volume_fraction keeps its material axis even with one material */
    if (f == 0) PetscCall(PetscViewerHDF5SetBaseDimension2(v, PETSC_TRUE));
    PetscCall(VecView(X[f], v));
    if (f == 0) PetscCall(PetscViewerHDF5SetBaseDimension2(v, PETSC_FALSE));
    PetscCall(VecDestroy(&X[f]));
  }
  PetscCall(PetscViewerHDF5PopGroup(v));
  /* the materials' names on volume_fraction, a string array (collective) */
  {
    hid_t       fid, ds, sp, ty, at;
    hsize_t     nm = (hsize_t)C->nmat;
    const char *nmz[PS_MAX_CELLMAT];
    for (m = 0; m < C->nmat; m++) nmz[m] = material_names ? material_names[C->mat[m]] : "";
    PetscCall(PetscViewerHDF5GetFileId(v, &fid));
    ds = H5Dopen2(fid, "/cells/volume_fraction", H5P_DEFAULT);
    PetscCheck(ds >= 0, PETSC_COMM_SELF, PETSC_ERR_FILE_UNEXPECTED, "cannot open /cells/volume_fraction");
    ty = H5Tcopy(H5T_C_S1);
    H5Tset_size(ty, H5T_VARIABLE);
    sp = H5Screate_simple(1, &nm, NULL);
    at = H5Acreate2(ds, "materials", ty, sp, H5P_DEFAULT, H5P_DEFAULT);
    PetscCheck(at >= 0, PETSC_COMM_SELF, PETSC_ERR_FILE_UNEXPECTED, "cannot write the attribute materials");
    PetscCheck(H5Awrite(at, ty, nmz) >= 0, PETSC_COMM_SELF, PETSC_ERR_FILE_UNEXPECTED, "cannot write the attribute materials");
    H5Aclose(at);
    H5Sclose(sp);
    H5Tclose(ty);
    H5Dclose(ds);
  }
  for (f = 0; f < 3; f++) PetscCall(DMDestroy(&dm[f]));
  PetscFunctionReturn(PETSC_SUCCESS);
}
