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
  Single velocity field: bodies and plies that touch stay bonded (no contact
  algorithm, no delamination).

  Units: SI.  Suffixes: _p marker, _i node.
*/
#ifndef PLYSHOCK_SOLVER_H
#define PLYSHOCK_SOLVER_H

#include "plyshock.h"

typedef enum {
  PS_SHAPE_LINEAR,
  PS_SHAPE_GIMP,
  PS_SHAPE_BSPLINE2
} PSShapeType;
PETSC_EXTERN const char *const PSShapeTypes[];

typedef enum {
  PS_BC_FREE,
  PS_BC_SYMMETRY,
  PS_BC_FIXED
} PSBCType;

/* Constitutive data of one material, SI units; filled from the deck. */
typedef struct {
  PetscReal rho0;          /* reference density (kg/m^3) */
  PetscInt  eos;           /* 0 none (hypoelastic bulk), 1 Mie-Grueneisen */
  PetscReal K;             /* bulk modulus for eos none (Pa) */
  PetscReal c0, s, gamma0; /* Mie-Grueneisen linear Us-up (m/s, -, -) */
  PetscReal G;             /* shear modulus (Pa); 0 = hydrodynamic */
  PetscInt  strength;      /* 0 none (elastic if G > 0), 1 elastic-plastic, 2 Johnson-Cook */
  PetscReal Y0;            /* elastic-plastic yield stress (Pa) */
  PetscReal A, B, n, C, m; /* Johnson-Cook strength (Pa, Pa, -, -, -) */
  PetscReal T_melt, T_room, eps_dot0; /* K, K, 1/s */
  PetscReal cv;            /* specific heat (J/kg/K) */
  PetscReal chi;           /* Taylor-Quinney factor */
  PetscInt  failure;       /* 0 none, 1 Johnson-Cook */
  PetscReal D[5];          /* Johnson-Cook failure D1..D5 */
  PetscReal spall;         /* spall pressure (Pa, negative; 0 = none) */
} PSMaterial;

/* Run parameters (deck `run:` section; -run_<key> overrides). */
typedef struct {
  PetscReal   t_end;           /* s */
  PetscReal   cfl;             /* - */
  PSShapeType shape;
  PetscReal   output_interval; /* s; 0 = only the end */
  PetscReal   c_linear, c_quadratic; /* artificial viscosity coefficients */
  PetscReal   pic_fraction;    /* PIC share of the velocity update (0 = FLIP) */
  PetscReal   dt_growth;       /* largest dt_{n+1}/dt_n */
  PetscReal   mass_threshold;  /* nodes lighter than this share of a full cell's mass get no velocity */
  PetscInt    max_steps;       /* stop after this many steps (0 = none) */
  PetscInt    history_interval;/* steps between history rows */
  PetscReal   dt_max;          /* s; 0 = none */
} PSRunParams;

/* Conserved totals, global. */
typedef struct {
  PetscReal mass, p[3], kinetic, internal;
  PetscReal lost_mass, lost_p[3], lost_energy;
  PetscReal max_pressure;
  PetscInt64 markers, lost_markers;
} PSTotals;

typedef struct {
  const PSScene *scene;
  PSRunParams    run;
  PSMaterial    *mat;            /* scene->nmaterial */
  PSBCType       bc[3][2];       /* per direction, lower and upper face */
  DM             da;             /* grid: dof = 1 + 2 dim (m, mv, f), padded by PS_PAD nodes */
  DM             sw;             /* markers */
  PetscInt       dim, pad;
  PetscReal      h[3];           /* cell size (m) */
  PetscReal      t, dt;          /* s */
  PetscInt       step;
  PetscInt      *lx[3];          /* DMDA ownership ranges (nodes) */
  PetscInt       nproc[3];
  PSTotals       lost;           /* booked removals, global, cumulative */
  PetscBool      need_plastic, need_temperature, need_damage;
} PSSolver;


#endif
