/*
  plic.h - piecewise-linear interface reconstruction (PLIC) in one Eulerian cell:
  Youngs' normals, the plane offset that cuts a given volume fraction (closed
  form, Scardovelli & Zaleski 2000), several materials by nested dissection
  ("onion skin"), and the volume of each material in the slab next to a face
  (the donor region of a direction-split remap sweep).

  Conventions (every routine):
  - The cell is the axis-aligned box [-h/2, h/2] (sizes h[3], m), coordinates
    relative to its centre so that round-off is relative to the cell size.  In 2D
    only x, y are used (n[2], h[2] ignored) and "volume" means area (m^2, per
    metre of depth).
  - A material's region is the side {x : n.x <= d} of its plane: the normal n
    points OUT of the material, n = -grad(alpha)/|grad(alpha)|.  n need not be a
    unit vector (volumes depend on its direction only; d scales with |n|), but
    the routines that return normals return unit ones.
  - Volume fractions are dimensionless, offsets d have the units of n.x.

  Plain C99, no PETSc objects, no allocation: called per mixed cell per sweep.
  Build on clip.h (the exact clipper) when more than one plane cuts a cell.
*/
#ifndef PLYSHOCK_PLIC_H
#define PLYSHOCK_PLIC_H

#include <stddef.h>

#define PS_PLIC_MAXMAT 8 /* materials in one cell (void counts as one if the caller keeps it) */

/* The reconstruction of one cell: nmat materials in dissection order; material
   k < nmat-1 owns {n[k].x <= d[k]} of what materials 0..k-1 left, the last one
   owns the rest.  A material with nothing to own gets a plane that touches the
   cell (or what is left of it) at one vertex: its region has zero volume. */
typedef struct {
  int    dim;                          /* 2 or 3 */
  int    nmat;                         /* 1 .. PS_PLIC_MAXMAT */
  double h[3];                         /* cell sizes (m) */
  double n[PS_PLIC_MAXMAT - 1][3];     /* plane normals, out of material k (any length) */
  double d[PS_PLIC_MAXMAT - 1];        /* plane offsets (units of n.x, relative to the cell centre) */
} PSPlicCell;

/* Youngs' normal of one material at a cell from the 3x3 (2D) or 3x3x3 (3D) block
   of its volume fractions: alpha points at the centre cell, the neighbour at
   (i+di, j+dj, k+dk) is alpha[di*sx + dj*sy + dk*sz] (strides in doubles; sz is
   unused in 2D).  n (unit, out of the material) = -grad(alpha)/|grad(alpha)|.
   Returns 0, or 1 when the block is flat (every scaled gradient component
   |d alpha/dx_i| h_i <= PS_PLIC_FLAT): n is then the fallback (1, 0, 0). */
#define PS_PLIC_FLAT 1e-12
int PSPlicYoungsNormal(int dim, const double *alpha, ptrdiff_t sx, ptrdiff_t sy, ptrdiff_t sz, const double h[3], double n[3]);

/* Volume (m^3; m^2 in 2D) of {x in the cell : n.x <= d}; closed form.  n = 0
   gives the whole cell when d >= 0 and nothing otherwise. */
double PSPlicVolume(int dim, const double n[3], double d, const double h[3]);

/* The offset d such that {x in the cell : n.x <= d} holds the fraction alpha
   (clamped to [0, 1]) of the cell; closed form.  alpha = 0 gives d = -M/2 and
   alpha = 1 gives d = M/2, M = sum |n_i| h_i (the planes through the cell's
   extreme vertices).  n = 0 gives d = 0. */
double PSPlicOffset(int dim, const double n[3], double alpha, const double h[3]);

/* Nested dissection: the planes of nmat materials with volume fractions alpha[]
   (dimensionless; material nmat-1 takes the rest whatever its alpha) and normals
   n[k] for k < nmat-1 (out of material k), in the caller's order.  One plane:
   PSPlicOffset; more: each offset solved on the polytope left by the previous
   materials with the exact clipper (a closed-form offset when the previous
   materials lie on one side of the plane, else exact piecewise-polynomial
   interpolation of the volume between vertex heights; to round-off).  Layered
   materials are cheapest when material k's normal is Youngs' normal of the
   fractions of materials 0..k together.  Returns 0, or -1 on bad
   input (nmat out of range, dim not 2 or 3, a clipper overflow). */
int PSPlicReconstruct(int dim, const double h[3], int nmat, const double alpha[], const double n[][3], PSPlicCell *cell);

/* Volume of each material (vol[0..nmat-1], m^3; m^2 in 2D) inside the slab of
   the cell within distance w (0 <= w <= h[axis], clamped) of its face on
   `axis` (0, 1, 2) and `side` (-1: the face at -h/2, +1: the face at +h/2).
   Closed form with one plane (the slab is a box), exact clipping with more.
   The volumes sum to the slab's volume w * (face area) to round-off (the last
   material gets the remainder, never below 0).  Returns 0, or -1 on bad input. */
int PSPlicSlabVolumes(const PSPlicCell *cell, int axis, int side, double w, double vol[]);

#endif
