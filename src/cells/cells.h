/*
  cells.h - Eulerian cell materials (internal): the shock-physics host around
  the markers, as in CTH.  See docs/cells.md for the method and its sources.

  State.  Cells are the elements of the node DMDA; a rank owns the cells whose
  lower corner node it owns (markers.c), and keeps them with a ghost layer of
  PS_CELL_GHOST cells in its own array (exchanged by halo.c's PetscSF).  Per
  cell and cell material k (the materials of `representation: cells` bodies,
  deck order) a block of ms reals:
      V_k  volume of material k in the cell (m^3; m^2 in 2D)
      M_k  mass (kg)
      E_k  internal energy M_k e_k (J)
      Q_k  nq mass-weighted advected quantities: with strength, M_k s_ij
           (deviator, stress components), M_k eps_p, M_k T
  then per cell: the volume fraction of markers (from their volumes), their
  compliance sum_p V_p / K_p, the artificial viscosity q (Pa).  Void is the volume not held by cell materials
  or markers.  Stored material by material: a plane of ms reals per ghosted
  cell for each material (PSCellsBlk: block (ci, k) at C->u + ci ms + k mst),
  then a plane per per-cell value (C->ux, PSCellsX).  A cell holds one
  material nearly everywhere, and a loop over cells reads that material's
  plane and the per-cell values it uses alone: their bytes, not nmat blocks
  per cell (a pass of the quadrants' four gases streamed 128 bytes per cell,
  now 24 and 8 for each per-cell value it reads).  The cell materials' momentum lives on the nodes, P^C_i (a
  staggered grid: thermodynamics in cells, velocity at nodes, like the
  markers' grid; CTH, Benson 1992), so cells and markers share one nodal
  velocity and one momentum solve.

  Step (step.c): after the markers' P2G the cells add their nodal mass
  m^C_i = sum_c M_c / 2^dim, momentum P^C_i and internal force
  f_i = -sum_c sum_k V_k (sigma_k - q I) grad N_i(x_c) (one-point Q1) with a
  viscous hourglass force; the grid update is shared; the cells' Lagrangian
  phase then takes the new nodal velocity (P^C_i = m^C_i v_i), deforms each
  cell as a box, shares the volume change among its materials (closure.c) and
  updates their energy and stress; the remap (remap.c) carries the cell
  materials and P^C back to the fixed grid, sweep by sweep.
*/
#ifndef PLYSHOCK_CELLS_H
#define PLYSHOCK_CELLS_H

#include "../step.h"

#define PS_MAX_CELLMAT 8
#define PS_RHO_MIN 1e-6 /* density, relative to the material's reference, below which the remap discards it (booked) */
#define PS_CELL_GHOST  3 /* ghost cells: the nodal remap needs fluxes of cells one out, whose donors' Youngs normals reach one further */

/* offsets in a material's block, and of the per-cell values after the blocks */
enum { PS_CV = 0, PS_CM = 1, PS_CE = 2, PS_CQ = 3 };
enum { PS_CX_AM = 0, PS_CX_CM = 1, PS_CX_Q = 2, PS_CX_V = 3, PS_CX_N = 4 }; /* markers' volume fraction and compliance sum V_p/K_p (m^3/Pa), q (Pa), the cell's volume during the remap (m^3) */

/* A cell's corners, the same for every cell: corner a (x
   fastest, 0..2^dim - 1) is node o + off[a] of the ghosted local array, o the
   cell's lower corner; grad N_a at the cell's centre (s_d / h_d times 1/2 for
   each other direction: the bilinear (trilinear) element's one-point
   quadrature); the hourglass patterns G_m(a) (2D xy; 3D xy, yz, xz, xyz;
   Flanagan & Belytschko 1981) are PSHourglassSign's constants, below.
   Built once, with the cells (PSCellsCreate),
   so the cells' loops do no index arithmetic, division or branching per
   corner. */
typedef struct {
  PetscInt  dim, nco;     /* corners */
  PetscInt  off[8];       /* node offsets from corner 0 */
  PetscReal gN[8][3];     /* grad N_a at the centre (1/m) */
  PetscReal khg;          /* hourglass coefficient over min h and 2^dim: kappa / (h 2^dim) (1/m) */
} PSCorners;

/* the hourglass pattern G_m(a) of corner a, a constant where a and m are
   (the loops over a cell's corners unroll): s_0 s_1, s_1 s_2, s_0 s_2,
   s_0 s_1 s_2 with s_d = +1 at the upper node along d, -1 at the lower (+-1,
   exact: G v is +-v, and kappa G h is +-kappa h; loaded from a table, as
   before, the step took 42 instructions per cell-update more) */
