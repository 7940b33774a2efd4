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

/* uniform GIMP in one direction: d = (x_p - x_i)/h, l = l_p/h (0 < l <= 1/2) */
static inline void PSGimp1(PetscReal d, PetscReal l, PetscReal ih, PetscReal *w, PetscReal *dw)
{
  const PetscReal a = fabs(d), sg = d < 0 ? -1.0 : 1.0;
  if (a < l) {
    *w  = 1.0 - (a * a + l * l) / (2.0 * l);
    *dw = -a / l;
  } else if (a < 1.0 - l) {
    *w  = 1.0 - a;
    *dw = -1.0;
  } else if (a < 1.0 + l) {
    *w  = (1.0 + l - a) * (1.0 + l - a) / (4.0 * l);
    *dw = -(1.0 + l - a) / (2.0 * l);
  } else {
    *w  = 0.0;
    *dw = 0.0;
  }
  /* dN/dx_p = dS/da * sign(d) / h */
  *dw *= sg * ih;
}

/* weights of marker x (m) with half size lp (m); ih = 1/h (1/m) */
static inline void PSShapeEval(PSShapeType type, PetscInt dim, const PetscReal lower[], const PetscReal ih[], const PetscReal x[], PetscReal lp, PSShape *S)
{
  PetscInt d, k;
  for (d = 0; d < dim; d++) {
    const PetscReal xi = (x[d] - lower[d]) * ih[d];
    switch (type) {
    case PS_SHAPE_LINEAR: {
      const PetscReal c = floor(xi), f = xi - c;
      S->i0[d]    = (PetscInt)c + PS_PAD;
      S->w[d][0]  = 1.0 - f;
      S->w[d][1]  = f;
      S->w[d][2]  = 0.0;
      S->dw[d][0] = -ih[d];
      S->dw[d][1] = ih[d];
      S->dw[d][2] = 0.0;
    } break;
    case PS_SHAPE_BSPLINE2: {
      const PetscReal b = floor(xi - 0.5), f = xi - b;
      S->i0[d]    = (PetscInt)b + PS_PAD;
      S->w[d][0]  = 0.5 * (1.5 - f) * (1.5 - f);
      S->w[d][1]  = 0.75 - (f - 1.0) * (f - 1.0);
      S->w[d][2]  = 0.5 * (f - 0.5) * (f - 0.5);
      S->dw[d][0] = (f - 1.5) * ih[d];
      S->dw[d][1] = -2.0 * (f - 1.0) * ih[d];
      S->dw[d][2] = (f - 0.5) * ih[d];
    } break;
    case PS_SHAPE_GIMP: {
      /* nodes i with |xi - i| < 1 + l, l <= 1/2: the (at most) 3 integers
         after xi - 1 - l */
      const PetscReal l = PetscMin(0.5, PetscMax(1e-6, lp * ih[d])), c = floor(xi - 1.0 - l) + 1.0;
      S->i0[d] = (PetscInt)c + PS_PAD;
      for (k = 0; k < 3; k++) PSGimp1(xi - (c + k), l, ih[d], &S->w[d][k], &S->dw[d][k]);
    } break;
    }
  }
  for (d = dim; d < 3; d++) {
    S->i0[d] = 0;
    for (k = 0; k < PS_SHAPE_MAXN; k++) S->w[d][k] = S->dw[d][k] = 0.0;
    S->w[d][0] = 1.0;
  }
}

#endif
