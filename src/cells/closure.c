/*
  closure.c - mixed cells (docs/cells.md, "Mixed cells").

  A cell holds cell materials k (V_k), the markers' volume V_M and void
  V_0 = V_c - sum V_k - V_M.  Its box changes volume by dV in the Lagrangian
  phase; PSCellsShareVolume (closure.h) decides each material's dV_k in two parts:

  1. the change itself.  Void closes first (a compression is taken by void
     while there is any) and takes an expansion where there is void worth
     the name, above PS_VOID_TRACE of the cell (the relaxation then lets a
     gas expand into any void, a trace too); the rest is shared in proportion to the
     compliances chi_k = V_k / K_k, K_k = rho_k c_k^2 (and the markers'
     sum_p V_p / K_p), so every participant sees the same pressure increment:
     the isentropic, linearised form of pressure equilibrium.
  2. pressure relaxation toward a common pressure (after Tipton; Shashkov,
     "Closure models for multidimensional cells in ALE methods", 2008): with
     the pressures p_k' after part 1, the equilibrium of the linearised
     equations of state is p* = sum chi_k p_k' / sum chi_k (p* = 0 with void,
     whose compliance is infinite: a gas expands into void), reached by
     dV_k += chi_k (p_k' - p*).  The step is limited so no material loses
     more than half its volume and void never goes negative; a gas next to
     copper (K 1e5 against 1e11 Pa, density ratio 1e4) then relaxes over a few
     steps instead of crushing the gas in one.  The relaxation's exchange
     (dVr, summing to zero without void) is work at the one pressure p*, so
     it moves energy between the materials and makes none (into void, p* = 0:
     a free expansion); the Lagrangian phase books it so.
  The markers take no part in the relaxation: their pressure is their own.

  PSCellsFitMarkers runs after the markers move: their volume in each cell
  (each marker in the cell holding its centroid, and its compliance) sets
  V_M; where the cell materials no longer fit beside it they are compressed,
  in proportion to their compliances, along their isentropes; that work, done
  by the markers' displacement, is booked as coupling_work (history.csv) so
  the energy balance stays honest.  In a cell with a corner where marker
  bodies meet in contact (contact.c) the overflow is discarded instead, its
  mass, energy and nodal momentum booked as lost (DiscardMomentum).
*/
#include "closure.h"
#include "../contact.h"