static inline PetscReal PSHourglassSign(PetscInt a, PetscInt m)
{
  const PetscReal s0 = (a & 1) ? 1.0 : -1.0, s1 = (a & 2) ? 1.0 : -1.0, s2 = (a & 4) ? 1.0 : -1.0;
  return m == 0 ? s0 * s1 : m == 1 ? s1 * s2 : m == 2 ? s0 * s2 : s0 * s1 * s2;
}

/* The Lagrangian phase's progress through a step (lagrange.c).  In a scene
   of cells alone (no marker bodies, no contact: nothing reads or writes the
   nodes between the predictor and the Lagrangian phase) on a rank without
   ghost nodes across y (2D) or z (3D), its units of cells (rows in 2D,
   planes in 3D) run one behind the predictor's, where their nodes have just
   been corrected, while the cells' state is still in the caches
   (PSCellsPredict); the units next to a rank above, and the ghost nodes,
   after the grid's halo (PSCellsLagrange).  Each unit, node and sum as in
   the phase's own pass, in the same order */
typedef struct {
  PetscBool fused; /* this step's units run behind the predictor's */
  PetscInt  next;  /* the next unit of cells to run (its index along y in 2D, z in 3D) */
  PetscInt  nb;    /* the local units of nodes done (LagrangeNodes) up to nb, from nb0 */
  PetscInt  nb0;   /* the first local unit of this rank's own nodes (the ghosts below it wait for the halo) */
  PetscReal smax;  /* the largest c + |v| + viscous term so far (m/s) */
} PSLagProgress;

/* The one-rank pipeline's window (lagrange.c, PSCellsPipeline): its
   temporaries, the P2G's nodal velocities (sVL), the predictor's v^n (vo)
   and force changes (df), per node, and the half-step values per cell
   (hs), are read within a few units of where they are written, so the
   pipeline keeps only a window of PS_WIN_UNITS units of each (in the
   caches, never written back to memory) and points C->sVL, vo, df and hs
   at it shifted by its first unit, so the kernels index it as the whole
   arrays (node o at vo[dim o + d]); when the units a phase is about to
   write pass its end, the units still read move to its start; the
   Lagrangian phase's end points them at the whole arrays again
   (PSCellsWindowEnd) */
#define PS_WIN_UNITS 16
typedef struct {
  PetscReal *buf;                 /* the four windows, one allocation (NULL until the first pipelined step) */
  PetscReal *vl, *vo, *df, *hs;   /* each window's start */
  PetscReal *full[4];             /* the whole arrays (sVL, vo, df, hs), which the pipeline does not touch */
  PetscInt   nu, cu;              /* reals per unit: of a node array (dim per node), and of hs (per cell around the owned nodes) */
  PetscInt   bn, bc;              /* the first local unit of nodes, and of cells (from C->xs), in the windows */
} PSCellsWindow;

