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

/* 4-wide |a| and clamp to [-1, 1] on the bits (GCC vector extensions: no
   branches, one instruction each) */
typedef long long PSv4i __attribute__((vector_size(4 * sizeof(long long))));
static inline PSv4 PSv4Abs(PSv4 a)
{
  const PSv4i mask = {0x7fffffffffffffffLL, 0x7fffffffffffffffLL, 0x7fffffffffffffffLL, 0x7fffffffffffffffLL};
  return (PSv4)((PSv4i)a & mask);
}
static inline PSv4 PSv4Clamp1(PSv4 a)
{
  const PSv4  one = {1.0, 1.0, 1.0, 1.0};
  const PSv4i hi = a > one, lo = a < -one;
  a = (PSv4)((hi & (PSv4i)one) | (~hi & (PSv4i)a));
  return (PSv4)((lo & (PSv4i)(-one)) | (~lo & (PSv4i)a));
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
      /* uniform GIMP (Bardenhagen & Kober 2004) is the hat N(t) = 1 - |t|
         averaged over the particle, d = x_p/h - i, l = l_p/h <= 1/2:
           S(d) = (H(d + l) - H(d - l)) / 2l,  dS/dd = (N(d + l) - N(d - l)) / 2l
         with H(t) = int_-1^t N = 1/2 + t - t|t|/2 on [-1, 1] (t clamped: S
         vanishes beyond |d| = 1 + l).  The nodes i with |xi - i| < 1 + l are
         the (at most) 3 integers after xi - 1 - l: one 4-wide evaluation, no
         branches (markers out of a regular lattice mispredicted the piecewise
         form's, and it divided twice per node) */
      const PetscReal l = PetscMin(0.5, PetscMax(1e-6, lp * ih[d])), c = floor(xi - 1.0 - l) + 1.0, i2l = 0.5 / l;
      const PSv4      k4 = {0.0, 1.0, 2.0, 3.0}, dd = (xi - c) - k4;
      const PSv4      tp = PSv4Clamp1(dd + l), tm = PSv4Clamp1(dd - l), ap = PSv4Abs(tp), am = PSv4Abs(tm);
      const PSv4      w = ((tp - tm) - 0.5 * (tp * ap - tm * am)) * i2l, dw = (am - ap) * (i2l * ih[d]);
      S->i0[d] = (PetscInt)c + PS_PAD;
      for (k = 0; k < 3; k++) {
        S->w[d][k]  = w[k];
        S->dw[d][k] = dw[k];
      }
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
