/*
  solver.h - the explicit MPM solver's context (internal).

  Transfer scheme: MUSL (Sulsky, Zhou & Schreyer 1995, "modified update stress
  last").  Per step:
    1. P2G       m_i = sum_p N_ip m_p,  (mv)_i = sum_p N_ip m_p v_p,
                 f_i = -sum_p V_p (sigma_p - q_p I) grad N_ip
    2. grid      (mv)_i += dt f_i, boundary conditions per face
    3. G2P       v_p = (1-a) [v_p + dt sum_i N_ip f_i/m_i] + a sum_i N_ip v_i  (FLIP/PIC, a = pic_fraction)
                 x_p += dt sum_i N_ip v_i^{n+1}
    4. re-project (mv)_i = sum_p N_ip m_p v_p^{n+1}, boundary conditions
    5. L_p = sum_i v_i grad N_ip; F_p <- (I + dt L_p) F_p; V_p = det F_p V0_p;
       stress update (materials.c), artificial viscosity q_p
    6. markers leaving the domain are removed and booked; the rest migrate to
       the rank owning their cell.
  Transfer scheme apic (run.transfer): APIC (Jiang et al. 2015) in the MLS-MPM
  form (Hu et al., ACM TOG 37, 2018), quadratic B-splines only (D_p = h^2/4 I):
    1. P2G       m_i = sum_p N_ip m_p,
                 (mv)_i = sum_p N_ip [m_p v_p + (m_p C_p - dt V_p (sigma_p - q_p I) D_p^-1)(x_i - x_p)]
                 (momentum, affine velocity and the internal force dt f_i in one pass)
    2. grid      v_i = (mv)_i / m_i, boundary conditions per face
    3. G2P       v_p = sum_i N_ip v_i,  C_p = sum_i N_ip v_i (x_i - x_p)^T D_p^-1,
                 x_p += dt v_p
    4. L_p = C_p (the MLS velocity gradient, consistent with the force), then
       step 5 and 6 as above.
  One transfer each way and 1 + dim values per node instead of 2 (1 + 2 dim)
  and dim: about half the grid traffic of MUSL.  Linear and angular momentum are
  conserved by the transfers; energy is lost in non-affine modes like PIC.

  Grid: the step works on each rank's ghosted local arrays; ghost nodes' sums
  go to their owners and the owners' values come back through a PetscSF
  (halo.c); zeroing and grid loops cover only the nodes the markers reach.

  Velocity fields: one, in which bodies and plies that touch stay bonded,
  unless the scene has marker bodies in contact (deck `contact:`, default
  friction 0 between different bodies): then each body (or group of bonded
  bodies) has its own field at the nodes where two or more meet, with a
  contact law there (contact.c, MUSL only).  Plies of a laminate stay bonded
  (no delamination).

  Units: SI.  Suffixes: _p marker, _i node.
*/
#ifndef PLYSHOCK_SOLVER_H
#define PLYSHOCK_SOLVER_H

#include <petscsf.h>
#include "plyshock.h"

typedef enum {
  PS_SHAPE_LINEAR,
  PS_SHAPE_GIMP,
  PS_SHAPE_BSPLINE2
} PSShapeType;
PETSC_EXTERN const char *const PSShapeTypes[];

typedef enum {
  PS_TRANSFER_MUSL,
  PS_TRANSFER_APIC
} PSTransferType;
PETSC_EXTERN const char *const PSTransferTypes[];

typedef enum {
  PS_BC_FREE,
  PS_BC_SYMMETRY,
  PS_BC_FIXED
} PSBCType;

/* Constitutive models are functions registered by name (materials/registry.c). */
typedef struct PSMaterial_ PSMaterial;
/* p = A + B e at relative volume J = V/V0; dvol = tr(D) dt (the step's volume
   strain, for incremental models); c2 = isentropic bulk sound speed^2 (m^2/s^2). */