typedef struct PSCells_ {
  PetscInt  dim;
  PetscInt  nmat;                 /* cell materials */
  PetscBool markers;              /* the scene has marker bodies */
  PetscInt  mat[PS_MAX_CELLMAT];  /* their material ids */
  PetscReal rho_min[PS_MAX_CELLMAT]; /* each one's density below which the remap discards it: PS_RHO_MIN rho0 (kg/m^3; remap.c) */
  PetscInt  gasf[PS_MAX_CELLMAT];    /* 1 for an ideal gas without a deviator: its one-material cells take the Lagrangian phases in SIMD lanes (lagrange.c) */
  PetscReal gam[PS_MAX_CELLMAT];     /* each one's gamma (the lanes' ideal gas; 0 for other EOS) */
  PetscInt  nq;                   /* advected quantities per material after E: 0, or ns + 2 */
  PetscInt  ns;                   /* stress components (4 in 2D, 6 in 3D) */
  PetscInt  ms;                   /* reals per material block: 3 + nq */
  PetscInt  dof;                  /* reals per cell: nmat ms + PS_CX_N */
  PetscInt  mst;                  /* reals between a cell's blocks of two successive materials: the plane's, ncl ms */
  PetscInt  nc[3];                /* cells per direction */
  PetscInt  cs[3], ce[3];         /* owned cells [cs, ce) */
  PetscInt  gs[3], gm[3];         /* ghosted cell box: corner and size */
  PetscInt  cst[3], coff;         /* its strides (1, gm[0], gm[0] gm[1]) and the index of cell (0, 0, 0) in it, negated (PSCellIdx) */
  PetscInt  xs[3], xm[3];         /* the cells around the owned nodes: corner and size (PSCellsXIdx) */
  PetscInt  ncl;                  /* cells in the ghosted box */
  PetscReal *u;                   /* the ghosted cell array, ncl x dof: nmat planes of ncl x ms, then PS_CX_N planes of ncl */
  PetscReal *ux;                  /* its per-cell planes, u + nmat mst: PS_CX_N of ncl reals */
  PetscSF   sfu;                  /* ghost exchange of u (halo.c) */
  PetscReal *dep;                 /* the markers' deposit per ghosted cell: volume fraction, compliance; then the fit's discarded mass */
  PetscBool dep_dirty;            /* dep holds a discard (else it is all zero, and the fit need not zero it) */
  PetscReal *sF, *sK, *sVL, *sA;  /* the remap's scratch (remap.c), kept between steps; sK and sVL (one and dim per local node; the remap's sVL in dim planes of nnl) from the start: the cells' P2G takes sVL before the remap */
  PetscReal *sVR;                 /* the remap's nodal velocities where its first sweep runs behind the Lagrangian phase (PSCellsRemapBehindOK), dim planes of nnl: the pipeline's P2G still reads sVL; allocated on first use */
  struct PSSweepProgress_ *rsp;   /* the remap's progress through its sweeps and its books of the step (remap.c); allocated on first use */
  PetscReal *sD;                  /* the remap's first sweep behind the Lagrangian phase on a rank with a neighbour below (remap.c, PSDeferred): what the units taken before the halo leave for the units after it; allocated on first use */
  PetscInt  *sDR, nsD, nsDR;      /* (its flux records' material ranges; the lengths) */
  PetscReal *sdP;                 /* the remap's KE fix: the momentum cut on a row of owned nodes, dim per node */
  PetscReal *sW;                  /* the remap's dual fluxes on a run of cells: per node column, dim planes of phi v_f and one of phi v_f^2 / 2, then a plane of flags (the cell's mid-plane carries anything), a run's length each; the Lagrangian phases' lanes use up to 15 + 2^dim dim + nh dim (the predictor's, lagrange.c) */
  PetscInt  *sR;                  /* per face of the flux ring: the materials [sR[0], sR[1]) its fluxes hold */
  PetscReal *sS;                  /* per ghosted cell with one material with mass: its density and Q/M (the remap's sweep) */
  PetscReal *sP;                  /* per ghosted cell: the material that fills it alone (its one material with mass, its volume above 0.999 of the cell's, no markers, no void), else -1, and -1 on the ghosted array's two faces along the sweep (the remap's sweep); a real, so the faces' lanes load it beside the others (FaceRunLanes) */
  PetscReal *sM;                  /* per ghosted cell: its one material's mass where sP >= 0 (FractionsUnits; the faces' lanes) */
  PetscInt  nsF;
  PetscReal *ec;                  /* the step's EOS values of each cell around the owned nodes, PS_EC per material present only (closure.c): PSCellsEC */
  PetscReal *hm;                  /* the predictor's half-step values of each material present in those cells, PSCellsHalfMat per material (lagrange.c): PSCellsHM */
  PetscInt  *eco, nec;            /* per cell around the owned nodes (PSCellsXIdx): the index of its slot for material 0 among the material slots of ec and hm (a pure cell has one slot, not nmat); their capacity (slots) */
  PetscSF   sfd;                  /* its ghost sums (halo.c) */
  DM        dac;                  /* cells without ghosts, dof reals (output, checkpoint) */
  PetscReal *P;                   /* nodal momentum of the cell materials, the node arrays' layout, dim per node */
  PetscReal *mcn;                 /* nodal mass of the cell materials m^C_i, one per local node */
  PetscReal *mco;                 /* the same before the remap's last sweep (remap.c swaps the two) */
  PetscReal *Mcell;               /* per ghosted cell: its cell materials' mass M_c (kg), as PSCellsNodalMass last summed it */
  short       *sole;              /* per ghosted cell: its one cell material with mass (0..nmat-1), PS_CELL_SEVERAL or PS_CELL_EMPTY (the same sum); a short, not a char: a store through a char pointer may alias anything, and the loops that write it would load every field they use again */
  PetscReal *vh;                  /* the nodal velocity that moves the cells' faces this step, dim per node */
  PetscReal *vo;                  /* the nodal velocity at t^n (PSCellsPredict), dim per node */
  PetscReal *df;                  /* the corrector's change of the cells' nodal force, dim per node */
  PetscReal *hs;                  /* per cell around the owned nodes: the predictor's half-step values q^h and hourglass rates (lagrange.c) */
  PetscSF   sfp;                  /* ghost exchange of P (halo.c) */
  PetscSF   sfk;                  /* ... of one real per node (the remap's KE fix) */
  PetscInt  nnl;                  /* local nodes */
  PetscReal Vc;                   /* cell volume (m^3; m^2 in 2D) */
  PetscReal hourglass;            /* hourglass viscosity coefficient (-) */
  PetscInt  sweep0;               /* first sweep direction of the next remap (alternates) */
  PetscReal remap_heat;           /* this rank: kinetic energy the remap put into internal energy (J) */
  PetscReal coupling_work;        /* this rank: work of fitting cell materials around the markers (J) */
  PetscReal discarded;            /* this rank: mass of traces discarded by the remap (kg; booked in lost_mass) */
  PetscInt  over;                 /* in a scene without marker bodies: the owned cells whose materials' volume exceeds the cell's (the fit's test, PSCellsFitMarkers), counted by the remap's heat after its last sweep; -1: not counted */
  PetscReal smax;                 /* this rank's largest c + |v| + viscous term of the cells (m/s) */
  PSLagProgress lag;              /* the Lagrangian phase's progress through the step (lagrange.c) */
  PSCellsWindow win;              /* the pipeline's window of its temporaries' units (lagrange.c) */
  PetscReal *acc;                 /* the P2G's sums of two units of nodes (lagrange.c, PSCellsSums): the mass and dim force planes of 2 nacc reals; NULL until the first step that takes them */
  PetscInt   nacc;                /* nodes per unit (a row in 2D, a plane in 3D) */
  PetscReal sat[7];               /* the cell that sets it: centre x (m, 3), c, |v|, viscous term (m/s), density (kg/m^3) */
  PSCorners  K;                   /* every cell's corners (lagrange.c) */
  PetscReal *Kmat;                /* bulk modulus of each material at its reference state (Pa): markers' compliance */
} PSCells;

