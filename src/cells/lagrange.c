/*
  lagrange.c - the cells' Lagrangian phase (cells.h; docs/cells.md).

  PSCellsToGrid (with the markers' P2G, event PSCellsP2G): each cell with
  material adds to its 2^dim corners the nodal mass M_c / 2^dim and the force
      f_i = -(sum_k V_k s_k - (p_f + q) V_m I) . grad N_i(x_c),
  p_f the closure's pressure (the compliance-weighted mean, closure.c),
  grad N_i at the cell centre of the bilinear (trilinear) element: one-point
  quadrature, exact for the constant stress of a cell.  One-point quadrature
  leaves the element's hourglass modes (the corner patterns +-1 of xy, and in
  3D yz, xz, xyz; Flanagan & Belytschko, IJNME 17, 1981) without stiffness;
  a viscous hourglass force f_i = -kappa rho c (V/h) sum_m G_m(i) g_m / 2^dim
  (rho the cell's mass per cell volume, so a sliver's damping scales with its mass),
  g_m = sum_j G_m(j) v_j, damps them (kappa = 0.1), and its work heats the
  cell.  The owned nodes add the cell materials' momentum P^C_i.

  PSCellsPredict (after the grid update, event PSCellsPredict): the
  predictor-corrector of the cells' force, which makes the Lagrangian phase's
  energy compatible (Caramana, Burton, Shashkov & Whalen, JCP 146, 1998,
  sec. 4: the work the nodal forces do on the nodes equals the work the cells'
  energies give up, to round-off).  The grid update with the force at t^n
  gives the predicted v*; at v^{n+1/2*} = (v^n + v*)/2 each cell's half-step
  state follows (half the volume change, its materials' pressures p_k^h, the
  viscosity q^h, the deviators s_k^h, the hourglass rates g_m^h); the nodes
  then take the force change, v^{n+1} = v* + dt (f^{n+1/2} - f^n)/m_i (the
  markers' force stays at t^n).

  PSCellsLagrange (after the corrector, event PSCellsLagrange): the cell
  materials take the new nodal velocity, P^C_i = m^C_i v^{n+1}; the faces move
  with v^{n+1/2} = (v^n + v^{n+1})/2: each cell's velocity gradient at its
  centre gives its volume change dV = V_c dt tr L (the volume its faces sweep,
  each moving with the mean velocity of its corners: exactly what the remap
  then moves back), which closure.c shares among the materials, the markers'
  part and void; each material's energy gives up the work of the half-step
  force, e1 = e0 - (p_k^h + q^h) dV_k / M_k + V_k s_k^h : D dt / M_k + its
  share of the hourglass work kappa sum_m g_m^h . g_m dt, its deviator the
  Jaumann rate with a J2 return (Wilkins 1964), as CTH carries strength in
  cells.  Before the corrector (symplectic Euler: force at t^n, faces with
  v^{n+1}) a sharp gas charge lost as much energy in its first step as its
  gas gained kinetic energy (2D, 50 MPa in air: -0.7% in the first step,
  -2.6% at 1 us; 3D -2.9%, -9%).

  Lanes: the cells' P2G (in a scene without strength), the predictor and
  the Lagrangian phase take each row's cells of one ideal gas (no markers,
  no void, no deviator) in SIMD lanes first (ToGridGasLanes,
  PredictGasLanes, LagrangeGasLanes: the same arithmetic in the same order,
  without a branch; GasLanesWalk: a run of one gas's cells in lanes, its
  inputs loaded from its blocks), then the row's loop takes their values and
  does the rest (P2G's corners to the nodes in lanes too, GasLanesNodes, in
  the loop's order; the predictor's corners' sums; the Lagrangian phase's
  stores of a run of one gas in lanes; every other cell whole).
  -run_lanes 1 skips the lanes, for checks (bitwise the same).

  In a scene of cells alone the Lagrangian phase runs a unit (row in 2D,
  plane in 3D) behind the predictor, where the corrector has just finished
  the unit's nodes and the cells' state is still in the caches
  (LagrangeBehind; PSLagProgress in cells.h); PSCellsLagrange then runs
  what is left.  -run_lanes 1 keeps it to a pass of its own.
*/
#include "cells.h"
#include "closure.h"

static PetscLogEvent EV_C2G = 0, EV_Lag = 0, EV_Pred = 0;

/* local index of cell (i, j, k)'s lower corner node */
static inline PetscInt CellNode(const PSIndex *ix, PetscInt dim, PetscInt i, PetscInt j, PetscInt k)
{
  return Lidx(ix, i + PS_PAD, j + PS_PAD, dim == 3 ? k + PS_PAD : 0);
}

/* the hourglass viscosity of a cell, kappa rho c V_c / h / 2^dim, rho its
   mass per cell volume (a sliver's damping scales with its mass) */
static inline PetscReal HourglassKappa(const PSCorners *K, PetscReal Mc, PetscReal cmax)
{
  return K->khg * Mc * cmax;
}

/* the hourglass rates g_m = sum_a G_m(a) v_a of the cell with lower corner
   node o, from nodal velocities v (dim per node); dim a constant where it is
   called (the phases' dim-specialised loops), so the loops unroll */
static inline void HourglassRatesDim(const PSCorners *K, const PetscInt dim, PetscInt o, const PetscReal *v, PetscReal hg[4][3])
{
  const PetscInt nco = 1 << dim, nh = dim == 3 ? 4 : 1;
  PetscInt       a, d, e;

  for (e = 0; e < 4; e++)
    for (d = 0; d < 3; d++) hg[e][d] = 0.0;
#pragma GCC unroll 8 /* (whole, so a kernel's cell loop around it runs in SIMD lanes in 3D too) */
  for (a = 0; a < nco; a++) {
    const PetscInt oa = o + K->off[a];
#pragma GCC unroll 3
    for (d = 0; d < dim; d++) {
#pragma GCC unroll 4
      for (e = 0; e < nh; e++) hg[e][d] += PSHourglassSign(a, e) * v[dim * oa + d];
    }
  }
}

/* mixture values of a cell: material mass and volume, and its signal speed:
   the largest sound speed among the materials that hold at least PS_TRACE
   of the materials' volume (a trace left by the remap next to an interface
   has no say in the time step, the viscosity or the hourglass force: its
   state is relaxed by the closure, and letting it decide made the time step
   follow round-off) */
#define PS_TRACE 1e-4
static inline void CellMix(const PSCells *C, const PetscReal *u, const PetscReal *ec, PetscInt m0, PetscInt m1, PetscReal *Mc, PetscReal *Vm, PetscReal *cmax)
{
  PetscInt m;
  if (m1 == m0 + 1) {
    /* one material (nearly every cell): the loops below, unrolled */
    const PetscReal M = u[m0 * C->mst + PS_CM], V = u[m0 * C->mst + PS_CV];
    *Mc   = PetscMax(M, 0.0);
    *Vm   = PetscMax(V, 0.0);
    *cmax = M > 0.0 && V >= PS_TRACE * *Vm ? PetscMax(0.0, ec[PS_EC * m0 + 1]) : 0.0;
    return;
  }
  *Mc = *Vm = *cmax = 0.0;
  for (m = m0; m < m1; m++) {
    *Mc += PetscMax(u[m * C->mst + PS_CM], 0.0);
    *Vm += PetscMax(u[m * C->mst + PS_CV], 0.0);
  }
  for (m = m0; m < m1; m++)
    if (u[m * C->mst + PS_CM] > 0.0 && u[m * C->mst + PS_CV] >= PS_TRACE * *Vm) *cmax = PetscMax(*cmax, ec[PS_EC * m + 1]);
}

/* The lanes' inputs (ToGridGasLanes, PredictGasLanes, LagrangeGasLanes):
   of each cell [0, nr) of a row (cell i0 + l, ghosted index ci0 + i0 + l,
   EOS slot index n0 + l) that holds one material of C->gasf alone (set
   with the cells, cells.c; GasLanesWalk takes no other cell): that
   material's M, V, E, EOS values, p_k^h (the predictor's, where it has
   run) and gamma */
typedef struct {
  PetscReal  M, V, E, ec0, ec1, ec2, pk, g;
  PetscReal *B; /* the material's block (V, M, E) of the cell: the Lagrangian phase's kernel stores its new V and E there */
} PSGasIn;

/* the kernels' own arguments */
typedef struct {
  PetscReal  dt, hm, fs; /* s, m (the largest cell size), P2G's force factor */
  PetscInt   w;          /* the planes' length */
  PetscReal *W;          /* the planes (the remap's scratch C->sW) */
  PetscReal  cl, cq;     /* the artificial viscosity's coefficients (S->run's; here, not loaded in the kernels: a store to a cell's plane may alias S->run, and the load, under the test of compression, stayed in the loop, a masked load the lanes do not take) */
} PSGasArgs;

static inline PSGasArgs GasLanesArgs(const PSSolver *S, PetscReal dt, PetscReal hm, PetscReal fs, PetscInt w, PetscReal *W)
{
  const PSGasArgs a = {dt, hm, fs, w, W, S->run.c_linear, S->run.c_quadratic};
  return a;
}

/* the reals of a cell's half-step slot (PSCellsHalfSize) as the lanes'
   loops index it: the constant in 2D, read from C at run time in 3D.  With
   the constant 13, GCC 12 takes a slot's 13 loads as a group of 13, which it
   neither interleaves nor loads one by one, and left the 3D Lagrangian walk
   and the predictor's force loop scalar until the thirty-sixth session;
   with a stride it does not know it loads them one by one into the lanes */
static inline PetscInt GasLanesHalfSize(const PSCells *C, const PetscInt dim)
{
  return dim == 3 ? PSCellsHalfSize(C) : 1 + dim;
}

enum { PS_GK_P2G, PS_GK_PREDICT, PS_GK_LAGRANGE };
static inline __attribute__((always_inline)) void ToGridGasCell(const PSSolver *, const PetscInt, PetscInt, PetscInt, PetscInt, PetscInt, PetscInt, const PSGasArgs *, PSGasIn);
static inline __attribute__((always_inline)) void PredictGasCell(const PSSolver *, const PetscInt, PetscInt, PetscInt, PetscInt, PetscInt, PetscInt, const PSGasArgs *, PSGasIn);
static inline __attribute__((always_inline)) void LagrangeGasCell(const PSSolver *, const PetscInt, PetscInt, PetscInt, PetscInt, PetscInt, PetscInt, const PSGasArgs *, PSGasIn);

/* kernel kind's arithmetic for the cell of lane l (kind a constant where it is called) */
static inline __attribute__((always_inline)) void GasLanesCell(const PSSolver *S, const PetscInt kind, const PetscInt dim, PetscInt ci0, PetscInt oc0, PetscInt n0, PetscInt i0, PetscInt l, const PSGasArgs *a, PSGasIn in)
{
  if (kind == PS_GK_P2G) ToGridGasCell(S, dim, ci0, oc0, n0, i0, l, a, in);
  else if (kind == PS_GK_PREDICT) PredictGasCell(S, dim, ci0, oc0, n0, i0, l, a, in);
  else LagrangeGasCell(S, dim, ci0, oc0, n0, i0, l, a, in);
}

/* The row's cells [0, nr) through kernel kind: a run of cells of one gas
   block (V, M, E; its EOS slots consecutive, a pure cell's one each) in SIMD
   lanes, its inputs loaded straight from the blocks (strided loads, no
   planes between: until the twenty-sixth session a gather copied every
   cell's inputs into planes first, about 5% of the quadrants' step); every
   other cell of one material of C->gasf alone, and any other cell its flag
   0 alone.  Returns whether a cell holds one material of C->gasf
   (the first one ends the search; a count over the row cost about 1% of
   the quadrants' step); where none does, the kernel's flag plane (flag, nr
   reals) is zeroed and no cell is taken: the lanes' arithmetic is not
   worth its time there */
static inline __attribute__((always_inline)) PetscInt GasLanesWalk(const PSSolver *S, const PetscInt kind, const PetscInt dim, PetscInt ci0, PetscInt oc0, PetscInt n0, PetscInt i0, PetscInt nr, const PSGasArgs *a, PetscReal *flag)
{
  const PSCells   *C = S->cells;
  PetscReal       *U  = C->u;
  const PetscReal *EC = C->ec, *HM = C->hm, *gam = C->gam;
  const PetscInt  *gasf = C->gasf;
  const PetscInt  *eco = C->eco, ms = C->ms, mst = C->mst, hmat = PSCellsHalfMat(C);
  const short     *sole = &C->sole[ci0 + i0];
  PetscInt         l, ng;

  for (l = 0; l < nr; l++)
    if (sole[l] >= 0 && gasf[sole[l]]) break;
  ng = l < nr;
  if (!ng) {
    for (l = 0; l < nr; l++) flag[l] = 0.0;
    return 0;
  }
  for (l = 0; l < nr; l++) {
    const PetscInt s = sole[l];
    PetscInt       e;
    if (!(s >= 0 && gasf[s])) {
      /* a cell of several materials, of none, or of a material not in
         C->gasf: its flag 0 alone (the phase's own loop takes the cell and
         reads none of the lane's other values).  Until the thirty-fifth
         session such a cell, or a run of such cells, took the kernel's
         arithmetic (out of lanes for a cell alone: a chain of scalar
         divisions in each of the three phases) only to set that flag */
      flag[l] = 0.0;
      continue;
    }
    e = eco[n0 + l] + s;
    if (ms == PS_CQ) {
      const PetscInt b = l + PSCellsSoleRun(&sole[l], nr - l);
      if (b - l >= PS_LANES_RUN) {
        const PetscInt   len = b - l, l0 = l;
        PetscReal       *Ub = &U[PS_CQ * (ci0 + i0 + l) + mst * s];
        const PetscReal *Eb = &EC[PS_EC * e], *Hb = &HM[hmat * e], g = gam[s];
        PetscInt         x;
#pragma GCC ivdep
        for (x = 0; x < len; x++) {
          const PSGasIn in = {Ub[PS_CQ * x + PS_CM], Ub[PS_CQ * x + PS_CV], Ub[PS_CQ * x + PS_CE], Eb[PS_EC * x], Eb[PS_EC * x + 1], Eb[PS_EC * x + 2], Hb[hmat * x], g, &Ub[PS_CQ * x]};
          GasLanesCell(S, kind, dim, ci0, oc0, n0, i0, l0 + x, a, in);
        }
        l = b - 1;
        continue;
      }
    }
    {
      PetscReal    *blk = &U[ms * (ci0 + i0 + l) + mst * s];
      const PSGasIn in  = {blk[PS_CM], blk[PS_CV], blk[PS_CE], EC[PS_EC * e], EC[PS_EC * e + 1], EC[PS_EC * e + 2], HM[hmat * e], gam[s], blk};
      GasLanesCell(S, kind, dim, ci0, oc0, n0, i0, l, a, in);
    }
  }
  return ng;
}