typedef PetscErrorCode (*PSEOSFn)(const PSMaterial *, PetscReal J, PetscReal p_old, PetscReal dvol, PetscReal *A, PetscReal *B, PetscReal *c2);
/* flow stress Y (Pa) at plastic strain, plastic strain rate (1/s), temperature (K) */
typedef PetscErrorCode (*PSStrengthFn)(const PSMaterial *, PetscReal eps_p, PetscReal eps_dot, PetscReal T, PetscReal *Y);
/* a strength model's check of its constants (errors name the value) */
typedef PetscErrorCode (*PSStrengthCheckFn)(const PSMaterial *);
/* equivalent plastic strain to failure at triaxiality sigma_m/sigma_eq, rate, temperature */
typedef PetscErrorCode (*PSFailureFn)(const PSMaterial *, PetscReal triax, PetscReal eps_dot, PetscReal T, PetscReal *eps_f);
/* ply failure indices of the four modes (fiber tension, fiber compression, matrix
   tension, matrix compression; a mode initiates at 1) from the stress in
   material axes, Voigt 11,22,33,23,13,12 (Pa) */
typedef PetscErrorCode (*PSPlyFailureFn)(const PSMaterial *, const PetscReal s[6], PetscReal F[4]);
struct PSMarkerState_;
/* one marker's constitutive update over a step (isotropic or orthotropic kernel) */
typedef PetscErrorCode (*PSUpdateFn)(const PSMaterial *, PetscInt dim, const PetscReal L[3][3], PetscReal dt, PetscReal h, PetscReal c_linear, PetscReal c_quadratic, struct PSMarkerState_ *, PetscReal *J, PetscReal *c);
/* the same update for four 3D markers of one material at once, lane by lane
   bitwise equal to PSUpdateFn (materials/update4.c) */
typedef PetscErrorCode (*PSUpdate4Fn)(const PSMaterial *, const PetscReal L[4][3][3], PetscReal dt, PetscReal h, PetscReal c_linear, PetscReal c_quadratic, struct PSMarkerState_ *s, PetscReal J[4], PetscReal c[4]);

/* 4-wide vectors of reals and of lane masks (GCC/Clang vector extension; AVX2
   with -march=native, plain scalar code elsewhere) */
typedef PetscReal  PSv4 __attribute__((vector_size(4 * sizeof(PetscReal))));
typedef PetscReal  PSv8 __attribute__((vector_size(8 * sizeof(PetscReal)))); /* one AVX-512 register, two AVX2 ones */
typedef PetscInt64 PSm4 __attribute__((vector_size(4 * sizeof(PetscInt64))));

/* Orthotropic ply data (material axes 1 = fiber, 2, 3), SI units. */
typedef struct {
  PetscReal C[36];   /* stiffness, Voigt 11,22,33,23,13,12 with engineering shear strains (Pa), row major */
  PetscReal K_R;     /* Reuss bulk modulus 1 / sum_{i,j<=3} S_ij (Pa) */
  PetscReal c2max;   /* largest eigenvalue of C in Mandel form / rho0: bounds every wave speed^2 (m^2/s^2) */
  PetscReal X[6];    /* strengths Xt, Xc, Yt, Yc, S12, S23 (Pa) */
  PetscReal Gc[4];   /* fracture energies of the four modes (J/m^2) */
  PetscReal E[4];    /* modulus of each mode's softening law: E1, E1, E2, E2 (Pa) */
} PSPly;

/* Zerilli-Armstrong constants (materials/strength_zerilli_armstrong.c). */
typedef struct {
  PetscReal C0;          /* athermal stress delta sigma_G' + k l^(-1/2) (Pa) */
  PetscReal C1, C2, C5;  /* bcc thermal, fcc thermal, bcc hardening stresses (Pa) */
  PetscReal C3, C4;      /* 1/K */
  PetscReal n;           /* bcc hardening exponent (-) */
} PSZerilliArmstrong;

/* Mechanical Threshold Stress constants (materials/strength_mts.c). */
typedef struct {
  PetscReal sigma_a;               /* athermal stress (Pa) */
  PetscReal mu_0, D, T_0;          /* shear modulus mu(T) = mu_0 - D/(exp(T_0/T) - 1) (Pa, Pa, K) */
  PetscReal k_over_b3;             /* Boltzmann constant / Burgers vector^3 (Pa/K) */
  PetscReal sigma_i, g_0i, eps_dot_0i, p_i, q_i; /* intrinsic barrier (Pa, -, 1/s, -, -); sigma_i = 0: none */
  PetscReal g_0e, eps_dot_0e, p_e, q_e;          /* evolving barrier (-, 1/s, -, -) */
  PetscReal a_0, a_1, a_2, a_3;    /* theta_0 = a_0 + a_1 ln rate + a_2 sqrt(rate) - a_3 T (Pa, Pa, Pa s^1/2, Pa/K) */
  PetscReal alpha;                 /* hardening-law shape (-) */
  PetscReal g_0es, eps_dot_es0, sigma_es0; /* saturation threshold (-, 1/s, Pa) */
} PSMTS;