/* whether the step re-projects the nodal velocity for the markers (musl,
   transfer_musl.c): a scene of cells alone (no marker bodies, no contact)
   has no reader of it, and its grid files give the grid's v^{n+1} instead */
static inline PetscBool PSSolverReprojects(const PSSolver *S)
{
  return S->run.transfer == PS_TRANSFER_MUSL && (!S->cells || S->cells->markers || S->contact) ? PETSC_TRUE : PETSC_FALSE;
}

/* the predictor's half-step values (lagrange.c): per material present
   p_k^h, and s_k^h (ns) where cell materials carry strength (C->hm,
   PSCellsHM), and per cell (C->hs) q^h, then the hourglass rates g_m^h (one
   mode of dim components in 2D, four in 3D; the cells' P2G leaves the rates
   at t^n there, the predictor reads them and writes g_m^h, the Lagrangian
   phase reads those).  Reals per material, and per cell */
static inline PetscInt PSCellsHalfMat(const PSCells *C)
{
  return 1 + (C->nq ? C->ns : 0);
}

static inline PetscInt PSCellsHalfSize(const PSCells *C)
{
  return 1 + (C->dim == 3 ? 4 : 1) * C->dim;
}

/* the cells' materials with mass: a cell holds one (nearly every cell), several, or none */
#define PS_CELL_SEVERAL (-1)
#define PS_CELL_EMPTY   (-2)

/* the SIMD lanes' runs (lagrange.c, remap.c, closure.c): the length of the
   run of cells sole[0 .. n) with the same sole material as the first, and
   the shortest run the lanes take (a shorter one costs more than it saves) */
#define PS_LANES_RUN 4
static inline PetscInt PSCellsSoleRun(const short *sole, PetscInt n)
{
  const short s0 = sole[0];
  PetscInt    b, q;
  /* sixteen at a time while all match (a loop without an exit inside, and
     not unrolled, which GCC compares in SIMD lanes; unrolled, as it was
     until the thirtieth session, GCC compared them one by one: 3.6% of the
     quadrants' instructions), then one at a time */
  for (b = 1; b + 16 <= n; b += 16) {
    int diff = 0;
#pragma GCC unroll 1
    for (q = b; q < b + 16; q++) diff |= sole[q] ^ s0;
    if (diff) break;
  }
  /* the last sixteen (overlapping those matched) where fewer remain: all
     match, and the run reaches n without the one-at-a-time tail */
  if (b < n && b + 16 > n && n >= 16) {
    int diff = 0;
#pragma GCC unroll 1
    for (q = n - 16; q < n; q++) diff |= sole[q] ^ s0;
    if (!diff) return n;
  }
  for (; b < n && sole[b] == s0; b++) {}
  return b;
}

/* the first l in [l1, e) whose lanes' flag is 0 (the lanes did not take its
   cell), or e: sixteen at a time while none is, and the last sixteen of
   [l1, e) at once, as PSCellsSoleRun */
static inline PetscInt PSLanesFlagRun(const PetscReal *flag, PetscInt l1, PetscInt e)
{
  PetscInt q;
  const PetscInt l0 = l1;
  for (; l1 + 16 <= e; l1 += 16) {
    int z = 0;
#pragma GCC unroll 1
    for (q = l1; q < l1 + 16; q++) z |= flag[q] == 0.0;
    if (z) break;
  }
  if (l1 < e && l1 + 16 > e && e - 16 >= l0) {
    int z = 0;
#pragma GCC unroll 1
    for (q = e - 16; q < e; q++) z |= flag[q] == 0.0;
    if (!z) return e;
  }
  while (l1 < e && flag[l1] != 0.0) l1++;
  return l1;
}

