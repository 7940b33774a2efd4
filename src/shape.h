/*
  shape.h - MPM shape functions, per direction (tensor products in 2D/3D).

  linear    hat functions, 2 nodes per direction
  gimp      uniform GIMP (Bardenhagen & Kober, CMES 5, 2004), particle half
            size l_p <= h/2 from the marker's initial size: its support
            |x_p - x_i| < h + l_p spans at most 3 nodes
  bspline2  quadratic B-splines (Steffen, Kirby & Berzins, IJNME 76, 2008),
            3 nodes

  Node indices returned are DMDA indices (physical node + PS_PAD).
*/
#ifndef PLYSHOCK_SHAPE_H
#define PLYSHOCK_SHAPE_H

#include <math.h>
#include "solver.h"

#define PS_SHAPE_MAXN 3

/* a marker's weights: n = 2 (linear) or 3 nodes per direction from i0 */
typedef struct PSShape_ {
  PetscInt  i0[3];                 /* first DMDA node per direction */
  PetscReal w[3][PS_SHAPE_MAXN];   /* weights (linear: the third is 0) */
  PetscReal dw[3][PS_SHAPE_MAXN];  /* derivatives d/dx (1/m) */
} PSShape;

/* nodes per direction of a shape function type */
static inline PetscInt PSShapeNodes(PSShapeType type)
{
  return type == PS_SHAPE_LINEAR ? 2 : 3;
}

/* GIMP's particle size in cell units per direction, l = l_p / h clamped to
   (0, 1/2], and 1/(2 l), 1/(4 l): set when l_p changes (uniform insertion
   repeats it), so that no division waits in each marker's weights */
typedef struct {
  PetscReal l[3], i2l[3], i4l[3];
} PSGimpSize;

static inline void PSGimpSizeSet(PetscReal lp, const PetscReal ih[], PSGimpSize *G)
{
  PetscInt d;
  for (d = 0; d < 3; d++) {
    G->l[d]   = PetscMin(0.5, PetscMax(1e-6, lp * ih[d]));
    G->i2l[d] = 0.5 / G->l[d];
    G->i4l[d] = 0.25 / G->l[d];
  }
}

/* where a marker sits: its first node, per direction its offset f in cells
   from that node and, for GIMP, the two terms of its reach past the middle
   node's near side (see PSShapeWeights).  88 bytes: what the MUSL passes keep
   between P2G and the gradient (PSShapeWeights turns it into the weights in a
   few operations, without the marker's size; storing the weights, 160
   bytes, cost P2G more than rebuilding them costs the later passes) */
typedef struct PSShapeAt_ {
  PetscInt  i0[3]; /* first DMDA node per direction */
  PetscReal f[3];  /* x_p/h - (i0 - PS_PAD) (-) */
  PetscReal q[3];  /* GIMP: g^2/4l, g = max(0, f - (1 - l)) (-); 0 for the other shapes */
  PetscReal gi[3]; /* GIMP: g/2l (-); 0 for the other shapes */
} PSShapeAt;

/* where marker x (m) sits; G: GIMP's size (PSGimpSizeSet, unused by the
   other shapes); ih = 1/h (1/m) */
static inline void PSShapeLocate(PSShapeType type, PetscInt dim, const PetscReal lower[], const PetscReal ih[], const PetscReal x[], const PSGimpSize *G, PSShapeAt *A)
{
  PetscInt d;
  for (d = 0; d < 3; d++) {
    const PetscReal xi = d < dim ? (x[d] - lower[d]) * ih[d] : 0.0;
    PetscReal       c  = 0.0;
    /* linear: the node below; B-splines: the node below xi - 1/2; GIMP: the
       (at most) 3 nodes with |xi - i| < 1 + l are the integers after
       xi - 1 - l */
    if (d < dim) c = type == PS_SHAPE_LINEAR ? floor(xi) : type == PS_SHAPE_BSPLINE2 ? floor(xi - 0.5) : floor(xi - 1.0 - G->l[d]) + 1.0;
    A->i0[d] = d < dim ? (PetscInt)c + PS_PAD : 0;
    A->f[d]  = xi - c;
    if (type == PS_SHAPE_GIMP && d < dim) {
      const PetscReal g = PetscMax(0.0, A->f[d] - (1.0 - G->l[d]));
      A->q[d]           = g * g * G->i4l[d];
      A->gi[d]          = g * G->i2l[d];
    } else A->q[d] = A->gi[d] = 0.0;
  }
}

