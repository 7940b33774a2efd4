/*
  contact.h - multi-velocity-field contact between marker bodies (internal;
  contact.c has the method and its sources, docs/contact.md the contract).

  Each field is a group of marker bodies joined by bonded pairs (the front end
  makes the groups, python/plyshock/scene.py).  A scene with one field (one
  body, or `contact: {type: bonded}`) has no PSContact: the step runs the
  single-field MUSL kernels unchanged.

  A laminate with `interface: cohesive` puts each ply in a field of its own
  (split[b]: ply j of body b is field field[b] + j), and the pair of two
  adjacent plies' fields carries a cohesive law (coh, cohp).

  Node layout of the field array g, per field k (fs = 4 + 4 dim reals):
      P2G    [m_k, (mv)_k, f_k, g_k = sum_p m_p grad N_ip, V_k = sum_p N_ip V_p, (m psi)_k = sum_p N_ip m_p psi_p, 0, 0]
      grid   [m_k, v_k^new, dv_k = v_k^new - v_k^old, g_k, V_k, dpsi_i, alpha_k, dv_f,k]   (shared nodes)
  (psi_p = (1 - D_p)^2 from the marker's interface damage D_p, cohesive scenes
  only; alpha_k 1 where the contact corrected field k (friction pairs), or the
  fraction of the way to the centre of mass the cohesive law moved it, which
  the re-projection repeats; dpsi_i the decrement of psi
  of the node's cohesive pair this step, -1 for fields not in one; dv_f,k the
  friction's tangential correction, which G2P books at the markers)
  and of the re-projection array h, per field k (dim reals):
      [(mv)_k] -> [v_k] (shared nodes).
  A node is shared when two or more fields carry more than mass_min there; only
  shared nodes use the fields, every other node the single field of the step's
  grid array (S->g, S->hv), which holds the sum of all fields.  Only markers
  that touch a shared node (near) pay for the fields: a first pass puts the
  fields' masses alone (mk) to find the shared nodes; the full fields' P2G,
  G2P and L_p run on the near markers only.  The single field's fast kernels
  (transfer_musl.c, unchanged) run on every marker first; the near markers'
  G2P and L_p are then redone from their field.
*/
#ifndef PLYSHOCK_CONTACT_H
#define PLYSHOCK_CONTACT_H

#include "step.h"

typedef struct PSContact_ {
  PetscInt   nfield;        /* velocity fields, >= 2 */
  PetscInt   nbody;         /* bodies of the scene */
  PetscInt  *field;         /* field of each body; -1: a body in cells (not a marker body) */
  PetscInt  *split;         /* per body: 1 = ply j of it is field field[b] + j (cohesive ply interfaces) */
  PetscReal *mu;            /* nfield x nfield Coulomb friction coefficients (-) */
  PetscInt  *coh;           /* nfield x nfield: the cohesive law between two fields (adjacent plies), -1 none */
  PetscInt   ncoh;          /* cohesive laws */
  PetscReal *cohp;          /* ncoh x 4: normal strength N (Pa), shear strength S (Pa), G_I, G_II (J/m^2) */
  PetscInt   fs;            /* reals per field and node in g: 4 + 4 dim */
  PetscInt   gdof, hdof;    /* reals per node: nfield fs, nfield dim */
  PetscInt   nl;            /* nodes of a rank's ghosted local array */
  PetscReal *g, *h;         /* ghosted local arrays (layouts above) */
  PetscSF    sfg, sfh;      /* their ghost exchange (halo.c) */
  PetscInt   zbox[3][2];    /* nodes the last step wrote: g and h are zero elsewhere */
  PetscReal *mk;            /* ghosted local array of the fields' nodal masses alone (nfield per node): which nodes are shared */
  PetscSF    sfm;           /* its ghost exchange */
  char      *shared;        /* per ghosted local node: 1 where two or more fields are heavier than mass_min */
  PetscReal *vs;            /* per owned shared node (dim): the single field's v^new before the cells' predictor (bodies in cells) */
  char      *near;          /* per marker: 1 if it touches a shared node (it takes the field kernels; the others the single field's) */
  PetscReal *vold;          /* per marker (dim): a near marker's velocity before G2P (the single field's G2P updates every marker first) */
  PetscInt   nnear;         /* capacity of near and vold (markers) */
  PetscReal  friction_work; /* this rank's friction impulses on its markers' mean velocities, cumulative (J) */
  PetscReal  interface_energy; /* this rank's energy the cohesive laws took (dissipated in opening), cumulative (J) */
} PSContact;

PETSC_INTERN PetscErrorCode PSContactDestroy(PSContact **);
PETSC_INTERN PetscErrorCode PSContactP2G(PSSolver *, PSFields *, const PSIndex *);
PETSC_INTERN PetscErrorCode PSContactGridSolve(PSSolver *, const PSIndex *, PetscReal dt);
PETSC_INTERN PetscErrorCode PSContactCellsSync(PSSolver *, const PSIndex *);
PETSC_INTERN PetscErrorCode PSContactG2P(PSSolver *, PSFields *, const PSIndex *, PetscReal dt);
PETSC_INTERN PetscErrorCode PSContactReproject(PSSolver *, PSFields *, const PSIndex *);

#endif