/* the cell materials [m0, m1) a loop over ghosted cell ci's materials visits:
   its one material with mass, or all (the others hold nothing: a material
   without mass is zeroed where it loses it, remap.c and closure.c, so
   skipping it changes no sum).  Valid from PSCellsNodalMass until the
   cells' masses next change (the remap's sweeps, the fit) */
static inline void PSCellsSoleRange(PetscInt s, PetscInt nmat, PetscInt *m0, PetscInt *m1)
{
  *m0 = s >= 0 ? s : 0;
  *m1 = s >= 0 ? s + 1 : (s == PS_CELL_EMPTY ? 0 : nmat);
}

static inline void PSCellsPresent(const PSCells *C, PetscInt ci, PetscInt *m0, PetscInt *m1)
{
  PSCellsSoleRange(C->sole[ci], C->nmat, m0, m1);
}

/* the fit's test (PSCellsFitMarkers), which the remap's heat makes for it in
   a scene without marker bodies (C->over): a cell is over its room (m^3,
   the cell's volume Vc less the markers') where the volume of its materials
   with mass, Vm, exceeds it by more than PS_FIT_TOL of Vc; a run of one gas
   tests the gas's volume in SIMD lanes */
#define PS_FIT_TOL 1e-12
static inline PetscBool PSCellsOverRoom(PetscReal Vm, PetscReal room, PetscReal Vc)
{
  return !(Vm - room <= PS_FIT_TOL * Vc) ? PETSC_TRUE : PETSC_FALSE;
}

/* the volume of the materials [m0, m1) of the cell block u that have mass (m^3) */
static inline PetscReal PSCellsVolumeWithMass(const PSCells *C, const PetscReal *u, PetscInt m0, PetscInt m1)
{
  PetscReal Vm = 0.0;
  PetscInt  m;
  for (m = m0; m < m1; m++)
    if (u[m * C->mst + PS_CM] > 0.0) Vm += u[m * C->mst + PS_CV];
  return Vm;
}

/* whether the ranks' nodes across y (2D) or x and y (3D) are all this
   rank's own (no ghost nodes across the units of rows or planes): where the
   cells' phases can run one unit behind another (PSLagProgress, the remap's
   PSKEProgress) */
static inline PetscBool PSCellsWholeAcross(const PSIndex *ix, PetscInt dim)
{
  PetscInt d;
  for (d = 0; d < dim - 1; d++)
    if (ix->gm[d] != ix->om[d]) return PETSC_FALSE;
  return PETSC_TRUE;
}

/* The material slots of cell n (PSCellsXIdx), for the materials present
   [m0, m1) (PSCellsPresent) only, set once per step by the EOS cache
   (closure.c): its EOS values for material m at PS_EC m, and its half-step
   values at hmat m (hmat = PSCellsHalfMat).  The index points below the
   cell's own slots by m0 (the arrays begin with nmat - 1 slots of padding,
   so it stays within them) */
#define PS_EC 3 /* cached per cell and material: p (Pa), c (m/s), compliance V/(rho c^2) (m^3/Pa) */
static inline PetscReal *PSCellsEC(const PSCells *C, PetscInt n)
{
  return C->ec + PS_EC * C->eco[n];
}

static inline PetscReal *PSCellsHM(const PSCells *C, PetscInt n, PetscInt hmat)
{
  return C->hm + hmat * C->eco[n];
}

/* index of ghosted cell (i, j, k) (global cell indices) */
static inline PetscInt PSCellIdx(const PSCells *C, PetscInt i, PetscInt j, PetscInt k)
{
  return i + j * C->cst[1] + k * C->cst[2] - C->coff; /* ((k - gs2) gm1 + (j - gs1)) gm0 + (i - gs0) */
}

/* The cells around this rank's owned nodes, [xs, xs + xm): the owned
   cells, and under a rank below them the layer of its cells (whose upper
   corners are owned here).  Each node's sums over its cells (the cells'
   mass and force in PSCellsToGrid, the predictor's force change, the
   initial momentum) are taken by the node's owner alone, over all of the
   node's cells in the order of the cell array, as on one rank: so they are
   the same, bitwise, on any number of ranks (a ghost sum of partial sums
   added them in another order: two gases on 2 ranks drifted from the run on
   1 by round-off that grew to 3% of a field's largest value within 10 steps).
   The index of cell (i, j, k) among them, for the per-cell arrays of the
   Lagrangian phase (C->ec, C->hs) */
static inline PetscInt PSCellsXIdx(const PSCells *C, PetscInt i, PetscInt j, PetscInt k)
{
  return ((k - C->xs[2]) * C->xm[1] + (j - C->xs[1])) * C->xm[0] + (i - C->xs[0]);
}