/* the weights and their derivatives where A says the marker sits */
static inline void PSShapeWeights(PSShapeType type, PetscInt dim, const PetscReal ih[], const PSShapeAt *A, PSShape *S)
{
  PetscInt d, k;
  for (d = 0; d < dim; d++) {
    const PetscReal f = A->f[d];
    S->i0[d] = A->i0[d];
    switch (type) {
    case PS_SHAPE_LINEAR:
      S->w[d][0]  = 1.0 - f;
      S->w[d][1]  = f;
      S->w[d][2]  = 0.0;
      S->dw[d][0] = -ih[d];
      S->dw[d][1] = ih[d];
      S->dw[d][2] = 0.0;
      break;
    case PS_SHAPE_BSPLINE2:
      S->w[d][0]  = 0.5 * (1.5 - f) * (1.5 - f);
      S->w[d][1]  = 0.75 - (f - 1.0) * (f - 1.0);
      S->w[d][2]  = 0.5 * (f - 0.5) * (f - 0.5);
      S->dw[d][0] = (f - 1.5) * ih[d];
      S->dw[d][1] = -2.0 * (f - 1.0) * ih[d];
      S->dw[d][2] = (f - 0.5) * ih[d];
      break;
    case PS_SHAPE_GIMP: {
      /* uniform GIMP (Bardenhagen & Kober 2004): the hat averaged over the
         particle, S(d) = 1 - (d^2 + l^2)/2l for |d| < l, 1 - |d| for
         l <= |d| < 1 - l, (1 + l - |d|)^2/4l for |d| < 1 + l, with d = x_p/h - i
         and l = l_p/h <= 1/2.  From the first of its 3 nodes the marker sits
         at f in [l, 1 + l), and with g = max(0, f - (1 - l)) the pieces are
           S_0 = 1 - f + g^2/4l,  S_2 = g^2/4l,  S_1 = 1 - S_0 - S_2 = f - g^2/2l,
           dS/dd = -1 + g/2l, 1 - g/l, g/2l:
         no branches, no division (the piecewise form divided twice per node
         and mispredicted off the lattice) */
      const PetscReal q = A->q[d], gi = A->gi[d];
      S->w[d][0]  = 1.0 - f + q;
      S->w[d][1]  = f - 2.0 * q;
      S->w[d][2]  = q;
      S->dw[d][0] = (gi - 1.0) * ih[d];
      S->dw[d][1] = (1.0 - 2.0 * gi) * ih[d];
      S->dw[d][2] = gi * ih[d];
    } break;
    }
  }
  for (d = dim; d < 3; d++) {
    S->i0[d] = 0;
    for (k = 0; k < PS_SHAPE_MAXN; k++) S->w[d][k] = S->dw[d][k] = 0.0;
    S->w[d][0] = 1.0;
  }
}

/* the nodes per direction that carry weight, n[d] <= N.  GIMP's support is
   2 nodes along a direction in which the particle lies inside one cell
   (g = 0 in PSShapeWeights: the third node's weight and derivative are
   exactly 0) and 3 where it straddles a node; B-splines' third node is zero
   only at f = 1/2 exactly.  Skipping a zero node changes no bit of any sum,
   so vs = PETSC_TRUE is exact for every shape (contact.c passes it); the
   MUSL kernels pass it only for GIMP, a constant there, so B-splines' fixed
   support pays no test.  GIMP's 27 nodes become 8 for a marker inside its
   cell.  Loops bounded by both N and n[d] (N a constant) still unroll. */
static inline __attribute__((always_inline)) void PSShapeSupport(const PSShape *sh, const PetscInt dim, const PetscInt N, const PetscBool vs, PetscInt n[3])
{
  PetscInt d;
  for (d = 0; d < 3; d++) n[d] = d < dim ? ((vs && sh->w[d][2] == 0.0 && sh->dw[d][2] == 0.0) ? 2 : N) : 1;
}

#endif