#define PS_CROWD 1e-3 /* cell materials below this fraction of a cell the markers crowd out are discarded */
/* bulk compliance chi = V / K (m^3/Pa) of a material block and its pressure */
static PetscErrorCode Compliance(const PSSolver *S, PetscInt m, const PetscReal *blk, PetscReal *chi, PetscReal *p)
{
  PetscReal c = 0.0, rho; /* (c: set by PSCellsPressure; GCC cannot see it on its error path) */

  PetscFunctionBeginUser;
  PetscCall(PSCellsPressure(S, m, blk, p, &c));
  rho  = blk[PS_CM] / blk[PS_CV];
  *chi = blk[PS_CV] / (rho * PetscMax(c * c, 1e-6)); /* a cold gas at p = 0: very compliant, still finite */
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* PSCellsPressure's ideal gas and EOSCache's compliance for a run of len
   cells c0 + x of one gas s (gamma g), its slots ec (PS_EC reals apart:
   consecutive, each cell one), in SIMD lanes: the same operations, a
   divisor 1 where the value is not used (a block without mass or volume
   gets zeros, as in the loop) */
static inline void EOSGasRun(const PSCells *C, PetscInt s, PetscReal g, PetscInt c0, PetscInt len, PetscReal *ec)
{
  const PetscReal *blk = &C->u[PS_CQ * c0 + s * C->mst];
  PetscInt         x;

#pragma GCC ivdep
  for (x = 0; x < len; x++) {
    const PetscReal V = blk[PS_CQ * x + PS_CV], M = blk[PS_CQ * x + PS_CM], E = blk[PS_CQ * x + PS_CE];
    const int       ok = (M > 0.0) & (V > 0.0); /* (&, not &&: no branch, or GCC keeps the loop scalar) */
    const PetscReal Vd = ok ? V : 1.0, Md = ok ? M : 1.0;
    const PetscReal p = (g - 1.0) * E / Vd, c = PetscSqrtReal(g * PetscMax(p, 0.0) * Vd / Md);
    const PetscReal chi = Vd * Vd / (Md * PetscMax(c * c, 1e-6));
    ec[PS_EC * x]     = ok ? p : 0.0;
    ec[PS_EC * x + 1] = ok ? c : 0.0;
    ec[PS_EC * x + 2] = ok ? chi : 0.0;
  }
}

/* The materials' pressure, sound speed and compliance of each cell around
   the owned nodes (PSCellsEC(C, PSCellsXIdx)[PS_EC m + ...]: the owned
   cells and the ghost layer whose forces reach owned nodes), once per step
   before the cells' P2G: the state does not change until the Lagrangian
   phase has used them.  Stored for the materials present only (a pure
   cell's PS_EC reals, not PS_EC nmat: the quadrants' four gases read and
   wrote 96 bytes per cell, now 24), in the order of the cells; every
   reader takes [m0, m1) (PSCellsPresent), which the remap and the fit
   alone change. */
PetscErrorCode PSCellsEOSCache(PSSolver *S)
{
  PSCells *C = S->cells;
  PetscInt j, k, n = 0;

  PetscFunctionBeginUser;
  PetscCall(PSCellsEOSSlots(S));
  for (k = C->xs[2]; k < C->ce[2]; k++)
    for (j = C->xs[1]; j < C->ce[1]; j++, n += C->ce[0] - C->xs[0]) PetscCall(PSCellsEOSRow(S, j, k, n));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* PSCellsEOSCache's slots: each cell's, after the padding, the cells in
   order, then the cells of the pipeline's edge units (PSCellsEdgeUnits);
   the cache's room */
PetscErrorCode PSCellsEOSSlots(PSSolver *S)
{
  PSCells *C = S->cells;
  PetscInt i, j, k, n, m0, m1, tot = C->nmat - 1, q, eu[2], en[2], e = C->dim - 1; /* (slots: the padding) */

  PetscFunctionBeginUser;
  PSCellsEdgeUnits(C, &eu[0], &en[0], &eu[1], &en[1]);
  if (!C->eco) PetscCall(PetscMalloc1(PetscMax(1, PSCellsSlots(C)), &C->eco));
  for (q = -1; q < 2; q++) {
    /* q = -1: the cells around the owned nodes; 0, 1: the edge units */
    const PetscInt nrow = C->ce[0] - C->xs[0], nall = C->nmat; /* (locals: the stores to eco could alias C's fields) */
    PetscInt      *eco  = C->eco, lo[3] = {C->xs[0], C->xs[1], C->xs[2]}, hi[3] = {C->ce[0], C->ce[1], C->ce[2]};
    if (q >= 0) {
      if (eu[q] < 0) continue;
      lo[e] = eu[q];
      hi[e] = eu[q] + 1;
    }
    n = q < 0 ? 0 : en[q];
    for (k = lo[2]; k < hi[2]; k++)
      for (j = lo[1]; j < hi[1]; j++) {
        const short *sole = &C->sole[PSCellIdx(C, C->xs[0], j, k)];
        for (i = 0; i < nrow; i++, n++) {
          PSCellsSoleRange(sole[i], nall, &m0, &m1); /* (PSCellsPresent's, on the locals) */
          eco[n] = tot - m0;
          tot += m1 - m0;
        }
      }
  }
  if (tot > C->nec) {
    /* (with room for a quarter more: mixed cells come and go) */
    PetscCall(PetscFree(C->ec));
    PetscCall(PetscFree(C->hm));
    C->nec = tot + tot / 4;
    PetscCall(PetscCalloc1(PS_EC * C->nec, &C->ec));
    PetscCall(PetscCalloc1(PSCellsHalfMat(C) * C->nec, &C->hm));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* PSCellsEOSCache's values of the row (j, k) of the cells around the owned
   nodes (PSCellsXIdx), its first cell's slot index n0 (after
   PSCellsEOSSlots): a run of an ideal gas's pure cells (no shear modulus)
   in lanes.  A row reads its own cells alone, so the cells' P2G takes a
   row's values just before it reads them */
PetscErrorCode PSCellsEOSRow(PSSolver *S, PetscInt j, PetscInt k, PetscInt n0)
{
  PSCells  *C = S->cells;
  PetscInt  i, m, n = n0, m0, m1;
  PetscBool gas[PS_MAX_CELLMAT];

  PetscFunctionBeginUser;
  for (m = 0; m < C->nmat; m++) gas[m] = C->gasf[m] && S->mat[C->mat[m]].G == 0.0 && C->ms == PS_CQ && S->run.lanes != 1 ? PETSC_TRUE : PETSC_FALSE;
  for (i = C->xs[0]; i < C->ce[0]; i++, n++) {
    const PetscInt   ci = PSCellIdx(C, i, j, k), s = C->sole[ci];
    const PetscReal *u  = &C->u[C->ms * ci];
    PetscReal       *ecn = PSCellsEC(C, n);
    if (s >= 0 && gas[s]) {
      const PetscInt b = i + PSCellsSoleRun(&C->sole[ci], C->ce[0] - i);
      if (b - i >= PS_LANES_RUN) {
        EOSGasRun(C, s, C->gam[s], ci, b - i, &ecn[PS_EC * s]); /* (a pure cell's one slot: the run's are consecutive) */
        n += b - i - 1;
        i = b - 1;
        continue;
      }
    }
    PSCellsPresent(C, ci, &m0, &m1);
    for (m = m0; m < m1; m++) {
      const PetscReal *blk = &u[m * C->mst];
      PetscReal       *ec  = &ecn[PS_EC * m];
      if (blk[PS_CM] <= 0.0 || blk[PS_CV] <= 0.0) {
        ec[0] = ec[1] = ec[2] = 0.0;
        continue;
      }
      PetscCall(PSCellsPressure(S, m, blk, &ec[0], &ec[1]));
      ec[2] = blk[PS_CV] * blk[PS_CV] / (blk[PS_CM] * PetscMax(ec[1] * ec[1], 1e-6)); /* V / (rho c^2); a cold gas at p = 0: very compliant, still finite */
    }
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* the general case of PSCellsShareVolume (closure.h), which takes a cell with
   one material and no void itself */
PetscErrorCode PSCellsShareVolumeGeneral(const PSSolver *S, PetscInt ci, const PetscReal *ec, PetscInt m0, PetscInt m1, PetscReal dV, PetscReal dVk[], PetscReal dVr[], PetscReal *pr)
{
  const PSCells   *C  = S->cells;
  const PetscReal *u = &C->u[C->ms * ci];
  const PetscReal  VM = *PSCellsX(C, ci, PS_CX_AM) * C->Vc, chiM = *PSCellsX(C, ci, PS_CX_CM);
  PetscReal       chi[PS_MAX_CELLMAT], p[PS_MAX_CELLMAT], Vm = 0.0, sumchi = 0.0, V0, rest, theta = 1.0, pstar = 0.0, sumd = 0.0;
  PetscInt        m, n = 0;
  PetscBool       hasvoid;

  PetscFunctionBeginUser;
  if (pr) *pr = 0.0;
  for (m = m0; m < m1; m++) {
    const PetscReal *blk = &u[m * C->mst];
    dVk[m] = chi[m] = p[m] = 0.0;
    if (dVr) dVr[m] = 0.0;
    if (blk[PS_CM] <= 0.0 || blk[PS_CV] <= 0.0) continue;
    chi[m] = ec[PS_EC * m + 2];
    p[m]   = ec[PS_EC * m];
    Vm += blk[PS_CV];
    sumchi += chi[m];
    n++;
  }
  if (!n) PetscFunctionReturn(PETSC_SUCCESS);
  V0 = PetscMax(C->Vc - Vm - VM, 0.0);
  /* 1. void first, the rest by compliance (closure.h) */
  rest = PSCellsVoidShare(C, dV, &V0);
  for (m = m0; m < m1; m++) dVk[m] = PSCellsMaterialShare(rest, chi[m], sumchi, chiM, u[m * C->mst + PS_CV]);
  /* 2. relaxation toward p* (p* = 0 with void) */
  hasvoid = V0 > PS_VOID_ROUNDOFF * C->Vc ? PETSC_TRUE : PETSC_FALSE;
  if (!hasvoid) {
    if (n < 2) PetscFunctionReturn(PETSC_SUCCESS);
    for (m = m0; m < m1; m++)
      if (chi[m] > 0.0) pstar += chi[m] * (p[m] - dVk[m] / chi[m]);
    pstar /= sumchi;
  }
  for (m = m0; m < m1; m++) {
    const PetscReal *blk = &u[m * C->mst];
    PetscReal        d;
    if (chi[m] <= 0.0) continue;
    d = chi[m] * (p[m] - dVk[m] / chi[m] - pstar);
    /* no material loses more than half its volume in one relaxation */
    if (blk[PS_CV] + dVk[m] + theta * d < 0.5 * (blk[PS_CV] + dVk[m])) theta = PetscMin(theta, 0.5 * (blk[PS_CV] + dVk[m]) / -d);
    sumd += d;
  }
  /* void cannot go negative (without void the shifts sum to zero) */
  if (hasvoid && sumd > 0.0 && V0 < theta * sumd) theta = V0 / sumd;
  for (m = m0; m < m1; m++)
    if (chi[m] > 0.0) {
      const PetscReal r = theta * chi[m] * (p[m] - dVk[m] / chi[m] - pstar);
      dVk[m] += r;
      if (dVr) dVr[m] = r;
    }
  if (pr) *pr = pstar;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* whether cell (i, j, k) has a corner where marker bodies meet in contact
   (contact.c's shared nodes of this step) */
static inline PetscBool ContactZone(const PSSolver *S, const PSIndex *ix, PetscInt i, PetscInt j, PetscInt k)
{
  const PetscInt dim = S->dim;
  PetscInt       a, b, c;
  for (c = 0; c < (dim == 3 ? 2 : 1); c++)
    for (b = 0; b < 2; b++)
      for (a = 0; a < 2; a++)
        if (S->contact->shared[Lidx(ix, i + PS_PAD + a, j + PS_PAD + b, dim == 3 ? k + PS_PAD + c : 0)]) return PETSC_TRUE;
  return PETSC_FALSE;
}

/* The fit's discards (C->dep: each owned cell's discarded mass) take their
   share of the nodal momentum with them at the node's velocity, booked as
   lost with its kinetic energy on the owned nodes (before, the nodes kept
   the momentum of the mass that left, and the rest sped up) */
static PetscErrorCode DiscardMomentum(PSSolver *S, const PSIndex *ix)
{
  PSCells        *C = S->cells;
  const PetscInt  dim = S->dim, nco = 1 << dim;
  PetscReal      *dm = C->df, *dep = C->dep; /* the predictor's scratch, free here: discarded mass per node (the whole array: PSCellsWindowEnd) */
  PetscInt        i, j, k, a, d, o, n = 0;
  PetscBool       any;

  PetscFunctionBeginUser;
  for (o = 0; o < C->ncl; o++) n += dep[2 * o] > 0.0;
  any = n > 0 ? PETSC_TRUE : PETSC_FALSE;
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &any, 1, MPIU_BOOL, MPI_LOR, PetscObjectComm((PetscObject)S->da)));
  if (!any) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(PSHaloBcast(C->sfd, dep)); /* the ghost cells' discards */
  C->dep_dirty = PETSC_TRUE;
  PetscCall(PetscArrayzero(dm, C->nnl));
  for (k = C->gs[2]; k < C->gs[2] + C->gm[2]; k++)
    for (j = C->gs[1]; j < C->gs[1] + C->gm[1]; j++)
      for (i = C->gs[0]; i < C->gs[0] + C->gm[0]; i++) {
        const PetscReal dmc = dep[2 * PSCellIdx(C, i, j, k)];
        if (dmc <= 0.0) continue;
        for (a = 0; a < nco; a++) {
          const PetscInt n0 = i + PS_PAD + (a & 1), n1 = j + PS_PAD + ((a >> 1) & 1), n2 = dim == 3 ? k + PS_PAD + ((a >> 2) & 1) : 0;
          if (n0 < ix->gs[0] || n0 >= ix->gs[0] + ix->gm[0] || n1 < ix->gs[1] || n1 >= ix->gs[1] + ix->gm[1]) continue;
          if (dim == 3 && (n2 < ix->gs[2] || n2 >= ix->gs[2] + ix->gm[2])) continue;
          dm[Lidx(ix, n0, n1, n2)] += dmc / nco;
        }
      }
  for (k = ix->gs[2]; k < ix->gs[2] + ix->gm[2]; k++)
    for (j = ix->gs[1]; j < ix->gs[1] + ix->gm[1]; j++)
      for (i = ix->gs[0]; i < ix->gs[0] + ix->gm[0]; i++) {
        const PetscBool own = i >= ix->os[0] && i < ix->os[0] + ix->om[0] && j >= ix->os[1] && j < ix->os[1] + ix->om[1] && (dim < 3 || (k >= ix->os[2] && k < ix->os[2] + ix->om[2]));
        PetscReal       m0, k2 = 0.0;
        o = Lidx(ix, i, j, k);
        if (dm[o] <= 0.0) continue;
        m0 = C->mcn[o] + dm[o]; /* the node's mass before the discards */
        for (d = 0; d < dim; d++) {
          const PetscReal v = C->P[dim * o + d] / m0;
          C->P[dim * o + d] -= dm[o] * v;
          k2 += v * v;
          if (own) S->lost_local.p[d] += dm[o] * v;
        }
        if (own) S->lost_local.kinetic += 0.5 * dm[o] * k2;
      }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Markers' volume and compliance into the cells (their share PS_CX_AM and
   compliance PS_CX_CM), each marker as a box of its volume centred on it
   (V_p^(1/dim) a side; the boxes tile a body as inserted) shared among the
   cells it overlaps, so a body's share of a cell grows smoothly as it moves
   in; boxes reaching a neighbour's cells are summed by the ghost exchange */
static PetscErrorCode DepositMarkers(PSSolver *S)
{
  PSCells        *C   = S->cells;
  const PetscInt  dim = S->dim;
  PetscInt        n, p, d, i, j, k, *mat, c;
  PetscReal      *x, *vol, *V0, *F, *dep = C->dep;

  PetscFunctionBeginUser;
  PetscCall(PetscArrayzero(dep, 2 * C->ncl));
  PetscCall(DMSwarmGetLocalSize(S->sw, &n));
  PetscCall(DMSwarmGetField(S->sw, PS_FIELD_X, NULL, NULL, (void **)&x));
  PetscCall(DMSwarmGetField(S->sw, PS_FIELD_VOLUME, NULL, NULL, (void **)&vol));
  PetscCall(DMSwarmGetField(S->sw, PS_FIELD_MATERIAL, NULL, NULL, (void **)&mat));
  PetscCall(DMSwarmGetField(S->sw, PS_FIELD_V0, NULL, NULL, (void **)&V0));
  PetscCall(DMSwarmGetField(S->sw, PS_FIELD_F, NULL, NULL, (void **)&F));
  for (p = 0; p < n; p++) {
    const PetscReal a0 = dim == 3 ? PetscCbrtReal(V0[p]) : PetscSqrtReal(V0[p]);
    PetscInt        c0[3] = {0, 0, 0};
    PetscReal       w[3][2] = {{1, 0}, {1, 0}, {1, 0}};
    /* per direction: the box's side a = a0 |F_dd| (it shortens along a
       compression, so a body's boxes keep tiling it in uniaxial strain), the
       two cells it can overlap and its share in each */
    for (d = 0; d < dim; d++) {
      const PetscReal a  = a0 * PetscAbsReal(F[p * dim * dim + d * dim + d]);
      const PetscReal lo = (x[p * dim + d] - 0.5 * a - S->scene->lower[d]) * S->ih[d], hi = lo + a * S->ih[d];
      const PetscReal f  = PetscFloorReal(lo);
      c0[d]   = (PetscInt)f;
      w[d][1] = hi > f + 1.0 ? (hi - (f + 1.0)) / (hi - lo) : 0.0;
      w[d][0] = 1.0 - w[d][1];
    }
    for (c = 0; c < (1 << dim); c++) {
      PetscInt  cc[3] = {0, 0, 0}, o;
      PetscReal share = 1.0;
      for (d = 0; d < dim; d++) {
        const PetscInt b = (c >> d) & 1;
        share *= w[d][b];
        /* clipped to the domain and the ghosted box (a box reaches one cell out) */
        cc[d] = PetscMin(PetscMax(c0[d] + b, PetscMax(C->gs[d], 0)), PetscMin(C->gs[d] + C->gm[d], C->nc[d]) - 1);
      }
      if (share <= 0.0) continue;
      o = PSCellIdx(C, cc[0], cc[1], cc[2]);
      dep[2 * o] += share * vol[p] / C->Vc;
      dep[2 * o + 1] += share * vol[p] / C->Kmat[mat[p]];
    }
  }
  PetscCall(DMSwarmRestoreField(S->sw, PS_FIELD_F, NULL, NULL, (void **)&F));
  PetscCall(DMSwarmRestoreField(S->sw, PS_FIELD_V0, NULL, NULL, (void **)&V0));
  PetscCall(DMSwarmRestoreField(S->sw, PS_FIELD_MATERIAL, NULL, NULL, (void **)&mat));
  PetscCall(DMSwarmRestoreField(S->sw, PS_FIELD_VOLUME, NULL, NULL, (void **)&vol));
  PetscCall(DMSwarmRestoreField(S->sw, PS_FIELD_X, NULL, NULL, (void **)&x));
  PetscCall(PSHaloReduce(C->sfd, dep));
  for (k = C->cs[2]; k < C->ce[2]; k++)
    for (j = C->cs[1]; j < C->ce[1]; j++)
      for (i = C->cs[0]; i < C->ce[0]; i++) {
        const PetscInt o = PSCellIdx(C, i, j, k);
        *PSCellsX(C, o, PS_CX_AM) = dep[2 * o];
        *PSCellsX(C, o, PS_CX_CM) = dep[2 * o + 1];
      }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The markers' share of each cell (DepositMarkers), then the cell materials
   fitted beside them.  A scene without marker bodies keeps the share 0 set
   at insertion, and where no cell needed fitting (nearly always: the remap
   gives each cell its volume back) the state, its ghosts and the nodal
   masses are the remap's: they are neither redone nor exchanged. */
PetscErrorCode PSCellsFitMarkers(PSSolver *S, PetscBool fit)
{
  PSCells  *C = S->cells;
  PetscInt  i, j, k, m, nfit = 0;
  PetscReal *dep = C->dep;
  PSIndex   ix;
  PetscBool none;

  PetscFunctionBeginUser;
  /* in a scene without marker bodies the remap's heat has counted the cells
     the fit's test finds over their room (C->over, HeatUnit): where none,
     the loop below is skipped */
  none    = fit && !C->markers && C->over == 0 ? PETSC_TRUE : PETSC_FALSE;
  C->over = -1;
  if (C->markers || !fit) PetscCall(DepositMarkers(S));
  /* dep now takes each cell's discarded mass (kg), for its nodes' momentum
     (zeroed only where something wrote it: without markers nearly never) */
  if (C->markers || !fit || C->dep_dirty) PetscCall(PetscArrayzero(dep, 2 * C->ncl));
  C->dep_dirty = PETSC_FALSE;
  PetscCall(PSGridIndex(S->da, &ix));
  /* fit: the cell materials compressed where they overflow the room beside
     the markers (not at insertion, which is exact: the boxes only
     approximate pieces cut at a body's edge) */
  for (k = C->cs[2]; k < (fit && !none ? C->ce[2] : C->cs[2]); k++)
    for (j = C->cs[1]; j < C->ce[1]; j++) {
      /* (the test of every cell in locals: the row's first index, the
         markers' share's plane, the cell volume) */
      const PetscInt   ci0 = PSCellIdx(C, 0, j, k), ms = C->ms, mst = C->mst, nm = C->nmat;
      const PetscReal *XA = PSCellsX(C, 0, PS_CX_AM), Vc = C->Vc;
      const short     *sole = C->sole;
      for (i = C->cs[0]; i < C->ce[0]; i++) {
        const PetscInt ci = ci0 + i;
        PetscReal     *u  = &C->u[ms * ci];
        PetscReal      Vm = 0.0, room = Vc * PetscMax(1.0 - XA[ci], 0.0), chi[PS_MAX_CELLMAT], pk[PS_MAX_CELLMAT], sumchi = 0.0, over;
        PetscInt       m0, m1, b;
        /* a run of cells of one gas block: the test below in SIMD lanes,
           the run passed over where no cell overflows (else each cell as
           below) */
        if (ms == PS_CQ && sole[ci] >= 0 && S->run.lanes != 1) {
          const PetscInt s = sole[ci];
          b = i + PSCellsSoleRun(&sole[ci], C->ce[0] - i);
          if (b - i >= PS_LANES_RUN) {
            const PetscReal *B = &C->u[PS_CQ * ci + s * mst], *XAr = &XA[ci];
            PetscInt         x, nover = 0;
#pragma GCC ivdep
            for (x = 0; x < b - i; x++) {
              const PetscReal Vx = 0.0 + B[PS_CQ * x + PS_CV]; /* (s has mass: it is the cell's sole) */
              nover += PSCellsOverRoom(Vx, Vc * PetscMax(1.0 - XAr[x], 0.0), Vc);
            }
            if (!nover) {
              i = b - 1;
              continue;
            }
          }
        }
        PSCellsSoleRange(sole[ci], nm, &m0, &m1); /* (PSCellsPresent; the others hold no mass) */
        Vm   = PSCellsVolumeWithMass(C, u, m0, m1);
        over = Vm - room;
        if (!PSCellsOverRoom(Vm, room, Vc)) continue; /* room enough (nearly every cell): no EOS needed */
        nfit++;
        for (m = 0; m < nm; m++) {
          chi[m] = 0.0;
          if (u[m * mst + PS_CM] <= 0.0) continue;
          PetscCall(Compliance(S, m, &u[m * mst], &chi[m], &pk[m]));
          sumchi += chi[m];
        }
        if (sumchi <= 0.0) continue;
        /* where the markers leave no room for less than PS_CROWD of a cell,
           that little is discarded (booked as lost) rather than crushed: a
           sliver squeezed against a marker body takes pressures that are no
           material's */
        if (Vm < PS_CROWD * Vc && room < Vm) {
          for (m = 0; m < nm; m++) {
            PetscReal *blk = &u[m * mst];
            PetscInt   q;
            dep[2 * ci] += blk[PS_CM];
            C->dep_dirty = PETSC_TRUE;
            S->lost_local.mass += blk[PS_CM];
            S->lost_local.internal += blk[PS_CE];
            C->discarded += blk[PS_CM];
            for (q = 0; q < ms; q++) blk[q] = 0.0;
          }
          continue;
        }
        /* in a cell at a node where marker bodies meet in contact
           (contact.c), the overflow is discarded, not crushed: there the
           cells' share moves with the fields' centre of mass, which neither
           body follows, and crushing the gas caught between two bodies drew
           its work from no one (the oblique plate in air: total x42,
           docs/contact.md) */
        if (S->contact && ContactZone(S, &ix, i, j, k)) {
          const PetscReal phi = PetscMin(over / Vm, 1.0);
          for (m = 0; m < nm; m++) {
            PetscReal *blk = &u[m * mst];
            PetscInt   q;
            dep[2 * ci] += phi * blk[PS_CM];
            C->dep_dirty = PETSC_TRUE;
            S->lost_local.mass += phi * blk[PS_CM];
            S->lost_local.internal += phi * blk[PS_CE];
            C->discarded += phi * blk[PS_CM];
            for (q = 0; q < ms; q++) blk[q] *= 1.0 - phi; /* mass, energy, volume and the extensive strength state */
          }
          continue;
        }
        /* no material is squeezed by more than a fifth of its volume in one
           step (the trapezoidal energy update stays accurate); the rest
           waits for the next */
        for (m = 0; m < nm; m++)
          if (chi[m] > 0.0) over = PetscMin(over, 0.2 * u[m * mst + PS_CV] * sumchi / chi[m]);
        for (m = 0; m < nm; m++) {
          const PSMaterial *M   = &S->mat[C->mat[m]];
          PetscReal        *blk = &u[m * mst];
          PetscReal         dVm, V1, A, B, c2, e1, p1;
          if (chi[m] <= 0.0) continue;
          dVm = -over * chi[m] / sumchi;
          V1  = blk[PS_CV] + dVm;
          PetscCall(PSCellsEOS(M, M->rho0 * V1 / blk[PS_CM], pk[m], dVm / blk[PS_CV], &A, &B, &c2));
          PSPressureEnergy(M, PETSC_FALSE, blk[PS_CE] / blk[PS_CM], 0.0, dVm / blk[PS_CM], pk[m], A, B, 0.0, &e1, &p1);
          C->coupling_work += blk[PS_CM] * e1 - blk[PS_CE];
          blk[PS_CE] = blk[PS_CM] * e1;
          blk[PS_CV] = V1;
        }
      }
    }
  if (!C->markers && fit) {
    PetscBool any = nfit > 0 ? PETSC_TRUE : PETSC_FALSE;
    PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &any, 1, MPIU_BOOL, MPI_LOR, PetscObjectComm((PetscObject)S->da)));
    if (!any) PetscFunctionReturn(PETSC_SUCCESS);
  }
  PetscCall(PSCellsExchange(C));
  PetscCall(PSCellsNodalMass(S, &ix, PETSC_FALSE));
  if (fit) PetscCall(DiscardMomentum(S, &ix));
  PetscFunctionReturn(PETSC_SUCCESS);
}