/* The lanes' pieces, each the scalar code's arithmetic in its order without
   a branch.  CellMix's one material: M_c, V_m and c_max from the material's
   M, V and sound speed c */
static inline void GasLanesMix(PetscReal M, PetscReal V, PetscReal c, PetscReal *Mc, PetscReal *Vm, PetscReal *cmax)
{
  const PetscReal c1 = PetscMax(0.0, c);
  *Mc   = PetscMax(M, 0.0);
  *Vm   = PetscMax(V, 0.0);
  *cmax = M > 0.0 && V >= PS_TRACE * *Vm ? c1 : 0.0;
}

/* PSCellsShareVolume's one-material case (PSCellsVoidShare,
   PSCellsMaterialShare): the material's share dVk of the cell's dV, and the
   void V0 after its share (the case holds where V0 <= PS_VOID_ROUNDOFF V_c) */
static inline void GasLanesShare(PetscReal Vc, PetscReal V, PetscReal VM, PetscReal chi, PetscReal chiM, PetscReal dV, PetscReal *dVk, PetscReal *V0e)
{
  const PetscReal V0 = PetscMax(Vc - V - VM, 0.0), take = PetscMin(-dV, V0), V0p = V0 + dV, V0n = V0 - take, rn = dV + take;
  const PetscBool neg = dV < 0.0, pv = V0 > PS_VOID_TRACE * Vc;
  const PetscReal rest = neg ? rn : (pv ? 0.0 : dV), dchi = chi > 0.0 ? chi + chiM : 1.0, sh = PetscMax(chiM == 0.0 ? rest : rest * chi / dchi, -0.5 * V);
  *V0e = neg ? V0n : (pv ? V0p : V0);
  *dVk = chi > 0.0 ? sh : 0.0;
}

/* PSViscosity */
static inline PetscReal GasLanesViscosity(PetscReal rho, PetscReal h, PetscReal trD, PetscReal c, PetscReal c_linear, PetscReal c_quadratic)
{
  const PetscReal qv = rho * h * (c_quadratic * h * trD * trD + c_linear * c * PetscAbsReal(trD));
  return trD < 0.0 ? qv : 0.0;
}

/* PSCellsForcePressure of one material of compliance chi at pressure p */
static inline PetscReal GasLanesForcePressure(PetscReal chi, PetscReal p)
{
  return chi > 0.0 ? p : 0.0;
}

/* corner a's force component d of a lane cell whose stress is a pressure,
   sg I (-sg grad N_a), with the viscous hourglass force of the rates hg
   (kap: HourglassKappa): P2G's corner force (hg the rates at t^n), and the
   predictor's change of it (sg and hg the changes) */
static inline __attribute__((always_inline)) PetscReal GasLanesCornerForce(const PSCorners *K, const PetscInt dim, PetscInt a, PetscInt d, PetscReal sg, PetscReal kap, const PetscReal hg[4][3])
{
  const PetscInt nh = dim == 3 ? 4 : 1;
  PetscReal      fd = 0.0;
  PetscInt       e;
  fd -= sg * K->gN[a][d];
#pragma GCC unroll 4
  for (e = 0; e < nh; e++) fd -= kap * PSHourglassSign(a, e) * hg[e][d];
  return fd;
}

/* The cells' P2G (ToGridGasCell: the cell of lane l, its inputs in;
   ToGridGasLanes: the row through GasLanesWalk) of the cells [0, nr) of a
   row (cell i0 + l in lane l, as PredictGasLanes) that hold one material
   with mass, an ideal gas (C->gasf), in a scene without strength:
   PSCellsToGridDim's arithmetic for such a cell, in its order, without a
   branch, so the row's loop takes it in SIMD lanes; the hourglass rates
   into the cell's slot of C->hs as there.  Into the planes of w reals at W:
   the flag (1: these values are P2G's; 0: its own loop takes the cell), the
   mass each corner takes, M_c / 2^dim, and corner a's force component d
   (times fs) in plane PS_GL_F + a dim + d */
enum { PS_GL_FLAG, PS_GL_MC, PS_GL_F }; /* (then the forces' 2^dim dim planes) */
static inline __attribute__((always_inline)) void ToGridGasCell(const PSSolver *S, const PetscInt dim, PetscInt ci0, PetscInt oc0, PetscInt n0, PetscInt i0, PetscInt l, const PSGasArgs *A, PSGasIn in)
{
  const PSCells   *C  = S->cells;
  const PetscReal *XQ = PSCellsX(C, 0, PS_CX_Q), *VL = C->sVL, fs = A->fs;
  const PetscInt   nco = 1 << dim, nh = dim == 3 ? 4 : 1, hsd = 1 + nh * dim, w = A->w; /* (PSCellsHalfSize) */
  const PSCorners *K  = &C->K;
  PetscReal       *HS = C->hs, *W = A->W;
  const PetscInt  ci = ci0 + i0 + l, oc = oc0 + i0 + l;
  const PetscReal M = in.M, V = in.V;
  PetscReal       Mc, Vm, cmax, hg[4][3], *gh = &HS[hsd * (n0 + l) + 1];
  PetscInt        a, d, e;
  /* sig = -(p_f + q) V_m I */
  GasLanesMix(M, V, in.ec1, &Mc, &Vm, &cmax);
  const PetscReal pf = GasLanesForcePressure(in.ec2, in.ec0), sg = 0.0 - Vm * pf - Vm * XQ[ci], kap = K->khg * Mc * cmax;
  HourglassRatesDim(K, dim, oc, VL, hg);
#pragma GCC unroll 4
  for (e = 0; e < nh; e++)
#pragma GCC unroll 3
    for (d = 0; d < dim; d++) gh[dim * e + d] = hg[e][d];
  W[PS_GL_MC * w + l] = Mc / nco;
#pragma GCC unroll 8
  for (a = 0; a < nco; a++)
#pragma GCC unroll 3
    for (d = 0; d < dim; d++) W[(PS_GL_F + a * dim + d) * w + l] = fs * GasLanesCornerForce(K, dim, a, d, sg, kap, hg);
  W[PS_GL_FLAG * w + l] = M > 0.0 ? 1.0 : 0.0;
}

static inline void ToGridGasLanes(const PSSolver *S, const PetscInt dim, PetscInt ci0, PetscInt oc0, PetscInt n0, PetscInt i0, PetscInt nr, PetscReal fs, PetscInt w, PetscReal *W)
{
  const PSGasArgs a = GasLanesArgs(S, 0.0, 0.0, fs, w, W);
  (void)GasLanesWalk(S, PS_GK_P2G, dim, ci0, oc0, n0, i0, nr, &a, &W[PS_GL_FLAG * w]);
}

/* the corner masses and forces of a row's lane cells [l0, l1) (ToGridGasLanes',
   or the predictor's force changes, PredictGasLanes') to the nodes (node o's
   mass at gm[sm o], its force's component d at gf[sf o + sc d]), in the
   cells' loops' order: a node of the run takes the corner B (one along x
   beyond A) of cell l - 1, then the corner A of cell l, each where own (the
   row's owned corners) has it; the pairs of corners (A, B) in SIMD lanes.
   Mq: the corner masses' plane (NULL: none); Fq: corner a's component d in
   plane a dim + d, of w reals each */
static inline void GasLanesNodes(const PetscInt dim, const PSCorners *K, PetscInt o0, PetscInt own, PetscInt l0, PetscInt l1, PetscInt w, const PetscReal *Mq, const PetscReal *Fq, PetscReal *gm, const PetscInt sm, PetscReal *gf, const PetscInt sf, const PetscInt sc)
{
  const PetscInt nco = 1 << dim;
  PetscInt       A, l, d;

  for (A = 0; A < nco; A += 2) {
    const PetscInt  B = A + 1, oA = o0 + K->off[A];
    const PetscBool fA = (own >> A) & 1, fB = (own >> B) & 1;
    PetscReal      *mA = Mq ? &gm[sm * oA] : NULL, *fAo = &gf[sf * oA];
    /* (node oA + l: cell l - 1's corner B (oA + l = o0 + (l - 1) + off[B]), then cell l's A) */
    if (fA) {
      if (Mq) mA[sm * l0] += Mq[l0];
      for (d = 0; d < dim; d++) fAo[sf * l0 + sc * d] += Fq[(A * dim + d) * w + l0];
    }
    if (Mq) {
#pragma GCC ivdep
      for (l = l0 + 1; l < l1; l++) {
        PetscReal m = mA[sm * l];
        if (fB) m = m + Mq[l - 1];
        if (fA) m = m + Mq[l];
        mA[sm * l] = m;
      }
    }
#pragma GCC ivdep
    for (l = l0 + 1; l < l1; l++) {
#pragma GCC unroll 3
      for (d = 0; d < dim; d++) {
        PetscReal f = fAo[sf * l + sc * d];
        if (fB) f = f + Fq[(B * dim + d) * w + l - 1];
        if (fA) f = f + Fq[(A * dim + d) * w + l];
        fAo[sf * l + sc * d] = f;
      }
    }
    if (fB) {
      if (Mq) mA[sm * l1] += Mq[l1 - 1];
      for (d = 0; d < dim; d++) fAo[sf * l1 + sc * d] += Fq[(B * dim + d) * w + l1 - 1];
    }
  }
}

/* the cell materials' nodal velocity P^C_i / m^C_i at t^n of the local nodes
   [o0, o1) into C->sVL (PSCellsToGridDim); returns the nodes done.  The
   arrays in locals and a divisor for every node (1 where the value is not
   used), so the loop runs in SIMD lanes (read through C, GCC left it scalar) */
static inline PetscInt ToGridNodes(PSCells *C, const PetscInt dim, PetscInt o0, PetscInt o1)
{
  const PetscReal *mcn = C->mcn, *P = C->P;
  PetscReal       *vl  = C->sVL;
  PetscInt         o, d;
#pragma GCC ivdep /* (sVL, P and mcn are apart) */
  for (o = o0; o < o1; o++) {
    const PetscReal mn = mcn[o], md = mn > 0.0 ? mn : 1.0;
#pragma GCC unroll 3
    for (d = 0; d < dim; d++) {
      const PetscReal r = P[dim * o + d] / md;
      vl[dim * o + d]   = mn > 0.0 ? r : r - r; /* (r - r: +0 for a finite P, the 0 of a node without mass; written so, P is loaded for every node, where a 0 let GCC load it only under the test, a masked strided load it cannot vectorize) */
    }
  }
  return PetscMax(o0, o1);
}

/* the cells' P2G over the units [u0, u1) of cells along y (2D) or z (3D),
   from where tp left it (PSCellsToGridDim: all of them at once; the
   Lagrangian pipeline: one at a time) */
typedef struct {
  PetscInt n;   /* the next cell's index among the cells around the owned nodes (PSCellsXIdx) */
  PetscInt nb;  /* the local nodes with their P^C_i / m^C_i in C->sVL */
  PetscInt nxt; /* the first unit of owned nodes without the cell materials' momentum (with sums: not yet in G) */
} PSToGridProgress;

/* The P2G's sums (ToGridUnits with sums, in a scene of cells alone with
   musl, where nothing else adds to G before the cells: PSCellsSums): the
   corners' masses and forces go to planes of two units of nodes, the unit
   of the cells' lower corners and the one above, C->acc (the mass plane,
   then dim force planes, of 2 nacc reals each; a unit's nodes in the order
   of the local array), added in the order they were added to G; once the
   unit of the lower corners has all its sums, its nodes are written to G
   whole (ToGridSumsToG), the upper unit's sums move down and the upper
   unit starts from zero.  G is not zeroed for it (PSGridReset): its nodes
   are written once a step, each value the same bits the zeroed G and its
   sums gave, and the P2G's adds go to planes in the caches in SIMD lanes
   where G's went to every fifth real of an array past the L2 */
PetscBool PSCellsSums(const PSSolver *S)
{
  const PSCells *C = S->cells;
  return C && !C->markers && !S->contact && S->run.transfer == PS_TRANSFER_MUSL && S->run.lanes != 1 ? PETSC_TRUE : PETSC_FALSE;
}

