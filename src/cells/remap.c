/*
  remap.c - the cells' remap phase (event PSCellsRemap; docs/cells.md).

  After the Lagrangian phase every cell holds its materials in a volume
  V_c + dt V_c tr L (PS_CX_V): its faces moved by delta_f = dt <v_d>_f (the
  mean velocity of the face's corners).  The remap moves the swept volumes
  back across the fixed faces, direction by direction (CTH, McGlaun, Thompson
  & Elrick 1990; the order alternates every step), so after the last sweep
  every cell has volume V_c again.  For a face moving by delta > 0 the donor
  is the cell behind it and the flux volume delta A is the slab of the donor
  next to the face holding that share of the donor's volume:
    materials   each material's part of the slab from the interface
                reconstruction (plic.c: Youngs' normals, offsets for the volume
                fractions, nested for several materials); the markers' part
                and void are left behind (the markers move themselves; void is
                the room no one holds);
    mass        rho_k of the donor with a van Leer-limited slope where donor
                and both neighbours along the sweep are pure in k (second
                order in smooth single-material flow; van Leer 1977);
    energy, advected strength state: per unit mass, limited the same way;
    momentum    on the staggered nodes: each cell's mid-plane carries the dual
                mass flux (F_lo + F_hi)/2 from its lower to its upper corner
                nodes (shared among the 2^(dim-1) node columns), which keeps
                the nodal mass m^C_i = sum_c M_c / 2^dim consistent with the
                cells' (Benson 1992's "half-index shift"; Margolin & Shashkov
                2004); the velocity carried is the upwind node's with a van
                Leer slope.
  Kinetic energy: remapping momentum conservatively loses kinetic energy (the
  KE discrepancy, Benson 1992); per node the kinetic energy carried by the
  same fluxes minus that of the remapped momentum goes into the internal
  energy of the cells around it, each by its share of the node's mass
  (DeBar's fix): total energy is conserved, and the amount is booked as
  remap_heat.
  Boundaries: a symmetry or fixed face has delta = 0; a free face lets
  material out (mass, momentum, kinetic and internal energy booked as lost)
  and lets void in.
*/
#include "cells.h"
#include "plic.h"

static PetscLogEvent EV_Remap = 0, EV_Prep, EV_Flux, EV_Halo, EV_KE, EV_KEBehind;

#define PS_DISCARD 1e-6 /* volume fraction below which a cell material is discarded (booked) */

static inline PetscReal VanLeer(PetscReal a, PetscReal b)
{
  return a * b > 0.0 ? 2.0 * a * b / (a + b) : 0.0;
}

/* VanLeer without a branch (the lanes: every value computed, a divisor 1
   where its value is not used), the same value */
static inline PetscReal VanLeerLanes(PetscReal a, PetscReal b)
{
  const PetscReal ab = a * b, sum = a + b, den = ab > 0.0 ? sum : 1.0, v = 2.0 * a * b / den;
  return ab > 0.0 ? v : 0.0;
}

/* The participants of the interface reconstruction, in dissection order:
   the markers (solid bodies first), the cell materials, void last.  Their
   cumulative volume fractions A_k = sum_{j <= k} alpha_j (of each cell's
   current volume) in a box one cell wider than the ghosted cells on every
   side (copies of the nearest cell outside the domain), so Youngs' normal of
   A_k is material k's in layered cells (plic.h) and every donor has its
   3x3(x3) block.  A plane per participant (A_k of cell c at A[k ps + c]):
   a run of cells writes each plane in SIMD lanes (FractionsRun), and
   Youngs' stencil reads one plane.  Void's, the last, is 1 everywhere and
   not stored (np - 1 planes); nor is the markers', the first, in a scene
   without them (0 everywhere; its plane is left unwritten).  Built a unit
   (row in 2D, plane in 3D) at a time during the sweep (FractionsUpTo), into
   a ring of units (RingSlot), as are the per-cell values the faces read
   (C->sS, sP, sM). */
typedef struct {
  PetscInt   np;            /* participants: markers, nmat materials, void */
  PetscInt   n[3], s[3];    /* box sizes and strides (doubles) within a plane of the ring; s[dim - 1], the unit's */
  PetscInt   ps;            /* the planes' stride: the cells in the ring's PS_RING + 3 units */
  PetscBool  mk;            /* the markers' plane A_0 is stored (a scene with markers; without, A_0 is 0: their share PS_CX_AM is 0 in every cell) */
  PetscInt   o[3];          /* global cell index of the box's first cell */
  PetscReal *A;             /* np planes of cumulative fractions */
  PetscInt   built;         /* the box's units (rows along y in 2D, planes along z in 3D) [0, built) are built (FractionsUpTo) */
} PSFractions;

/* The rings.  The fractions' planes and the per-cell values of the faces'
   fast paths (C->sS, sP, sM) are kept for PS_RING units (rows in 2D, planes
   in 3D), not for the whole box: a sweep reads the units of its faces'
   donors and their neighbours, four at most (the faces of slice s read the
   cells of slices s - 2 .. s + 1, and Youngs' stencils one unit either side
   of a donor), and the builder runs one unit ahead (two at the box's end),
   so the values stay in the caches where a box's were written to memory
   and read back (the 512^2 quadrants: 16 MiB a sweep).  Unit u is written
   to slot u mod R, and slots 0, 1 and 2 again after the ring's end (slots
   R .. R + 2), so the units u - 2 .. u + 1 around any unit are in
   consecutive slots, unit u's at RingSlot(u): the stencils' strides are the
   box's.  (The fractions' box numbers its units from the one beyond the
   ghosted cells, the per-cell values from the ghosted array's first) */
#define PS_RING 8
static inline PetscInt RingSlot(PetscInt u)
{
  const PetscInt r = u % PS_RING;
  return r < 2 ? r + PS_RING : r;
}

/* the shift from the ghosted index of a cell of the ghosted array's unit
   (row in 2D, plane in 3D) lu to its index in the per-cell values' ring */
static inline PetscInt RingShift(const PSCells *C, PetscInt lu)
{
  return (RingSlot(lu) - lu) * C->cst[C->dim - 1];
}

/* a ring's slot (of len reals), just written, again after the ring's end
   where it is one of the three that RingSlot's readers find there */
static inline void RingRepeat(PetscReal *ring, PetscInt slot, PetscInt len)
{
  PetscInt i;
  if (slot < 3)
    for (i = 0; i < len; i++) ring[(PS_RING + slot) * len + i] = ring[slot * len + i];
}

/* FractionsUnits's values for a run of len cells c0 + x of one gas s (a
   block of V, M, E), each alone with mass in its cell, inside the box's row
   (a0: the first one's fraction A_0; planes ps apart): the divisions and
   tests in SIMD lanes, the values each material's plane takes into W's
   first two planes (of length w), then the planes in lanes too; the
   per-cell values at c + ws in their ring */
static inline void FractionsRun(PSCells *C, PetscInt s, PetscInt c0, PetscInt len, PetscReal *a0, PetscInt ps, PetscBool mk, PetscInt w, PetscReal *W, PetscInt ws)
{
  const PetscInt   nm = C->nmat;
  const PetscReal  Vc = C->Vc, *blk = &C->u[PS_CQ * c0 + s * C->mst], *XV = C->ux + PS_CX_V * C->ncl, *XA = C->ux + PS_CX_AM * C->ncl;
  const PetscReal  sd = s;
  PetscReal       *sS = C->sS + 2 * ws, *sP = C->sP + ws, *sM = C->sM + ws;
  PetscInt         x, m;

#pragma GCC ivdep
  for (x = 0; x < len; x++) {
    const PetscInt  c = c0 + x;
    const PetscReal Vs = blk[PS_CQ * x + PS_CV], Ms = blk[PS_CQ * x + PS_CM], Es = blk[PS_CQ * x + PS_CE], V = XV[c];
    const PetscReal iV = 1.0 / V, acc = PetscMin(XA[c] * Vc * iV, 1.0), a2 = PetscMin(acc + Vs * iV, 1.0);
    sS[2 * c]     = Ms / Vs;
    sS[2 * c + 1] = Es / Ms;
    sM[c]         = Ms;
    sP[c]         = acc <= 1e-12 && 1.0 - a2 <= 1e-12 && Vs > 0.999 * V ? sd : -1.0;
    W[x]          = PetscMin(acc, 1.0);
    W[w + x]      = a2;
  }
  /* the markers' plane (A_0, with markers); the materials' planes: below s
     none (a1), from s on s's volume (a2) */
  if (mk)
    for (x = 0; x < len; x++) a0[x] = W[x];
  for (m = 0; m < nm; m++) {
    const PetscReal *Wm = &W[m < s ? 0 : w];
    PetscReal       *am = &a0[(1 + m) * ps];
    for (x = 0; x < len; x++) am[x] = Wm[x];
  }
}

/* the box's sizes and strides, the ring's planes and the per-cell planes
   (sS, sP, sM) allocated on first use; no unit built yet (FractionsUpTo
   builds them) */