/* Constitutive data of one material, SI units; filled from the deck. */
struct PSMaterial_ {
  PetscReal    rho0;            /* reference density (kg/m^3) */
  PetscReal    K;               /* bulk modulus of the hypoelastic EOS "none" (Pa) */
  PetscReal    c0, s, gamma0;   /* Mie-Grueneisen linear Us-up (m/s, -, -) */
  PetscReal    gamma;           /* ideal gas: ratio of specific heats (-) */
  PetscReal    G;               /* shear modulus (Pa); 0 = hydrodynamic */
  PetscReal    Y0;              /* elastic-plastic yield stress (Pa) */
  PetscReal    A, B, n, C, m;   /* Johnson-Cook strength (Pa, Pa, -, -, -) */
  PSZerilliArmstrong za;        /* Zerilli-Armstrong strength */
  PSMTS        mts;             /* Mechanical Threshold Stress strength */
  PetscReal    T_melt, T_room;  /* K */
  PetscReal    eps_dot0;        /* Johnson-Cook reference rate (1/s) */
  PetscReal    cv;              /* specific heat (J/kg/K) */
  PetscReal    chi;             /* Taylor-Quinney factor */
  PetscReal    D[5];            /* Johnson-Cook failure D1..D5 */
  PetscReal    spall;           /* spall pressure (Pa, negative; 0 = none) */
  PSEOSFn      eos_fn;
  PSStrengthFn strength_fn;     /* NULL: no strength (elastic deviator if G > 0) */
  PSFailureFn  failure_fn;      /* NULL: no failure */
  PetscBool    aniso;           /* orthotropic ply (materials/orthotropic.c) */
  PSPly        ply;
  PSPlyFailureFn ply_failure_fn; /* NULL: no ply failure */
  PSUpdateFn   update_fn;       /* the kernel for this material, chosen by PSMaterialInit */
  PSUpdate4Fn  update4_fn;      /* its 4-marker 3D form; NULL: none (plies, metal failure) */
};

/* Run parameters (deck `run:` section; -run_<key> overrides). */
typedef struct {
  PetscReal   t_end;           /* s */
  PetscReal   cfl;             /* - */
  PSShapeType shape;
  PSTransferType transfer;     /* musl (default) or apic (bspline2 only) */
  PetscReal   output_interval; /* s; 0 = only the end */
  PetscReal   c_linear, c_quadratic; /* artificial viscosity coefficients */
  PetscReal   pic_fraction;    /* PIC share of the velocity update (0 = FLIP) */
  PetscReal   dt_growth;       /* largest dt_{n+1}/dt_n */
  PetscReal   mass_threshold;  /* nodes lighter than this share of a full cell's mass get no velocity */
  PetscInt    max_steps;       /* stop after this many steps (0 = none) */
  PetscInt    history_interval;/* steps between history rows */
  PetscInt    progress_interval;/* steps between progress lines on rank 0 (0: every ~2 s of wall time) */
  PetscReal   dt_max;          /* s; 0 = none */
  PetscBool   fbar;            /* cell-averaged volumetric rate (Delta-F-bar anti-locking) */
  PetscInt    lanes;           /* markers per call of the 3D isotropic kernel: 4 (vectorised) or 1 (scalar; option only, for checks); 1 also keeps the cells' phases to their scalar loops, the Lagrangian phase and the remap's KE fix to passes of their own (PSLagProgress, PSKEProgress), the cells' P2G, grid update and predictor apart (PSCellsPipeline), and the fit's test to the fit */
  PetscReal   checkpoint_interval;      /* s of simulated time between checkpoints; 0 = at every output time */
  PetscReal   checkpoint_wall_interval; /* s of wall time between checkpoints; 0 = none */
  PetscReal   dt_floor;        /* the run stops when the CFL time step falls below this share of the initial one (0 = never) */
  PetscBool   hugepages;       /* the process's large arrays on transparent huge pages (memory.c; Linux; option only) */
} PSRunParams;

/* Where the outputs stand (run.c); checkpointed, so a restart continues the
   same output times and numbers. */