static inline PetscErrorCode ToGridSumsStart(PSSolver *S, const PSIndex *ix, const PetscInt dim)
{
  PSCells       *C  = S->cells;
  const PetscInt nu = dim == 3 ? ix->gm[0] * ix->gm[1] : ix->gm[0];

  PetscFunctionBeginUser;
  if (!C->acc) {
    C->nacc = nu;
    PetscCall(PetscMalloc1(2 * nu * (1 + dim), &C->acc));
  }
  PetscCheck(PSGridDof(S) == (dim == 3 ? 8 : 5), PETSC_COMM_SELF, PETSC_ERR_PLIB, "the P2G sums take musl's G of %d reals per node, not %" PetscInt_FMT, dim == 3 ? 8 : 5, PSGridDof(S));
  PetscCheck(C->nacc == nu, PETSC_COMM_SELF, PETSC_ERR_PLIB, "the P2G sums' units hold %" PetscInt_FMT " nodes, the grid's %" PetscInt_FMT, C->nacc, nu);
  PetscCall(PetscArrayzero(C->acc, 2 * nu * (1 + dim)));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* n nodes of a row into G, from local node o0 on: their sums from a (the
   node's mass at a[0], its force's component d at a[2 nu (1 + d)]; NULL: no
   cell's corner, 0), the velocity's slots the cells' momentum P^C added to
   0 where own (PSGridAddOwnedUnits adds it to the zeroed G on the owned
   nodes alone), the rest 0 */
static inline void SumsToGRow(PetscReal *g, const PetscReal *P, const PetscReal *a, const PetscInt dim, PetscInt nu, PetscInt o0, PetscInt n, const PetscBool own)
{
  const PetscInt dof = dim == 3 ? 8 : 5, fo = dof - dim; /* (musl's G, PSGridDof: ToGridSumsStart checks it) */
  PetscInt       q, d;

  if (a) {
#pragma GCC ivdep
    for (q = 0; q < n; q++) {
      PetscReal       *gn = &g[dof * (o0 + q)];
      const PetscReal *pn = &P[dim * (o0 + q)];
      gn[0]               = a[q];
#pragma GCC unroll 3
      for (d = 0; d < dim; d++) gn[1 + d] = own ? 0.0 + pn[d] : 0.0;
      for (d = 1 + dim; d < fo; d++) gn[d] = 0.0;
#pragma GCC unroll 3
      for (d = 0; d < dim; d++) gn[fo + d] = a[2 * nu * (1 + d) + q];
    }
  } else {
#pragma GCC ivdep
    for (q = 0; q < n; q++) {
      PetscReal       *gn = &g[dof * (o0 + q)];
      const PetscReal *pn = &P[dim * (o0 + q)];
      gn[0]               = 0.0;
#pragma GCC unroll 3
      for (d = 0; d < dim; d++) gn[1 + d] = own ? 0.0 + pn[d] : 0.0;
      for (d = 1 + dim; d < dof; d++) gn[d] = 0.0;
    }
  }
}

/* G's nodes of the units [u0, u1) along y (2D) or z (3D) from the sums,
   unit ra's in the lower of C->acc's two units (any other unit's nodes have
   no cell's corner), a row at a time, its owned nodes apart from its ghosts
   (SumsToGRow); then the upper unit's sums down, the upper unit zeroed,
   where ra was among them (its successor's sums move down) */
static inline __attribute__((always_inline)) void ToGridSumsToGDim(PSSolver *S, const PSIndex *ix, const PetscInt dim, PetscInt u0, PetscInt u1, PetscInt ra)
{
  PSCells         *C = S->cells;
  const PetscInt   e = dim - 1, nu = C->nacc, x0 = ix->gs[0], x1 = ix->gs[0] + ix->gm[0], xa = ix->os[0], xb = ix->os[0] + ix->om[0];
  const PetscReal *P = C->P;
  PetscReal       *g = S->g, *acc = C->acc;
  PetscInt         u, q, j, k, p;

  u0 = PetscMax(u0, ix->gs[e]);
  u1 = PetscMin(u1, ix->gs[e] + ix->gm[e]);
  for (u = u0; u < u1; u++) {
    const PetscInt o0 = (u - ix->gs[e]) * nu;
    for (k = dim == 3 ? u : ix->gs[2]; k < (dim == 3 ? u + 1 : ix->gs[2] + 1); k++)
      for (j = dim == 3 ? ix->gs[1] : u; j < (dim == 3 ? ix->gs[1] + ix->gm[1] : u + 1); j++) {
        const PetscInt   orow = Lidx(ix, x0, j, k);                             /* (the row's first node) */
        const PetscReal *a    = u == ra ? &acc[orow - o0] : NULL;               /* (its sums) */
        const PetscBool  rown = j >= ix->os[1] && j < ix->os[1] + ix->om[1] && (dim < 3 || (k >= ix->os[2] && k < ix->os[2] + ix->om[2]));
        if (rown && xb > xa) {
          SumsToGRow(g, P, a, dim, nu, orow, xa - x0, PETSC_FALSE);
          SumsToGRow(g, P, a ? a + xa - x0 : NULL, dim, nu, orow + xa - x0, xb - xa, PETSC_TRUE);
          SumsToGRow(g, P, a ? a + xb - x0 : NULL, dim, nu, orow + xb - x0, x1 - xb, PETSC_FALSE);
        } else SumsToGRow(g, P, a, dim, nu, orow, x1 - x0, PETSC_FALSE);
      }
  }
  if (ra >= u0 && ra < u1)
    for (p = 0; p < 1 + dim; p++) {
      PetscReal *a = &acc[2 * nu * p];
      for (q = 0; q < nu; q++) {
        a[q]      = a[nu + q];
        a[nu + q] = 0.0;
      }
    }
}

/* (out of line, as GCC kept it before the pipeline's edge units changed its
   choice; dim a constant in each copy) */
static __attribute__((noinline)) void ToGridSumsToG(PSSolver *S, const PSIndex *ix, const PetscInt dim, PetscInt u0, PetscInt u1, PetscInt ra)
{
  if (dim == 2) ToGridSumsToGDim(S, ix, 2, u0, u1, ra);
  else ToGridSumsToGDim(S, ix, 3, u0, u1, ra);
}

static inline PetscErrorCode ToGridUnits(PSSolver *S, const PSIndex *ix, PetscReal dt, const PetscInt dim, const PetscBool strength, const PetscBool sums, PetscInt u0, PetscInt u1, PSToGridProgress *tp)
{
  PSCells        *C = S->cells;
  const PetscReal *XQ = PSCellsX(C, 0, PS_CX_Q); /* the per-cell plane of q (PSCellsX) */
  const PetscInt  nco = 1 << dim, nh = dim == 3 ? 4 : 1, dof = PSGridDof(S), fo = S->run.transfer == PS_TRANSFER_APIC ? 1 : dof - dim, hsd = PSCellsHalfSize(C);
  const PetscReal fs = S->run.transfer == PS_TRANSFER_APIC ? dt : 1.0; /* apic: the force enters as momentum dt f */
  const PetscInt  nw = PSCellsPlaneLen(C, ix); /* (the lanes' plane length: the remap's scratch C->sW, free here) */
  const PetscBool lanes = !strength && S->run.lanes != 1 ? PETSC_TRUE : PETSC_FALSE; /* (without strength; -run_lanes 1: the scalar loop alone, for checks) */
  const PetscInt  sm = sums ? 1 : dof, sf = sums ? 1 : dof, sc = sums ? 2 * C->nacc : 1; /* (node o's mass at gm[sm o], its force's component d at gf[sf o + sc d]: G's, or the sums': ToGridSumsStart) */
  PetscReal      *gm = S->g, *gf = S->g + fo, *W = C->sW;
  PetscInt        i, j, k, m, a, d, e, n = tp->n, orow, nb = tp->nb, nxt = tp->nxt, un;

  PetscFunctionBeginUser;
  /* every cell around the owned nodes, to its owned corners (PSCellsXIdx:
     each node's sum in one order on any number of ranks), a row (2D) or
     plane (3D) at a time with the nodes' values around it: before the cells
     of unit u, the cell materials' nodal velocity P^C_i / m^C_i at t^n of the
     nodes up to unit u + 1, into the remap's scratch C->sVL (free until the
     remap: the hourglass rates below read it, each node divided once per
     step, not once per corner; nb: the local nodes done); after them, the
     cell materials' momentum on the owned nodes up to unit u, which have all
     the cells' sums (the ghosts' would count twice; nxt: the first unit
     without it) */
  for (un = u0; un < u1; un++) {
    k = dim == 3 ? un : C->xs[2];
    if (sums) { /* (the sums' two units: the unit's lower corners', un + PS_PAD, and its upper corners') */
      const PetscInt b = (un + PS_PAD - ix->gs[dim - 1]) * C->nacc;
      gm = C->acc - b;
      gf = C->acc + 2 * C->nacc - b;
    }
    for (j = dim == 3 ? C->xs[1] : un; j < (dim == 3 ? C->ce[1] : un + 1); j++) {
      PetscInt ci0, oc0, xa, xb;
      nb = ToGridNodes(C, dim, nb, PSCellsNodesThrough(ix, dim, C->nnl, dim == 3 ? k : j));
      PSCellsRow(C, ix, dim, j, k, &ci0, &oc0, &xa, &xb);
      PetscCall(PSCellsEOSRow(S, j, k, n));
      if (lanes) ToGridGasLanes(S, dim, ci0, oc0, n, C->xs[0], C->ce[0] - C->xs[0], fs, nw, W);
      for (i = C->xs[0], orow = PSCellsOwnedRow(ix, dim, j, k); i < C->ce[0]; i++, n++) {
        const PetscInt   ci = ci0 + i;
        const PetscReal *u  = &C->u[C->ms * ci];
        const PetscReal *ec = PSCellsEC(C, n);
        const PetscInt   oc = oc0 + i, own = orow & (i >= xa && i < xb ? 0xff : PSCellsOwnedAxis(ix, 0, i)); /* (its owned corners) */
        PetscReal        sig[3][3] = {{0}}, Mc, Vm, cmax, hg[4][3], kap;
        PetscInt         m0, m1;
        if (lanes && i >= xa && i < xb && W[PS_GL_FLAG * nw + i - C->xs[0]] != 0.0) {
          /* a run of the lanes' cells whose corners are the row's owned ones:
             their corners to the nodes in lanes, in this loop's order */
          const PetscInt l0 = i - C->xs[0];
          PetscInt       l1 = l0 + 1;
          l1 = PSLanesFlagRun(&W[PS_GL_FLAG * nw], l1, PetscMin(xb, C->ce[0]) - C->xs[0]); /* (xb may lie beyond the row's cells) */
          GasLanesNodes(dim, &C->K, oc0 + C->xs[0], orow, l0, l1, nw, &W[PS_GL_MC * nw], &W[PS_GL_F * nw], gm, sm, gf, sf, sc);
          n += l1 - l0 - 1;
          i += l1 - l0 - 1;
          continue;
        }
        PSCellsPresent(C, ci, &m0, &m1);
        CellMix(C, u, ec, m0, m1, &Mc, &Vm, &cmax);
        if (Mc <= 0.0) continue;
        /* sum_k V_k s_k - (p_f + q) V_m I, p_f the closure's pressure (closure.c) */
        {
          const PetscReal pf = PSCellsForcePressure(ec, m0, m1);
          for (d = 0; d < 3; d++) sig[d][d] -= Vm * pf;
        }
        for (m = m0; m < m1; m++) {
          const PetscReal *blk = &u[m * C->mst];
          if (blk[PS_CM] <= 0.0) continue;
          if (strength) {
            const PetscReal *sm = &blk[PS_CQ], im = 1.0 / blk[PS_CM];
            sig[0][0] += blk[PS_CV] * sm[0] * im;
            sig[1][1] += blk[PS_CV] * sm[1] * im;
            sig[2][2] += blk[PS_CV] * sm[2] * im;
            if (dim == 3) {
              sig[1][2] = sig[2][1] = sig[1][2] + blk[PS_CV] * sm[3] * im;
              sig[0][2] = sig[2][0] = sig[0][2] + blk[PS_CV] * sm[4] * im;
              sig[0][1] = sig[1][0] = sig[0][1] + blk[PS_CV] * sm[5] * im;
            } else sig[0][1] = sig[1][0] = sig[0][1] + blk[PS_CV] * sm[3] * im;
          }
        }
        for (d = 0; d < 3; d++) sig[d][d] -= Vm * XQ[ci];
        /* the hourglass rates of the cell materials' nodal velocities (kept in
           the cell's slot for g_m^h, C->hs, where the predictor reads them as
           the rates at t^n before it writes g_m^h); the corners' mass and force */
        HourglassRatesDim(&C->K, dim, oc, C->sVL, hg);
        {
          PetscReal *gh = &C->hs[hsd * n + 1];
          for (e = 0; e < nh; e++)
            for (d = 0; d < dim; d++) gh[dim * e + d] = hg[e][d];
        }
        kap = HourglassKappa(&C->K, Mc, cmax);
        for (a = 0; a < nco; a++) {
          const PetscInt o = oc + C->K.off[a];
          if (!((own >> a) & 1)) continue;
          gm[sm * o] += Mc / nco;
          for (d = 0; d < dim; d++) {
            PetscReal fd = 0.0;
            if (strength)
              for (e = 0; e < dim; e++) fd -= sig[d][e] * C->K.gN[a][e];
            else fd -= sig[d][d] * C->K.gN[a][d];
            for (e = 0; e < nh; e++) fd -= kap * PSHourglassSign(a, e) * hg[e][d];
            gf[sf * o + sc * d] += fs * fd;
          }
        }
      }
      if (dim == 2) {
        if (sums) ToGridSumsToG(S, ix, dim, nxt, j + PS_PAD + 1, j + PS_PAD);
        else PSGridAddOwnedUnits(S, ix, C->P, dim, S->g + 1, dof, nxt, j + PS_PAD + 1);
        nxt = j + PS_PAD + 1;
      }
    }
    if (dim == 3) {
      if (sums) ToGridSumsToG(S, ix, dim, nxt, k + PS_PAD + 1, k + PS_PAD);
      else PSGridAddOwnedUnits(S, ix, C->P, dim, S->g + 1, dof, nxt, k + PS_PAD + 1);
      nxt = k + PS_PAD + 1;
    }
  }
  tp->n   = n;
  tp->nb  = nb;
  tp->nxt = nxt;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* the P2G's start: the EOS cache's slots (PSCellsEOSCache: each row's values
   in ToGridUnits, before its cells read them), the sums' zero where sums */
static inline PetscErrorCode ToGridStart(PSSolver *S, const PSIndex *ix, const PetscInt dim, const PetscBool sums, PSToGridProgress *tp)
{
  PetscFunctionBeginUser;
  PetscCall(PSCellsEOSSlots(S));
  if (sums) PetscCall(ToGridSumsStart(S, ix, dim));
  tp->n   = 0;
  tp->nb  = 0;
  tp->nxt = PETSC_MIN_INT;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* the nodes the P2G's units left (with sums: unit nxt's, the upper corners'
   of the last unit, in the sums' lower unit) */
static inline void ToGridEnd(PSSolver *S, const PSIndex *ix, const PetscInt dim, const PetscBool sums, const PSToGridProgress *tp)
{
  PSCells *C = S->cells;
  (void)ToGridNodes(C, dim, tp->nb, C->nnl);
  if (sums) ToGridSumsToG(S, ix, dim, tp->nxt, PETSC_MAX_INT, tp->nxt);
  else PSGridAddOwnedUnits(S, ix, C->P, dim, S->g + 1, PSGridDof(S), tp->nxt, PETSC_MAX_INT);
}

/* the cells' mass and force to the nodes: dim and strength constants where
   it is called (PSCellsToGrid picks 2D or 3D, and whether any cell material
   has strength, C->nq > 0), so the per-cell loops unroll, and without
   strength the stress is a pressure: the corners take its diagonal alone */
static inline PetscErrorCode PSCellsToGridDim(PSSolver *S, const PSIndex *ix, PetscReal dt, const PetscInt dim, const PetscBool strength)
{
  PSCells         *C = S->cells;
  PSToGridProgress tp;

  PetscFunctionBeginUser;
  if (!EV_C2G) PetscCall(PetscLogEventRegister("PSCellsP2G", 0, &EV_C2G));
  PetscCall(PetscLogEventBegin(EV_C2G, 0, 0, 0, 0));
  if (PSCellsSums(S)) { /* (the sums: G is not zeroed, PSGridReset; sums a constant in each branch, so ToGridUnits' adds are compiled for the sums' strides or G's) */
    PetscCall(ToGridStart(S, ix, dim, PETSC_TRUE, &tp));
    PetscCall(ToGridUnits(S, ix, dt, dim, strength, PETSC_TRUE, C->xs[dim - 1], C->ce[dim - 1], &tp));
    ToGridEnd(S, ix, dim, PETSC_TRUE, &tp);
  } else {
    PetscCall(ToGridStart(S, ix, dim, PETSC_FALSE, &tp));
    PetscCall(ToGridUnits(S, ix, dt, dim, strength, PETSC_FALSE, C->xs[dim - 1], C->ce[dim - 1], &tp));
    ToGridEnd(S, ix, dim, PETSC_FALSE, &tp);
  }
  PetscCall(PetscLogEventEnd(EV_C2G, 0, 0, 0, 0));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode PSCellsToGrid(PSSolver *S, const PSIndex *ix, PetscReal dt)
{
  const PetscBool strength = S->cells->nq > 0 ? PETSC_TRUE : PETSC_FALSE;

  PetscFunctionBeginUser;
  if (S->dim == 2 && strength) PetscCall(PSCellsToGridDim(S, ix, dt, 2, PETSC_TRUE));
  else if (S->dim == 2) PetscCall(PSCellsToGridDim(S, ix, dt, 2, PETSC_FALSE));
  else if (strength) PetscCall(PSCellsToGridDim(S, ix, dt, 3, PETSC_TRUE));
  else PetscCall(PSCellsToGridDim(S, ix, dt, 3, PETSC_FALSE));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* L at the centre of the cell with lower corner node o from the nodal
   velocities v (dim per node), and the largest corner speed */
static inline void CellGradientDim(const PSCorners *K, const PetscInt dim, PetscInt o, const PetscReal *v0, PetscReal L[3][3], PetscReal vmax[1])
{
  PetscInt  a, d, e;
  PetscReal v2max = 0.0;
  for (d = 0; d < 3; d++)
    for (e = 0; e < 3; e++) L[d][e] = 0.0;
#pragma GCC unroll 8 /* (whole: as HourglassRatesDim) */
  for (a = 0; a < (1 << dim); a++) {
    const PetscReal *v  = &v0[dim * (o + K->off[a])];
    PetscReal        v2 = 0.0;
#pragma GCC unroll 3
    for (d = 0; d < dim; d++) {
      v2 += v[d] * v[d];
#pragma GCC unroll 3
      for (e = 0; e < dim; e++) L[d][e] += v[d] * K->gN[a][e];
    }
    v2max = PetscMax(v2max, v2);
  }
  *vmax = PetscSqrtReal(v2max);
}

/* one material's deviator over the step: Jaumann rate 2G D' + W s - s W, J2
   return against its flow stress; returns the deviatoric work per volume */
static PetscErrorCode Deviator(const PSMaterial *M, PetscInt dim, const PetscReal L[3][3], PetscReal dt, PetscReal rho, PetscReal *sq, PetscReal Mk, PetscReal *w)
{
  PetscReal s0[3][3], s[3][3], D[3][3], W[3][3], trD, s2 = 0.0, DD = 0.0;
  PetscReal im = 1.0 / Mk, ep = sq[dim == 3 ? 6 : 4] * im, T = sq[dim == 3 ? 7 : 5] * im;
  PetscInt  a, b, c;

  PetscFunctionBeginUser;
  /* unpack s = M s / M (stored components xx, yy, zz, [yz, xz,] xy) */
  for (a = 0; a < 3; a++)
    for (b = 0; b < 3; b++) s0[a][b] = 0.0;
  s0[0][0] = sq[0] * im;
  s0[1][1] = sq[1] * im;
  s0[2][2] = sq[2] * im;
  if (dim == 3) {
    s0[1][2] = s0[2][1] = sq[3] * im;
    s0[0][2] = s0[2][0] = sq[4] * im;
    s0[0][1] = s0[1][0] = sq[5] * im;
  } else s0[0][1] = s0[1][0] = sq[3] * im;
  trD = L[0][0] + L[1][1] + L[2][2];
  for (a = 0; a < 3; a++)
    for (b = 0; b < 3; b++) {
      D[a][b] = 0.5 * (L[a][b] + L[b][a]) - (a == b ? trD / 3.0 : 0.0);
      W[a][b] = 0.5 * (L[a][b] - L[b][a]);
    }
  for (a = 0; a < 3; a++)
    for (b = 0; b < 3; b++) {
      PetscReal r = 2.0 * M->G * D[a][b];
      for (c = 0; c < 3; c++) r += W[a][c] * s0[c][b] - s0[a][c] * W[c][b];
      s[a][b] = s0[a][b] + dt * r;
      s2 += s[a][b] * s[a][b];
      DD += D[a][b] * D[a][b];
    }
  if (M->strength_fn) {
    const PetscReal seq = PetscSqrtReal(1.5 * s2);
    PetscReal       Y;
    PetscCall(M->strength_fn(M, ep, PetscSqrtReal(2.0 / 3.0 * DD), T, &Y));
    if (seq > Y) {
      const PetscReal dep = (seq - Y) / (3.0 * M->G);
      for (a = 0; a < 3; a++)
        for (b = 0; b < 3; b++) s[a][b] *= Y / seq;
      ep += dep;
      if (M->cv > 0.0) T += M->chi * Y * dep / (rho * M->cv);
    }
  }
  /* trapezoidal deviatoric work per unit volume */
  *w = 0.0;
  for (a = 0; a < 3; a++)
    for (b = 0; b < 3; b++) *w += 0.5 * (s0[a][b] + s[a][b]) * D[a][b] * dt;
  sq[0] = Mk * s[0][0];
  sq[1] = Mk * s[1][1];
  sq[2] = Mk * s[2][2];
  if (dim == 3) {
    sq[3] = Mk * s[1][2];
    sq[4] = Mk * s[0][2];
    sq[5] = Mk * s[0][1];
  } else sq[3] = Mk * s[0][1];
  sq[dim == 3 ? 6 : 4] = Mk * ep;
  sq[dim == 3 ? 7 : 5] = Mk * T;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* the largest signal speed so far, and the cell that has it (C->sat, for
   the time step's guard); a NaN speed always wins */
static inline void Fastest(const PSSolver *S, PetscInt i, PetscInt j, PetscInt k, PetscReal c, PetscReal v, PetscReal sq, PetscReal rho, PetscReal *smax)
{
  PSCells       *C      = S->cells;
  const PetscInt ijk[3] = {i, j, k};
  PetscInt       d;
  if (c + v + sq <= *smax) return;
  *smax = c + v + sq;
  if (!(*smax == *smax)) *smax = PETSC_MAX_REAL;
  for (d = 0; d < 3; d++) C->sat[d] = d < S->dim ? S->scene->lower[d] + (ijk[d] + 0.5) * S->h[d] : 0.0;
  C->sat[3] = c;
  C->sat[4] = v;
  C->sat[5] = sq;
  C->sat[6] = rho;
}

/* The predictor's half-step values (PredictGasCell: the cell of lane l, its
   inputs in; PredictGasLanes: the row through GasLanesWalk, then the force
   changes) of the cells [0, nr) of a row (cell i0 + l in lane l; ghosted
   index ci0 + i0 + l, lower corner node oc0 + i0 + l, EOS slot index
   n0 + l) that hold one material with mass, an ideal gas
   (C->gasf, C->gam its gamma) without markers or void (PSCellsShareVolume's
   one-material case): the predictor's arithmetic for such a cell, in its
   order, without a branch (every test a choice between values computed
   before it, a divisor 1 where its value is not used), so the row's loop
   takes it in SIMD lanes.  Into the planes of w reals at W: the flag (1: the
   values are the predictor's, 0: the predictor's own loop takes the cell),
   q^h, the force's change of pressure -V_m (p_f^h + q^h - p_f^n - q^n), p_k^h,
   the mass M_c and the sound speed c_max (the hourglass viscosity) */
enum { PS_PL_FLAG, PS_PL_QH, PS_PL_DSIG, PS_PL_PK, PS_PL_MC, PS_PL_CMAX, PS_PL_F }; /* (then the force changes' 2^dim dim planes, the hourglass rates' nh dim) */
static inline __attribute__((always_inline)) void PredictGasCell(const PSSolver *S, const PetscInt dim, PetscInt ci0, PetscInt oc0, PetscInt n0, PetscInt i0, PetscInt l, const PSGasArgs *A, PSGasIn in)
{
  const PSCells   *C  = S->cells;
  const PetscReal *XQ = PSCellsX(C, 0, PS_CX_Q), *XAM = PSCellsX(C, 0, PS_CX_AM), *XCM = PSCellsX(C, 0, PS_CX_CM);
  const PetscReal *vh = C->vh, Vc = C->Vc, cl = A->cl, cq = A->cq, dt = A->dt, hm = A->hm;
  const PetscInt   nco = 1 << dim, w = A->w;
  const PSCorners *K  = &C->K;
  PetscReal       *W  = A->W;
  PetscInt         a;
  const PetscInt  ci = ci0 + i0 + l, oc = oc0 + i0 + l;
  const PetscReal M = in.M, V = in.V, E = in.E, ec0 = in.ec0, ec2 = in.ec2, Q = XQ[ci];
  PetscReal       Mc, Vm, cmax, dVk, V0e, L0 = 0.0, L1 = 0.0, L2 = 0.0, trD;
  GasLanesMix(M, V, in.ec1, &Mc, &Vm, &cmax);
  /* the diagonal of CellGradientDim's L, in its order */
#pragma GCC unroll 8
  for (a = 0; a < nco; a++) {
    const PetscReal *v = &vh[dim * (oc + K->off[a])];
    L0 += v[0] * K->gN[a][0];
    L1 += v[1] * K->gN[a][1];
    if (dim == 3) L2 += v[2] * K->gN[a][2];
  }
  trD = L0 + L1 + L2;
  /* half the volume change, shared; the ideal gas's p_k^h (the predictor's two divisions) */
  const PetscReal dVh = 0.5 * Vc * dt * trD;
  GasLanesShare(Vc, V, XAM[ci] * Vc, ec2, XCM[ci], dVh, &dVk, &V0e);
  const PetscReal V1 = PetscMax(V + dVk, 0.5 * V), V1d = V1 > 0.0 ? V1 : 1.0, dV = V1 - V, iV1 = 1.0 / V1d, g1 = in.g - 1.0;
  const PetscReal den = 1.0 + 0.5 * g1 * dV * iV1, dd = den != 0.0 ? den : 1.0, pk0 = g1 * iV1 * (E - dV * (0.5 * ec0 + Q)) / dd, pk = PetscMax(pk0, 0.0);
  const PetscReal Vh = 0.0 + V1, Vhd = Vh != 0.0 ? Vh : 1.0;
  /* q^h at Mc / Vh; p_f^h and p_f^n */
  const PetscReal qh = GasLanesViscosity(Mc / Vhd, hm, trD, cmax, cl, cq), dp = GasLanesForcePressure(ec2, pk) + qh - GasLanesForcePressure(ec2, ec0) - Q;
  const PetscBool ok = M > 0.0 && V > 0.0 && V0e <= PS_VOID_ROUNDOFF * Vc;
  W[PS_PL_FLAG * w + l] = ok ? 1.0 : 0.0;
  W[PS_PL_QH * w + l]   = qh;
  W[PS_PL_DSIG * w + l] = 0.0 - Vm * dp;
  W[PS_PL_PK * w + l]   = pk;
  W[PS_PL_MC * w + l]   = Mc;
  W[PS_PL_CMAX * w + l] = cmax;
}

static inline void PredictGasLanes(const PSSolver *S, const PetscInt dim, PetscInt ci0, PetscInt oc0, PetscInt n0, PetscInt i0, PetscInt nr, PetscReal dt, PetscReal hm, PetscBool forces, PetscInt w, PetscReal *W)
{
  const PSCells   *C  = S->cells;
  const PetscReal *vh = C->vh;
  const PetscInt   nco = 1 << dim, nh = dim == 3 ? 4 : 1, hsd = GasLanesHalfSize(C, dim), pg = PS_PL_F + nco * dim; /* (the hourglass rates' first plane) */
  const PSCorners *K  = &C->K;
  const PetscReal *HS = C->hs;
  const PSGasArgs  A  = GasLanesArgs(S, dt, hm, 0.0, w, W);
  PetscInt         l, a;

  if (!GasLanesWalk(S, PS_GK_PREDICT, dim, ci0, oc0, n0, i0, nr, &A, &W[PS_PL_FLAG * w])) return;
  /* without strength the force change at the corners (the loop's, for a
     run of lane cells inside the row's owned corners): the hourglass rates
     at v^{n+1/2*} (for the cell's slot, which holds those at t^n until the
     loop copies them) and the change of the hourglass force and of
     -V_m (p + q) I */
  if (!forces) return;
#pragma GCC ivdep
  for (l = 0; l < nr; l++) {
    const PetscInt   oc = oc0 + i0 + l;
    const PetscReal *gh = &HS[hsd * (n0 + l) + 1], kap = K->khg * W[PS_PL_MC * w + l] * W[PS_PL_CMAX * w + l], ds = W[PS_PL_DSIG * w + l];
    PetscReal        hgh[4][3], dh[4][3];
    PetscInt         d, e;
    HourglassRatesDim(K, dim, oc, vh, hgh);
#pragma GCC unroll 4
    for (e = 0; e < nh; e++)
#pragma GCC unroll 3
      for (d = 0; d < dim; d++) {
        W[(pg + dim * e + d) * w + l] = hgh[e][d];
        dh[e][d]                      = hgh[e][d] - gh[dim * e + d]; /* (the rates' change) */
      }
#pragma GCC unroll 8
    for (a = 0; a < nco; a++)
#pragma GCC unroll 3
      for (d = 0; d < dim; d++) W[(PS_PL_F + a * dim + d) * w + l] = GasLanesCornerForce(K, dim, a, d, ds, kap, dh);
  }
}

/* a lane cell's p_k^h into its material's slot (lane l, slot n, ghosted
   index ci; its deviator's none: 0) */
static inline void PredictLanePk(const PSCells *C, PetscInt n, PetscInt ci, PetscInt hmat, const PetscReal *W, PetscInt nw, PetscInt l)
{
  PetscReal *pk = &PSCellsHM(C, n, hmat)[C->sole[ci] * hmat];
  PetscInt   e;
  for (e = 1; e < hmat; e++) pk[e] = 0.0;
  pk[0] = W[PS_PL_PK * nw + l];
}

/* a lane cell's values that the predictor's loop stores: its p_k^h
   (PredictLanePk) and q^h into the cell's half-step slot hs */
static inline void PredictLaneCell(const PSCells *C, PetscInt n, PetscInt ci, PetscInt hmat, const PetscReal *W, PetscInt nw, PetscInt l, PetscReal *hs)
{
  PredictLanePk(C, n, ci, hmat, W, nw, l);
  hs[0] = W[PS_PL_QH * nw + l];
}

/* the predictor's node values of the local nodes [o0, o1): v^n (the grid's
   old velocity: musl keeps v_new - v_old; apic the cells' own P^C/m^C) into
   vo, v^{n+1/2*} = (v^n + v*)/2 into vh, and df zeroed for the cells' force
   changes */
static inline void PredictNodes(PSSolver *S, const PetscInt dim, PetscBool musl, PetscInt o0, PetscInt o1)
{
  PSCells         *C   = S->cells;
  const PetscInt   dof = PSGridDof(S);
  const PetscReal *mcn = C->mcn, *P = C->P, *g = S->g; /* (locals, a divisor for every node: the loops in SIMD lanes) */
  PetscReal       *vo = C->vo, *vh = C->vh, *df = C->df;
  PetscInt         o, d;
  if (musl) {
#pragma GCC ivdep
    for (o = o0; o < o1; o++)
#pragma GCC unroll 3
      for (d = 0; d < dim; d++) {
        const PetscReal vs = g[dof * o + 1 + d];
        vo[dim * o + d]    = vs - g[dof * o + dof - dim + d];
        vh[dim * o + d]    = 0.5 * (vo[dim * o + d] + vs);
        df[dim * o + d]    = 0.0;
      }
  } else {
#pragma GCC ivdep
    for (o = o0; o < o1; o++) {
      const PetscReal mn = mcn[o], md = mn > 0.0 ? mn : 1.0;
#pragma GCC unroll 3
      for (d = 0; d < dim; d++) {
        const PetscReal vs = g[dof * o + 1 + d], r = P[dim * o + d] / md;
        vo[dim * o + d]    = mn > 0.0 ? r : vs;
        vh[dim * o + d]    = 0.5 * (vo[dim * o + d] + vs);
        df[dim * o + d]    = 0.0;
      }
    }
  }
}

/* the corrector of owned node o (physical index ip): v^{n+1} = v* + dt df/m,
   the boundary conditions where bc (a node on a face of the domain; a
   constant where it is called), musl's dv = v^{n+1} - v^n where dv */
static inline __attribute__((always_inline)) void CorrectNode(PSSolver *S, const PetscInt dim, const PetscInt dof, PetscReal dt, const PetscBool bc, PetscBool dv, const PetscInt ip[3], PetscInt o)
{
  PSCells   *C  = S->cells;
  PetscReal *gn = &S->g[dof * o], vn[3] = {0, 0, 0};
  PetscInt   d;
  if (gn[0] <= S->mass_min) return;
  for (d = 0; d < dim; d++) vn[d] = gn[1 + d] + dt * C->df[dim * o + d] / gn[0];
  if (bc) PSNodeBCDim(S, dim, ip, vn);
  for (d = 0; d < dim; d++) gn[1 + d] = vn[d];
  if (dv) {
    /* the markers' increment dv = v^{n+1} - v_M^n from their own old
       nodal velocity v_M^n = (m v^n - P^C_i) / (m - m^C_i): the cells
       take P^C_i = m^C_i v^{n+1} (PSCellsLagrange), so at a node where
       both are and move apart the markers' FLIP increment from the
       mixed v^n left the total momentum short by (m^C P^M - m^M P^C)/m
       (a copper plate leaving into still air lost 7e-5 of its momentum
       in 1.5 us); now markers and cells together keep it to round-off */
    const PetscReal mM = gn[0] - C->mcn[o];
    for (d = 0; d < dim; d++) {
      PetscReal vM = C->vo[dim * o + d];
      if (C->mcn[o] > 0.0 && mM > 1e-9 * gn[0]) vM = (gn[0] * vM - C->P[dim * o + d]) / mM;
      gn[dof - dim + d] = vn[d] - vM;
    }
  }
}

/* the corrector of the owned nodes (i, j, k), i in [lo[0], hi[0]), j in
   [j0, j1), k in [k0, k1) (their df whole), [lo, hi) the owned nodes of
   the step's box.  Each node alone; a row inside the domain takes the
   boundary conditions at its ends alone (PSNodeBCDim leaves the others: its
   test per node was 0.6% of the quadrants' instructions), and musl's dv
   only in a scene with markers or contact (it is the markers' G2P's, and
   contact's; without them the next step's grid reset zeroes it unread) */
static inline void CorrectNodes(PSSolver *S, const PSIndex *ix, PetscReal dt, const PetscInt dim, PetscBool musl, const PetscInt lo[3], const PetscInt hi[3], PetscInt j0, PetscInt j1, PetscInt k0, PetscInt k1)
{
  const PetscInt  dof = PSGridDof(S);
  const PetscBool dv  = musl && (S->cells->markers || S->contact) ? PETSC_TRUE : PETSC_FALSE;
  PetscInt        i, j, k;

  for (k = k0; k < k1; k++)
    for (j = j0; j < j1; j++) {
      PetscInt xa, xb, ip[3] = {0, j - PS_PAD, dim == 3 ? k - PS_PAD : 0};
      PSNodeRowInside(S, dim, lo[0], hi[0], j, k, &xa, &xb);
      for (i = lo[0]; i < xa; i++) {
        ip[0] = i - PS_PAD;
        CorrectNode(S, dim, dof, dt, PETSC_TRUE, dv, ip, Lidx(ix, i, j, k));
      }
      for (i = xa; i < xb; i++) {
        ip[0] = i - PS_PAD;
        CorrectNode(S, dim, dof, dt, PETSC_FALSE, dv, ip, Lidx(ix, i, j, k));
      }
      for (i = xb; i < hi[0]; i++) {
        ip[0] = i - PS_PAD;
        CorrectNode(S, dim, dof, dt, PETSC_TRUE, dv, ip, Lidx(ix, i, j, k));
      }
    }
}

/* PredictNodes up to the nodes of grid index u + 1 + PS_PAD along y (2D) or z
   (3D), the upper corners of the cells of index u, from the local node *nb on */
static inline void PredictNodesUpTo(PSSolver *S, const PSIndex *ix, const PetscInt dim, PetscBool musl, PetscInt u, PetscInt *nb)
{
  const PetscInt e1 = PSCellsNodesThrough(ix, dim, S->cells->nnl, u);
  if (e1 > *nb) {
    PredictNodes(S, dim, musl, *nb, e1);
    *nb = e1;
  }
}

/* CorrectNodes of the owned nodes of the step's box [lo, hi) up to grid
   index u + PS_PAD along y (2D) or z (3D), the lower corners of the cells
   of index u, from *nxt on */
static inline void CorrectNodesUpTo(PSSolver *S, const PSIndex *ix, PetscReal dt, const PetscInt dim, PetscBool musl, const PetscInt lo[3], const PetscInt hi[3], PetscInt u, PetscInt *nxt)
{
  const PetscInt e = dim - 1, u1 = PetscMin(u + PS_PAD + 1, hi[e]);
  if (u1 <= *nxt) return;
  if (dim == 2) CorrectNodes(S, ix, dt, dim, musl, lo, hi, *nxt, u1, lo[2], hi[2]);
  else CorrectNodes(S, ix, dt, dim, musl, lo, hi, lo[1], hi[1], *nxt, u1);
  *nxt = u1;
}

static inline PetscErrorCode LagrangeBehind(PSSolver *, const PSIndex *, PetscReal, const PetscInt, PetscInt);

/* the predictor-corrector over the units [u0, u1) of cells along y (2D) or
   z (3D), from where pp left it (PSCellsPredictDim: all of them at once;
   the Lagrangian pipeline: one at a time) */
typedef struct {
  PetscInt n;   /* the next cell's index among the cells around the owned nodes (PSCellsXIdx) */
  PetscInt nb;  /* the local nodes with the predictor's v^n, v^{n+1/2*} and zero df (PredictNodes) */
  PetscInt nxt; /* the first unit of owned nodes without the corrector */
} PSPredictProgress;

static inline PetscErrorCode PredictUnits(PSSolver *S, const PSIndex *ix, PetscReal dt, const PetscInt dim, const PetscBool strength, PetscInt u0, PetscInt u1, PSPredictProgress *pp)
{
  PSCells        *C = S->cells;
  const PetscReal *XQ = PSCellsX(C, 0, PS_CX_Q); /* the per-cell plane of q (PSCellsX) */
  const PetscInt  nco = 1 << dim, nh = dim == 3 ? 4 : 1, ns = C->ns, hsd = PSCellsHalfSize(C), hmat = PSCellsHalfMat(C);
  const PetscBool musl = S->run.transfer == PS_TRANSFER_MUSL;
  const PetscInt  nw = PSCellsPlaneLen(C, ix); /* (the lanes' plane length: the remap's scratch C->sW, free here) */
  const PetscBool lanes = S->run.lanes != 1 ? PETSC_TRUE : PETSC_FALSE; /* (-run_lanes 1: the scalar loop alone, for checks) */
  PetscReal       hm = 0.0, *W = C->sW;
  PetscInt        i, j, k, m, d, e, a, lo[3], hi[3], n = pp->n, orow, nb = pp->nb, nxt = pp->nxt, un;

  PetscFunctionBeginUser;
  for (d = 0; d < dim; d++) hm = PetscMax(hm, S->h[d]);
  Clip(S->zbox, ix->os, ix->om, lo, hi);
  /* every cell around the owned nodes (PSCellsXIdx), its force change to
     its owned corners.  A row (2D) or plane (3D) of cells at a time, with
     the nodes' values pipelined around it, each node's own arithmetic as in
     separate passes: before the cells of unit u, the nodes up to unit
     u + 1 take v^n, v^{n+1/2*} and a zero df (PredictNodes; nb: the local
     nodes done); after them, the owned nodes up to unit u have all their
     force changes (the loop goes up along y, z) and take the corrector
     (CorrectNodes; nxt: the first unit of nodes without it).  A node's row
     is read and written while in the caches, not in three passes */
  for (un = u0; un < u1; un++) {
    k = dim == 3 ? un : C->xs[2];
    if (dim == 3) PredictNodesUpTo(S, ix, dim, musl, k, &nb);
    for (j = dim == 3 ? C->xs[1] : un; j < (dim == 3 ? C->ce[1] : un + 1); j++) {
      PetscInt ci0, oc0, xa, xb;
      if (dim == 2) PredictNodesUpTo(S, ix, dim, musl, j, &nb);
      PSCellsRow(C, ix, dim, j, k, &ci0, &oc0, &xa, &xb);
      if (lanes) PredictGasLanes(S, dim, ci0, oc0, n, C->xs[0], C->ce[0] - C->xs[0], dt, hm, !strength, nw, W);
      for (i = C->xs[0], orow = PSCellsOwnedRow(ix, dim, j, k); i < C->ce[0]; i++, n++) {
        const PetscInt   ci = ci0 + i, l = i - C->xs[0];
        const PetscReal *u  = &C->u[C->ms * ci];
        const PetscReal *ec = PSCellsEC(C, n);
        PetscReal       *hmn = PSCellsHM(C, n, hmat), *qh = &C->hs[hsd * n], *gh = qh + 1;
        const PetscInt   oc = oc0 + i, own = orow & (i >= xa && i < xb ? 0xff : PSCellsOwnedAxis(ix, 0, i)); /* (its owned corners) */
        PetscReal        L[3][3], vmax, trD, dVh, dVk[PS_MAX_CELLMAT], Mc, Vm, cmax, Vh = 0.0, sc = 0.0, sp = 0.0, dsig[3][3] = {{0}}, hgh[4][3], hg0[4][3], kap;
        PetscInt         m0, m1;
        if (lanes && !strength && i >= xa && i < xb && W[PS_PL_FLAG * nw + l] != 0.0) {
          /* a run of the lanes' cells whose corners are the row's owned ones
             (without strength): each one's p_k^h, q^h and hourglass rates
             from the lanes, their force changes to the nodes in lanes, in
             this loop's order (GasLanesNodes) */
          const PetscInt pg = PS_PL_F + nco * dim;
          PetscInt       l1 = l + 1, x;
          l1 = PSLanesFlagRun(&W[PS_PL_FLAG * nw], l1, PetscMin(xb, C->ce[0]) - C->xs[0]); /* (xb may lie beyond the row's cells) */
          {
            /* each cell's p_k^h (q^h below) into the slot of its material,
               eco[n] + sole (PSCellsHM): where the run's slots follow one
               another (cells of one gas: one slot each, in order; checked in
               SIMD lanes) and hold p alone (no strength), a loop of stores
               in SIMD lanes; else one by one (PredictLanePk) */
            const PetscInt *eco = &C->eco[n - l];
            const short    *so  = &C->sole[ci - l];
            const PetscInt  z0  = eco[l] + so[l];
            PetscInt        gap = 0;
            for (x = l; x < l1; x++) gap |= (eco[x] + so[x]) ^ (z0 + x - l);
            if (!gap && hmat == 1) {
              PetscReal       *pk = &C->hm[z0 - l];
              const PetscReal *Wp = &W[PS_PL_PK * nw];
              for (x = l; x < l1; x++) pk[x] = Wp[x];
            } else
              for (x = l; x < l1; x++) PredictLanePk(C, n + x - l, ci + x - l, hmat, W, nw, x);
          }
          {
            /* each cell's q^h and hourglass rates into its slot, side by side:
               a loop of its own, which GCC runs in SIMD lanes */
            PetscReal *hs0 = &C->hs[hsd * n];
#pragma GCC ivdep
            for (x = l; x < l1; x++) {
              PetscReal *hx = &hs0[hsd * (x - l)];
              hx[0]         = W[PS_PL_QH * nw + x];
#pragma GCC unroll 12
              for (e = 0; e < nh * dim; e++) hx[1 + e] = W[(pg + e) * nw + x];
            }
          }
          GasLanesNodes(dim, &C->K, oc0 + C->xs[0], orow, l, l1, nw, NULL, &W[PS_PL_F * nw], NULL, 0, C->df, dim, 1);
          n += l1 - l - 1;
          i += l1 - l - 1;
          continue;
        }
        if (lanes && W[PS_PL_FLAG * nw + l] != 0.0) {
          /* a cell of the lanes: their values, and what the loop below
             leaves (its material's p_k^h, q^h, the force's change) */
          PredictLaneCell(C, n, ci, hmat, W, nw, l, qh);
          for (d = 0; d < 3; d++) dsig[d][d] = W[PS_PL_DSIG * nw + l];
          Mc   = W[PS_PL_MC * nw + l];
          cmax = W[PS_PL_CMAX * nw + l];
        } else {
          PSCellsPresent(C, ci, &m0, &m1);
          CellMix(C, u, ec, m0, m1, &Mc, &Vm, &cmax);
          if (Mc <= 0.0) continue;
          /* the half-step state at v^{n+1/2*}: half the volume change, shared */
          CellGradientDim(&C->K, dim, oc, C->vh, L, &vmax);
          trD = L[0][0] + L[1][1] + L[2][2];
          dVh = 0.5 * C->Vc * dt * trD;
          PetscCall(PSCellsShareVolume(S, ci, ec, m0, m1, dVh, dVk, NULL, NULL));
          for (m = m0; m < m1; m++) {
            const PSMaterial *M   = &S->mat[C->mat[m]];
            const PetscReal  *blk = &u[m * C->mst];
            PetscReal        *pk = &hmn[m * hmat], *sk = pk + 1, A, B, c2, e1, V1, J;
            /* (only the materials with mass read it: the Lagrangian phase; a
               material without strength has p alone, without GCC's call of memset) */
            if (hmat == 1) pk[0] = 0.0;
            else
              for (e = 0; e < hmat; e++) pk[e] = 0.0;
            if (blk[PS_CM] <= 0.0) continue;
            V1 = PetscMax(blk[PS_CV] + dVk[m], 0.5 * blk[PS_CV]);
            if (M->eos_fn == PSEOSIdealGas && M->spall >= 0.0) {
              /* the ideal gas (A = 0, B = (gamma - 1) M / V1): PSPressureEnergy's
                 update multiplied through by M_k, E1 = (E - dV (p0/2 + q)) /
                 (1 + (gamma - 1) dV / (2 V1)), p = (gamma - 1) E1 / V1: two
                 divisions instead of seven (the same values to round-off) */
              const PetscReal dV = V1 - blk[PS_CV], iV1 = 1.0 / V1;
              pk[0] = (M->gamma - 1.0) * iV1 * (blk[PS_CE] - dV * (0.5 * ec[PS_EC * m] + XQ[ci])) / (1.0 + 0.5 * (M->gamma - 1.0) * dV * iV1);
            } else {
              J = M->rho0 * V1 / blk[PS_CM];
              PetscCall(PSCellsEOS(M, J, ec[PS_EC * m], (V1 - blk[PS_CV]) / blk[PS_CV], &A, &B, &c2));
              PSPressureEnergy(M, PETSC_FALSE, blk[PS_CE] / blk[PS_CM], 0.0, (V1 - blk[PS_CV]) / blk[PS_CM], ec[PS_EC * m], A, B, XQ[ci], &e1, &pk[0]);
            }
            if (M->gamma > 0.0) pk[0] = PetscMax(pk[0], 0.0); /* an ideal gas holds no tension */
            Vh += V1;
            sc += ec[PS_EC * m + 2];
            sp += ec[PS_EC * m + 2] * pk[0];
            /* the deviator half a step on (a copy: the Lagrangian phase takes the whole step) */
            if (strength && M->G > 0.0) {
              PetscReal sq[8], w;
              for (e = 0; e < C->nq; e++) sq[e] = blk[PS_CQ + e];
              PetscCall(Deviator(M, dim, L, 0.5 * dt, blk[PS_CM] / V1, sq, blk[PS_CM], &w));
              for (e = 0; e < ns; e++) {
                sk[e] = sq[e] / blk[PS_CM];
                sq[e] = blk[PS_CQ + e] / blk[PS_CM];
              }
              /* the force's deviatoric part changes by V_k (s_k^h - s_k^n) */
              {
                PetscReal Sh[3][3], Sn[3][3];
                ForceStress(dim, sk, 0.0, Sh);
                ForceStress(dim, sq, 0.0, Sn);
                for (d = 0; d < 3; d++)
                  for (e = 0; e < 3; e++) dsig[d][e] += blk[PS_CV] * (Sh[d][e] - Sn[d][e]);
              }
            }
          }
          /* q^h at the half step's density and rate; the force's pressure part
             changes by -(p_f^h + q^h - p_f^n - q^n) V_m I, p_f the compliance-
             weighted mean (PSCellsForcePressure) */
          *qh = PSViscosity(Mc / Vh, hm, trD, cmax, S->run.c_linear, S->run.c_quadratic);
          {
            const PetscReal pfh = sc > 0.0 ? (m1 == m0 + 1 ? hmn[m0 * hmat] : sp / sc) : 0.0, dp = pfh + *qh - PSCellsForcePressure(ec, m0, m1) - XQ[ci];
            for (d = 0; d < 3; d++) dsig[d][d] -= Vm * dp;
          }
        }
        /* hourglass rates at v^{n+1/2*} (kept for the Lagrangian phase's heat)
           and at t^n (the cells' nodal velocity, as PSCellsToGrid) */
        HourglassRatesDim(&C->K, dim, oc, C->vh, hgh);
        for (e = 0; e < nh; e++)
          for (d = 0; d < dim; d++) {
            hg0[e][d]        = gh[dim * e + d]; /* the rates of the cells' nodal velocity at t^n, as PSCellsToGrid left them */
            gh[dim * e + d] = hgh[e][d];
          }
        kap = HourglassKappa(&C->K, Mc, cmax);
        /* the force change at the corners */
        for (a = 0; a < nco; a++) {
          PetscReal *dfa = &C->df[dim * (oc + C->K.off[a])];
          if (!((own >> a) & 1)) continue;
          for (d = 0; d < dim; d++) {
            PetscReal fd = 0.0;
            if (strength)
              for (e = 0; e < dim; e++) fd -= dsig[d][e] * C->K.gN[a][e];
            else fd -= dsig[d][d] * C->K.gN[a][d];
            for (e = 0; e < nh; e++) fd -= kap * PSHourglassSign(a, e) * (hgh[e][d] - hg0[e][d]);
            dfa[d] += fd;
          }
        }
      }
      if (dim == 2) {
        CorrectNodesUpTo(S, ix, dt, dim, musl, lo, hi, j, &nxt);
        if (C->lag.fused) PetscCall(LagrangeBehind(S, ix, dt, dim, j - 1)); /* (its upper corners, j + PS_PAD, corrected) */
      }
    }
    if (dim == 3) {
      CorrectNodesUpTo(S, ix, dt, dim, musl, lo, hi, k, &nxt);
      if (C->lag.fused) PetscCall(LagrangeBehind(S, ix, dt, dim, k - 1));
    }
  }
  pp->n   = n;
  pp->nb  = nb;
  pp->nxt = nxt;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* the predictor's start: the Lagrangian phase one unit behind, in a scene of
   cells alone on a rank without ghost nodes across the units
   (PSLagProgress); -run_lanes 1 keeps it to its own pass, for checks */
static inline void PredictStart(PSSolver *S, const PSIndex *ix, const PetscInt dim, PSPredictProgress *pp)
{
  PSCells *C = S->cells;
  PetscInt lo[3], hi[3];

  Clip(S->zbox, ix->os, ix->om, lo, hi);
  pp->n        = 0;
  pp->nb       = 0;
  pp->nxt      = lo[dim - 1];
  C->lag.fused = !C->markers && !S->contact && S->run.lanes != 1 && PSCellsWholeAcross(ix, dim) ? PETSC_TRUE : PETSC_FALSE;
  C->lag.next  = C->cs[dim - 1];
  C->lag.nb    = ix->os[dim - 1] - ix->gs[dim - 1];
  C->lag.nb0   = C->lag.nb;
  C->lag.smax  = 0.0;
}

/* the nodes the predictor's units left: the predictor's values of every
   local node, and the corrector of the owned ones */
static inline void PredictEnd(PSSolver *S, const PSIndex *ix, PetscReal dt, const PetscInt dim, const PSPredictProgress *pp)
{
  PSCells        *C    = S->cells;
  const PetscBool musl = S->run.transfer == PS_TRANSFER_MUSL;
  PetscInt        lo[3], hi[3];

  Clip(S->zbox, ix->os, ix->om, lo, hi);
  PredictNodes(S, dim, musl, pp->nb, C->nnl);
  if (dim == 2) CorrectNodes(S, ix, dt, dim, musl, lo, hi, pp->nxt, hi[1], lo[2], hi[2]);
  else CorrectNodes(S, ix, dt, dim, musl, lo, hi, lo[1], hi[1], pp->nxt, hi[2]);
}

/* the predictor-corrector: dim and strength constants where it is called
   (PSCellsPredict picks them as PSCellsToGrid), so the per-cell loops
   unroll, and without strength the force's change is a pressure's; the
   ghosts' values after it */
static inline PetscErrorCode PSCellsPredictDim(PSSolver *S, const PSIndex *ix, PetscReal dt, const PetscInt dim, const PetscBool strength)
{
  PSCells          *C = S->cells;
  PSPredictProgress pp;

  PetscFunctionBeginUser;
  if (!EV_Pred) PetscCall(PetscLogEventRegister("PSCellsPredict", 0, &EV_Pred));
  PetscCall(PetscLogEventBegin(EV_Pred, 0, 0, 0, 0));
  PredictStart(S, ix, dim, &pp);
  PetscCall(PredictUnits(S, ix, dt, dim, strength, C->xs[dim - 1], C->ce[dim - 1], &pp));
  PredictEnd(S, ix, dt, dim, &pp);
  PetscCall(PetscLogEventEnd(EV_Pred, 0, 0, 0, 0));
  PetscCall(PSHaloBcast(S->sfg, S->g));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The cells' P2G, the grid update and the predictor-corrector (with the
   Lagrangian phase behind it) as one pipeline of units: after the P2G of
   the cells of unit u the owned nodes through grid index u + PS_PAD have
   all their cells' sums (cells u - 1 and u), and take the grid update; the
   predictor's unit u - 1 then has its nodes' v* (its upper corners, u +
   PS_PAD).  So each unit's cells and nodes are read by the three phases
   while still in the caches, not in three passes over the state (the 512^2
   quadrants' state is 150 MiB: PSCellsToGrid and PSCellsPredict each read
   it from memory).  Every cell, node and sum is the separate phases' own,
   in the same order.  In a scene of cells alone (no marker bodies: their
   P2G and G2P stand between the phases; no contact, whose grid solve does)
   under musl, on a rank without ghost nodes across the units (one rank,
   or ranks along y in 2D and z in 3D alone: the ghost nodes next to the
   owned ones are computed in the pipeline as their owner computes them,
   PipelineDim, where PSGridSolve's halo would come between the phases);
   -run_lanes 1 keeps the separate phases, for checks.  The scenes are the
   P2G's sums' (PSCellsSums) on such a rank: the pipeline's P2G takes them */
static PetscLogEvent EV_Pipe = 0;

PetscBool PSCellsPipelined(const PSSolver *S, const PSIndex *ix)
{
  const PetscInt e = S->dim - 1;

  if (!PSCellsSums(S) || !PSCellsWholeAcross(ix, S->dim)) return PETSC_FALSE;
  /* (ranks along y (2D) or z (3D) alone: the ghost nodes next to the owned
     ones and one more, whose values the edge units' cells read, local) */
  if (ix->os[e] > ix->gs[e] && ix->os[e] - 2 < ix->gs[e]) return PETSC_FALSE;
  if (ix->os[e] + ix->om[e] < ix->gs[e] + ix->gm[e] && ix->os[e] + ix->om[e] + 2 > ix->gs[e] + ix->gm[e]) return PETSC_FALSE;
  return PETSC_TRUE;
}

/* the window's pointers at its first units (bn, bc): C->sVL, vo, df and hs
   shifted so that the whole arrays' indices land in the windows (a pointer
   below the window's start, never dereferenced below it) */
static inline void WindowPoint(PSCells *C)
{
  PSCellsWindow *w = &C->win;
  C->sVL           = w->vl - w->bn * w->nu;
  C->vo            = w->vo - w->bn * w->nu;
  C->df            = w->df - w->bn * w->nu;
  C->hs            = w->hs - w->bc * w->cu;
}

/* C->sVL, vo, df and hs the whole arrays again, where the window had them
   (the step's Lagrangian phase ends with it, PSCellsLagrange; and
   PSCellsDestroy): outside the pipeline and the Lagrangian phase behind it
   they are always the whole arrays, so scratch users (the fit's discarded
   momentum, closure.c) and the separate phases take them as they are */
void PSCellsWindowEnd(PSCells *C)
{
  PSCellsWindow *w = &C->win;
  if (!w->buf) return;
  C->sVL = w->full[0];
  C->vo  = w->full[1];
  C->df  = w->full[2];
  C->hs  = w->full[3];
}

/* the window at the step's start (allocated at the first): its first units
   the arrays' first */
static inline PetscErrorCode WindowStart(PSSolver *S, const PSIndex *ix, const PetscInt dim)
{
  PSCells       *C = S->cells;
  PSCellsWindow *w = &C->win;

  PetscFunctionBeginUser;
  if (!w->buf) {
    w->nu      = dim * (dim == 3 ? ix->gm[0] * ix->gm[1] : ix->gm[0]);
    w->cu      = PSCellsHalfSize(C) * (dim == 3 ? C->xm[0] * C->xm[1] : C->xm[0]);
    w->full[0] = C->sVL;
    w->full[1] = C->vo;
    w->full[2] = C->df;
    w->full[3] = C->hs;
    PetscCall(PetscMalloc1(PS_WIN_UNITS * (3 * w->nu + w->cu), &w->buf));
    w->vl = w->buf;
    w->vo = w->vl + PS_WIN_UNITS * w->nu;
    w->df = w->vo + PS_WIN_UNITS * w->nu;
    w->hs = w->df + PS_WIN_UNITS * w->nu;
  }
  w->bn = 0;
  w->bc = 0;
  WindowPoint(C);
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* the window made to hold the local units of nodes [n0, n1) and of cells
   [c0, c1) (from C->xs): n0 and c0 the first still read, n1 and c1 past
   the last about to be written.  Where n1 or c1 passes the window's end,
   the units from n0 (c0) on move to its start */
static inline PetscErrorCode WindowFit(PSCells *C, PetscInt n0, PetscInt n1, PetscInt c0, PetscInt c1)
{
  PSCellsWindow *w = &C->win;

  PetscFunctionBeginUser;
  n0 = PetscMax(n0, w->bn);
  c0 = PetscMax(c0, w->bc);
  PetscCheck(n1 - n0 <= PS_WIN_UNITS && c1 - c0 <= PS_WIN_UNITS, PETSC_COMM_SELF, PETSC_ERR_PLIB, "the pipeline's window of %d units cannot hold node units [%" PetscInt_FMT ", %" PetscInt_FMT ") and cell units [%" PetscInt_FMT ", %" PetscInt_FMT ")", PS_WIN_UNITS, n0, n1, c0, c1);
  if (n1 > w->bn + PS_WIN_UNITS || c1 > w->bc + PS_WIN_UNITS) {
    const PetscInt sn = n0 - w->bn, sc = c0 - w->bc;
    PetscCall(PetscArraymove(w->vl, w->vl + sn * w->nu, (PS_WIN_UNITS - sn) * w->nu));
    PetscCall(PetscArraymove(w->vo, w->vo + sn * w->nu, (PS_WIN_UNITS - sn) * w->nu));
    PetscCall(PetscArraymove(w->df, w->df + sn * w->nu, (PS_WIN_UNITS - sn) * w->nu));
    PetscCall(PetscArraymove(w->hs, w->hs + sc * w->cu, (PS_WIN_UNITS - sc) * w->cu));
    w->bn = n0;
    w->bc = c0;
    WindowPoint(C);
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

static inline PetscErrorCode PipelineDim(PSSolver *S, const PSIndex *ix, PetscReal dt, const PetscInt dim, const PetscBool strength)
{
  PSCells          *C = S->cells;
  const PetscInt    e = dim - 1, u0 = C->xs[e], u1 = C->ce[e];
  PSToGridProgress  tp;
  PSPredictProgress pp;
  PetscInt          u, gn = PETSC_MIN_INT; /* (gn: the first unit of nodes without the grid update) */
  const PetscBool   behind = PSCellsRemapBehindOK(S, ix); /* the remap's first sweep behind the Lagrangian phase (remap.c) */
  const PetscBool   win    = behind && ix->gm[dim - 1] == ix->om[dim - 1]; /* the window of temporaries: one rank's (docs/speed.md, forty-fourth session) */
  PSIndex           iw     = *ix; /* (the nodes the P2G and the grid update take: the owned ones and the ghost nodes next to them) */
  PetscInt          eu[2], en[2];

  PetscFunctionBeginUser;
  if (!EV_Pipe) PetscCall(PetscLogEventRegister("PSCellsPipeline", 0, &EV_Pipe));
  PetscCall(PetscLogEventBegin(EV_Pipe, 0, 0, 0, 0));
  /* Under a rank below or above (along y in 2D, z in 3D: PSCellsPipelined),
     the ghost nodes next to the owned ones are computed here as their owner
     computes them: each one's sums over all its cells, in the order of the
     cell array (the edge units' cells, PSCellsEdgeUnits, give their
     corners there and nowhere else), and its grid update; so the
     predictor's cells under and over the owned nodes have their corners' v*
     without the grid's halo between the phases, and each value is the
     owner's, bitwise.  The corrector corrects the owned nodes alone, and
     the ghosts take the owners' values after it (PSHaloBcast) */
  PSCellsEdgeUnits(C, &eu[0], &en[0], &eu[1], &en[1]);
  if (ix->os[e] > ix->gs[e]) {
    iw.os[e] -= 1;
    iw.om[e] += 1;
  }
  if (ix->os[e] + ix->om[e] < ix->gs[e] + ix->gm[e]) iw.om[e] += 1;
  PetscCall(ToGridStart(S, ix, dim, PETSC_TRUE, &tp)); /* (the P2G's sums: G is not zeroed, PSGridReset) */
  PredictStart(S, ix, dim, &pp);
  if (behind) {
    if (win) PetscCall(WindowStart(S, ix, dim)); /* (where the remap, which reads sVL otherwise, runs behind: it reads sVR) */
    PetscCall(PetscLogEventEnd(EV_Pipe, 0, 0, 0, 0)); /* (the remap's own event: PSCellsRemap; the pipeline's paused) */
    PetscCall(PSCellsRemapBehindBegin(S, ix));
    PetscCall(PetscLogEventBegin(EV_Pipe, 0, 0, 0, 0));
  }
  for (u = eu[0] >= 0 ? eu[0] : u0; u < (eu[1] >= 0 ? eu[1] + 1 : u1); u++) {
    /* the window: from the first units still read, the Lagrangian phase's
       nodes (vo) and cells (hs), the corrector's nodes (vo, df), the
       predictor's cells of unit u - 1 and their corners (hs, df), the P2G's
       cells of unit u and their corners (hs, sVL), to the P2G's and the
       predictor's nodes through the upper corners of unit u + 1 (where it
       runs: one rank, no edge units; the remap's first sweep behind the
       phase runs on ranks along y in 2D too, without the window) */
    if (win) PetscCall(WindowFit(C, PetscMin(PetscMin(C->lag.nb, pp.nxt - ix->gs[e]), u - 1 + PS_PAD - ix->gs[e]), u + 2 + PS_PAD - ix->gs[e], PetscMin(C->lag.next, u - 1) - C->xs[e], u + 1 - C->xs[e]));
    /* the P2G of unit u (an edge unit's cells from their own slots; one
       call of ToGridUnits, inlined once with dim and strength constant) */
    if (u == eu[0]) tp.n = en[0];
    else if (u == eu[1]) tp.n = en[1];
    else if (u == u0) tp.n = 0;
    PetscCall(ToGridUnits(S, &iw, dt, dim, strength, PETSC_TRUE, u, u + 1, &tp));
    if (u < u0 || u >= u1) continue; /* (an edge unit: the corners of the cells around the owned nodes complete its ghost nodes' sums) */
    PSGridUpdateMUSLUnits(S, &iw, dt, S->g, gn, u + PS_PAD + 1);
    gn = u + PS_PAD + 1;
    if (u > u0) PetscCall(PredictUnits(S, ix, dt, dim, strength, u - 1, u, &pp));
    if (behind && u > u0) PetscCall(PSCellsRemapBehind(S, ix, dt, EV_Pipe)); /* (EV_Pipe paused while it runs) */
  }
  if (win) PetscCall(WindowFit(C, PetscMin(PetscMin(C->lag.nb, pp.nxt - ix->gs[e]), u1 - 2 + PS_PAD - ix->gs[e]), ix->gm[e], PetscMin(C->lag.next, u1 - 1) - C->xs[e], u1 - C->xs[e])); /* (the rest: every unit above them) */
  ToGridEnd(S, &iw, dim, PETSC_TRUE, &tp);
  PSGridUpdateMUSLUnits(S, &iw, dt, S->g, gn, PETSC_MAX_INT);
  if (u1 > u0) PetscCall(PredictUnits(S, ix, dt, dim, strength, u1 - 1, u1, &pp));
  PredictEnd(S, ix, dt, dim, &pp);
  if (ix->gm[e] != ix->om[e]) PetscCall(PSHaloBcast(S->sfg, S->g)); /* (the ghosts: their owners' corrected values) */
  PetscCall(PetscLogEventEnd(EV_Pipe, 0, 0, 0, 0));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode PSCellsPipeline(PSSolver *S, const PSIndex *ix, PetscReal dt)
{
  const PetscBool strength = S->cells->nq > 0 ? PETSC_TRUE : PETSC_FALSE;

  PetscFunctionBeginUser;
  if (S->dim == 2 && strength) PetscCall(PipelineDim(S, ix, dt, 2, PETSC_TRUE));
  else if (S->dim == 2) PetscCall(PipelineDim(S, ix, dt, 2, PETSC_FALSE));
  else if (strength) PetscCall(PipelineDim(S, ix, dt, 3, PETSC_TRUE));
  else PetscCall(PipelineDim(S, ix, dt, 3, PETSC_FALSE));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode PSCellsPredict(PSSolver *S, const PSIndex *ix, PetscReal dt)
{
  const PetscBool strength = S->cells->nq > 0 ? PETSC_TRUE : PETSC_FALSE;

  PetscFunctionBeginUser;
  if (S->dim == 2 && strength) PetscCall(PSCellsPredictDim(S, ix, dt, 2, PETSC_TRUE));
  else if (S->dim == 2) PetscCall(PSCellsPredictDim(S, ix, dt, 2, PETSC_FALSE));
  else if (strength) PetscCall(PSCellsPredictDim(S, ix, dt, 3, PETSC_TRUE));
  else PetscCall(PSCellsPredictDim(S, ix, dt, 3, PETSC_FALSE));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The Lagrangian phase's values (LagrangeGasCell: the cell of lane l, its
   inputs in; LagrangeGasLanes: the row through GasLanesWalk) of the cells
   [0, nr) of a row (cell i0 + l in lane l, as PredictGasLanes) that hold
   one material with mass, an ideal gas without a deviator (C->gasf) and
   without markers or void: the phase's arithmetic for such a cell, in its
   order, without a branch, so the row's loop takes it in SIMD lanes.  The
   cell's volume V_c + dV and q into its per-cell planes (C->ux), and the
   material's new volume and energy into its block (in.B: with its mass
   again, unchanged, so the three stores make a group without gaps, which
   GCC takes in lanes); where the flag is 0 the block keeps its volume and
   energy (stored again), and the phase's own loop takes the cell, among
   them one whose volume would not stay positive or whose energy would go
   negative, which that loop reports or books.  Into the planes of w reals
   at W: the flag (1: these values are the phase's), the time step's speed
   c_max + |v| + q/(rho c) and its parts (Fastest's viscous term, density,
   c_max and the largest corner speed).  (Until the thirty-sixth session
   the volumes, energy and q went through planes too, and a loop copied
   them to the cells after the walk; a store into the cells' arrays in the
   kernel left the walk out of lanes, because the coefficients of q, read
   from S->run under the test of compression, stayed in the loop (the store
   may alias them) as masked loads the lanes do not take: they now come in
   PSGasArgs; and the flag's && made a branch, under which GCC moved
   the energy's arithmetic and its loads: the flag's tests are now combined
   with &) */
enum { PS_LL_FLAG, PS_LL_SPEED, PS_LL_SQ, PS_LL_RHO, PS_LL_CMAX, PS_LL_VMAX };
static inline __attribute__((always_inline)) void LagrangeGasCell(const PSSolver *S, const PetscInt dim, PetscInt ci0, PetscInt oc0, PetscInt n0, PetscInt i0, PetscInt l, const PSGasArgs *A, PSGasIn in)
{
  const PSCells   *C   = S->cells;
  const PetscReal *XAM = PSCellsX(C, 0, PS_CX_AM), *XCM = PSCellsX(C, 0, PS_CX_CM);
  PetscReal       *XV = PSCellsX(C, 0, PS_CX_V), *XQ = PSCellsX(C, 0, PS_CX_Q);
  const PetscReal *HS = C->hs, *vh = C->vh, Vc = C->Vc, cl = A->cl, cq = A->cq, dt = A->dt, hm = A->hm;
  const PetscInt   nh = dim == 3 ? 4 : 1, hsd = GasLanesHalfSize(C, dim), w = A->w;
  const PSCorners *K  = &C->K;
  PetscReal       *W  = A->W;
  const PetscInt   ci = ci0 + i0 + l, oc = oc0 + i0 + l;
  const PetscReal  M = in.M, V = in.V, E = in.E, pk = in.pk;
  const PetscReal *hs = &HS[hsd * (n0 + l)], qh = hs[0], *gh = hs + 1;
  PetscReal        L[3][3], vmax, hg[4][3], hgw = 0.0, Mc, Vm, cmax, dVk, V0e;
  PetscInt         e, d;
  /* CellGradientDim's L and corner speed; the cell's volume change, shared
     (the one-material case: dVr = 0, p* = 0) */
  CellGradientDim(K, dim, oc, vh, L, &vmax);
  const PetscReal trD = L[0][0] + L[1][1] + L[2][2], dV = Vc * dt * trD, dVr = 0.0, pr = 0.0;
  GasLanesMix(M, V, in.ec1, &Mc, &Vm, &cmax);
  GasLanesShare(Vc, V, XAM[ci] * Vc, in.ec2, XCM[ci], dV, &dVk, &V0e);
  /* q */
  const PetscReal Vmd = Vm > 0.0 ? Vm : 1.0, rho = Mc / Vmd, q = GasLanesViscosity(rho, hm, trD, cmax, cl, cq);
  /* hourglass heating, kappa sum_m g_m^h . g_m dt (HourglassKappa) */
  const PetscReal kap = K->khg * Mc * cmax;
  HourglassRatesDim(K, dim, oc, vh, hg);
#pragma GCC unroll 4
  for (e = 0; e < nh; e++)
#pragma GCC unroll 3
    for (d = 0; d < dim; d++) hgw += kap * gh[dim * e + d] * hg[e][d] * dt;
  /* the material's volume and energy (no deviator: wh = 0) */
  const PetscReal V1 = V + dVk, wh = 0.0; /* (the hourglass heat all the material's: M_k / M_c is 1, not hgw M / M) */
  const PetscReal E1 = E + hgw + wh - (pk + qh) * (dVk - dVr) - (pr + qh) * dVr;
  /* the time step's viscous term (Fastest's) */
  const PetscReal rq = rho > 0.0 ? rho : 1.0, cq2 = PetscMax(cmax, 0.5 * PetscSqrtReal(q / rq)), sqd = q > 0.0 ? rho * cq2 : 1.0, sq0 = q / sqd, sq = q > 0.0 ? sq0 : 0.0;
  const int       ok = (M > 0.0) & (V > 0.0) & (V0e <= PS_VOID_ROUNDOFF * Vc) & (V1 > 0.0) & !(E1 < 0.0);
  XV[ci]                 = Vc + dV;
  XQ[ci]                 = q;
  in.B[PS_CV]            = ok ? V1 : V;
  in.B[PS_CM]            = M;
  in.B[PS_CE]            = ok ? E1 : E;
  W[PS_LL_FLAG * w + l]  = ok ? 1.0 : 0.0;
  W[PS_LL_SPEED * w + l] = cmax + vmax + sq;
  W[PS_LL_SQ * w + l]    = sq;
  W[PS_LL_RHO * w + l]   = rho;
  W[PS_LL_CMAX * w + l]  = cmax;
  W[PS_LL_VMAX * w + l]  = vmax;
}

static inline void LagrangeGasLanes(const PSSolver *S, const PetscInt dim, PetscInt ci0, PetscInt oc0, PetscInt n0, PetscInt i0, PetscInt nr, PetscReal dt, PetscReal hm, PetscInt w, PetscReal *W)
{
  const PSGasArgs A = GasLanesArgs(S, dt, hm, 0.0, w, W);
  (void)GasLanesWalk(S, PS_GK_LAGRANGE, dim, ci0, oc0, n0, i0, nr, &A, &W[PS_LL_FLAG * w]);
}

/* the Lagrangian phase's nodes of the local units (rows along y in 2D,
   planes along z in 3D) [u0, u1): v^{n+1/2} = (v^n + v^{n+1})/2 into vh
   with the walls holding the faces on them, and P^C_i = m^C_i v^{n+1}.
   Returns the units done (u1, or u0 if more) */
static inline PetscInt LagrangeNodes(PSSolver *S, const PSIndex *ix, const PetscInt dim, PetscInt u0, PetscInt u1)
{
  PSCells         *C   = S->cells;
  const PetscInt   dof = PSGridDof(S);
  const PetscReal *v   = S->g + 1; /* (v^{n+1}: component d of node o at v[dof o + d]) */
  PetscInt         i, j, k, d, o, lo[3] = {ix->gs[0], ix->gs[1], ix->gs[2]}, hi[3] = {ix->gs[0] + ix->gm[0], ix->gs[1] + ix->gm[1], ix->gs[2] + ix->gm[2]};

  u1 = PetscMin(u1, ix->gm[dim - 1]);
  if (u1 <= u0) return u0;
  lo[dim - 1] = ix->gs[dim - 1] + u0;
  hi[dim - 1] = ix->gs[dim - 1] + u1;
  for (k = lo[2]; k < hi[2]; k++)
    for (j = lo[1]; j < hi[1]; j++) {
      const PetscInt   orow = Lidx(ix, 0, j, k), x0 = ix->gs[0], x1 = ix->gs[0] + ix->gm[0]; /* (node (i, j, k) is orow + i) */
      const PetscReal *vo = C->vo, *mcn = C->mcn; /* (locals: the row's loop in SIMD lanes) */
      PetscReal       *vh = C->vh, *P = C->P;
#pragma GCC ivdep
      for (i = x0; i < x1; i++)
#pragma GCC unroll 3
        for (d = 0; d < dim; d++) {
          o                  = orow + i;
          vh[dim * o + d]    = 0.5 * (vo[dim * o + d] + v[dof * o + d]);
          P[dim * o + d]     = mcn[o] * v[dof * o + d];
        }
      PSNodeBCRow(S, dim, orow, x0, x1, j, k, vh); /* walls hold the faces on them */
    }
  return u1;
}

/* the Lagrangian phase of one unit of cells c (the row j = c in 2D, the
   plane k = c in 3D), its nodes' values first (LagrangeNodes, up to the
   unit's upper corners, from lp->nb on); dim a constant where it is called,
   so the per-cell loops unroll */
static inline PetscErrorCode LagrangeUnit(PSSolver *S, const PSIndex *ix, PetscReal dt, const PetscInt dim, PetscInt c, PSLagProgress *lp)
{
  PSCells        *C = S->cells;
  PetscReal      *XQ = PSCellsX(C, 0, PS_CX_Q), *XV = PSCellsX(C, 0, PS_CX_V); /* the per-cell planes of q and the cells' volumes (PSCellsX) */
  const PetscInt  nh = dim == 3 ? 4 : 1, hsd = PSCellsHalfSize(C), hmat = PSCellsHalfMat(C);
  const PetscInt  nw = PSCellsPlaneLen(C, ix); /* (the lanes' plane length: the remap's scratch C->sW, free here) */
  const PetscBool lanes = S->run.lanes != 1 ? PETSC_TRUE : PETSC_FALSE; /* (-run_lanes 1: the scalar loop alone, for checks) */
  const PetscInt  k0 = dim == 3 ? c : C->cs[2], k1 = dim == 3 ? c + 1 : C->ce[2], j0 = dim == 3 ? C->cs[1] : c, j1 = dim == 3 ? C->ce[1] : c + 1;
  PetscReal       hm = 0.0, smax = lp->smax, *W = C->sW;
  PetscInt        i, j, k, m, d;

  PetscFunctionBeginUser;
  for (d = 0; d < dim; d++) hm = PetscMax(hm, S->h[d]);
  /* the cell materials take the new nodal velocity (every local node: the
     remap reads ghost nodes too), and their faces move with v^{n+1/2} =
     (v^n + v^{n+1})/2, on which the half-step force does its work
     (PSCellsPredict): LagrangeNodes, a row (2D) or plane (3D) of nodes
     just before the first cells that read it (lp->nb: the units of nodes
     done) */
  lp->nb = LagrangeNodes(S, ix, dim, lp->nb, PSCellsUnitsThrough(ix, dim, c));
  for (k = k0; k < k1; k++)
    for (j = j0; j < j1; j++) {
      PetscInt       ci0, oc0;
      const PetscInt x0 = PSCellsXIdx(C, 0, j, k);
      PSCellsRow(C, ix, dim, j, k, &ci0, &oc0, NULL, NULL);
      if (lanes) LagrangeGasLanes(S, dim, ci0, oc0, x0 + C->cs[0], C->cs[0], C->ce[0] - C->cs[0], dt, hm, nw, W);
      for (i = C->cs[0]; i < C->ce[0]; i++) {
        const PetscInt   ci = ci0 + i, n = x0 + i, l = i - C->cs[0];
        PetscReal       *u  = &C->u[C->ms * ci];
        const PetscReal *ec = PSCellsEC(C, n); /* this step's EOS values, from the cells' P2G */
        const PetscReal *hmn = PSCellsHM(C, n, hmat), *hs = &C->hs[hsd * n], qh = hs[0]; /* the predictor's half-step values; q^h */
        PetscReal        L[3][3], vmax, dV, trD, Mc = 0.0, Vm = 0.0, cmax = 0.0, rho, q, dVk[PS_MAX_CELLMAT], dVr[PS_MAX_CELLMAT], pr, hgw = 0.0;
        const PetscInt   oc = oc0 + i;
        PetscInt         m0, m1;
        if (lanes && W[PS_LL_FLAG * nw + l] != 0.0) {
          /* a run of the lanes' cells (their state already stored by the
             lanes): the time step's speeds in the cells' order, as below
             (Fastest, where one is not below the largest so far; first
             whether any is, in SIMD lanes: the largest so far only grows, so
             where none passes the first, none passes its later values; the
             test one by one was 0.6% of the quadrants' instructions) */
          const PetscInt   len = PSLanesFlagRun(&W[PS_LL_FLAG * nw + l], 1, C->ce[0] - i);
          const PetscReal *Wv = &W[PS_LL_SPEED * nw + l], *Wc = &W[PS_LL_CMAX * nw + l], *Wm = &W[PS_LL_VMAX * nw + l], *Ws = &W[PS_LL_SQ * nw + l], *Wr = &W[PS_LL_RHO * nw + l];
          PetscInt         x;
          int              up = 0;
          for (x = 0; x < len; x++) up |= !(Wv[x] <= smax);
          if (up)
            for (x = 0; x < len; x++)
              if (!(Wv[x] <= smax)) Fastest(S, i + x, j, k, Wc[x], Wm[x], Ws[x], Wr[x], &smax);
          i += len - 1;
          continue;
        }
        CellGradientDim(&C->K, dim, oc, C->vh, L, &vmax);
        /* the cell's volume change V_c dt tr L (the net volume the faces sweep,
           each moving with the mean velocity of its corners: the remap moves
           exactly this back) and its share among materials, markers, void */
        trD = L[0][0] + L[1][1] + L[2][2];
        dV  = C->Vc * dt * trD;
        XV[ci] = C->Vc + dV;
        PSCellsPresent(C, ci, &m0, &m1);
        CellMix(C, u, ec, m0, m1, &Mc, &Vm, &cmax);
        if (Mc <= 0.0) continue;
        PetscCall(PSCellsShareVolume(S, ci, ec, m0, m1, dV, dVk, dVr, &pr));
        /* artificial viscosity of the cell (compression only) at v^{n+1/2}, for
           the next step's force (this step's energy takes the half step's q^h,
           whose force the nodes felt) */
        rho                        = Mc / Vm;
        q                          = PSViscosity(rho, hm, trD, cmax, S->run.c_linear, S->run.c_quadratic);
        XQ[ci] = q;
        /* hourglass heating: the work of the half step's hourglass force on
           v^{n+1/2}, kappa sum_m g_m^h . g_m dt */
        {
          const PetscReal *gh  = hs + 1, kap = HourglassKappa(&C->K, Mc, cmax);
          PetscReal        hg[4][3];
          PetscInt         e;
          HourglassRatesDim(&C->K, dim, oc, C->vh, hg);
          for (e = 0; e < nh; e++)
            for (d = 0; d < dim; d++) hgw += kap * gh[dim * e + d] * hg[e][d] * dt;
        }
        /* each material: energy, pressure, deviator */
        for (m = m0; m < m1; m++) {
          const PSMaterial *M   = &S->mat[C->mat[m]];
          PetscReal        *blk = &u[m * C->mst];
          const PetscReal  *pk  = &hmn[m * hmat], *sk = pk + 1;
          PetscReal         wdev = 0.0, wh = 0.0, V1, E1;
          if (blk[PS_CM] <= 0.0) continue;
          V1 = blk[PS_CV] + dVk[m];
          PetscCheck(V1 > 0.0, PETSC_COMM_SELF, PETSC_ERR_NOT_CONVERGED, "cell (%" PetscInt_FMT ", %" PetscInt_FMT ", %" PetscInt_FMT ") material %" PetscInt_FMT " would reach volume %g <= 0 at step %" PetscInt_FMT ", t = %g s: lower run.cfl or refine the grid",
                     i, j, k, C->mat[m], (double)V1, S->step + 1, (double)S->t);
          if (C->nq && M->G > 0.0) {
            /* the deviator over the whole step; its work is the half step's,
               V_k s_k^h : D dt (the force's deviatoric part was V_k s_k^h) */
            PetscCall(Deviator(M, dim, L, dt, blk[PS_CM] / V1, &blk[PS_CQ], blk[PS_CM], &wdev));
            PetscReal Sh[3][3];
            PetscInt  a, e;
            ForceStress(dim, sk, 0.0, Sh);
            for (a = 0; a < 3; a++)
              for (e = 0; e < 3; e++) wh += Sh[a][e] * L[a][e];
            wh *= blk[PS_CV] * dt;
          }
          /* E1 = E0 + hourglass heat by mass share + deviatoric work - (p_k^h +
             q^h) (dV_k - dVr_k) - (p* + q^h) dVr_k (E = M_k e): the work the
             half-step force did on v^{n+1/2}, and the relaxation's exchange
             at the one pressure p* (closure.c) */
          E1 = blk[PS_CE] + (m1 == m0 + 1 ? hgw : hgw * blk[PS_CM] / Mc) + wh - (pk[0] + qh) * (dVk[m] - dVr[m]) - (pr + qh) * dVr[m];
          /* an ideal gas holds no negative energy: a trace the closure expands
             several-fold in one step would reach e < 0 (p < 0, no sound
             speed); it is set to 0 and what that adds booked (a negative loss) */
          if (M->gamma > 0.0 && E1 < 0.0) {
            S->lost_local.internal += E1;
            E1 = 0.0;
          }
          blk[PS_CV] = V1;
          blk[PS_CE] = E1;
        }
        /* the viscous term q/(rho c) (as the markers'), with c kept at least
           sqrt(q/rho)/2 so a cold gas (c -> 0) does not stop the run: for
           q = rho c_q du^2 the term is then at most 2 sqrt(c_q) du, the
           order of the quadratic viscosity's own explicit limit h/(2 c_q du) */
        Fastest(S, i, j, k, cmax, vmax, q > 0.0 ? q / (rho * PetscMax(cmax, 0.5 * PetscSqrtReal(q / rho))) : 0.0, rho, &smax);
      }
    }
  lp->smax = smax;
  lp->next = c + 1;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* the Lagrangian phase's units that can run behind the predictor's (a scene
   of cells alone: PSCellsPredictDim) up to unit c: those whose nodes are
   all this rank's own, so that the predictor has corrected them (the units
   next to a rank above wait for the halo: PSCellsLagrangeDim) */
static inline PetscErrorCode LagrangeBehind(PSSolver *S, const PSIndex *ix, PetscReal dt, const PetscInt dim, PetscInt c)
{
  PSCells       *C = S->cells;
  const PetscInt e = dim - 1;

  PetscFunctionBeginUser;
  c = PetscMin(c, PetscMin(C->ce[e] - 1, ix->os[e] + ix->om[e] - 2 - PS_PAD)); /* (the unit's upper corners, grid index c + 1 + PS_PAD, owned) */
  while (C->lag.next <= c) PetscCall(LagrangeUnit(S, ix, dt, dim, C->lag.next, &C->lag));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* the Lagrangian phase: the units of cells the predictor has not run
   behind it (all of them unless C->lag.fused), then the nodes it has not
   reached (the ghosts below this rank's own, above the cells' last unit);
   dim a constant where it is called */
static inline PetscErrorCode PSCellsLagrangeDim(PSSolver *S, const PSIndex *ix, PetscReal dt, const PetscInt dim)
{
  PSCells       *C = S->cells;
  const PetscInt e = dim - 1;
  PetscInt       c;

  PetscFunctionBeginUser;
  if (!EV_Lag) PetscCall(PetscLogEventRegister("PSCellsLagrange", 0, &EV_Lag));
  PetscCall(PetscLogEventBegin(EV_Lag, 0, 0, 0, 0));
  if (!C->lag.fused) {
    C->lag.next = C->cs[e];
    C->lag.nb   = 0;
    C->lag.nb0  = 0;
    C->lag.smax = 0.0;
  }
  for (c = C->lag.next; c < C->ce[e]; c++) PetscCall(LagrangeUnit(S, ix, dt, dim, c, &C->lag));
  (void)LagrangeNodes(S, ix, dim, 0, C->lag.nb0);                /* (the ghosts below, after the halo) */
  (void)LagrangeNodes(S, ix, dim, C->lag.nb, ix->gm[dim - 1]);   /* (the nodes above the cells') */
  C->smax      = C->lag.smax;
  C->lag.fused = PETSC_FALSE;
  PSCellsWindowEnd(C); /* (the last units it read: the pipeline's window, if it ran) */
  PetscCall(PetscLogEventEnd(EV_Lag, 0, 0, 0, 0));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode PSCellsLagrange(PSSolver *S, const PSIndex *ix, PetscReal dt)
{
  PetscFunctionBeginUser;
  if (S->dim == 2) PetscCall(PSCellsLagrangeDim(S, ix, dt, 2));
  else PetscCall(PSCellsLagrangeDim(S, ix, dt, 3));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* c + |v| over the cells (the first dt, restarts) */
PetscErrorCode PSCellsMaxSpeed(PSSolver *S)
{
  PSCells  *C = S->cells;
  PSIndex   ix;
  PetscInt  i, j, k, a, d;
  PetscReal smax = 0.0;

  PetscFunctionBeginUser;
  PetscCall(PSGridIndex(S->da, &ix));
  PetscCall(PSCellsEOSCache(S));
  for (k = C->cs[2]; k < C->ce[2]; k++)
    for (j = C->cs[1]; j < C->ce[1]; j++)
      for (i = C->cs[0]; i < C->ce[0]; i++) {
        const PetscInt ci = PSCellIdx(C, i, j, k);
        PetscReal      Mc, Vm, cmax, vmax = 0.0;
        PetscInt       m0, m1;
        PSCellsPresent(C, ci, &m0, &m1); /* (the EOS cache holds these alone) */
        CellMix(C, &C->u[C->ms * ci], PSCellsEC(C, PSCellsXIdx(C, i, j, k)), m0, m1, &Mc, &Vm, &cmax);
        if (Mc <= 0.0) continue;
        for (a = 0; a < C->K.nco; a++) {
          const PetscInt o  = CellNode(&ix, S->dim, i, j, k) + C->K.off[a];
          PetscReal      v2 = 0.0;
          for (d = 0; d < S->dim; d++) v2 += C->mcn[o] > 0.0 ? PetscSqr(C->P[S->dim * o + d] / C->mcn[o]) : 0.0;
          vmax = PetscMax(vmax, PetscSqrtReal(v2));
        }
        Fastest(S, i, j, k, cmax, vmax, 0.0, Mc / Vm, &smax);
      }
  C->smax = smax;
  PetscFunctionReturn(PETSC_SUCCESS);
}