/* the per-cell slots of C->eco and C->hs: the cells around the owned nodes
   (PSCellsXIdx), and room for the two edge units where the rank has a
   neighbour along y (2D) or z (3D) */
static inline PetscInt PSCellsSlots(const PSCells *C)
{
  const PetscInt e = C->dim - 1, nx = C->xm[0] * C->xm[1] * C->xm[2];
  return nx + (C->cs[e] > 0 || C->ce[e] < C->nc[e] ? 2 * (nx / PetscMax(C->xm[e], 1)) : 0);
}

/* The units of ghost cells along y (2D) or z (3D) next to the cells around
   the owned nodes that the pipeline of a rank with neighbours along that
   direction alone also takes (lagrange.c, PipelineDim): the unit below them
   (xs - 1, under a rank below, where it lies in the domain) and the one
   above (ce, under a rank above): their corners' sums give the ghost nodes
   next to the owned ones, computed there as their owner computes them.
   Each a unit (-1: none) and the index of its first cell among the per-cell
   slots (C->eco, C->hs: after the PSCellsXIdx cells, PSCellsSlots) */
static inline void PSCellsEdgeUnits(const PSCells *C, PetscInt *lo, PetscInt *nlo, PetscInt *hi, PetscInt *nhi)
{
  const PetscInt e = C->dim - 1, nx = C->xm[0] * C->xm[1] * C->xm[2], unit = nx / PetscMax(C->xm[e], 1);
  *lo  = C->cs[e] >= 2 ? C->xs[e] - 1 : -1; /* (cs >= 1: a rank below; xs - 1 = cs - 2 >= 0, in the ghost box of PS_CELL_GHOST) */
  *hi  = C->ce[e] < C->nc[e] && C->ce[e] > C->cs[e] ? C->ce[e] : -1;
  *nlo = nx;
  *nhi = nx + unit;
}

/* which corners of a cell are owned nodes: bit a for the corner at offset
   K.off[a] (bit d of a: the upper node along d).  Along one direction d, for
   the cell's index c along it: the corners whose node along d is owned (the
   loops over cells take it once per row, plane and cell) */
static inline PetscInt PSCellsOwnedAxis(const PSIndex *ix, PetscInt d, PetscInt c)
{
  static const PetscInt lower[3] = {0x55, 0x33, 0x0f}; /* the corners a with bit d of a zero */
  const PetscInt        n        = c + PS_PAD;         /* the cell's lower node along d */
  const PetscBool       lo = n >= ix->os[d] && n < ix->os[d] + ix->om[d], hi = n + 1 >= ix->os[d] && n + 1 < ix->os[d] + ix->om[d];
  return (lo ? lower[d] : 0) | (hi ? ~lower[d] & 0xff : 0);
}

/* the local rows of nodes along y (2D) or planes along z (3D) up to the
   upper corners of the cells of index u along that direction (not clipped
   to the local array): what a phase that walks the cells a row or plane at
   a time makes of its nodes' values before it reaches those cells */
static inline PetscInt PSCellsUnitsThrough(const PSIndex *ix, PetscInt dim, PetscInt u)
{
  return PetscMax(u + 2 + PS_PAD - ix->gs[dim - 1], 0);
}

/* the same as a prefix of the local node array (nnl nodes) */
static inline PetscInt PSCellsNodesThrough(const PSIndex *ix, PetscInt dim, PetscInt nnl, PetscInt u)
{
  const PetscInt unit = dim == 3 ? ix->gm[0] * ix->gm[1] : ix->gm[0];
  return PetscMin(PSCellsUnitsThrough(ix, dim, u) * unit, nnl);
}

/* ... along y and z, for a row of cells (j, k) */
static inline PetscInt PSCellsOwnedRow(const PSIndex *ix, PetscInt dim, PetscInt j, PetscInt k)
{
  return ((1 << (1 << dim)) - 1) & PSCellsOwnedAxis(ix, 1, j) & (dim == 3 ? PSCellsOwnedAxis(ix, 2, k) : 0xff);
}

/* a row of cells (j, k): cell (i, j, k)'s ghosted index (PSCellIdx) is
   ci0 + i and its lower corner node's local index oc0 + i; the cells
   [xa, xb) have both their corners along x owned (PSCellsOwnedAxis(ix, 0,
   i) = 0xff: the loops test the row's ends alone; xa, xb may be NULL) */
static inline void PSCellsRow(const PSCells *C, const PSIndex *ix, PetscInt dim, PetscInt j, PetscInt k, PetscInt *ci0, PetscInt *oc0, PetscInt *xa, PetscInt *xb)
{
  *ci0 = PSCellIdx(C, 0, j, k);
  *oc0 = Lidx(ix, PS_PAD, j + PS_PAD, dim == 3 ? k + PS_PAD : 0);
  if (xa) *xa = ix->os[0] - PS_PAD;                 /* the lower node i + PS_PAD >= os */
  if (xb) *xb = ix->os[0] + ix->om[0] - PS_PAD - 1; /* the upper node i + PS_PAD + 1 < os + om */
}