typedef struct {
  PetscInt  index;    /* number of the next markers_NNNNN.h5 */
  PetscReal t_next;   /* time of the next output (s) */
  PetscReal interval; /* the output interval they were planned with (s) */
} PSOutputSchedule;

/* Error code of the run-time guards that every rank raises together (the
   front end then reports the message once and exits with status 2); any other
   error during a run may come from one rank alone. */
#define PS_ERR_RUN 256

/* Conserved totals, global (or one rank's booked removals). */
typedef struct {
  PetscReal  mass, p[3], kinetic, internal;          /* kg, kg m/s, J, J (per metre of depth in 2D) */
  PetscReal  lost_mass, lost_p[3], lost_energy;      /* booked removals through free faces */
  PetscReal  max_pressure;                           /* Pa */
  PetscReal  remap_heat;                             /* J: kinetic energy the cells' remap put into internal energy (included in internal) */
  PetscReal  coupling_work;                          /* J: work of fitting cell materials around the markers (included in internal) */
  PetscReal  friction_work;                          /* J: kinetic energy the contact's friction removed (contact.c), cumulative */
  PetscReal  interface_energy;                       /* J: energy the cohesive ply interfaces' law took as they opened (contact.c), cumulative */
  PetscInt64 markers, lost_markers;
} PSTotals;

typedef struct {
  const PSScene *scene;
  PSRunParams    run;
  PSMaterial    *mat;            /* scene->nmaterial */
  PSBCType       bc[3][2];       /* per direction, lower and upper face */
  PetscInt       nc[3];          /* cells per direction (scene->cells; 1 beyond dim) */
  DM             da;             /* grid nodes, PS_PAD nodes outside the domain on each side */
  DM             dag;            /* the same grid with the step's node layout of G (step.h: PSGridDof) */
  DM             dav;            /* the same grid with the re-projection's layout (musl; PSReprojectDof) */
  DM             sw;             /* markers */
  Vec            G, Gl, H, Hl;   /* grid vectors: global (output) and ghosted local (the step) (G on dag, H on dav) */
  PetscReal     *gbuf, *hbuf;    /* the allocations behind Gl and Hl ... */
  PetscReal     *g, *hv;         /* ... and their arrays, which start on a 64-byte boundary */
  struct PSCells_ *cells;        /* Eulerian cell materials (cells/); NULL in a scene without cell bodies */
  struct PSContact_ *contact;    /* velocity fields of bodies in contact (contact.c); NULL: the single field */
  PetscSF        sfg, sfh;       /* ghost exchange of Gl and Hl (halo.c) */
  PetscInt       dim, pad;
  PetscReal      h[3];           /* cell size (m) */
  PetscReal      ih[3], Dinv[3]; /* 1/h (1/m), 4/h^2 (1/m^2) */
  PetscReal      t, dt;          /* s */
  PetscReal      smax;           /* global max of wave speed + |v| + viscous term (m/s) */
  PetscReal      mass_min;       /* node mass below which a node carries no velocity (kg) */
  PetscInt       step;
  PetscInt       nstep_here;     /* steps this solver has taken (not counting a restart's): the huge pages' schedule (memory.c) */
  PetscInt      *lx[3];          /* DMDA node ownership: rank k owns [lx[k], lx[k+1]) */
  PetscInt       nproc[3];
  PetscReal     *dx;             /* scratch: marker displacement of the step */
  struct PSShapeAt_ *at;         /* scratch (musl): where each marker sits at x_p^n, from P2G to the gradient */
  PetscInt       ncache;         /* room in the scratch arrays (markers) */
  PSTotals       lost_local;     /* this rank's booked removals, cumulative */
  PetscInt       ngauge;         /* gauges: each follows one marker (its id) */
  PetscInt64    *gauge_id;
  PetscInt       ndamage;        /* damage components per marker (scene) */
  PetscReal     *Lp;             /* scratch (fbar): each marker's velocity gradient, 9 reals */
  PetscInt       cs[3], ce[3], ncell; /* owned cells [cs, ce) (fbar) */
  PetscReal     *cell_V, *cell_trL;   /* per owned cell: sum V_p, sum V_p tr L_p (fbar) */
  PetscBool      has_ply;        /* the scene has laminates: markers carry a ply id */
  PetscBool      axi;            /* 2D axisymmetric (x = r, y = z; scene->axisymmetric): hoop terms in P2G and L_p */
  PetscInt       zbox[3][2];     /* DMDA nodes [lo, hi) the last step wrote: the grid vectors are zero outside */
  PetscBool      zall;           /* zero the grid vectors whole before the next step */
  PetscReal      dt0;            /* the run's first CFL time step (s): run.dt_floor's reference; checkpointed */
  PSOutputSchedule out;          /* the outputs' schedule (run.c); checkpointed */
  PetscBool      restarted;      /* the state came from a checkpoint (PSSolverRestart) */
  const char *const *body_names, *const *material_names; /* for messages, during PSSolverRun */
} PSSolver;