static PetscErrorCode FractionsSetup(PSCells *C, PSFractions *fr)
{
  const PetscInt dim = C->dim, nm = C->nmat, ms = C->ms;
  PetscInt       e;

  PetscFunctionBeginUser;
  fr->np = nm + 2;
  for (e = 0; e < 3; e++) {
    fr->n[e] = e < dim ? C->gm[e] + 2 : 1;
    fr->o[e] = e < dim ? C->gs[e] - 1 : 0;
  }
  fr->s[0]  = 1;
  fr->s[1]  = fr->n[0];
  fr->s[2]  = fr->n[0] * fr->n[1];
  fr->ps    = (PS_RING + 3) * fr->s[dim - 1];
  fr->mk    = C->markers;
  fr->built = 0;
  if (!fr->A) PetscCall(PetscMalloc1(fr->ps * (fr->np - 1), &fr->A)); /* (void's A, 1 everywhere, is not stored: SlabVolumes) */
  if (!C->sS) { /* (zeroed: the faces' lanes load the values of cells they do not use) */
    const PetscInt nr = (PS_RING + 3) * C->cst[dim - 1];
    PetscCall(PetscCalloc3(nr * (ms - 1), &C->sS, nr, &C->sP, nr, &C->sM));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* The box's units [u0, u1) (rows along y in 2D, planes along z in 3D): the
   cumulative fractions, and the per-cell values of the ghosted cells they
   copy, each into its ring (RingSlot).  A unit reads the cells of its own unit alone (the nearest ghosted
   one), so it is built before the sweep updates them (FractionsUpTo) */
static void FractionsUnits(PSCells *C, PSFractions *fr, PetscInt d, PetscBool lanes, PetscInt w, PetscReal *W, PetscInt u0, PetscInt u1)
{
  const PetscInt     dim = C->dim, nm = C->nmat, ms = C->ms, e = dim - 1;
  const PetscInt     gs[3] = {C->gs[0], C->gs[1], C->gs[2]}, gl[3] = {C->gs[0] + C->gm[0] - 1, C->gs[1] + C->gm[1] - 1, C->gs[2] + C->gm[2] - 1};
  const PetscInt     o[3] = {fr->o[0], fr->o[1], fr->o[2]}, n[3] = {fr->n[0], fr->n[1], fr->n[2]}, s[3] = {fr->s[0], fr->s[1], fr->s[2]}, mst = C->mst, ps = fr->ps;
  const PetscBool    mk = fr->mk;
  const PetscInt     cst1 = C->cst[1], cst2 = C->cst[2], coff = C->coff;
  const PetscReal    Vc = C->Vc, *U = C->u, *XV = C->ux + PS_CX_V * C->ncl, *XA = C->ux + PS_CX_AM * C->ncl;
  const short       *Sole = C->sole;
  PetscReal         *A = fr->A, *sS = C->sS, *sP = C->sP, *sM = C->sM;
  PetscInt           i, j, m, q, u;

  for (u = u0; u < u1; u++) {
    const PetscInt k = dim == 3 ? u : 0, j0 = dim == 3 ? 0 : u, j1 = dim == 3 ? n[1] : u + 1; /* (the unit's plane k, its rows [j0, j1)) */
    /* (the builder writes a unit's plain slot, u mod PS_RING, where the
       readers' RingSlot and RingShift map units 0 and 1 mod PS_RING to the
       slots after the ring's end: RingRepeat below copies them there) */
    const PetscInt slot = u % PS_RING;                                                           /* (the unit's slot in the fractions' ring) */
    const PetscInt gu = PetscMin(PetscMax(u + o[e], gs[e]), gl[e]) - gs[e];                      /* (the ghosted unit it copies) */
    const PetscInt ws = (gu % PS_RING - gu) * C->cst[e];                                         /* (its cells' shift into the per-cell values' ring) */
    for (j = j0; j < j1; j++) {
      /* the nearest cell of the ghosted box: its row's, then along x */
      const PetscInt cr = PetscMin(PetscMax(j + o[1], gs[1]), gl[1]) * cst1 + (dim == 3 ? PetscMin(PetscMax(k + o[2], gs[2]), gl[2]) : 0) * cst2 - coff;
      PetscReal     *ar = &A[slot * s[e] + (dim == 3 ? j * s[1] : 0)]; /* (the row's first cell in the ring) */
      for (i = 0; i < n[0]; i++) {
        const PetscInt   ci = cr + PetscMin(PetscMax(i + o[0], gs[0]), gl[0]), sole = Sole[ci]; /* PSCellIdx */
        const PetscReal *uc = &U[ms * ci], V = XV[ci];
        PetscReal       *a = &ar[i * s[0]], acc;
        PetscInt         m0, m1, b;
        /* a run of a gas's cells inside the ghosted row (not its copies
           outside): FractionsRun, the same values in SIMD lanes */
        if (lanes && sole >= 0 && i >= 1) {
          b = i + PSCellsSoleRun(&Sole[ci], n[0] - 1 - i);
          if (b - i >= PS_LANES_RUN) {
            FractionsRun(C, sole, ci, b - i, a, ps, mk, w, W, ws);
            i = b - 1;
            continue;
          }
        }
        /* a cell with one material with mass: its density and the advected
           quantities per unit mass, which the faces around it read three
           times a sweep (donor, and neighbour of each side's donor) */
        if (sole >= 0) {
          const PetscReal *blk = &uc[sole * mst];
          PetscReal       *sp  = &sS[(ms - 1) * (ci + ws)];
          sp[0]       = blk[PS_CM] / blk[PS_CV];
          sM[ci + ws] = blk[PS_CM];
          if (ms == PS_CQ) sp[1] = blk[PS_CE] / blk[PS_CM]; /* a gas's block: e alone, without the loop */
          else
            for (q = PS_CE; q < ms; q++) sp[q - PS_CE + 1] = blk[q] / blk[PS_CM];
        }
        /* (one division per cell, not one per participant) */
        const PetscReal iV = 1.0 / V;
        acc = PetscMin(XA[ci] * Vc * iV, 1.0);
        if (mk) a[0] = acc;
        /* the materials present add their volume; the others hold none (a
           material without mass is zeroed where it loses it: adding their
           0 changed no sum), and their planes are not read.  With them the
           material that fills the cell alone, for the faces' fast path
           (FaceRun): none in a cell of several or none, or with markers or
           void above round-off (A_0, 1 - A_nm).  (A copy outside the
           ghosted cells writes its nearest cell's value again: the same) */
        if (sole >= 0) { /* (the loop below for one material, without its test per material) */
          const PetscReal a1 = PetscMin(acc, 1.0), a2 = PetscMin(acc + uc[sole * mst + PS_CV] * iV, 1.0);
          for (m = 0; m < sole; m++) a[(1 + m) * ps] = a1;
          for (; m < nm; m++) a[(1 + m) * ps] = a2; /* (a[nm] = a2) */
          sP[ci + ws] = acc <= 1e-12 && 1.0 - a2 <= 1e-12 && uc[sole * mst + PS_CV] > 0.999 * V ? sole : -1;
        } else {
          sP[ci + ws] = -1.0;
          PSCellsSoleRange(sole, nm, &m0, &m1);
          for (m = 0; m < nm; m++) {
            if (m >= m0 && m < m1) acc += uc[m * mst + PS_CV] * iV;
            a[(1 + m) * ps] = PetscMin(acc, 1.0);
          }
        }
      }
    }
    /* none on the ghosted array's two faces along d (their neighbours along
       d are not in it): those of the ghosted unit this unit copies, each
       time it is written (the last of its two writers, the unit beyond the
       ghosted ones, is built with it: FractionsUpTo) */
    {
      PetscInt l[3], lo[3] = {0, 0, 0}, hi[3] = {C->gm[0], C->gm[1], dim == 3 ? C->gm[2] : 1}, f;
      lo[e] = gu;
      hi[e] = gu + 1;
      for (f = 0; f < 2; f++) {
        PetscInt lf[3] = {lo[0], lo[1], lo[2]}, hf[3] = {hi[0], hi[1], hi[2]};
        lf[d] = PetscMax(lf[d], f ? C->gm[d] - 1 : 0);
        hf[d] = PetscMin(hf[d], f ? C->gm[d] : 1);
        for (l[2] = lf[2]; l[2] < hf[2]; l[2]++)
          for (l[1] = lf[1]; l[1] < hf[1]; l[1]++)
            for (l[0] = lf[0]; l[0] < hf[0]; l[0]++) sP[l[0] + l[1] * C->cst[1] + l[2] * C->cst[2] + ws] = -1.0;
      }
    }
    /* the rings' first slots again after their ends (RingRepeat): the
       fractions' stored planes (the markers' with them), the per-cell values */
    for (m = mk ? 0 : 1; m < fr->np - 1; m++) RingRepeat(&A[m * ps], slot, s[e]);
    RingRepeat(sP, gu % PS_RING, C->cst[e]);
    RingRepeat(sM, gu % PS_RING, C->cst[e]);
    RingRepeat(sS, gu % PS_RING, (ms - 1) * C->cst[e]);
  }
}

/* the box's units up to the one of global index g along y (2D) or z (3D),
   before the sweep reads them or updates their cells: the faces of a slice
   or line read the donors' neighbours and Youngs' stencils one unit beyond
   it at most, and its cells are updated after.  The last ghosted unit and
   its copy beyond are built together (both write its per-cell values) */
static inline void FractionsUpTo(PSCells *C, PSFractions *fr, PetscInt d, PetscBool lanes, PetscInt w, PetscReal *W, PetscInt g)
{
  const PetscInt e = C->dim - 1, n = fr->n[e];
  PetscInt       b = g - fr->o[e] + 1;
  if (b >= n - 2) b = n;
  if (b > fr->built) {
    FractionsUnits(C, fr, d, lanes, w, W, fr->built, b);
    fr->built = b;
  }
}

/* Volumes of each cell material (vol[0..nmat-1]) in the slab of width w (m)
   next to the donor's face (side -1 lower, +1 upper) along d.  The donor (a,
   its cumulative fractions) is a box of the cell's transverse size and its
   current volume; its participants are reconstructed by nested dissection
   (plic.c) with Youngs' normals of the cumulative fractions; the markers'
   and void's part of the slab stays.  A pure donor gives the whole slab to
   its one material.  V: the donor's volume (m^3).  Returns the cell
   material the slab holds alone, or PS_SLAB_MIXED (several participants),
   or PS_SLAB_NONE (no cell material). */
#define PS_SLAB_MIXED (-1)
#define PS_SLAB_NONE  (-2)
static PetscInt SlabVolumes(const PSSolver *S, const PSFractions *fr, const PetscReal *a, PetscReal V, PetscInt d, PetscInt side, PetscReal w, PetscReal vol[])
{
  const PSCells  *C = S->cells;
  const PetscInt  dim = S->dim, nm = C->nmat;
  const PetscReal A = C->Vc / S->h[d];
  PetscReal        alpha[PS_PLIC_MAXMAT], nrm[PS_PLIC_MAXMAT][3], pv[PS_PLIC_MAXMAT], h[3], prev = 0.0;
  PetscInt         part[PS_PLIC_MAXMAT], np = 0, k, m;
  PSPlicCell       cell;

  for (m = 0; m < nm; m++) vol[m] = 0.0;
  /* the participants present in the donor (fraction above round-off) */
  for (k = 0; k < fr->np; k++) {
    const PetscReal A_k = k + 1 < fr->np ? (k > 0 || fr->mk ? a[k * fr->ps] : 0.0) : 1.0, ak = A_k - prev; /* (void, the last, fills the rest: its A_k is 1, not stored; nor the markers' A_0 without them, 0) */
    prev = A_k;
    if (ak <= 1e-12) continue;
    PetscCheckAbort(np < PS_PLIC_MAXMAT, PETSC_COMM_SELF, PETSC_ERR_SUP, "more than %d participants in a cell", PS_PLIC_MAXMAT);
    part[np]  = k;
    alpha[np] = ak;
    np++;
  }
  if (np == 0) return PS_SLAB_NONE;
  if (np == 1) {
    if (part[0] >= 1 && part[0] <= nm) {
      vol[part[0] - 1] = w * A;
      return part[0] - 1;
    }
    return PS_SLAB_NONE;
  }
  for (k = 0; k < 3; k++) h[k] = k < dim ? S->h[k] : 1.0;
  h[d] = V / A; /* the donor's current extent along the sweep */
  for (k = 0; k + 1 < np; k++) PSPlicYoungsNormal(dim, a + part[k] * fr->ps, fr->s[0], fr->s[1], fr->s[2], S->h, nrm[k]);
  if (PSPlicReconstruct(dim, h, np, alpha, (const double(*)[3])nrm, &cell) || PSPlicSlabVolumes(&cell, d, side, w, pv)) {
    /* a clipper overflow (never seen): the volume fractions' shares */
    for (k = 0; k < np; k++) pv[k] = alpha[k] * w * A;
  }
  for (k = 0; k < np; k++)
    if (part[k] >= 1 && part[k] <= nm) vol[part[k] - 1] = pv[k];
  return PS_SLAB_MIXED;
}

/* the sweeps' face scratch, kept between steps: face fluxes (fs planes of
   nface reals: the faces and their planes' padding, PSCellsPadPlane) and
   the range of materials each face's fluxes hold (the nodal kinetic energy
   and velocity, sK and sVL, are allocated with the cells) */
static PetscErrorCode ScratchSize(PSCells *C, PetscInt nface, PetscInt fs)
{
  PetscFunctionBeginUser;
  if (nface * fs > C->nsF) {
    PetscCall(PetscFree2(C->sF, C->sR));
    PetscCall(PetscMalloc2(nface * fs, &C->sF, 2 * nface, &C->sR));
    C->nsF = nface * fs;
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* local index of physical node n */
static inline PetscInt Node(const PSIndex *ix, PetscInt dim, const PetscInt n[3])
{
  return Lidx(ix, n[0] + PS_PAD, n[1] + PS_PAD, dim == 3 ? n[2] + PS_PAD : 0);
}

/* physical node index n along e is in this rank's owned range */
static inline PetscBool OwnedIndex(const PSIndex *ix, PetscInt e, PetscInt n)
{
  return n + PS_PAD >= ix->os[e] && n + PS_PAD < ix->os[e] + ix->om[e] ? PETSC_TRUE : PETSC_FALSE;
}

/* a sweep's directions and strides: along d, the transverse t1 and t2 (t2
   only in 3D); node strides in the local node array, cell strides in the
   ghosted cell array */
typedef struct {
  PetscInt d, t1, t2;
  PetscInt sd, s1, s2; /* nodes */
  PetscInt cd;         /* cells, along d */
} PSSweepDirs;

static void SweepDirs(const PSCells *C, const PSIndex *ix, PetscInt dim, PetscInt d, PSSweepDirs *w)
{
  const PetscInt ns[3] = {1, ix->gm[0], ix->gm[0] * ix->gm[1]}, cs[3] = {1, C->gm[0], C->gm[0] * C->gm[1]};
  w->d  = d;
  w->t1 = dim == 3 ? (d + 1) % 3 : 1 - d;
  w->t2 = dim == 3 ? (d + 2) % 3 : 2;
  w->sd = ns[d];
  w->s1 = ns[w->t1];
  w->s2 = dim == 3 ? ns[w->t2] : 0;
  w->cd = cs[d];
}

/* the fluxes through one face (signed, + along d); F = per material (dV, dM,
   dE, dQ...) then the face's volume delta A and the total mass flux, value
   q at F[q ft] (the records are planes over a run's faces, ft apart).  Only
   the materials [R[0], R[1]) are written (a pure donor's one, or all): the
   others carry nothing, and the cell update reads no more (no zeroing of
   every material's fluxes for every face) */
static inline void FaceFlux(const PSSolver *S, const PSIndex *ix, const PSFractions *fr, PetscReal dt, const PSSweepDirs *sw, const PetscInt dim, const PetscInt i[3], PetscReal *F, PetscInt ft, PetscInt *R)
{
  const PSCells  *C = S->cells;
  const PetscInt  mst = C->mst, ms = C->ms, nm = C->nmat, d = sw->d;
  const PetscReal A = C->Vc / S->h[d], *v = C->vh;
  const PetscReal *ud;
  PetscReal        Vd;
  const PetscReal *fa;
  PetscReal        delta = 0.0, vol[PS_MAX_CELLMAT], w, side;
  PetscInt         a, b, c[3], m, m0, m1, q, o0, uc, s, rs;

  /* the face's displacement: the mean of its corners' velocities along d */
  o0 = Node(ix, dim, i);
  for (a = 0; a < (dim == 3 ? 2 : 1); a++)
    for (b = 0; b < 2; b++) delta += v[dim * (o0 + b * sw->s1 + a * sw->s2) + d];
  delta *= dt / (dim == 3 ? 4.0 : 2.0);
  F[nm * ms * ft]       = delta * A;
  F[(nm * ms + 1) * ft] = 0.0;
  R[0] = nm; /* empty: [nm, 0), so the union of ranges is a min and a max */
  R[1] = 0;
  if (delta == 0.0) return;
  /* the donor: the cell behind the face; none outside the domain (void enters) */
  c[0] = i[0];
  c[1] = i[1];
  c[2] = i[2];
  if (delta > 0.0) c[d] -= 1;
  side = delta > 0.0 ? 1.0 : -1.0;
  if (c[d] < 0 || c[d] >= C->nc[d]) return;
  uc = PSCellIdx(C, c[0], c[1], c[2]);
  ud = &C->u[ms * uc];
  Vd = *PSCellsX(C, uc, PS_CX_V);
  fa = &fr->A[(c[0] - fr->o[0]) * fr->s[0] + (dim == 3 ? (c[1] - fr->o[1]) * fr->s[1] + RingSlot(c[2] - fr->o[2]) * fr->s[2] : RingSlot(c[1] - fr->o[1]) * fr->s[1])]; /* (the ring's slot of its unit) */
  rs = RingShift(C, i[dim - 1] - C->gs[dim - 1]); /* (the per-cell values of the donor and its neighbours, around the face's unit) */
  w  = PetscMin(PetscAbsReal(delta) * A / Vd, 1.0); /* the slab's share of the donor */
  /* the materials in the slab.  A donor whose one material with mass fills
     it (no markers, no void above round-off: the others hold no volume) gives
     it the whole slab, as SlabVolumes does (the same value, without its
     search of the participants); else a pure donor's one, or all (vol 0 skips) */
  s = C->sole[uc];
  if (s >= 0 && (fr->mk ? fa[0] : 0.0) <= 1e-12 && 1.0 - fa[nm * fr->ps] <= 1e-12) {
    vol[s] = w * Vd / A * A;
    m0     = s;
  } else m0 = SlabVolumes(S, fr, fa, Vd, d, (PetscInt)side, w * Vd / A, vol);
  m1 = m0 >= 0 ? m0 + 1 : (m0 == PS_SLAB_MIXED ? nm : 0);
  m0 = PetscMax(m0, 0);
  if (m0 < m1) {
    R[0] = m0;
    R[1] = m1;
  }
  for (m = m0; m < m1; m++) {
    const PetscReal *blk = &ud[m * mst], *nb[2] = {NULL, NULL}, *spd, *spn[2] = {NULL, NULL};
    PetscReal        dM, off = side * 0.5 * (1.0 - w), rho;
    PetscBool        pure;
    if (vol[m] <= 0.0 || blk[PS_CM] <= 0.0) {
      for (q = 0; q < ms; q++) F[(m * ms + q) * ft] = 0.0;
      continue;
    }
    /* the density and per-unit-mass values of the donor and its
       neighbours: FractionsUnits's where the cell has m alone (the same
       divisions), else here */
    spd = s == m ? &C->sS[(ms - 1) * (uc + rs)] : NULL;
    rho = spd ? spd[0] : blk[PS_CM] / blk[PS_CV];
    /* van Leer slopes where the donor and its neighbours along d are pure in m */
    pure = blk[PS_CV] > 0.999 * Vd ? PETSC_TRUE : PETSC_FALSE;
    for (a = 0; a < 2 && pure; a++) {
      const PetscInt c2 = c[d] + (a ? 1 : -1);
      if (c2 < C->gs[d] || c2 >= C->gs[d] + C->gm[d]) {
        pure = PETSC_FALSE;
        break;
      }
      const PetscInt un = uc + (a ? sw->cd : -sw->cd);
      nb[a]  = &C->u[ms * un + mst * m];
      spn[a] = C->sole[un] == m ? &C->sS[(ms - 1) * (un + rs)] : NULL;
      if (nb[a][PS_CM] <= 0.0 || nb[a][PS_CV] <= 0.999 * *PSCellsX(C, un, PS_CX_V)) pure = PETSC_FALSE;
    }
    if (pure) {
      const PetscReal r0 = spn[0] ? spn[0][0] : nb[0][PS_CM] / nb[0][PS_CV], r1 = spn[1] ? spn[1][0] : nb[1][PS_CM] / nb[1][PS_CV];
      dM = PetscMin(PetscMax(vol[m] * (rho + off * VanLeer(rho - r0, r1 - rho)), 0.0), blk[PS_CM]);
    } else dM = PetscMin(vol[m] * rho, blk[PS_CM]);
    F[(m * ms + PS_CV) * ft] = side * vol[m];
    F[(m * ms + PS_CM) * ft] = side * dM;
    for (q = PS_CE; q < ms; q++) {
      PetscReal s0 = spd ? spd[q - PS_CE + 1] : blk[q] / blk[PS_CM];
      if (pure) {
        const PetscReal s1 = spn[0] ? spn[0][q - PS_CE + 1] : nb[0][q] / nb[0][PS_CM], s2 = spn[1] ? spn[1][q - PS_CE + 1] : nb[1][q] / nb[1][PS_CM];
        s0 += off * VanLeer(s0 - s1, s2 - s0);
      }
      F[(m * ms + q) * ft] = side * dM * s0;
    }
    F[(nm * ms + 1) * ft] += side * dM;
  }
}

/* FaceRun's arithmetic for the faces k in [ka, kb) of a run whose two
   possible donors (the cells below and above each face) all hold material
   s alone (C->sole: a face whose donor and both its neighbours along d are
   filled by one material has two such donors), written straight into the
   face records of s (F: value q of material m at F[(m ms + q) ft + k]) and
   a flag per face into fl (1: the values are FaceFlux's for that face; 0:
   FaceRun's loop takes the face).  o0: face 0's lower node, u0 the cell
   above it, jd0 its index along d, jx 1 along x, else 0.  The same values,
   without a branch: both donors and their neighbours are loaded
   (FractionsUnits's planes: sP, the material that fills a cell; sM its mass;
   sS its density and e; cell u's at u + rs in their ring), and chosen by
   the sign of the face's displacement;
   a face that FaceRun's test would send elsewhere has the flag 0, and the
   values it leaves in s's records are not read (the face's range, R, says
   which materials it carries).  A face at rest (a gas at rest, or moving
   across d) keeps its flag 1 where its fluxes come out zero (+-0; FaceOne
   gave it an empty range): the cells add those zeros in lanes
   (CellUpdateLanes), where an empty range sent them one by one to
   CellUpdate, which adds nothing; adding +-0 changes no value but a -0,
   which no cell's V, M or E holds, so every result is bitwise the same (a
   gas at rest ran 1.19-1.21x faster, twenty-eighth session).  Gas blocks
   only (ms = PS_CQ), on ghosted cells k - 2 cd .. k + cd */
static inline void FaceRunLanes(const PSCells *C, const PetscInt dim, const PetscReal *v, PetscInt d, PetscInt s1, PetscInt s2, PetscInt o0, PetscInt u0, PetscInt rs, PetscInt jd0, PetscInt jx, PetscInt cd, PetscReal A, PetscReal hdt, PetscInt ka, PetscInt kb, PetscInt s, PetscReal *F, PetscInt ft, PetscReal *fl)
{
  const PetscReal *XV = PSCellsX(C, 0, PS_CX_V), *sS = C->sS + 2 * rs, *sP = C->sP + rs, *sM = C->sM + rs; /* (the per-cell values' ring, at the ghosted indices) */
  const PetscInt   nm = C->nmat;
  const PetscReal  ncr = (PetscReal)C->nc[d], jd0r = (PetscReal)jd0, jxr = (PetscReal)jx;
  PetscReal       *FA = &F[nm * PS_CQ * ft], *FT = &F[(nm * PS_CQ + 1) * ft], *FV = &F[(s * PS_CQ + PS_CV) * ft], *FM = &F[(s * PS_CQ + PS_CM) * ft], *FE = &F[(s * PS_CQ + PS_CE) * ft];
  PetscInt         k;

#pragma GCC ivdep
  for (k = ka; k < kb; k++) {
    const PetscInt o = o0 + k, uN = u0 + k, uP = uN - cd; /* donor uP (below) where delta > 0, else uN */
    PetscReal      delta;
    if (dim == 3) delta = 0.0 + v[dim * o + d] + v[dim * (o + s1) + d] + v[dim * (o + s2) + d] + v[dim * (o + s1 + s2) + d];
    else delta = 0.0 + v[dim * o + d] + v[dim * (o + s1) + d];
    delta *= hdt;
    const PetscBool pos = delta > 0.0;
    /* the four cells' fill (-1: none), density and e: below the lower donor, the two donors, above the upper */
    const PetscReal f0 = sP[uP - cd], f1 = sP[uP], f2 = sP[uN], f3 = sP[uN + cd];
    const PetscReal r0 = sS[2 * (uP - cd)], r1 = sS[2 * uP], r2 = sS[2 * uN], r3 = sS[2 * (uN + cd)];
    const PetscReal e0 = sS[2 * (uP - cd) + 1], e1 = sS[2 * uP + 1], e2 = sS[2 * uN + 1], e3 = sS[2 * (uN + cd) + 1];
    const PetscReal fd = pos ? f1 : f2, fm = pos ? f0 : f1, fp = pos ? f2 : f3; /* the donor's and its neighbours' */
    const PetscReal rb = pos ? r0 : r1, rho = pos ? r1 : r2, ra = pos ? r2 : r3;
    const PetscReal eb = pos ? e0 : e1, ed = pos ? e1 : e2, ea = pos ? e2 : e3;
    const PetscReal V = pos ? XV[uP] : XV[uN], M = pos ? sM[uP] : sM[uN];
    const PetscReal w1 = PetscMin(PetscAbsReal(delta) * A / V, 1.0), vol = w1 * V / A * A;
    const PetscReal side = pos ? 1.0 : -1.0, off = side * 0.5 * (1.0 - w1);
    const PetscReal dM = PetscMin(PetscMax(vol * (rho + off * VanLeerLanes(rho - rb, ra - rho)), 0.0), M);
    const PetscReal jr = jd0r + jxr * (PetscReal)k; /* (the index along d as a real, not folded back to an integer: GCC 12 puts no choice by a test of reals between tests of integers in SIMD lanes) */
    const PetscReal room = pos ? jr - 1.0 : ncr - 1.0 - jr;  /* >= 0: the donor inside the domain */
    fl[k] = (delta == 0.0 && vol == 0.0 && dM == 0.0) || (room >= 0.0 && fd >= 0.0 && fm == fd && fp == fd && vol > 0.0) ? 1.0 : 0.0; /* (at rest: the zeros checked, not assumed of V and rho) */
    FA[k] = delta * A;
    FV[k] = side * vol;
    FM[k] = side * dM;
    FE[k] = side * dM * (ed + off * VanLeerLanes(ed - eb, ea - ed));
    FT[k] = 0.0 + side * dM;
  }
}

/* face k of a run along x (FaceRun's j0, o0, u0) alone, into F[k] (planes
   ft apart) and R[2 k]: a face whose donor and both its neighbours along d
   are filled by one material takes the arithmetic of FaceFlux's loop for a
   pure donor with van Leer slopes, in its order, on FractionsUnits's
   values, without its tests and with the indices carried along the run
   (FaceFlux spent about 220 instructions on such a face, most of them on
   indices and tests); any other face (a mixed, partial or boundary donor)
   takes FaceFlux itself, which gives such a face the same values */
static inline __attribute__((always_inline)) void FaceOne(const PSSolver *S, const PSIndex *ix, const PSFractions *fr, PetscReal dt, const PSSweepDirs *sw, const PetscInt dim, const PetscInt j0[3], PetscInt o0, PetscInt u0, PetscInt rs, PetscInt k, PetscReal *F, PetscInt ft, PetscInt *R)
{
  const PSCells   *C = S->cells;
  const PetscInt   mst = C->mst, ms = C->ms, nm = C->nmat, d = sw->d, cd = sw->cd, sp = ms - 1, spcd = sp * cd, nc = C->nc[d];
  const PetscReal  A = C->Vc / S->h[d], hdt = dt / (dim == 3 ? 4.0 : 2.0), *v = C->vh, *fill = C->sP + rs; /* (the per-cell values' ring, at the ghosted indices) */
  const PetscReal *U = C->u, *XV = PSCellsX(C, 0, PS_CX_V), *sS = C->sS + sp * rs;
  const PetscInt   o = o0 + k;
  PetscReal        delta, *Fk = &F[k];
  PetscInt         cdn, uc, s, q;

  /* the face's displacement (FaceFlux's sum, from 0) */
  if (dim == 3) delta = 0.0 + v[dim * o + d] + v[dim * (o + sw->s1) + d] + v[dim * (o + sw->s2) + d] + v[dim * (o + sw->s1 + sw->s2) + d];
  else delta = 0.0 + v[dim * o + d] + v[dim * (o + sw->s1) + d];
  delta *= hdt;
  /* the donor along d */
  cdn = j0[d] + (d == 0 ? k : 0) - (delta > 0.0 ? 1 : 0);
  uc  = u0 + k - (delta > 0.0 ? cd : 0);
  if (delta == 0.0 || cdn < 0 || cdn >= nc) { /* nothing crosses, or void enters (FaceFlux's values) */
    Fk[nm * ms * ft]       = delta * A;
    Fk[(nm * ms + 1) * ft] = 0.0;
    R[2 * k]               = nm;
    R[2 * k + 1]           = 0;
    return;
  }
  /* the donor and both its neighbours filled by one material s
     (FractionsUnits's C->sP: FaceFlux's tests for its slopes, and more) */
  s = (PetscInt)fill[uc];
  if (s >= 0 && fill[uc - cd] == fill[uc] && fill[uc + cd] == fill[uc]) {
    const PetscReal *blk = &U[ms * uc + mst * s];
    const PetscReal  V = XV[uc], w = PetscMin(PetscAbsReal(delta) * A / V, 1.0), vol = w * V / A * A;
    if (vol > 0.0) {
      const PetscReal *spd = &sS[sp * uc], *sp0 = spd - spcd, *sp1 = spd + spcd;
      const PetscReal  side = delta > 0.0 ? 1.0 : -1.0, off = side * 0.5 * (1.0 - w), rho = spd[0];
      const PetscReal  dM = PetscMin(PetscMax(vol * (rho + off * VanLeer(rho - sp0[0], sp1[0] - rho)), 0.0), blk[PS_CM]);
      PetscReal       *Fm = &Fk[s * ms * ft];
      Fk[nm * ms * ft] = delta * A;
      Fm[PS_CV * ft]   = side * vol;
      Fm[PS_CM * ft]   = side * dM;
      if (ms == PS_CQ) Fm[PS_CE * ft] = side * dM * (spd[1] + off * VanLeer(spd[1] - sp0[1], sp1[1] - spd[1]));
      else
        for (q = 1; q < ms - 1; q++) Fm[(q + 1) * ft] = side * dM * (spd[q] + off * VanLeer(spd[q] - sp0[q], sp1[q] - spd[q]));
      Fk[(nm * ms + 1) * ft] = 0.0 + side * dM;
      R[2 * k]               = s;
      R[2 * k + 1]           = s + 1;
      return;
    }
  }
  {
    const PetscInt j[3] = {j0[0] + k, j0[1], j0[2]};
    FaceFlux(S, ix, fr, dt, sw, dim, j, Fk, ft, &R[2 * k]);
  }
}

/* the faces j0 + k e_x, k < n (a run along x: a slice's row, or a line along
   d = x), into F[k] (planes ft apart: value q at F[q ft + k]) and R[2 k].
   A gas's stretch of faces whose two possible donors hold one gas s alone
   (found on C->sole sixteen cells at a time, PSCellsSoleRun) takes
   FaceRunLanes, in SIMD lanes, straight into s's records, where the cells
   two below to one above each face are in the ghosted array (faces at rest
   too); the faces it flags 0 (next to none inside a gas), and every other
   face, take FaceOne */
static inline void FaceRun(const PSSolver *S, const PSIndex *ix, const PSFractions *fr, PetscReal dt, const PSSweepDirs *sw, const PetscInt dim, const PetscInt j0[3], PetscInt n, PetscReal *F, PetscInt ft, PetscInt *R)
{
  const PSCells  *C = S->cells;
  const PetscInt  d = sw->d, cd = sw->cd;
  const PetscReal A = C->Vc / S->h[d], hdt = dt / (dim == 3 ? 4.0 : 2.0);
  const PetscInt  o0 = Node(ix, dim, j0), u0 = PSCellIdx(C, j0[0], j0[1], j0[2]), rs = RingShift(C, j0[dim - 1] - C->gs[dim - 1]); /* (rs: the per-cell values' ring, around the run's unit) */
  const short    *sole = C->sole;
  PetscReal      *fl = C->sW; /* (the lanes' flags) */
  PetscInt        k, ka = 0, kb = 0;

  if (C->ms == PS_CQ && S->run.lanes != 1) {
    if (d == 0) {
      ka = PetscMax(C->gs[0] + 2 - j0[0], 0);
      kb = PetscMin(C->gs[0] + C->gm[0] - 1 - j0[0], n);
    } else if (j0[d] - 2 >= C->gs[d] && j0[d] + 1 <= C->gs[d] + C->gm[d] - 1) kb = n;
    kb = PetscMax(kb, ka);
  }
  for (k = 0; k < n;) {
    /* a stretch [k, e) of faces whose donors (cells u0 + k - cd and u0 + k)
       hold gas s alone: along x the cells [k - 1, e) of the run, across x
       the two rows' [k, e) */
    if (k >= ka && k < kb && sole[u0 + k] >= 0 && sole[u0 + k - cd] == sole[u0 + k]) {
      const PetscInt s = sole[u0 + k];
      PetscInt       e = k + PSCellsSoleRun(&sole[u0 + k], kb - k), x, nz = 0;
      if (d > 0) e = PetscMin(e, k + PSCellsSoleRun(&sole[u0 + k - cd], kb - k));
      if (e - k >= PS_LANES_RUN) {
        FaceRunLanes(C, dim, C->vh, d, sw->s1, sw->s2, o0, u0, rs, j0[d], d == 0 ? 1 : 0, cd, A, hdt, k, e, s, F, ft, fl);
        for (x = k; x < e; x++) {
          R[2 * x]     = s;
          R[2 * x + 1] = s + 1;
        }
        for (x = k; x < e; x++) nz += fl[x] == 0.0;
        /* the faces the lanes left (flag 0) to FaceOne, in order: sixteen
           without one passed over at once (tested in SIMD lanes), until the
           last is done (testing every face of the stretch one by one was
           0.6% of the quadrants' instructions) */
        for (x = k; nz > 0;) {
          const PetscInt xe = PetscMin(x + 16, e);
          if (xe - x == 16) {
            int z = 0;
            PetscInt q;
#pragma GCC unroll 1
            for (q = x; q < xe; q++) z |= fl[q] == 0.0;
            if (!z) {
              x = xe;
              continue;
            }
          }
          for (; x < xe; x++)
            if (fl[x] == 0.0) {
              FaceOne(S, ix, fr, dt, sw, dim, j0, o0, u0, rs, x, F, ft, R);
              nz--;
            }
        }
        k = e;
        continue;
      }
    }
    FaceOne(S, ix, fr, dt, sw, dim, j0, o0, u0, rs, k, F, ft, R);
    k++;
  }
}

/* a slice's index range in x and y: the box's [lo, hi) across d below it in
   the loop nest, j's own index elsewhere (j[d] is the slice) */
static inline void SliceRange(PetscInt d, const PetscInt lo[3], const PetscInt hi[3], const PetscInt j[3], PetscInt jl[2], PetscInt jh[2])
{
  PetscInt e;
  for (e = 0; e < 2; e++) {
    jl[e] = e < d ? lo[e] : j[e];
    jh[e] = e < d ? hi[e] : j[e] + 1;
  }
}

/* a free face of the domain lets a boundary node's share out: the mass out
   (kg) at the node's velocity v, its momentum (P) and kinetic energy (K)
   booked as lost */
static inline void Outflow(PSSolver *S, PetscInt dim, PetscReal out, const PetscReal *v, PetscInt nv, PetscReal *P, PetscReal *K)
{
  PetscReal k2 = 0.0;
  PetscInt  q;
  for (q = 0; q < dim; q++) {
    P[q] -= out * v[q * nv];
    S->lost_local.p[q] += out * v[q * nv];
    k2 += v[q * nv] * v[q * nv];
  }
  *K -= 0.5 * out * k2;
  S->lost_local.kinetic += 0.5 * out * k2;
}

/* the velocity a node column carries across a cell's mid-plane: the upwind
   node's vu with a van Leer slope toward the mid-plane (vd downwind, vb
   beyond upwind; g = (1 - nu)/2), and its square (DualFlux); v: the
   nodes' component planes of length nv (VL) */
static inline void MidPlaneVelocity(const PetscInt dim, const PetscReal *vu, const PetscReal *vd, const PetscReal *vb, PetscInt nv, PetscReal g, PetscReal vf[3], PetscReal *v2)
{
  PetscInt q;
  *v2 = 0.0;
  for (q = 0; q < dim; q++) {
    vf[q] = vu[q * nv] + g * VanLeer(vu[q * nv] - vb[q * nv], vd[q * nv] - vu[q * nv]);
    *v2 += vf[q] * vf[q];
  }
}

/* DualFlux's arithmetic for the cells k in [ka, kb) of a run whose dual
   fluxes need no test (CellRun's fast range; o0: the run's first cell's
   lower corner node, Fl, Fh its faces' flux records (fs planes, ft apart), Mc0 its
   cells' masses before the sweep): per node column c (b + 2 a) the momentum
   phi v_f (dim planes) and the kinetic energy phi v_f^2 / 2 it carries across
   the cell's mid-plane, into W (plane l of column c at W[(c (dim + 1) + l) w]).
   The same values as DualFlux's, without a branch: every candidate node is
   loaded (the upwind, downwind and beyond-upwind nodes of either direction;
   the fast range has them all) and chosen by value, a divisor is 1 where the
   value is not used, so the loop runs in SIMD lanes.  CellRun then adds them
   to the nodes in DualFlux's order */
static inline void DualFluxLanes(const PetscInt dim, const PetscReal *VL, PetscInt nv, const PetscReal *mcn, const PetscReal *Mc0, const PetscReal *Fl, const PetscReal *Fh, PetscInt fs, PetscInt ft, PetscInt o0, PetscInt sd, PetscInt s1, PetscInt s2, PetscInt ka, PetscInt kb, PetscInt w, PetscReal *W)
{
  const PetscInt ncol = dim == 3 ? 4 : 2;
  PetscInt       k, c, q;

#pragma GCC ivdep
  for (k = ka; k < kb; k++) {
    const PetscReal Flo = Fl[(fs - 1) * ft + k], Fhi = Fh[(fs - 1) * ft + k], F = Flo + Fhi, Mc = Mc0[k], Md = Mc > 0.0 ? Mc : 1.0;
    const PetscReal phi = 0.5 * F / ncol, rF = PetscMin(PetscAbsReal(F) / Md, 1.0), nu = Mc > 0.0 ? rF : 1.0, g = 0.5 * (1.0 - nu);
    const PetscBool up = phi > 0.0;
#pragma GCC unroll 4
    for (c = 0; c < ncol; c++) { /* (column c: b = c & 1, a = c >> 1) */
      const PetscInt  oL = o0 + k + (c & 1) * s1 + (c >> 1) * s2;
      const PetscReal mLm = mcn[oL - sd], mUp = mcn[oL + 2 * sd], mb = up ? mLm : mUp;
      PetscReal       v2 = 0.0;
#pragma GCC unroll 3
      for (q = 0; q < dim; q++) {
        const PetscReal *Vq = &VL[q * nv], vL = Vq[oL], vU = Vq[oL + sd], vLm = Vq[oL - sd], vUp = Vq[oL + 2 * sd];
        const PetscReal vu = up ? vL : vU, vd = up ? vU : vL, vb = mb > 0.0 ? (up ? vLm : vUp) : vu;
        const PetscReal vf = vu + g * VanLeerLanes(vu - vb, vd - vu);
        v2 += vf * vf;
        W[(c * (dim + 1) + q) * w + k] = phi * vf;
      }
      W[(c * (dim + 1) + dim) * w + k] = phi * 0.5 * v2;
    }
    W[ncol * (dim + 1) * w + k] = Flo != 0.0 || Fhi != 0.0 ? 1.0 : 0.0; /* (the cell's mid-plane carries anything) */
  }
}

/* the dual fluxes of DualFluxLanes (W) to the nodes, for the cells k in
   [ka, kb) of a run: corner r = 2 c + side of a cell (column c, side 0 its
   lower node, which gives up phi v_f, 1 its upper, which takes it) is node
   o0 + k + off_r.  A node in the run takes one corner of each of two cells
   at most: cell j - 1's (its corner B, one along x beyond A), then cell j's
   (A), the order of DualFlux cell by cell; so the nodes of a pair of corners
   (A, B) take them in SIMD lanes, with the same sums in the same order.  A
   cell whose mid-plane carries nothing (its flag in W) gives nothing.
   rows (2D): bit 0 the corners on the cells' lower row of nodes along y
   (the pair whose A corner is corner 0, along either d), bit 1 those on the
   upper row; 3 all (in 3D always) */
static inline void DualFluxNodes(const PetscInt dim, PetscInt o0, PetscInt sd, PetscInt s1, PetscInt s2, PetscInt ka, PetscInt kb, PetscInt w, const PetscReal *W, PetscReal *P, PetscReal *K, PetscInt rows)
{
  const PetscInt   ncol = dim == 3 ? 4 : 2, nco = 2 * ncol;
  const PetscReal *Wf   = &W[ncol * (dim + 1) * w];
  PetscInt         off[8], r, rb, j, q;

  for (r = 0; r < nco; r++) off[r] = ((r >> 1) & 1) * s1 + (r >> 2) * s2 + (r & 1) * sd;
  for (r = 0; r < nco; r++) {
    /* r is an A corner (none one below it along x); rb its B */
    for (rb = 0; rb < nco && off[rb] != off[r] - 1; rb++) {}
    if (rb < nco) continue;
    if (!(rows & (r == 0 ? 1 : 2))) continue; /* (a row of nodes left for later: PSDeferred) */
    for (rb = 0; rb < nco && off[rb] != off[r] + 1; rb++) {}
    {
      const PetscReal  sA = r & 1 ? 1.0 : -1.0, sB = rb & 1 ? 1.0 : -1.0;
      const PetscReal *WA = &W[(r >> 1) * (dim + 1) * w], *WB = &W[(rb >> 1) * (dim + 1) * w];
      PetscReal       *PA = &P[dim * (o0 + off[r])], *KA = &K[o0 + off[r]];
      /* node ka: cell ka's A alone (cell ka - 1 is not in the range) */
      if (Wf[ka] != 0.0) {
        for (q = 0; q < dim; q++) PA[dim * ka + q] = PA[dim * ka + q] + sA * WA[q * w + ka];
        KA[ka] = KA[ka] + sA * WA[dim * w + ka];
      }
      /* nodes ka + 1 .. kb - 1: cell j - 1's B, then cell j's A */
#pragma GCC ivdep
      for (j = ka + 1; j < kb; j++) {
        const PetscBool fb = Wf[j - 1] != 0.0, fa = Wf[j] != 0.0;
        PetscReal       pb, pa, p;
#pragma GCC unroll 3
        for (q = 0; q < dim; q++) {
          p                 = PA[dim * j + q];
          pb                = p + sB * WB[q * w + j - 1];
          p                 = fb ? pb : p;
          pa                = p + sA * WA[q * w + j];
          PA[dim * j + q] = fa ? pa : p;
        }
        p      = KA[j];
        pb     = p + sB * WB[dim * w + j - 1];
        p      = fb ? pb : p;
        pa     = p + sA * WA[dim * w + j];
        KA[j] = fa ? pa : p;
      }
      /* node kb: cell kb - 1's B alone */
      if (Wf[kb - 1] != 0.0) {
        for (q = 0; q < dim; q++) PA[dim * kb + q] = PA[dim * kb + q] + sB * WB[q * w + kb - 1];
        KA[kb] = KA[kb] + sB * WB[dim * w + kb - 1];
      }
    }
  }
}

/* the momentum's dual flux of cell j (lower corner j): its mid-plane carries
   (F_lo + F_hi)/2 (the total mass fluxes of its faces along d) from its
   lower to its upper corner nodes, shared among the 2^(dim-1) node columns,
   at the upwind node's velocity with a van Leer slope; free faces of the
   domain let the boundary node's share out.  VL, K: the nodes' velocity and
   kinetic energy before the sweep; P (the nodal momentum) and K take the
   owned nodes' change; rows as DualFluxNodes's (2D: along d = x a column b
   is a row of nodes, along d = y a side is) */
static inline void DualFlux(PSSolver *S, const PSIndex *ix, const PSSweepDirs *sw, const PetscInt dim, const PetscInt i[3], PetscReal Flo, PetscReal Fhi, const PetscReal *VL, PetscReal *P, PetscReal *K, PetscInt rows)
{
  const PSCells  *C = S->cells;
  const PetscInt  d = sw->d, t1 = sw->t1, t2 = sw->t2, sd = sw->sd, s1 = sw->s1, s2 = sw->s2, ncol = dim == 3 ? 4 : 2, nv = C->nnl;
  const PetscBool bl = i[d] == 0 && Flo < 0.0;             /* outflow through a free face below */
  const PetscBool bu = i[d] + 1 == C->nc[d] && Fhi > 0.0;  /* or above */
  PetscReal       phi, Mc, nu, g;
  PetscInt        a, b, q, o0, ou, od, ob;
  PetscBool       up, inb, own0, own1;

  if (Flo == 0.0 && Fhi == 0.0) return; /* nothing crosses this cell */
  phi = 0.5 * (Flo + Fhi) / ncol;
  /* the share of the upwind half cell that crosses the mid-plane: the
     Courant number of the momentum's slope correction */
  Mc = C->Mcell[PSCellIdx(C, i[0], i[1], i[2])]; /* before the sweep (PSCellsNodalMass) */
  nu = Mc > 0.0 ? PetscMin(PetscAbsReal(Flo + Fhi) / Mc, 1.0) : 1.0;
  g  = 0.5 * (1.0 - nu);
  o0 = Node(ix, dim, i);
  /* per cell, not per column and component: the upwind, downwind and
     beyond-upwind nodes' offsets from a column's lower node (beyond: none
     outside the domain), and which of the column's two nodes are owned along d */
  up    = phi > 0.0;
  inb   = up ? i[d] > 0 : i[d] + 1 < C->nc[d];
  ou    = up ? 0 : sd;
  od    = up ? sd : 0;
  ob    = up ? -sd : 2 * sd;
  own0  = OwnedIndex(ix, d, i[d]);
  own1  = OwnedIndex(ix, d, i[d] + 1);
  if (!own0 && !own1) return;
  for (a = 0; a < (dim == 3 ? 2 : 1); a++)
    for (b = 0; b < 2; b++) {
      const PetscInt   oL = o0 + b * s1 + a * s2, oU = oL + sd;
      const PetscReal *vL = &VL[oL], *vU = &VL[oU], *vu = &VL[oL + ou], *vd = &VL[oL + od];
      const PetscReal *vb = inb && C->mcn[oL + ob] > 0.0 ? &VL[oL + ob] : vu;
      PetscReal        vf[3], v2;
      /* the column's nodes are this rank's if its transverse indices are */
      if (!(OwnedIndex(ix, t1, i[t1] + b) && (dim < 3 || OwnedIndex(ix, t2, i[t2] + a)))) continue;
      MidPlaneVelocity(dim, vu, vd, vb, nv, g, vf, &v2);
      if (own0 && (rows & (d == dim - 1 ? 1 : 1 << b))) {
        for (q = 0; q < dim; q++) P[dim * oL + q] -= phi * vf[q];
        K[oL] -= phi * 0.5 * v2;
        /* free faces of the domain: outflow takes the boundary node's share */
        if (bl) Outflow(S, dim, -Flo / ncol, vL, nv, &P[dim * oL], &K[oL]);
      }
      if (own1 && (rows & (d == dim - 1 ? 2 : 1 << b))) {
        for (q = 0; q < dim; q++) P[dim * oU + q] += phi * vf[q];
        K[oU] += phi * 0.5 * v2;
        if (bu) Outflow(S, dim, Fhi / ncol, vU, nv, &P[dim * oU], &K[oU]);
      }
    }
}

/* material m's block b of cell after its update: traces below PS_DISCARD of
   the cell (a round-off residue, or what a face flux leaves behind against a
   marker body) are discarded, as CTH does, their mass and internal energy
   booked as lost; so is a volume with next to no mass (below PS_RHO_MIN of
   the reference density: a face flux's volume outran its mass), which the
   next compression would heat without bound, q dV / M_k.  A block all zero
   (the material absent before and after) has nothing to discard */
static inline void DiscardTrace(PSSolver *S, PetscInt m, PetscReal *b)
{
  PSCells *C = S->cells;
  PetscInt q;
  if (!(b[PS_CM] <= 0.0 || b[PS_CV] <= PS_DISCARD * C->Vc || b[PS_CM] < C->rho_min[m] * b[PS_CV])) return;
  for (q = 0; q < C->ms && b[q] == 0.0; q++) {}
  if (q == C->ms) return;
  S->lost_local.mass += b[PS_CM];
  S->lost_local.internal += b[PS_CE];
  C->discarded += b[PS_CM];
  for (q = 0; q < C->ms; q++) b[q] = 0.0;
}

/* an owned cell's update (i, its index ci in the ghosted array, u its state
   and V its volume) from its faces' fluxes fl (lower) and fh (upper),
   which hold the materials [rl[0], rl[1]) and [rh[0], rh[1]): in through the
   lower face, out through the upper.  Materials in neither range are not
   touched (their fluxes are zero: u + (0 - 0) is u), and only those fluxed
   or with mass before the sweep are tested for discard (the others are all
   zero, which the test skips).  inner: the cell is neither the domain's
   first nor its last along d (no free face of the domain).  Always inline:
   GCC kept it out of line, and the call cost about 15 instructions per cell
   and sweep */
static inline __attribute__((always_inline)) void CellUpdate(PSSolver *S, const PSSweepDirs *sw, const PetscInt i[3], PetscInt ci, PetscBool inner, PetscReal *u, PetscReal *V, const PetscReal *fl, const PetscReal *fh, PetscInt ft, const PetscInt rl[2], const PetscInt rh[2])
{
  PSCells        *C = S->cells;
  const PetscInt  d = sw->d, ms = C->ms, mst = C->mst, nm = C->nmat, fs = nm * ms + 2;
  PetscInt        m, q, f0, f1, m0, m1;

  /* nearly every cell of a single-material region: it holds material s
     alone, and each face carries s alone or nothing, inside the domain
     along d.  The general path's arithmetic below, in its order, without
     its ranges: the other materials hold and take nothing (zero:
     PSCellsPresent), so the cell's mass is s's and s the one with mass
     unless it is discarded */
  m = C->sole[ci];
  const PetscBool sl = rl[0] == m && rl[1] == m + 1, sh = rh[0] == m && rh[1] == m + 1;
  if (m >= 0 && inner && (sl || (rl[0] == nm && rl[1] == 0)) && (sh || (rh[0] == nm && rh[1] == 0))) {
    /* (a face that carries nothing, its range empty: a face at rest, in a
       gas at rest or moving across d; the general path adds its 0, and
       touches the block only if a face carries m) */
    PetscReal       *b = &u[m * mst];
    const PetscReal *l = &fl[m * ms * ft], *h = &fh[m * ms * ft];
    if (sl && sh) {
      if (ms == PS_CQ) { /* a block without advected strength (a gas): V, M, E unrolled (the loop, its length known only at run time, took 49 instructions for these three) */
        b[0] += l[0] - h[0];
        b[1] += l[ft] - h[ft];
        b[2] += l[2 * ft] - h[2 * ft];
      } else
        for (q = 0; q < ms; q++) b[q] += l[q * ft] - h[q * ft];
    } else if (sl)
      for (q = 0; q < ms; q++) b[q] += l[q * ft] - 0.0;
    else if (sh)
      for (q = 0; q < ms; q++) b[q] += 0.0 - h[q * ft];
    *V += fl[nm * ms * ft] - fh[nm * ms * ft];
    DiscardTrace(S, m, b);
    C->Mcell[ci] = b[PS_CM]; /* (PSCellsCellMass's sum: the others add zeros) */
    C->sole[ci]  = (short)(b[PS_CM] > 0.0 ? m : PS_CELL_EMPTY);
    return;
  }
  /* the materials fluxed: the union of the faces' ranges (an empty one is
     [nmat, 0); the materials between them take 0 - 0) */
  f0 = PetscMin(rl[0], rh[0]);
  f1 = PetscMax(rl[1], rh[1]);
  for (m = f0; m < f1; m++) {
    const PetscBool inl = m >= rl[0] && m < rl[1] ? PETSC_TRUE : PETSC_FALSE, inh = m >= rh[0] && m < rh[1] ? PETSC_TRUE : PETSC_FALSE;
    if (ms == PS_CQ) /* (a gas's block: unrolled, as the fast path above) */
      for (q = 0; q < PS_CQ; q++) u[m * mst + q] += (inl ? fl[(m * PS_CQ + q) * ft] : 0.0) - (inh ? fh[(m * PS_CQ + q) * ft] : 0.0);
    else
      for (q = 0; q < ms; q++) u[m * mst + q] += (inl ? fl[(m * ms + q) * ft] : 0.0) - (inh ? fh[(m * ms + q) * ft] : 0.0);
  }
  *V += fl[nm * ms * ft] - fh[nm * ms * ft];
  /* with the materials that had mass before the sweep */
  PSCellsPresent(C, ci, &m0, &m1);
  if (m0 < m1) {
    m0 = PetscMin(m0, f0);
    m1 = PetscMax(m1, f1);
  } else {
    m0 = f0;
    m1 = f1;
  }
  for (m = m0; m < m1; m++) DiscardTrace(S, m, &u[m * mst]);
  /* outflow through free faces of the domain */
  if (i[d] == 0 && fl[(fs - 1) * ft] < 0.0)
    for (m = rl[0]; m < rl[1]; m++) {
      S->lost_local.mass -= fl[(m * ms + PS_CM) * ft];
      S->lost_local.internal -= fl[(m * ms + PS_CE) * ft];
    }
  if (i[d] + 1 == C->nc[d] && fh[(fs - 1) * ft] > 0.0)
    for (m = rh[0]; m < rh[1]; m++) {
      S->lost_local.mass += fh[(m * ms + PS_CM) * ft];
      S->lost_local.internal += fh[(m * ms + PS_CE) * ft];
    }
  /* its mass for the nodes (PSCellsNodalMass after the sweep; DualFlux has read the
     one before the sweep) */
  PSCellsCellMass(C, ci);
}

/* CellUpdate's fast path for the cells u0 + k, k in [k0, k1), of a run
   that all hold gas s alone inside the domain along d, each of whose faces
   carries s alone (Fl, Fh: the run's flux records, planes ft apart): the
   sums in SIMD lanes, in CellUpdate's order, and DiscardTrace's test; a
   cell it flags (next to never: a trace, or a volume without mass) takes
   DiscardTrace after the lanes, in the cells' order, as CellUpdate does */
static inline void CellUpdateLanes(PSSolver *S, PetscInt s, PetscInt u0, PetscInt k0, PetscInt k1, const PetscReal *Fl, const PetscReal *Fh, PetscInt ft, PetscReal *W)
{
  PSCells        *C = S->cells;
  const PetscInt  ov = C->nmat * PS_CQ, os = s * PS_CQ;
  const PetscReal Vmin = PS_DISCARD * C->Vc, rmin = C->rho_min[s];
  PetscReal      *B = &C->u[s * C->mst], *XV = PSCellsX(C, 0, PS_CX_V), *Mcell = C->Mcell;
  PetscInt        k, nd = 0;

#pragma GCC ivdep
  for (k = k0; k < k1; k++) {
    const PetscInt   ci = u0 + k;
    const PetscReal *l = &Fl[os * ft + k], *h = &Fh[os * ft + k];
    PetscReal       *b = &B[PS_CQ * ci];
    const PetscReal  b0 = b[0] + (l[0] - h[0]), b1 = b[1] + (l[ft] - h[ft]), b2 = b[2] + (l[2 * ft] - h[2 * ft]);
    b[0]      = b0;
    b[1]      = b1;
    b[2]      = b2;
    XV[ci]    = XV[ci] + (Fl[ov * ft + k] - Fh[ov * ft + k]);
    Mcell[ci] = b1;
    W[k]      = !(b1 > 0.0) || b0 <= Vmin || b1 < rmin * b0 ? 1.0 : 0.0; /* (DiscardTrace's test, or a mass CellUpdate would not call s's) */
  }
  for (k = k0; k < k1; k++) nd += W[k] != 0.0;
  if (nd)
    for (k = k0; k < k1; k++)
      if (W[k] != 0.0) {
        PetscReal *b = &B[PS_CQ * (u0 + k)];
        DiscardTrace(S, s, b);
        Mcell[u0 + k]  = b[PS_CM];
        C->sole[u0 + k] = (short)(b[PS_CM] > 0.0 ? s : PS_CELL_EMPTY);
      }
}

/* whether any of the sixteen cells q0 .. q0 + 15 of a run (so: their C->sole)
   does not hold gas s alone or has a face (Rl, Rh: the ranges of their lower
   and upper faces) that does not carry s alone: a loop without an exit
   inside, not unrolled, which GCC runs in SIMD lanes (CellRun) */
static inline PetscBool RunBreaks16(const short *so, const PetscInt *Rl, const PetscInt *Rh, PetscInt s, PetscInt q0)
{
  PetscInt diff = 0, q;
#pragma GCC unroll 1
  for (q = q0; q < q0 + 16; q++) diff |= ((PetscInt)so[q] ^ s) | (Rl[2 * q] ^ s) | (Rl[2 * q + 1] ^ (s + 1)) | (Rh[2 * q] ^ s) | (Rh[2 * q + 1] ^ (s + 1));
  return diff ? PETSC_TRUE : PETSC_FALSE;
}

/* the cells j0 + k e_x, k < n (a run along x), between their faces' fluxes
   Fl[k] (lower) and Fh[k] (upper; planes ft apart): each one's dual flux, then its
   update if it is owned (the order of the slices' loop).  A cell inside the
   domain along d whose node columns are all this rank's (the ownership
   depends on x only through a range, found once per run) takes DualFlux's
   arithmetic here, in its order, without its per-cell and per-column tests;
   any other takes DualFlux itself.  rows: the dual fluxes' rows of nodes
   (DualFluxNodes; 3 all); 1, the lower row alone, gives no update (the
   run's dual fluxes to a row left for later, PSDeferred) */
static inline void CellRun(PSSolver *S, const PSIndex *ix, const PSSweepDirs *sw, const PetscInt dim, const PetscInt j0[3], PetscInt n, const PetscReal *Fl, const PetscReal *Fh, PetscInt ft, const PetscInt *Rl, const PetscInt *Rh, const PetscReal *VL, PetscReal *P, PetscReal *K, PetscInt rows)
{
  const PSCells  *C = S->cells;
  const PetscInt  d = sw->d, sd = sw->sd, s1 = sw->s1, s2 = sw->s2, fs = C->nmat * C->ms + 2;
  const PetscInt  o0 = Node(ix, dim, j0), u0 = PSCellIdx(C, j0[0], j0[1], j0[2]);
  const PetscBool owned = j0[1] >= C->cs[1] && j0[2] >= C->cs[2]; /* across x (x: below) */
  const PetscBool innerd = j0[d] > 0 && j0[d] + 1 < C->nc[d];   /* the run inside the domain along d (d > 0; along x: each cell) */
  const PetscReal *Mcell = C->Mcell, *mcn = C->mcn;              /* (in locals) */
  PetscReal       *U = C->u, *XV = PSCellsX(C, 0, PS_CX_V);
  const PetscInt  nw = PSCellsPlaneLen(C, ix); /* (W's plane length: C->sW's) */
  PetscReal       *W = C->sW;
  const PetscBool lanes = C->ms == PS_CQ && S->run.lanes != 1 ? PETSC_TRUE : PETSC_FALSE; /* (CellUpdateLanes: gas blocks) */
  PetscInt        xa, xb, ka, kb, k;
  PetscBool       ok;

  /* the range [xa, xb) of x where the cell's dual flux needs no test: inside
     the domain along d (no outflow, a node beyond the upwind one) and its
     2^dim nodes owned (OwnedIndex of each index and its successor) */
  if (d == 0) {
    ok = OwnedIndex(ix, 1, j0[1]) && OwnedIndex(ix, 1, j0[1] + 1) && (dim < 3 || (OwnedIndex(ix, 2, j0[2]) && OwnedIndex(ix, 2, j0[2] + 1)));
    xa = PetscMax(ix->os[0] - PS_PAD, 1);
    xb = PetscMin(ix->os[0] + ix->om[0] - PS_PAD - 1, C->nc[0] - 1);
  } else {
    const PetscInt e = 3 - d; /* in 3D the index across d other than x */
    ok = j0[d] > 0 && j0[d] + 1 < C->nc[d] && OwnedIndex(ix, d, j0[d]) && OwnedIndex(ix, d, j0[d] + 1) && (dim < 3 || (OwnedIndex(ix, e, j0[e]) && OwnedIndex(ix, e, j0[e] + 1)));
    xa = ix->os[0] - PS_PAD;
    xb = ix->os[0] + ix->om[0] - PS_PAD - 1;
  }
  if (!ok || S->run.lanes == 1) xb = xa; /* (-run_lanes 1: DualFlux alone, for checks) */
  /* the fast range's dual fluxes, in SIMD lanes (a run's cells, k) */
  ka = PetscMin(PetscMax(xa - j0[0], 0), n);
  kb = PetscMin(PetscMax(xb - j0[0], ka), n);
  DualFluxLanes(dim, VL, C->nnl, mcn, &Mcell[u0], Fl, Fh, fs, ft, o0, sd, s1, s2, ka, kb, nw, W);
  /* the cells before the fast range, its dual fluxes to the nodes (all
     before its first cell's update: the update touches no node; the cells
     before it have given theirs, the cells after it give theirs after),
     then the cells after it: the order of one loop over the run's cells */
  for (k = 0; k < n; k++) {
    if (k == ka && ka < kb) {
      DualFluxNodes(dim, o0, sd, s1, s2, ka, kb, nw, W, P, K, rows);
      k = kb;
      if (k >= n) break;
    }
    {
      const PetscInt j[3] = {j0[0] + k, j0[1], j0[2]};
      DualFlux(S, ix, sw, dim, j, Fl[k + (fs - 1) * ft], Fh[k + (fs - 1) * ft], VL, P, K, rows);
    }
  }
  /* the owned cells' updates, after the run's dual fluxes (a dual flux
     reads its own cell's mass before the update alone, and the two book
     different sums): a run of cells of one gas in lanes (CellUpdateLanes),
     any other cell CellUpdate */
  if (!owned || rows == 1) return;
  for (k = PetscMax(C->cs[0] - j0[0], 0); k < n; k++) {
    const PetscInt x = j0[0] + k, ci = u0 + k;
    const PetscInt s = C->sole[ci];
    if (lanes && s >= 0) {
      /* the run: inside the domain along d (b below bmax), each cell s alone
         and each face carrying s alone; sixteen cells at a time while all
         match (a loop without an exit inside, not unrolled, which GCC
         compares in SIMD lanes: one at a time, this scan was 3% of the pure
         gas's instructions), then one at a time */
      const short   *so   = &C->sole[u0];
      const PetscInt bmax = d == 0 ? (j0[0] + k > 0 ? PetscMin(n, C->nc[0] - 1 - j0[0]) : k) : (innerd ? n : k);
      PetscInt       b    = k;
      for (; b + 16 <= bmax; b += 16)
        if (RunBreaks16(so, Rl, Rh, s, b)) break;
      if (b < bmax && b + 16 > bmax && bmax - 16 >= k && !RunBreaks16(so, Rl, Rh, s, bmax - 16)) b = bmax; /* (the last sixteen at once, as PSCellsSoleRun) */
      while (b < bmax && so[b] == s && Rl[2 * b] == s && Rl[2 * b + 1] == s + 1 && Rh[2 * b] == s && Rh[2 * b + 1] == s + 1) b++;
      if (b - k >= PS_LANES_RUN) {
        CellUpdateLanes(S, s, u0, k, b, Fl, Fh, ft, W);
        k = b - 1;
        continue;
      }
    }
    {
      const PetscInt   j[3] = {x, j0[1], j0[2]};
      const PetscReal *fl = &Fl[k], *fh = &Fh[k];
      CellUpdate(S, sw, j, ci, d == 0 ? x > 0 && x + 1 < C->nc[0] : innerd, &U[C->ms * ci], &XV[ci], fl, fh, ft, &Rl[2 * k], &Rh[2 * k]);
    }
  }
}

/* the KE fix's bounds of owned node o (sweep along the node stride sd): its
   velocity kept within the range of each component over the node and its
   neighbours along d before the sweep that had mass (VL in planes of nv,
   mco; inm, inp: the neighbours are in the local array), its momentum P cut
   to it (none on a node at or below mass_min), what is cut into dP.  Without
   a branch (every load made, every test a choice between values, computed
   before it; a divisor for every node), so a row's loop takes it in SIMD
   lanes; a neighbour out of the array is the node itself again, and one
   without mass leaves the bounds as they were: neither changes them */
static inline void KEBounds(const PetscInt dim, PetscInt sd, PetscInt o, PetscBool inm, PetscBool inp, const PetscReal *mcn, const PetscReal *mco, PetscReal mass_min, const PetscReal *VL, PetscInt nv, PetscReal *P, PetscReal *dP)
{
  const PetscInt  sm = inm ? sd : 0, sp = inp ? sd : 0, om = o - sm, op = o + sp; /* (a neighbour out of the array is the node itself again: the same bounds; sm, sp the same over a row) */
  const PetscReal mn = mcn[o], mv = mn > mass_min ? mn : 1.0;
  PetscInt        q;

#pragma GCC unroll 3
  for (q = 0; q < dim; q++) {
    const PetscReal vm = VL[q * nv + om], v0 = VL[q * nv + o], vp = VL[q * nv + op], pq = P[dim * o + q], r = pq / mv;
    PetscReal       lo = PETSC_MAX_REAL, hi = -PETSC_MAX_REAL, pn;
    PetscReal       l, h, c;
    l  = PetscMin(lo, vm);
    h  = PetscMax(hi, vm);
    lo = mco[om] > 0.0 ? l : lo;
    hi = mco[om] > 0.0 ? h : hi;
    l  = PetscMin(lo, v0);
    h  = PetscMax(hi, v0);
    lo = mco[o] > 0.0 ? l : lo;
    hi = mco[o] > 0.0 ? h : hi;
    l  = PetscMin(lo, vp);
    h  = PetscMax(hi, vp);
    lo = mco[op] > 0.0 ? l : lo;
    hi = mco[op] > 0.0 ? h : hi;
    c  = mn * PetscMin(PetscMax(r, lo), hi);
    pn = lo <= hi ? c : pq;
    pn = mn <= mass_min ? 0.0 : pn;
    dP[q]          = pq - pn;
    P[dim * o + q] = pn;
  }
}

/* the KE fix's progress through a sweep (SweepDim): on a rank whose nodes
   along x (2D; x and y in 3D) are all its own, in a sweep without a free
   face along d (its outflow books momentum into the same sums during the
   faces' pass), the KE fix of each unit of nodes (a row in 2D, a plane in
   3D) runs right behind the cells' update (KEBehind), while the unit's
   nodes are in the caches, and after the last sweep the heat of each unit
   of cells behind it; the units left (next to a rank above: its ghost
   cells and nodes; next to a rank below: the unit whose cells below are
   that rank's, and its cells) run after the halo.  Every unit and node is
   the separate passes' own; the books' sums (what is cut, the heat) run in
   the units' order, from node0 (cell0) up, then the units below them, in
   that order fused or not (so on a rank without a neighbour below, the
   units in increasing order).  Until the thirty-ninth session a rank with
   a neighbour below kept the separate passes; fused, two ranks splitting
   the 512^2 quadrants along y run 1.10x faster (docs/speed.md) */
typedef struct {
  PetscBool fused;   /* the KE fix behind the cells' update */
  PetscInt  node0;   /* the first owned unit of nodes whose cells on both sides are owned (grid index along y, z; the rank's first without a neighbour below) */
  PetscInt  cell0;   /* the first unit of owned cells whose lower corners are in unit node0 or above */
  PetscInt  node;    /* the next owned unit of nodes without its KE fix (from node0) */
  PetscInt  cell;    /* the next unit of owned cells without its heat (after the last sweep; from cell0) */
  PetscReal lost[3]; /* S->lost_local.p, the same sums in registers */
  PetscReal heat;    /* C->remap_heat, the same */
} PSKEProgress;

/* a row's values a[0 .. n) in PS_SUM_LANES partial sums, a[j] into sum j
   mod PS_SUM_LANES (a multiple of 2 and 3: with dim values per node, sum k
   holds component k mod dim), each in the row's order: the books' sums of
   a row (KEUnit's cut, HeatUnit's heat), added into them in the sums'
   order.  One sum in the row's order was a chain of additions each waiting
   for the one before (4 cycles a value) */
#define PS_SUM_LANES 12
static inline void SumLanes(const PetscReal *a, PetscInt n, PetscReal acc[PS_SUM_LANES])
{
  PetscInt j, k;
  for (k = 0; k < PS_SUM_LANES; k++) acc[k] = 0.0;
  for (j = 0; j + PS_SUM_LANES <= n; j += PS_SUM_LANES)
#pragma GCC unroll 12
    for (k = 0; k < PS_SUM_LANES; k++) acc[k] += a[j + k];
  for (k = 0; j + k < n; k++) acc[k] += a[j + k];
}

/* the KE fix of the owned nodes of unit r (grid index along y in 2D, z in
   3D), row by row: their velocity kept within the range of each component
   over the node and its neighbours along d before the sweep (VL, with the
   masses before it, mco: a node the sweep nearly empties divides a
   remainder of round-off size by a mass of round-off size; and without
   mass no momentum), what is cut booked as lost; then the boundary
   conditions (a wall takes the momentum into it).  After the last sweep,
   with it, the kinetic energy carried through the remap's sweeps minus that
   of the remapped momentum, d_i per owned node, into K (its own node's
   value is read first), as d_i / (2^dim m_i), for the cells (HeatUnit).
   (Once a step, not once a sweep: the sum over the sweeps of each one's d_i
   is this d_i, as each sweep's kinetic energy before it is the one after
   the sweep before; the heat is then not carried by the later sweeps, and
   the cells' ghosts need no exchange between sweeps) */
static inline void KEUnit(PSSolver *S, const PSIndex *ix, const PSSweepDirs *sw, const PetscInt dim, PetscBool last, PetscInt r, const PetscReal *VL, const PetscReal *mcn, const PetscReal *mco, PetscReal lost[3])
{
  PSCells        *C = S->cells;
  const PetscInt  d = sw->d, nv = C->nnl, x0 = ix->os[0], x1 = ix->os[0] + ix->om[0];
  const PetscReal mass_min = S->mass_min;
  PetscReal      *P = C->P, *K = C->sK, *dP = C->sdP;
  PetscReal       cut[3] = {lost[0], lost[1], lost[2]}; /* (the same sums, in registers: lost could alias the arrays) */
  PetscInt        i[3], x, q;

  i[0] = x0; /* (along d = x the row's own tests: KEBounds) */
  i[2] = dim == 3 ? r : 0;
  for (i[1] = dim == 3 ? ix->os[1] : r; i[1] < (dim == 3 ? ix->os[1] + ix->om[1] : r + 1); i[1]++) {
    const PetscInt orow = Lidx(ix, 0, i[1], i[2]); /* (node (x, i1, i2) is orow + x) */
    PetscInt       xa = x0, xb = x1;
    /* a row across d (d = y, z): its neighbours along d are in the local
       array or not for the whole row; along d = x only the row's first and
       last nodes can lack one, and take the test of their own (KEBounds) */
    if (d == 0) {
      xa = x0 + 1;
      xb = PetscMax(x1 - 1, xa);
      KEBounds(dim, sw->sd, orow + x0, x0 - 1 >= ix->gs[0], x0 + 1 < ix->gs[0] + ix->gm[0], mcn, mco, mass_min, VL, nv, P, &dP[0]);
      if (x1 - 1 > x0) KEBounds(dim, sw->sd, orow + x1 - 1, x1 - 2 >= ix->gs[0], x1 < ix->gs[0] + ix->gm[0], mcn, mco, mass_min, VL, nv, P, &dP[dim * (x1 - 1 - x0)]);
    }
    {
      const PetscBool inm = i[d] - 1 >= ix->gs[d] || d == 0, inp = i[d] + 1 < ix->gs[d] + ix->gm[d] || d == 0;
#pragma GCC ivdep /* (P, dP, VL, mcn and mco are apart) */
      for (x = xa; x < xb; x++) KEBounds(dim, sw->sd, orow + x, inm, inp, mcn, mco, mass_min, VL, nv, P, &dP[dim * (x - x0)]);
    }
    /* what was cut, the row's in partial sums (SumLanes) */
    {
      PetscReal acc[PS_SUM_LANES];
      PetscInt  k;
      SumLanes(dP, dim * (x1 - x0), acc);
      for (k = 0; k < PS_SUM_LANES; k++) cut[k % dim] += acc[k];
    }
    PSNodeBCRow(S, dim, orow, x0, x1, i[1], i[2], P); /* the boundary conditions */
    /* d_i / (2^dim m_i), over the row */
    if (last)
      for (x = x0; x < x1; x++) {
        const PetscInt  o  = orow + x;
        const PetscReal mn = mcn[o], mv = mn > 0.0 ? mn : 1.0; /* (a divisor for every node: the row's loop without a branch) */
        PetscReal       p2 = 0.0;
        for (q = 0; q < dim; q++) p2 += P[dim * o + q] * P[dim * o + q];
        const PetscReal dk = (K[o] - 0.5 * p2 / mv) / ((1 << dim) * mv);
        K[o]               = mn > 0.0 ? dk : 0.0;
      }
  }
  for (q = 0; q < 3; q++) lost[q] = cut[q];
}

/* after the last sweep, the heat of the owned cells of unit c (y in 2D, z in
   3D), whose corners hold d_i / (2^dim m_i) (KEUnit; the ghosts' from their
   owners): each cell takes from each corner the share M_c / (2^dim m_i) of
   d_i, the share it has in the node's mass (the sum over cells is the sum
   over nodes), and each of its materials the share M_k / M_c of that; the
   heat's sum into heat, in the cells' order.  In a scene without marker
   bodies, the cells whose materials' volume exceeds the cell's by more
   than 1e-12 of it (the fit's test, PSCellsFitMarkers: nothing between
   here and the fit changes a volume, and without markers each cell's room
   is the cell) are counted into C->over, so that the fit need not read
   the state again to find none (nearly always) */
static inline void HeatUnit(PSSolver *S, const PSIndex *ix, const PetscInt dim, PetscInt c, PetscReal *heat_sum)
{
  PSCells         *C = S->cells;
  const PetscInt   mst = C->mst, ms = C->ms, nm = C->nmat;
  const PetscBool  lanes = ms == PS_CQ && S->run.lanes != 1 ? PETSC_TRUE : PETSC_FALSE; /* (gas blocks) */
  const PetscReal *Mcell = C->Mcell, *K = C->sK; /* after the sweep (CellUpdate; PSCellsNodalMassUnits for the ghosts) */
  const short     *sole = C->sole;
  PetscReal       *U = C->u, heat = *heat_sum; /* (the same sum, in a register) */
  const PetscReal  Vc = C->Vc; /* (the fit's test, without markers: the room is Vc 1.0, as the fit computes it) */
  PetscInt         off[8], i[3], a, m, over = 0;

  for (a = 0; a < (1 << dim); a++) off[a] = C->K.off[a];
  i[2] = dim == 3 ? c : 0;
  for (i[1] = dim == 3 ? C->cs[1] : c; i[1] < (dim == 3 ? C->ce[1] : c + 1); i[1]++) {
    PetscInt   ci0, o00;
    PetscReal *H = C->sW - C->cs[0]; /* (each cell's heat along the row, H[i], summed after it) */
    PSCellsRow(C, ix, dim, i[1], i[2], &ci0, &o00, NULL, NULL); /* (cell x: ci0 + x, its lower corner node o00 + x) */
    for (i[0] = C->cs[0]; i[0] < C->ce[0]; i[0]++) {
      const PetscInt ci = ci0 + i[0], o0 = o00 + i[0];
      PetscReal     *u = &U[ms * ci], Mc = Mcell[ci], dE = 0.0;
      PetscInt       m0, m1, b;
      /* a run of cells of one gas s (with mass: M_c = M_s): their heat in
         SIMD lanes */
      if (lanes && sole[ci] >= 0) {
        const PetscInt s = sole[ci];
        b = i[0] + PSCellsSoleRun(&sole[ci], C->ce[0] - i[0]);
        if (b - i[0] >= PS_LANES_RUN) {
          const PetscInt   len = b - i[0];
          PetscReal       *B   = &U[PS_CQ * ci + s * mst], *W = &H[i[0]];
          const PetscReal *Mr  = &Mcell[ci], *Kr = &K[o0];
          PetscInt         x;
#pragma GCC ivdep
          for (x = 0; x < len; x++) {
            PetscReal dEx = 0.0;
#pragma GCC unroll 8
            for (a = 0; a < (1 << dim); a++) dEx += Kr[x + off[a]];
            B[PS_CQ * x + PS_CE] = B[PS_CQ * x + PS_CE] + dEx * B[PS_CQ * x + PS_CM];
            W[x]                 = dEx * Mr[x];
            over += PSCellsOverRoom(0.0 + B[PS_CQ * x + PS_CV], Vc * 1.0, Vc); /* (s has mass: it is the cell's sole; the fit's lanes' test) */
          }
          i[0] = b - 1;
          continue;
        }
      }
      H[i[0]] = 0.0;
      if (Mc <= 0.0) continue;
      /* (a node without mass holds d_i = 0: above, and its owner's value
         on the ghosts) */
      for (a = 0; a < (1 << dim); a++) dE += K[o0 + off[a]]; /* per unit of the cell's mass */
      PSCellsSoleRange(sole[ci], nm, &m0, &m1); /* the materials present, as found after the sweep (PSCellsPresent) */
      for (m = m0; m < m1; m++) u[m * mst + PS_CE] += dE * u[m * mst + PS_CM];
      H[i[0]] = dE * Mc;
      over += PSCellsOverRoom(PSCellsVolumeWithMass(C, u, m0, m1), Vc * 1.0, Vc); /* (the fit's test of one cell) */
    }
    /* the row's heat into the books, in partial sums (SumLanes), the
       same with -run_lanes 1 */
    {
      PetscReal acc[PS_SUM_LANES];
      PetscInt  k;
      SumLanes(C->sW, C->ce[0] - C->cs[0], acc);
      for (k = 0; k < PS_SUM_LANES; k++) heat += acc[k];
    }
  }
  *heat_sum = heat;
  if (C->over >= 0) C->over += over;
}

/* the KE fix behind the cells' update (PSKEProgress), once the cells of
   unit c (y in 2D, z in 3D) have theirs: the owned units of nodes through
   c + PS_PAD, whose cells (units n - PS_PAD - 1 and n - PS_PAD) have all
   given their dual fluxes and have their new masses, take their new nodal
   masses (into mco, swapped in after the sweep) and their KE fix; after the
   last sweep, the units of cells whose upper corners have theirs (a unit
   past the nodes' is read by no face left) take their heat.  In 2D the rows
   of nodes go in batches of PS_KE_BATCH: one at a time, the short runs over
   the nodes' arrays took the 256^2 quadrants 3% longer than the separate
   passes (docs/speed.md) */
#define PS_KE_BATCH 8
static inline PetscErrorCode KEBehind(PSSolver *S, const PSIndex *ix, const PSSweepDirs *sw, const PetscInt dim, PetscBool last, PetscInt c, const PetscReal *VL, PSKEProgress *kp)
{
  PSCells       *C = S->cells;
  const PetscInt e = dim - 1, nl = PetscMin(c + PS_PAD, ix->os[e] + ix->om[e] - 1);

  PetscFunctionBeginUser;
  if (!kp->fused || nl - kp->node + 1 < (dim == 2 ? PS_KE_BATCH : 1)) PetscFunctionReturn(PETSC_SUCCESS); /* (the units left after the faces: below) */
  PetscCall(PetscLogEventBegin(EV_KEBehind, 0, 0, 0, 0));
  for (; kp->node <= nl; kp->node++) {
    PetscCall(PSCellsNodalMassGather(S, ix, C->mco, kp->node, kp->node + 1));
    KEUnit(S, ix, sw, dim, last, kp->node, VL, C->mco, C->mcn, kp->lost);
  }
  if (last)
    for (; kp->cell < C->ce[e] && kp->cell + PS_PAD + 1 < kp->node; kp->cell++) HeatUnit(S, ix, dim, kp->cell, &kp->heat);
  PetscCall(PetscLogEventEnd(EV_KEBehind, 0, 0, 0, 0));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* A sweep's progress through its units: the outer loop's index (a row of
   cells j along y for d = x in 2D, the slice lead along y for d = y in 2D,
   the plane along z in 3D: j[2] for d = x, i[2] for d = y, the slice lead
   for d = z), so the remap's first sweep can run behind the Lagrangian
   phase a unit at a time (PSCellsRemapBehind) and the rest after it (the
   other sweeps: all their units at once).  The remap's books of the step
   (lost: mass, momentum, energies through free faces and discards) are
   summed apart from the rest of the step's, from zero, and added to
   S->lost_local at the remap's end (PSCellsRemap), so their order is the
   same whether the first sweep runs behind the Lagrangian phase (whose
   closure books into the same totals) or not */
typedef struct PSSweepProgress_ {
  PetscBool    on;      /* a sweep begun and not ended */
  PetscBool    behind;  /* this step's first sweep runs behind the Lagrangian phase */
  PetscInt     d;       /* the sweep's direction */
  PetscBool    first, last;
  PetscBool    lanes;   /* FractionsRun's gas blocks */
  PetscInt     nw;      /* the lanes' scratch C->sW: planes of nw */
  PetscInt     ft;      /* the flux records' planes in C->sF: ft apart (a line's faces along x, a slice's across) */
  PetscInt     lo[3], hi[3], ns;
  PetscInt     u, u1;   /* the outer loop's next unit, its end */
  PetscInt     nprep;   /* the local nodes [0, nprep) have their VL (and K in the first sweep) */
  PetscReal   *VL;      /* the nodes' velocities before the sweep (C->sVL, or C->sVR behind) */
  PSSweepDirs  sw;
  PSKEProgress kp;
  PSFractions  fr;
  PSTotals     lost;    /* the remap's books this step (swapped with S->lost_local while it runs) */
  PetscInt     ud;      /* PSDeferred: the first unit of cells the sweep takes before the halo, or -1 */
  PetscBool    early;   /* PSDeferred: the units from ud on run (before the halo); PETSC_FALSE: those below (after it) */
  PetscBool    saved;   /* PSDeferred: unit ud's fractions and per-cell values before the sweep kept */
  PetscInt     rj[3], rn; /* PSDeferred: unit ud's run of cells (its dual fluxes to its lower row of nodes come after the units below) */
  struct PSDeferred_ {
    PetscReal *A, *S, *P, *M; /* unit ud's fractions' planes and per-cell values (FractionsUnits's ring slots) */
    PetscReal *Mc;            /* unit ud's run's cells' masses before the sweep */
    PetscReal *Fl, *Fh;       /* its faces' records (plane fs - 1, the mass fluxes, alone; along x Fh = Fl + 1) */
    PetscReal *F;             /* along y the face slices ud - 1 and ud's records */
    PetscInt  *R;             /* and their material ranges */
  } def;                      /* PSDeferred: what the early units keep for the others (in C->sD, C->sDR: DeferredArrays) */
} PSSweepProgress;
typedef struct PSDeferred_ PSDeferred;

/* The remap's first sweep behind the Lagrangian phase on a rank with a
   neighbour below (2D, ranks along y: PSCellsRemapBehindOK).  Its lowest
   units read ghost cells, which come with the remap's halo after the
   Lagrangian phase; and the cells and nodes the rank below takes as its
   ghosts (the owned rows cs .. cs + 2, the owned nodes' lowest two rows)
   must go to it as the Lagrangian phase left them.  So the sweep takes the
   units of cells from ud = cs + 3 up behind the Lagrangian phase (early),
   and the units below after the halo: the cells' fractions and per-cell
   values of those units built again from the state the halo brought,
   unit ud's as they were before the sweep (kept when the early units built
   them: the early units have updated its cells since); along y the
   faces of slices ud - 1 and ud, taken early (their donors' neighbours
   are owned cells, and the faces of slice ud - 1 read the cells of unit ud
   as the sweep found them) and kept for the cells of slices ud - 2 and
   ud - 1.  Every cell, face and value is the one the sweep computes in
   order on one rank.
   The nodes: row n (grid index along y) takes the dual fluxes of the cells
   of rows n - 1 - PS_PAD (its upper row) and n - PS_PAD (its lower row), in
   that order; the early unit ud's dual fluxes to its lower row (n = ud +
   PS_PAD) wait until the units below have given theirs (CellRun's rows),
   and are then computed again from what they read (the unit's cells'
   masses before the sweep and the faces' mass fluxes, kept), so every sum
   is taken in the one-rank order.  The KE fix takes the nodes from that
   row up after the halo (kp->node0).  The rank below needs nothing of the
   kind: its units next to its neighbour above wait for the halo as on one
   rank the box's last ones wait for the Lagrangian phase (RemapBehindDim's
   bound keeps them, and its nodes the rank above reads, untouched).  The
   kept values: sp->def, in C->sD (and C->sDR).  ud - cs is the ghost rows'
   count (PS_CELL_GHOST), and a rank takes it with 2 PS_CELL_GHOST + 2 rows
   or more (PSCellsRemapBehindOK: units before the halo between those next
   to either neighbour) */

/* PSDeferred's arrays (sp->def) in C->sD and C->sDR, grown where this
   sweep needs more (SweepBegin) */
static PetscErrorCode DeferredArrays(PSCells *C, PSSweepProgress *sp)
{
  PSDeferred    *b = &sp->def;
  const PetscInt e = C->dim - 1, fs = C->nmat * C->ms + 2, ce = C->cst[e];
  const PetscInt nA = (sp->fr.np - 1) * sp->fr.s[e], nS = (C->ms - 1) * ce, nF = fs * sp->ft + 1;
  const PetscInt n = nA + nS + 3 * ce + 2 * nF + 2 * fs * sp->ft, nr = 4 * sp->ns;

  PetscFunctionBeginUser;
  if (n > C->nsD) {
    PetscCall(PetscFree(C->sD));
    PetscCall(PetscMalloc1(n, &C->sD));
    C->nsD = n;
  }
  if (nr > C->nsDR) {
    PetscCall(PetscFree(C->sDR));
    PetscCall(PetscMalloc1(nr, &C->sDR));
    C->nsDR = nr;
  }
  b->A  = C->sD;
  b->S  = b->A + nA;
  b->P  = b->S + nS;
  b->M  = b->P + ce;
  b->Mc = b->M + ce;
  b->Fl = b->Mc + ce;
  b->Fh = b->Fl + nF;
  b->F  = b->Fh + nF;
  b->R  = C->sDR;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* unit ud's fractions' planes and per-cell values (its slots in the rings,
   FractionsUnits) kept, or put back (and their copies after the rings'
   ends: RingRepeat) */
static PetscErrorCode DeferredUnit(PSCells *C, PSFractions *fr, const PSDeferred *b, PetscInt ud, PetscBool restore)
{
  const PetscInt e = C->dim - 1, ce = C->cst[e], ms = C->ms, se = fr->s[e], slot = (ud - fr->o[e]) % PS_RING, gslot = (ud - C->gs[e]) % PS_RING;
  PetscReal     *S = &C->sS[(ms - 1) * gslot * ce], *P = &C->sP[gslot * ce], *M = &C->sM[gslot * ce];
  PetscInt       m;

  PetscFunctionBeginUser;
  for (m = fr->mk ? 0 : 1; m < fr->np - 1; m++) {
    PetscReal *a = &fr->A[m * fr->ps + slot * se];
    if (restore) {
      PetscCall(PetscArraycpy(a, &b->A[m * se], se));
      RingRepeat(&fr->A[m * fr->ps], slot, se);
    } else PetscCall(PetscArraycpy(&b->A[m * se], a, se));
  }
  if (restore) {
    PetscCall(PetscArraycpy(S, b->S, (ms - 1) * ce));
    PetscCall(PetscArraycpy(P, b->P, ce));
    PetscCall(PetscArraycpy(M, b->M, ce));
    RingRepeat(C->sP, gslot, ce);
    RingRepeat(C->sM, gslot, ce);
    RingRepeat(C->sS, gslot, (ms - 1) * ce);
  } else {
    PetscCall(PetscArraycpy(b->S, S, (ms - 1) * ce));
    PetscCall(PetscArraycpy(b->P, P, ce));
    PetscCall(PetscArraycpy(b->M, M, ce));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* the early unit ud's run of cells j0, n (its faces' records Fl, Fh,
   planes ft apart) before CellRun updates them: what its dual fluxes to
   its lower row of nodes read (the cells' masses, the faces' mass fluxes) */
static PetscErrorCode DeferredRunKeep(PSSolver *S, PSSweepProgress *sp, const PetscInt j0[3], PetscInt n, const PetscReal *Fl, const PetscReal *Fh)
{
  PSCells          *C  = S->cells;
  const PetscInt    fs = C->nmat * C->ms + 2, ft = sp->ft, q = (fs - 1) * ft;
  const PSDeferred *b  = &sp->def;

  PetscFunctionBeginUser;
  PetscCall(PetscArraycpy(b->Mc, &C->Mcell[PSCellIdx(C, j0[0], j0[1], j0[2])], n));
  PetscCall(PetscArraycpy(&b->Fl[q], &Fl[q], n + (sp->d == 0 ? 1 : 0))); /* (along x Fh is Fl + 1) */
  if (sp->d != 0) PetscCall(PetscArraycpy(&b->Fh[q], &Fh[q], n));
  sp->rj[0] = j0[0];
  sp->rj[1] = j0[1];
  sp->rj[2] = j0[2];
  sp->rn    = n;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* the remap's books in S->lost_local while it runs, the rest of the step's
   kept aside (and back) */
static inline void BooksSwap(PSSolver *S, PSSweepProgress *sp)
{
  const PSTotals t = S->lost_local;
  S->lost_local    = sp->lost;
  sp->lost         = t;
}

/* the nodal velocities of the local nodes [e0, e1) before the sweep (VL,
   in dim planes of nnl: component q of node e at VL[q nnl + e], so a run of
   cells or nodes loads its velocities in SIMD lanes: DualFluxLanes,
   KEBounds), and in the first sweep their kinetic energies (K): the same
   fluxes carry them through every sweep, and the KE fix compares them with
   the remapped momentum's once, after the last */
static inline void PrepNodes(PSCells *C, const PetscInt dim, PetscBool first, PetscReal *VL, PetscInt e0, PetscInt e1)
{
  const PetscReal *mcn = C->mcn, *P = C->P;
  PetscReal       *K  = C->sK;
  const PetscInt   nv = C->nnl;
  PetscInt         e, q;
#pragma GCC ivdep
  for (e = e0; e < e1; e++) {
    const PetscReal im = mcn[e] > 0.0 ? 1.0 / mcn[e] : 0.0;
    PetscReal       p2 = 0.0;
#pragma GCC unroll 3
    for (q = 0; q < dim; q++) {
      VL[q * nv + e] = P[dim * e + q] * im;
      p2 += P[dim * e + q] * P[dim * e + q];
    }
    if (first) K[e] = 0.5 * p2 * im; /* (a test of the loop's invariant: GCC makes two loops of it) */
  }
}

/* a sweep along d begun: its directions, the KE fix's progress, the faces'
   box and scratch, the fractions' box; the nodal velocities (PrepNodes) of
   every local node unless it runs behind the Lagrangian phase (then a unit
   of nodes at a time, as the phase gives them their momentum) */
static inline PetscErrorCode SweepBegin(PSSolver *S, const PSIndex *ix, PSSweepProgress *sp, PetscInt d, PetscBool first, PetscBool last, const PetscInt dim)
{
  PSCells       *C  = S->cells;
  const PetscInt fs = C->nmat * C->ms + 2;
  PetscInt       e, q;

  PetscFunctionBeginUser;
  sp->on    = PETSC_TRUE;
  sp->d     = d;
  sp->first = first;
  sp->last  = last;
  sp->lanes = C->ms == PS_CQ && S->run.lanes != 1 ? PETSC_TRUE : PETSC_FALSE; /* (FractionsRun: gas blocks) */
  sp->nw    = PSCellsPlaneLen(C, ix);
  SweepDirs(C, ix, dim, d, &sp->sw);
  /* the first sweep behind the Lagrangian phase on a rank with a neighbour
     below: its units from ud up before the halo, the others after it
     (PSDeferred) */
  sp->ud    = sp->behind && first && dim == 2 && ix->gs[dim - 1] < ix->os[dim - 1] ? C->cs[dim - 1] + PS_CELL_GHOST : -1;
  sp->early = sp->ud >= 0 ? PETSC_TRUE : PETSC_FALSE;
  sp->saved = PETSC_FALSE;
  /* the KE fix behind the cells' update, where it can (PSKEProgress);
   -run_lanes 1 keeps it to its own pass, for checks */
  {
    PSKEProgress  *kp = &sp->kp;
    const PetscInt e0 = dim - 1, nend = ix->os[e0] + ix->om[e0];
    kp->fused = S->run.lanes != 1 && PSCellsWholeAcross(ix, dim) && S->bc[d][0] != PS_BC_FREE && S->bc[d][1] != PS_BC_FREE ? PETSC_TRUE : PETSC_FALSE;
    /* on a rank with a neighbour below, the units of nodes from the first
       whose cells on both sides are owned (physical node n - PS_PAD has
       cells n - PS_PAD - 1 and n - PS_PAD), and the cells whose corners are
       among them; the units below them (their cells' ghosts) come after the
       halo, after the others (in that order fused or not: the books' sums
       the same both ways) */
    kp->node0 = ix->gs[e0] < ix->os[e0] ? PetscMin(PetscMax(ix->os[e0], C->cs[e0] + PS_PAD + 1), nend) : ix->os[e0];
    if (sp->ud >= 0) kp->node0 = PetscMin(PetscMax(kp->node0, sp->ud + PS_PAD + 1), nend); /* (PSDeferred: the early unit's lower row of nodes and those below after the halo) */
    kp->cell0 = ix->gs[e0] < ix->os[e0] ? PetscMin(PetscMax(C->cs[e0], kp->node0 - PS_PAD), C->ce[e0]) : C->cs[e0];
    kp->node  = kp->node0;
    kp->cell  = kp->cell0;
    for (q = 0; q < 3; q++) kp->lost[q] = S->lost_local.p[q]; /* (no outflow where fused: read now or after the faces, the same) */
    kp->heat = C->remap_heat;
  }
  if (last) C->over = !C->markers && S->run.lanes != 1 ? 0 : -1; /* (HeatUnit; -run_lanes 1: the fit's own pass, for checks) */
  /* faces along d of the cells around the owned nodes, [cs - 1, ce) in every
     direction (clipped to the domain), one more along d */
  for (e = 0; e < 3; e++) {
    sp->lo[e] = e < dim ? PetscMax(C->cs[e] - 1, 0) : 0;
    sp->hi[e] = e < dim ? C->ce[e] : 1;
  }
  sp->hi[d] += 1;
  for (e = 0, sp->ns = 1; e < d; e++) sp->ns *= sp->hi[e] - sp->lo[e]; /* faces in a slice (SweepUnit) */
  /* the outer loop's units (SweepUnit) */
  if (d == dim - 1) {
    sp->u  = sp->lo[d];
    sp->u1 = sp->hi[d] + 2;
  } else {
    sp->u  = sp->lo[dim - 1];
    sp->u1 = sp->hi[dim - 1];
  }
  if (sp->ud >= 0) sp->u = d == dim - 1 ? sp->ud - 1 : sp->ud; /* (PSDeferred: the early units; along y from the faces of slice ud - 1) */
  PetscCall(PetscLogEventBegin(EV_Prep, 0, 0, 0, 0));
  sp->ft = PSCellsPadPlane(d == 0 ? sp->hi[0] - sp->lo[0] : sp->ns); /* (the flux records' planes: PSCellsPadPlane) */
  PetscCall(ScratchSize(C, d == 0 ? sp->ft : 3 * sp->ft, fs)); /* a line's faces along x, or three slices' */
  PetscCall(FractionsSetup(C, &sp->fr));
  if (sp->ud >= 0) PetscCall(DeferredArrays(C, sp)); /* (here, once the sweep's sizes are known) */
  sp->nprep = 0;
  if (!sp->behind) {
    PrepNodes(C, dim, first, sp->VL, 0, C->nnl);
    sp->nprep = C->nnl;
  }
  PetscCall(PetscLogEventEnd(EV_Prep, 0, 0, 0, 0));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* one unit of the sweep's outer loop (sp->u).  Faces, the momentum's dual
   fluxes and the cells' update, slice by slice along d (a slice: the faces
   or cells with one index i_d), within each line or plane across d in the
   order of the cell array (z, y, x): the faces of slice s read the cells of
   slices s - 2 .. s + 1 (donor and its neighbours along d), so the cells of
   slice c take their update once the faces of slice c + 2 are done, and
   three slices of faces in a ring are all the sweep keeps.  Each cell's
   arithmetic, and the order of every sum (the nodes' momentum, the books),
   is that of separate passes over all faces, then all cells.  The
   fractions and per-cell values of the cells before the sweep
   (FractionsUpTo), a row (2D) or plane (3D) of the box at a time, one ahead
   of the faces that read them: they are read while still in the caches (a
   separate pass over the box before the faces wrote them all to memory and
   read them back, 8 of the 512^2 quadrants' 150 ns per cell-update), and
   each unit is built before the sweep updates its cells */
static inline PetscErrorCode SweepUnit(PSSolver *S, const PSIndex *ix, PSSweepProgress *sp, PetscReal dt, const PetscInt dim)
{
  PSCells           *C = S->cells;
  const PetscInt     d = sp->d, fs = C->nmat * C->ms + 2, ns = sp->ns, ft = sp->ft, *lo = sp->lo, *hi = sp->hi, U = sp->u, ud = sp->ud;
  const PSSweepDirs *sw = &sp->sw;
  PSFractions       *fr = &sp->fr;
  PetscReal         *F = C->sF, *K = C->sK, *VL = sp->VL, *P = C->P;
  PetscInt          *R = C->sR;

  PetscFunctionBeginUser;
  /* (PSDeferred: unit ud's fractions and per-cell values kept before the
     early units update its cells) */
  if (ud >= 0 && sp->early && !sp->saved) {
    FractionsUpTo(C, fr, d, sp->lanes, sp->nw, C->sW, ud);
    PetscCall(DeferredUnit(C, fr, &sp->def, ud, PETSC_FALSE));
    sp->saved = PETSC_TRUE;
  }
  if (d == 0) {
    /* along x a slice is one face: line by line instead, all its faces (they
       read the cells before the sweep only), then its cells in order: the
       same arithmetic and sums, in the same order, as the slices' ring below
       (the unit: the row U in 2D, the plane U in 3D) */
    const PetscInt nf = hi[0] - lo[0];
    PetscInt       j[3];
    j[2] = dim == 3 ? U : 0;
    for (j[1] = dim == 3 ? lo[1] : U; j[1] < (dim == 3 ? hi[1] : U + 1); j[1]++) {
      const PetscBool first = ud >= 0 && sp->early && U == ud; /* (PSDeferred: its lower row's dual fluxes later) */
      j[0] = lo[0];
      FractionsUpTo(C, fr, d, sp->lanes, sp->nw, C->sW, U + 1);
      FaceRun(S, ix, fr, dt, sw, dim, j, nf, F, ft, R);
      if (first) PetscCall(DeferredRunKeep(S, sp, j, nf - 1, F, &F[1]));
      CellRun(S, ix, sw, dim, j, nf - 1, F, &F[1], ft, R, &R[2], VL, P, K, first ? 2 : 3);
    }
    PetscCall(KEBehind(S, ix, sw, dim, sp->last, U, VL, &sp->kp)); /* (the row or plane of cells U done) */
  } else {
    /* the slices along d: one pass of them per plane U (d = y in 3D), or
       the slice U (d = y in 2D, d = z).  PSDeferred: the early units from
       the faces of slice ud - 1 and the cells of slice ud on, the faces of
       slices ud - 1 and ud kept; the units below after the halo, through
       the cells of slice ud - 1 (those faces put back) */
    const PetscInt l0 = d == dim - 1 ? U : lo[d], l1 = d == dim - 1 ? U + 1 : hi[d] + 2;
    PetscInt       lead, c;
    for (lead = l0; lead < l1; lead++) {
      const PetscBool faces = ud < 0 || (sp->early ? lead >= ud - 1 : lead < ud - 1);
      /* the faces of slice lead */
      if (lead < hi[d] && faces) {
        FractionsUpTo(C, fr, d, sp->lanes, sp->nw, C->sW, (dim == 3 && d == 1 ? U : lead) + 1);
        PetscReal *Fs = &F[(lead % 3) * ft * fs];
        PetscInt  *Rs = &R[(lead % 3) * ns * 2];
        PetscInt   j[3] = {0, 0, dim == 3 && d == 1 ? U : 0}, jl[2], jh[2], n = 0;
        j[d] = lead;
        SliceRange(d, lo, hi, j, jl, jh);
        for (j[1] = jl[1]; j[1] < jh[1]; j[1]++, n += jh[0] - jl[0]) {
          j[0] = jl[0];
          FaceRun(S, ix, fr, dt, sw, dim, j, jh[0] - jl[0], &Fs[n], ft, &Rs[2 * n]);
        }
        if (ud >= 0 && (lead == ud - 1 || lead == ud)) { /* (kept: the cells of slices ud - 2 and ud - 1 read them after the halo) */
          PetscCall(PetscArraycpy(&sp->def.F[(lead - ud + 1) * ft * fs], Fs, ft * fs));
          PetscCall(PetscArraycpy(&sp->def.R[(lead - ud + 1) * ns * 2], Rs, 2 * ns));
        }
      } else if (ud >= 0 && !sp->early && (lead == ud - 1 || lead == ud)) {
        PetscCall(PetscArraycpy(&F[(lead % 3) * ft * fs], &sp->def.F[(lead - ud + 1) * ft * fs], ft * fs));
        PetscCall(PetscArraycpy(&R[(lead % 3) * ns * 2], &sp->def.R[(lead - ud + 1) * ns * 2], 2 * ns));
      }
      /* the cells of slice c = lead - 2, between faces c and c + 1 */
      c = lead - 2;
      if (c >= lo[d] && c < hi[d] - 1 && (ud < 0 || (sp->early ? c >= ud : c < ud))) {
        const PetscReal *Fl = &F[(c % 3) * ft * fs], *Fh = &F[((c + 1) % 3) * ft * fs];
        const PetscInt  *Rl = &R[(c % 3) * ns * 2], *Rh = &R[((c + 1) % 3) * ns * 2];
        const PetscBool  first = ud >= 0 && sp->early && c == ud; /* (PSDeferred: its lower row's dual fluxes later) */
        PetscInt         j[3] = {0, 0, dim == 3 && d == 1 ? U : 0}, jl[2], jh[2], n = 0;
        j[d] = c;
        SliceRange(d, lo, hi, j, jl, jh);
        for (j[1] = jl[1]; j[1] < jh[1]; j[1]++, n += jh[0] - jl[0]) {
          j[0] = jl[0];
          if (first) PetscCall(DeferredRunKeep(S, sp, j, jh[0] - jl[0], &Fl[n], &Fh[n]));
          CellRun(S, ix, sw, dim, j, jh[0] - jl[0], &Fl[n], &Fh[n], ft, &Rl[2 * n], &Rh[2 * n], VL, P, K, first ? 2 : 3);
        }
        if (d == dim - 1) PetscCall(KEBehind(S, ix, sw, dim, sp->last, c, VL, &sp->kp)); /* (the slice c: a unit) */
      }
    }
    if (dim == 3 && d == 1) PetscCall(KEBehind(S, ix, sw, dim, sp->last, U, VL, &sp->kp)); /* (the plane U) */
  }
  sp->u++;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* PSDeferred's units after the halo: the units of cells below ud (their
   fractions and per-cell values built again, unit ud's put back), then the
   early unit ud's dual fluxes to its lower row of nodes, from what they read
   (its cells' masses before the sweep put back for them, and taken away
   again after).  Then the sweep is whole: its box's fractions built (none
   is read again) */
static inline PetscErrorCode DeferredUnits(PSSolver *S, const PSIndex *ix, PSSweepProgress *sp, PetscReal dt, const PetscInt dim)
{
  PSCells          *C = S->cells;
  const PetscInt    e = dim - 1, ud = sp->ud, u1 = sp->u1, n = sp->rn;
  PSFractions      *fr = &sp->fr;
  const PSDeferred *b  = &sp->def;
  PetscReal        *Mc;

  PetscFunctionBeginUser;
  sp->early = PETSC_FALSE;
  fr->built = 0;
  FractionsUpTo(C, fr, sp->d, sp->lanes, sp->nw, C->sW, ud - 1);
  PetscCall(DeferredUnit(C, fr, b, ud, PETSC_TRUE));
  fr->built = ud - fr->o[e] + 1;
  for (sp->u = sp->lo[e]; sp->u < (sp->d == e ? ud + 2 : ud);) PetscCall(SweepUnit(S, ix, sp, dt, dim));
  /* unit ud's dual fluxes to its lower row of nodes */
  Mc = &C->Mcell[PSCellIdx(C, sp->rj[0], sp->rj[1], sp->rj[2])];
  PetscCall(PetscArraycpy(b->F, Mc, n)); /* (the cells' masses after the sweep, aside in b->F: no longer read) */
  PetscCall(PetscArraycpy(Mc, b->Mc, n));
  CellRun(S, ix, &sp->sw, dim, sp->rj, n, b->Fl, sp->d == 0 ? &b->Fl[1] : b->Fh, sp->ft, NULL, NULL, sp->VL, C->P, C->sK, 1);
  PetscCall(PetscArraycpy(Mc, b->F, n));
  fr->built = fr->n[e];
  sp->u     = u1;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* the sweep's end: the box's fractions whole (as every sweep leaves it),
   the cells' new state to the ghosts, the new nodal masses, the KE fix of
   the units not done behind the cells, and after the last sweep the heat */
static inline PetscErrorCode SweepEnd(PSSolver *S, const PSIndex *ix, PSSweepProgress *sp, const PetscInt dim)
{
  PSCells           *C = S->cells;
  const PSSweepDirs *sw = &sp->sw;
  PSKEProgress      *kp = &sp->kp;
  const PetscReal   *VL = sp->VL;
  PetscInt           q, r, c;

  PetscFunctionBeginUser;
  FractionsUpTo(C, &sp->fr, sp->d, sp->lanes, sp->nw, C->sW, sp->fr.o[dim - 1] + sp->fr.n[dim - 1]); /* (the rest: the box whole) */
  PetscCall(PetscLogEventEnd(EV_Flux, 0, 0, 0, 0));
  /* the cells' new state to the ghosts; the new nodal masses into mcn, the
     ones before the sweep kept in mco (the velocity bounds below) */
  PetscCall(PetscLogEventBegin(EV_Halo, 0, 0, 0, 0));
  PetscCall(PSCellsExchange(C));
  {
    PetscReal *t = C->mco;
    C->mco = C->mcn;
    C->mcn = t;
  }
  /* the owned cells' masses: CellUpdate; every local node's m^C_i but the
     units' the KE fix behind the cells has summed, [node0, node): those
     above them, then those below (next to a rank below) */
  PetscCall(PSCellsNodalMassUnits(S, ix, PETSC_TRUE, kp->fused ? kp->node : PETSC_MIN_INT, PETSC_MAX_INT));
  if (kp->fused && kp->node0 > ix->os[dim - 1]) PetscCall(PSCellsNodalMassGather(S, ix, C->mcn, PETSC_MIN_INT, kp->node0)); /* (the units below the fused ones) */
  PetscCall(PetscLogEventEnd(EV_Halo, 0, 0, 0, 0));
  PetscCall(PetscLogEventBegin(EV_KE, 0, 0, 0, 0));
  /* the KE fix of the owned units of nodes not done behind the cells
     (KEUnit), in the same order, the sums continued */
  if (!kp->fused)
    for (q = 0; q < 3; q++) kp->lost[q] = S->lost_local.p[q]; /* (after the faces' outflow) */
  for (r = kp->node; r < ix->os[dim - 1] + ix->om[dim - 1]; r++) KEUnit(S, ix, sw, dim, sp->last, r, VL, C->mcn, C->mco, kp->lost);
  for (r = ix->os[dim - 1]; r < kp->node0; r++) KEUnit(S, ix, sw, dim, sp->last, r, VL, C->mcn, C->mco, kp->lost); /* (next to a rank below) */
  for (q = 0; q < 3; q++) S->lost_local.p[q] = kp->lost[q];
  PetscCall(PSHaloBcast(C->sfp, C->P));
  /* after the last sweep, d_i to the ghosts; then the heat of the owned
     cells not done behind the KE fix (HeatUnit), in the same order */
  if (sp->last) {
    PetscCall(PSHaloBcast(C->sfk, C->sK));
    for (c = kp->cell; c < C->ce[dim - 1]; c++) HeatUnit(S, ix, dim, c, &kp->heat);
    for (c = C->cs[dim - 1]; c < kp->cell0; c++) HeatUnit(S, ix, dim, c, &kp->heat); /* (next to a rank below) */
    C->remap_heat = kp->heat;
  }
  PetscCall(PetscLogEventEnd(EV_KE, 0, 0, 0, 0));
  sp->on = PETSC_FALSE;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* the sweep's units from sp->u on, then its end; dim a constant where it
   is called (Sweep picks 2D or 3D), so the loops over a face's corners and
   a node's components unroll */
static inline PetscErrorCode SweepRest(PSSolver *S, const PSIndex *ix, PSSweepProgress *sp, PetscReal dt, const PetscInt dim)
{
  PetscFunctionBeginUser;
  if (sp->nprep < S->cells->nnl) { /* (the nodes the Lagrangian phase gave their momentum after the units behind it) */
    PetscCall(PetscLogEventBegin(EV_Prep, 0, 0, 0, 0));
    PrepNodes(S->cells, dim, sp->first, sp->VL, sp->nprep, S->cells->nnl);
    sp->nprep = S->cells->nnl;
    PetscCall(PetscLogEventEnd(EV_Prep, 0, 0, 0, 0));
  }
  PetscCall(PetscLogEventBegin(EV_Flux, 0, 0, 0, 0));
  while (sp->u < sp->u1) PetscCall(SweepUnit(S, ix, sp, dt, dim));
  if (sp->ud >= 0 && sp->early) PetscCall(DeferredUnits(S, ix, sp, dt, dim)); /* (the units below the early ones, after the halo) */
  PetscCall(SweepEnd(S, ix, sp, dim)); /* (ends EV_Flux) */
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode Sweep(PSSolver *S, const PSIndex *ix, PSSweepProgress *sp, PetscReal dt, PetscInt d, PetscBool first, PetscBool last)
{
  PetscFunctionBeginUser;
  if (!sp->on) PetscCall(SweepBegin(S, ix, sp, d, first, last, S->dim));
  if (S->dim == 2) PetscCall(SweepRest(S, ix, sp, dt, 2));
  else PetscCall(SweepRest(S, ix, sp, dt, 3));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static inline PetscErrorCode RegisterEvents(void)
{
  PetscFunctionBeginUser;
  if (!EV_Remap) {
    PetscCall(PetscLogEventRegister("PSCellsRemap", 0, &EV_Remap));
    PetscCall(PetscLogEventRegister("PSCellsPrep", 0, &EV_Prep));
    PetscCall(PetscLogEventRegister("PSCellsFlux", 0, &EV_Flux));
    PetscCall(PetscLogEventRegister("PSCellsHalo", 0, &EV_Halo));
    PetscCall(PetscLogEventRegister("PSCellsKE", 0, &EV_KE));
    PetscCall(PetscLogEventRegister("PSCellsKEBehind", 0, &EV_KEBehind)); /* (inside PSCellsFlux) */
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* the remap's progress (allocated on first use), its books zeroed for the
   step, the fractions' planes kept between steps (C->sA) */
static PetscErrorCode RemapStart(PSSolver *S, PetscBool behind)
{
  PSCells         *C = S->cells;
  PSSweepProgress *sp;

  PetscFunctionBeginUser;
  if (!C->rsp) PetscCall(PetscNew(&C->rsp));
  sp = C->rsp;
  PetscCall(PetscMemzero(&sp->fr, sizeof(sp->fr)));
  PetscCall(PetscMemzero(&sp->lost, sizeof(sp->lost)));
  sp->fr.A  = C->sA;
  sp->on    = PETSC_FALSE;
  sp->behind = behind;
  if (behind && !C->sVR) PetscCall(PetscMalloc1(C->nnl * S->dim, &C->sVR));
  sp->VL = behind ? C->sVR : C->sVL;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* whether the remap's first sweep can run behind the Lagrangian phase: a
   scene the cells' pipeline serves (PSCellsPipelined) on one rank (the
   remap's exchange of the Lagrangian state and momentum before its first
   sweep is then empty), or in 2D on ranks along y with eight rows of cells
   or more each (PSDeferred: the units next to a rank below after that
   exchange; next to a rank above they wait for it as the box's last ones
   wait for the phase) */
PetscBool PSCellsRemapBehindOK(const PSSolver *S, const PSIndex *ix)
{
  const PSCells *C = S->cells;
  PetscInt       nu = -1, np = -1;

  if (!PSCellsPipelined(S, ix)) return PETSC_FALSE;
  if (PetscSFGetGraph(C->sfu, NULL, &nu, NULL, NULL) || PetscSFGetGraph(C->sfp, NULL, &np, NULL, NULL)) return PETSC_FALSE;
  if (nu == 0 && np == 0) return PETSC_TRUE;
  /* ranks along y in 2D (PSDeferred), each with rows enough for units
     before and after the halo */
  return S->dim == 2 && C->ce[1] - C->cs[1] >= 2 * PS_CELL_GHOST + 2 ? PETSC_TRUE : PETSC_FALSE;
}

/* the remap's first sweep behind the Lagrangian phase (lagrange.c's
   pipeline, PSCellsRemapBehindOK): begun before the phase's first unit
   (PSCellsRemapBehindBegin), then after each of its units of cells
   (PSCellsRemapBehind) the nodes the phase has given their momentum P^C_i
   (C->lag.nb units) take their velocities (PrepNodes), and the sweep's
   units run while the cells they read (through the unit above:
   FractionsUpTo, the faces' donors' neighbours), with a unit to spare, have
   their Lagrangian state, short of the box's last three units
   (FractionsUpTo builds those all at once), and while the nodes they read
   (through the upper corners of the unit above) have their velocities; in
   2D once PS_BEHIND_BATCH rows can run (one at a time, the log events
   around each, which scripts/bench's phases read, were 1.5% of the 256^2
   quadrants' step).  The pipeline's event (pause) is paused while it runs,
   so the two events' times do not overlap.  The rest of the sweep runs in
   PSCellsRemap, which finds it begun */
PetscErrorCode PSCellsRemapBehindBegin(PSSolver *S, const PSIndex *ix)
{
  PSCells *C = S->cells;

  PetscFunctionBeginUser;
  PetscCall(RegisterEvents());
  PetscCall(PetscLogEventBegin(EV_Remap, 0, 0, 0, 0));
  PetscCall(RemapStart(S, PETSC_TRUE));
  BooksSwap(S, C->rsp);
  PetscCall(SweepBegin(S, ix, C->rsp, C->sweep0 == 0 ? 0 : S->dim - 1, PETSC_TRUE, PETSC_FALSE, S->dim));
  BooksSwap(S, C->rsp);
  PetscCall(PetscLogEventEnd(EV_Remap, 0, 0, 0, 0));
  PetscFunctionReturn(PETSC_SUCCESS);
}

#define PS_BEHIND_BATCH 4
static inline PetscErrorCode RemapBehindDim(PSSolver *S, const PSIndex *ix, PetscReal dt, PetscLogEvent pause, const PetscInt dim)
{
  PSCells         *C  = S->cells;
  PSSweepProgress *sp = C->rsp;
  const PetscInt   e = dim - 1, unit = dim == 3 ? ix->gm[0] * ix->gm[1] : ix->gm[0];
  const PetscInt   nodes = PetscMin(C->lag.nb * unit, C->nnl);
  PetscInt         umax = PetscMin(C->lag.next - 3, C->gs[e] + C->gm[e] - 4); /* (the last unit it may run: the phase has done the cells two units above it, and the box's last three units wait) */

  PetscFunctionBeginUser;
  umax = PetscMin(umax, nodes / unit + ix->gs[e] - PS_PAD - 3); /* (its upper corners' velocities, with a unit to spare) */
  if (umax - sp->u + 1 < (dim == 2 ? PS_BEHIND_BATCH : 1)) PetscFunctionReturn(PETSC_SUCCESS); /* (in 2D rows in batches: below) */
  PetscCall(PetscLogEventEnd(pause, 0, 0, 0, 0));
  PetscCall(PetscLogEventBegin(EV_Remap, 0, 0, 0, 0));
  BooksSwap(S, sp);
  if (nodes > sp->nprep) {
    PetscCall(PetscLogEventBegin(EV_Prep, 0, 0, 0, 0));
    PrepNodes(C, dim, sp->first, sp->VL, sp->nprep, nodes);
    sp->nprep = nodes;
    PetscCall(PetscLogEventEnd(EV_Prep, 0, 0, 0, 0));
  }
  PetscCall(PetscLogEventBegin(EV_Flux, 0, 0, 0, 0));
  while (sp->u <= umax && sp->u < sp->u1) PetscCall(SweepUnit(S, ix, sp, dt, dim));
  PetscCall(PetscLogEventEnd(EV_Flux, 0, 0, 0, 0));
  BooksSwap(S, sp);
  PetscCall(PetscLogEventEnd(EV_Remap, 0, 0, 0, 0));
  PetscCall(PetscLogEventBegin(pause, 0, 0, 0, 0));
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode PSCellsRemapBehind(PSSolver *S, const PSIndex *ix, PetscReal dt, PetscLogEvent pause)
{
  PetscFunctionBeginUser;
  if (S->dim == 2) PetscCall(RemapBehindDim(S, ix, dt, pause, 2));
  else PetscCall(RemapBehindDim(S, ix, dt, pause, 3));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* the remap: its sweeps (the first perhaps begun behind the Lagrangian
   phase), its books added to the step's */
PetscErrorCode PSCellsRemap(PSSolver *S, const PSIndex *ix, PetscReal dt)
{
  PSCells         *C = S->cells;
  PSSweepProgress *sp;
  PetscInt         s, d, q;

  PetscFunctionBeginUser;
  PetscCall(RegisterEvents());
  PetscCall(PetscLogEventBegin(EV_Remap, 0, 0, 0, 0));
  if (!C->rsp || !C->rsp->on) PetscCall(RemapStart(S, PETSC_FALSE));
  sp = C->rsp;
  BooksSwap(S, sp);
  /* ghosts of the Lagrangian state (volumes, energies) and momentum (none
     where the first sweep ran behind the Lagrangian phase on one rank:
     PSCellsRemapBehindOK) */
  PetscCall(PSCellsExchange(C));
  PetscCall(PSHaloBcast(C->sfp, C->P));
  /* where the first sweep began behind the Lagrangian phase on a rank with
     neighbours, the ghost nodes' velocities (and kinetic energies) it took
     from their momentum before their owners' came: again (PrepNodes; the
     units that read them run after the halo) */
  if (sp->on && sp->nprep > 0 && ix->gm[S->dim - 1] != ix->om[S->dim - 1]) {
    const PetscInt e = S->dim - 1, unit = S->dim == 3 ? ix->gm[0] * ix->gm[1] : ix->gm[0];
    const PetscInt lo = PetscMin((ix->os[e] - ix->gs[e]) * unit, sp->nprep), hi = (ix->os[e] + ix->om[e] - ix->gs[e]) * unit;
    PrepNodes(C, S->dim, sp->first, sp->VL, 0, lo);
    if (hi < sp->nprep) PrepNodes(C, S->dim, sp->first, sp->VL, hi, sp->nprep);
  }
  for (s = 0; s < S->dim; s++) {
    d = C->sweep0 == 0 ? s : S->dim - 1 - s;
    /* (a sweep ends with its cells' exchange; the heat of the KE fix, which
       would change the owned cells after it, comes after the last sweep
       alone: a face between two ranks is fluxed by both, each from its own
       copy of the donor, so the copies must agree) */
    PetscCall(Sweep(S, ix, sp, dt, d, s == 0 ? PETSC_TRUE : PETSC_FALSE, s == S->dim - 1 ? PETSC_TRUE : PETSC_FALSE));
  }
  C->sweep0 = 1 - C->sweep0;
  C->sA     = sp->fr.A;
  PetscCall(PSCellsExchange(C)); /* the heat of the KE fix */
  /* the remap's books into the step's */
  BooksSwap(S, sp);
  S->lost_local.mass += sp->lost.mass;
  for (q = 0; q < 3; q++) S->lost_local.p[q] += sp->lost.p[q];
  S->lost_local.kinetic += sp->lost.kinetic;
  S->lost_local.internal += sp->lost.internal;
  sp->behind = PETSC_FALSE;
  PetscCall(PetscLogEventEnd(EV_Remap, 0, 0, 0, 0));
  PetscFunctionReturn(PETSC_SUCCESS);
}