/* ... and in all directions, of cell (i, j, k) */
static inline PetscInt PSCellsOwnedCorners(const PSIndex *ix, PetscInt dim, PetscInt i, PetscInt j, PetscInt k)
{
  return PSCellsOwnedRow(ix, dim, j, k) & PSCellsOwnedAxis(ix, 0, i);
}

/* ghosted cell ci's block of material m, and its per-cell value f (PS_CX_*) */
static inline PetscReal *PSCellsBlk(const PSCells *C, PetscInt ci, PetscInt m)
{
  return C->u + C->ms * ci + C->mst * m;
}

static inline PetscReal *PSCellsX(const PSCells *C, PetscInt ci, PetscInt f)
{
  return C->ux + f * C->ncl + ci;
}

/* ghosted cell ci's dof reals, cell by cell (material blocks in order, then
   the per-cell values: the layout of C->dac, output and checkpoints), out of
   the planes and back */
static inline void PSCellsCopyOut(const PSCells *C, PetscInt ci, PetscReal *out)
{
  PetscInt m, q;
  for (m = 0; m < C->nmat; m++)
    for (q = 0; q < C->ms; q++) out[m * C->ms + q] = PSCellsBlk(C, ci, m)[q];
  for (q = 0; q < PS_CX_N; q++) out[C->nmat * C->ms + q] = *PSCellsX(C, ci, q);
}

static inline void PSCellsCopyIn(PSCells *C, PetscInt ci, const PetscReal *in)
{
  PetscInt m, q;
  for (m = 0; m < C->nmat; m++)
    for (q = 0; q < C->ms; q++) PSCellsBlk(C, ci, m)[q] = in[m * C->ms + q];
  for (q = 0; q < PS_CX_N; q++) *PSCellsX(C, ci, q) = in[C->nmat * C->ms + q];
}

/* the stride of scratch planes of n reals each (the lanes' C->sW, the
   sweeps' flux records C->sF): n padded to 24 mod 512 reals, so that
   successive planes start 192 bytes apart modulo 4 KiB, and 21 of them
   never closer.  A core matches a load against the stores still in flight
   by the address's low 12 bits first: with rows of 513-515 reals (the
   512^2 quadrants) every plane began 8-24 bytes after the one before modulo 4 KiB,
   so a loop that stores to one plane and loads another at the same index
   waited on stores it did not read (4K aliasing); the quadrants at 512^2
   took 1.07x the time (docs/speed.md, forty-third session) */
static inline PetscInt PSCellsPadPlane(PetscInt n)
{
  return n + ((24 - n) % 512 + 512) % 512;
}

/* the length of each plane of the lanes' scratch C->sW: a ghosted row of
   nodes or of cells, the longer, padded (PSCellsPadPlane) */
static inline PetscInt PSCellsPlaneLen(const PSCells *C, const PSIndex *ix)
{
  return PSCellsPadPlane(PetscMax(ix->gm[0], C->gm[0]));
}

/* ghosted cell ci's mass M_c (the sum over its materials, in order) and its
   materials with mass, into C->Mcell and C->sole */
static inline void PSCellsCellMass(PSCells *C, PetscInt ci)
{
  const PetscReal *u    = &C->u[C->ms * ci];
  PetscReal        Mc   = 0.0;
  PetscInt         sole = PS_CELL_EMPTY, m;
  for (m = 0; m < C->nmat; m++) {
    Mc += u[m * C->mst + PS_CM];
    if (u[m * C->mst + PS_CM] > 0.0) sole = sole == PS_CELL_EMPTY ? m : PS_CELL_SEVERAL;
  }
  C->Mcell[ci] = Mc;
  C->sole[ci]  = (short)sole;
}

/* a cell material's EOS (the registry's model, materials.h): the ideal gas,
   most cells' material, evaluated here as PSEOSIdealGas does (the same
   operations, so the same values), any other model through its function
   (the call per material and cell was 6% of a gas step) */
static inline PetscErrorCode PSCellsEOS(const PSMaterial *M, PetscReal J, PetscReal p_old, PetscReal dvol, PetscReal *A, PetscReal *B, PetscReal *c2)
{
  if (M->eos_fn == PSEOSIdealGas) {
    const PetscReal rho = M->rho0 / J;
    *A  = 0.0;
    *B  = (M->gamma - 1.0) * rho;
    *c2 = M->gamma * PetscMax(p_old, 0.0) / rho;
    return PETSC_SUCCESS;
  }
  return M->eos_fn(M, J, p_old, dvol, A, B, c2);
}