PETSC_EXTERN PetscErrorCode PSSolverCreate(const PSScene *, DM da, DM sw, const PSRunParams *, const PSMaterial *, const PetscInt bc[6], PSSolver **);
PETSC_EXTERN PetscErrorCode PSSolverDestroy(PSSolver **);
PETSC_EXTERN PetscErrorCode PSSolverInitialState(PSSolver *);
PETSC_EXTERN PetscErrorCode PSRunParamsRead(MPI_Comm, PSRunParams *);
PETSC_EXTERN PetscErrorCode PSRunParamsCheck(const PSRunParams *, const char **key, char msg[], size_t len);
PETSC_EXTERN PetscErrorCode PSRunParamsSetFromOptions(MPI_Comm, PSRunParams *);
PETSC_EXTERN PetscErrorCode PSSolverMaxSpeed(PSSolver *);
PETSC_EXTERN PetscErrorCode PSSolverStep(PSSolver *, PetscReal t_stop);
PETSC_EXTERN PetscErrorCode PSSolverMigrate(PSSolver *);
PETSC_EXTERN PetscErrorCode PSSolverTotals(PSSolver *, PSTotals *);
PETSC_EXTERN PetscErrorCode PSSolverRun(PSSolver *, const char outdir[], PetscInt nattr, const char *const attr_names[], const char *const attr_values[], const char *const body_names[], const char *const material_names[]);
PETSC_EXTERN PetscErrorCode PSSolverSetGauges(PSSolver *, PetscInt n, const PetscInt64 ids[]);
PETSC_EXTERN PetscErrorCode PSSolverSetContact(PSSolver *, PetscInt nbody, const PetscInt field[], const PetscInt split[], PetscInt nfield, const PetscReal mu[], const PetscInt coh[], PetscInt ncoh, const PetscReal cohp[]);
PETSC_EXTERN PetscErrorCode PSSolverCheckpoint(PSSolver *, const char filename[]);
PETSC_EXTERN PetscErrorCode PSSolverRestart(PSSolver *, const char filename[]);
PETSC_EXTERN PetscErrorCode PSSolverCellsGet(PSSolver *, PetscInt cs[3], PetscInt cm[3], PetscInt layout[3], PetscReal *out);
PETSC_EXTERN PetscErrorCode PSSolverCellNodesGet(PSSolver *, PetscInt ns[3], PetscInt nm[3], PetscReal *out);
PETSC_EXTERN PetscErrorCode PSCheckpointVerify(MPI_Comm, const PSScene *, const char filename[], char msg[], size_t len);
PETSC_EXTERN PetscReal      PSSolverCFLTimeStep(const PSSolver *);
PETSC_INTERN PetscErrorCode PSHaloCreate(PSSolver *, PetscInt dof, PetscSF *);
PETSC_INTERN PetscErrorCode PSHaloCreateBox(MPI_Comm, PetscInt dim, const PetscInt N[3], const PetscInt nproc[3], PetscInt *const lx[3], PetscInt sw, PetscInt nb, PetscInt bs, PetscInt nx, PetscSF *);
PETSC_INTERN PetscErrorCode PSHaloReduce(PetscSF, PetscReal *);
PETSC_INTERN PetscErrorCode PSHaloBcast(PetscSF, PetscReal *);
PETSC_EXTERN PetscErrorCode PSMaterialInit(PSMaterial *, const char eos[], const char strength[], const char failure[]);
PETSC_EXTERN PetscErrorCode PSMaterialDrive(const PSMaterial *, const PetscReal axes0[9], PetscInt nsteps, const PetscReal L[], PetscReal dt, PetscReal h, PetscReal sig[], PetscReal axes[], PetscReal dmg[], PetscReal pe[]);

#endif
