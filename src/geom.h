/*
  geom.h - regions of bodies and the exact piece kernel (internal).

  A region is a body, or one ply of a laminate.  Against a box (a sub-cell) a
  region is OUT, IN, or CUT by half-spaces; flat bodies (laminates, boxes,
  cylinder caps, 2D cylinders) are exact half-space sets, curved surfaces
  (spheres, disks, cylinder mantles) are refined by bisection of the box and
  replaced by a plane at the finest level.
*/
#ifndef PLYSHOCK_GEOM_H
#define PLYSHOCK_GEOM_H

#include "plyshock.h"
#include "clip.h"

#define PS_MAX_REGION_PLANES 8   /* 6 faces of an oriented box, or 2 caps + 1 mantle plane */
#define PS_MAX_SUB            8   /* higher-priority bodies over one piece */
#define PS_MAX_LEVEL         14   /* curved refinement levels below a sub-cell */

/* Relative tolerance that decides a plane just touching a box (planes that
   coincide with cell faces to round-off neither cut nor make slivers). */
#define PS_TOUCH_TOL 1e-13

typedef struct {
  const PSBody *body;
  PetscInt      ply;     /* ply id, or -1 for the whole body */
  PetscReal     h_fine;  /* largest box side at which a curved cut is made planar (m) */
  int           nflat;   /* flat faces of the region ... */
  PSPlane       flat[6]; /* ... as half-spaces n.x <= d (absolute) */
} PSRegion;

typedef enum {
  PS_OUT = 0,
  PS_IN  = 1,
  PS_CUT = 2
} PSCut;

PETSC_INTERN void PSRegionSetup(const PSScene *, const PSBody *, PetscInt ply, PetscReal cell_h, PSRegion *);
PETSC_INTERN void PSSubCellBounds(const PSScene *, const PetscInt idx[3], PetscInt s, const PetscInt q[3], double lo[3], double hi[3]);
PETSC_INTERN void PSCellRange(const PSScene *, const PetscReal lo[3], const PetscReal hi[3], PetscInt cs[3], PetscInt ce[3]);
PETSC_INTERN PSCut PSRegionClassify(PetscInt dim, const PSRegion *, const double lo[3], const double hi[3]);
PETSC_INTERN PetscInt PSBodyLocatePoint(PetscInt dim, const PSBody *, const double x[3]);
PETSC_INTERN void PSPieceMoments(PetscInt dim, const double lo[3], const double hi[3], int nin, const PSRegion *in, int nsub, const PSRegion *sub, double m[4]);

#endif