/* pressure p (Pa) and sound speed c (m/s) of cell material k from its block
   (V, M, E, ...): p = A + B e at rho = M / V, c^2 from the EOS and 4G/3rho.
   Inline: the EOS cache calls it per cell and material every step */
static inline PetscErrorCode PSCellsPressure(const PSSolver *S, PetscInt k, const PetscReal *blk, PetscReal *p, PetscReal *c)
{
  const PSMaterial *M = &S->mat[S->cells->mat[k]];
  PetscReal         J, A, B, c2, e;

  if (blk[PS_CM] <= 0.0 || blk[PS_CV] <= 0.0) {
    *p = 0.0;
    *c = 0.0;
    return PETSC_SUCCESS;
  }
  if (M->eos_fn == PSEOSIdealGas && M->G == 0.0) {
    /* the ideal gas from the block's sums, two divisions instead of six:
       p = (gamma - 1) E / V, c^2 = gamma p V / M (the same values as below
       to round-off) */
    *p = (M->gamma - 1.0) * blk[PS_CE] / blk[PS_CV];
    if (M->spall < 0.0 && *p < M->spall) *p = 0.0;
    *c = PetscSqrtReal(M->gamma * PetscMax(*p, 0.0) * blk[PS_CV] / blk[PS_CM]);
    return PETSC_SUCCESS;
  }
  J = M->rho0 * blk[PS_CV] / blk[PS_CM];
  e = blk[PS_CE] / blk[PS_CM];
  PetscCall(PSCellsEOS(M, J, 0.0, 0.0, &A, &B, &c2));
  *p = A + B * e;
  if (M->spall < 0.0 && *p < M->spall) *p = 0.0;
  PetscCall(PSCellsEOS(M, J, *p, 0.0, &A, &B, &c2)); /* c^2 of the ideal gas needs p */
  *c = PetscSqrtReal(PetscMax(c2, 0.0) + 4.0 * M->G * J / (3.0 * M->rho0));
  return PETSC_SUCCESS;
}

PETSC_INTERN PetscErrorCode PSCellsCreate(PSSolver *, const PSMaterial *);
PETSC_INTERN PetscErrorCode PSCellsDestroy(PSCells **);
PETSC_INTERN PetscErrorCode PSCellsInsert(PSSolver *);
PETSC_INTERN PetscErrorCode PSCellsToGrid(PSSolver *, const PSIndex *, PetscReal dt);
PETSC_INTERN PetscErrorCode PSCellsPredict(PSSolver *, const PSIndex *, PetscReal dt);
PETSC_INTERN PetscBool      PSCellsPipelined(const PSSolver *, const PSIndex *);
PETSC_INTERN PetscBool      PSCellsSums(const PSSolver *);
PETSC_INTERN PetscErrorCode PSCellsPipeline(PSSolver *, const PSIndex *, PetscReal dt);
PETSC_INTERN void           PSCellsWindowEnd(PSCells *);
PETSC_INTERN PetscErrorCode PSCellsLagrange(PSSolver *, const PSIndex *, PetscReal dt);
PETSC_INTERN PetscErrorCode PSCellsRemap(PSSolver *, const PSIndex *, PetscReal dt);
PETSC_INTERN PetscBool      PSCellsRemapBehindOK(const PSSolver *, const PSIndex *);
PETSC_INTERN PetscErrorCode PSCellsRemapBehindBegin(PSSolver *, const PSIndex *);
PETSC_INTERN PetscErrorCode PSCellsRemapBehind(PSSolver *, const PSIndex *, PetscReal dt, PetscLogEvent pause);
PETSC_INTERN PetscErrorCode PSCellsFitMarkers(PSSolver *, PetscBool fit);
PETSC_INTERN PetscErrorCode PSCellsMaxSpeed(PSSolver *);
PETSC_INTERN PetscErrorCode PSCellsTotals(PSSolver *, PetscReal loc[6], PetscReal *pmax);
PETSC_INTERN PetscErrorCode PSCellsExchange(PSCells *);
PETSC_INTERN PetscErrorCode PSCellsNodalMass(PSSolver *, const PSIndex *, PetscBool owned_set);
PETSC_INTERN PetscErrorCode PSCellsNodalMassUnits(PSSolver *, const PSIndex *, PetscBool owned_set, PetscInt n0, PetscInt n1);
PETSC_INTERN PetscErrorCode PSCellsNodalMassGather(PSSolver *, const PSIndex *, PetscReal *mcn, PetscInt n0, PetscInt n1);
PETSC_INTERN PetscErrorCode PSCellsWrite(PSSolver *, PetscViewer, const char *const material_names[]);
PETSC_INTERN PetscErrorCode PSCellsCheckpoint(PSSolver *, PetscViewer);
PETSC_INTERN PetscErrorCode PSCellsRestart(PSSolver *, PetscViewer);

#endif
