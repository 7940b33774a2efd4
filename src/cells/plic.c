/*
  plic.c - PLIC interface geometry in one cell (see plic.h for the conventions).

  The plane offset (PSPlicOffset) and its inverse (PSPlicVolume) follow
  Scardovelli & Zaleski, "Analytical relations connecting linear interfaces and
  volume fractions in rectangular grids", J. Comput. Phys. 164 (2000) 228-237:
  the box is mapped onto the unit square/cube, the normal's components made
  non-negative by reflections, scaled by the cell sizes, normalised to sum 1 and
  sorted, m1 <= m2 (<= m3); the volume of {m.s <= a} is then a piecewise
  polynomial of a (their eqs. for the unit cube), and its inverse has closed
  forms (a square root in 2D; a cube root, a square root, or the trigonometric
  root of a cubic in 3D).  Two things keep it robust where the published forms
  lose accuracy:
  - only a <= 1/2 is ever evaluated or inverted; the other half follows from
    the symmetry V(1 - a) = 1 - V(a), so alpha -> 1 is as accurate as alpha -> 0;
  - in 3D the middle range m1 <= a < m1 + m2 is written as
      6 m2 m3 V = 3a(a - m1) + m1^2 - ((a - m2)_+^3 + (a - m3)_+^3) / m1,
    where (a - m2)_+ and (a - m3)_+ are < m1, so nothing large is divided by a
    small m1 (a normal nearly in a face plane); the cubic in that range is
    solved for t = (a - m2)/m1 in [0, 1), which is well conditioned for any m1,
    and every root is polished by one Newton step on that forward form.

  Youngs' normal: Youngs, "Time-dependent multi-material flow with large fluid
  distortion", in Numerical Methods for Fluid Dynamics (Morton & Baines, eds.,
  Academic Press 1982) 273-285, for 2D; the 3D form from Youngs, "An interface
  tracking method for a 3D Eulerian hydrodynamics code", AWRE report
  44/92/35 (1984), as written out in Rider & Kothe, J. Comput. Phys. 141 (1998)
  112-152, and Pilliod & Puckett, J. Comput. Phys. 199 (2004) 465-502: the
  gradient at each corner of the cell from the cells that share it, averaged
  over the corners.  That is the centred difference across the cell weighted
  (1,2,1) across it in 2D and (1,2,1)x(1,2,1) in 3D.

  Several materials: nested dissection ("onion skin", e.g. Benson, Comput.
  Methods Appl. Mech. Engrg. 99 (1992) 235-394, section on interface
  reconstruction; Tangram's MOF/VOF nested dissection).  Material k's offset
  is bracketed by two closed-form offsets on the whole cell (for the fractions
  target/V and (target + taken)/V), and each is exact when what the previous
  materials took lies wholly on one side of the plane (layers), which one clip
  each checks.  Otherwise: the volume cut from a convex polytope P by
  {n.x <= u} is a polynomial of degree dim in u between consecutive vertex
  heights n.x_v, so a binary search over the vertex heights inside the bracket
  (one exact clip per step) finds that interval, and the exact interpolant of
  the polynomial there (dim - 1 more clips) gives u by a safeguarded Newton
  root: exact to round-off, no tolerance.
*/
#include <math.h>
#include <string.h>
#include "../clip.h"
#include "plic.h"

#define PS_PLIC_PI 3.14159265358979323846
/* a closed-form offset is taken on a cut polytope when it cuts the wanted volume
   to this fraction of the cell */
#define PS_PLIC_LAYER_TOL 1e-14

/* ------------------------------------------- the unit square and cube ---- */

/* Unit square, 0 <= m1 <= m2, m1 + m2 = 1, 0 <= a <= 1/2: area of {m.s <= a}
   (Scardovelli & Zaleski 2000, the 2D relations). */
static inline double SquareLower(double m1, double m2, double a)
{
  if (a <= 0.0) return 0.0;
  if (a < m1) return a * a / (2.0 * m1 * m2);
  return (a - 0.5 * m1) / m2; /* m2 >= 1/2 */
}

/* Its inverse for 0 <= V <= 1/2. */
static inline double SquareLowerInverse(double m1, double m2, double V)
{
  if (V <= 0.0) return 0.0;
  if (V < 0.5 * m1 / m2) return sqrt(2.0 * m1 * m2 * V); /* the corner triangle */
  return m2 * V + 0.5 * m1;
}

/* Unit cube, 0 <= m1 <= m2 <= m3, sum 1, 0 <= a <= 1/2: volume of {m.s <= a}
   (Scardovelli & Zaleski 2000, the 3D relations, middle range rewritten, see top). */
static inline double CubeLower(const double m[3], double a)
{
  const double m1 = m[0], m2 = m[1], m3 = m[2];
  double       N;
  if (a <= 0.0) return 0.0;
  if (a < m1) return a * a * a / (6.0 * m1 * m2 * m3);  /* corner tetrahedron */
  if (a >= m1 + m2) return (a - 0.5 * (m1 + m2)) / m3; /* a slanted prism; m3 >= 1/2 here */
  N = 3.0 * a * (a - m1) + m1 * m1;                     /* m1 <= a < m1 + m2, so m2 > 0 */
  if (a > m2) N -= (a - m2) * (a - m2) * (a - m2) / m1;  /* a - m2 < m1 */
  if (a > m3) N -= (a - m3) * (a - m3) * (a - m3) / m1;  /* a - m3 < m1 */
  return N / (6.0 * m2 * m3);
}

/* dV/da of CubeLower: the area of the cut. */
static inline double CubeLowerSlope(const double m[3], double a)
{
  const double m1 = m[0], m2 = m[1], m3 = m[2];
  double       N;
  if (a <= 0.0) return 0.0;
  if (a < m1) return a * a / (2.0 * m1 * m2 * m3);
  if (a >= m1 + m2) return 1.0 / m3;
  N = 2.0 * a - m1;
  if (a > m2) N -= (a - m2) * (a - m2) / m1;
  if (a > m3) N -= (a - m3) * (a - m3) / m1;
  return N / (2.0 * m2 * m3);
}

/* The middle root of the depressed cubic y^3 + p y + q = 0 with p < 0 and three
   real roots (Viete's trigonometric form). */
static inline double CubicMiddleRoot(double p, double q)
{
  const double r = sqrt(-p / 3.0);
  double       c = 1.5 * q / (p * r); /* = (3q / 2p) sqrt(-3/p) */
  if (c > 1.0) c = 1.0;
  if (c < -1.0) c = -1.0;
  return 2.0 * r * cos(acos(c) / 3.0 - 2.0 * PS_PLIC_PI / 3.0);
}

/* Inverse of CubeLower for 0 <= V <= 1/2 (Scardovelli & Zaleski 2000, the 3D
   inverse relations), polished by one Newton step. */
static double CubeLowerInverse(const double m[3], double V)
{
  const double m1 = m[0], m2 = m[1], m3 = m[2], m12 = m1 + m2;
  double       a, V2, Vend, slope;

  if (V <= 0.0) return 0.0;
  if (m1 > 0.0 && V < m1 * m1 / (6.0 * m2 * m3)) {
    a = cbrt(6.0 * m1 * m2 * m3 * V); /* corner tetrahedron */
  } else if (V < (V2 = CubeLower(m, m2))) {
    a = 0.5 * m1 + sqrt(fmax(2.0 * m2 * m3 * V - m1 * m1 / 12.0, 0.0)); /* m1 <= a < m2: a quadratic */
  } else if (V <= (Vend = CubeLower(m, fmin(m3, m12))) && m1 > 0.0) {
    /* m2 <= a < min(m3, m12): a = m2 + m1 t, t in [0, 1) solves
       t - (r/6)(1 - (1 - t)^3) = tau, r = m1/m2 <= 1, tau = m3 (V - V2)/m1 */
    const double r = m1 / m2, tau = m3 * (V - V2) / m1;
    double       t;
    if (r < 1e-3) { /* a contraction by r/2: four steps reach round-off */
      int i;
      t = tau;
      for (i = 0; i < 4; i++) t = tau + r / 6.0 * (1.0 - (1.0 - t) * (1.0 - t) * (1.0 - t));
    } else { /* s = 1 - t: s^3 - (6/r) s + (6/r)(1 - tau) - 1 = 0, the middle root */
      t = 1.0 - CubicMiddleRoot(-6.0 / r, 6.0 / r * (1.0 - tau) - 1.0);
    }
    a = m2 + m1 * fmin(fmax(t, 0.0), 1.0);
  } else if (m3 < m12) {
    /* m3 <= a <= 1/2: y = a - 1/2 solves y^3 + P y + Q = 0, P = (3/2)(sum m^2 - 1/2) < 0 */
    const double P = 0.75 * ((m3 - m2) * (m3 - m2) - m1 * (2.0 * (m2 + m3) - m1));
    const double Q = 3.0 * m1 * m2 * m3 * (V - 0.5);
    a = P < 0.0 ? 0.5 + CubicMiddleRoot(P, Q) : 0.5;
  } else {
    a = m3 * V + 0.5 * m12; /* m12 <= a <= 1/2: linear */
  }
  a     = fmin(fmax(a, 0.0), 0.5);
  slope = CubeLowerSlope(m, a);
  if (slope > 0.0) a = fmin(fmax(a - (CubeLower(m, a) - V) / slope, 0.0), 0.5);
  return a;
}

/* m_i = |n_i| h_i sorted ascending and normalised to sum 1; returns the sum M
   (the range of n.x over the cell is [-M/2, M/2]). */
static inline double Canonical(int dim, const double n[3], const double h[3], double m[3])
{
  double M, t;
  m[0] = fabs(n[0]) * h[0];
  m[1] = fabs(n[1]) * h[1];
  m[2] = dim == 3 ? fabs(n[2]) * h[2] : 0.0;
  M    = m[0] + m[1] + m[2];
  if (!(M > 0.0)) return 0.0;
  m[0] /= M;
  m[1] /= M;
  m[2] /= M;
  if (dim == 2) {
    if (m[0] > m[1]) { t = m[0]; m[0] = m[1]; m[1] = t; }
  } else {
    if (m[0] > m[1]) { t = m[0]; m[0] = m[1]; m[1] = t; }
    if (m[1] > m[2]) { t = m[1]; m[1] = m[2]; m[2] = t; }
    if (m[0] > m[1]) { t = m[0]; m[0] = m[1]; m[1] = t; }
  }
  return M;
}

static inline double BoxVolume(int dim, const double h[3])
{
  return dim == 3 ? h[0] * h[1] * h[2] : h[0] * h[1];
}

double PSPlicVolume(int dim, const double n[3], double d, const double h[3])
{
  double       m[3], a, f;
  const double M = Canonical(dim, n, h, m), Vb = BoxVolume(dim, h);

  if (M == 0.0) return d >= 0.0 ? Vb : 0.0;
  /* {n.x <= d} in the cell = {m.s <= a} in the unit cell, a = d/M + 1/2 */
  a = d / M + 0.5;
  if (a <= 0.0) return 0.0;
  if (a >= 1.0) return Vb;
  if (dim == 2) f = a <= 0.5 ? SquareLower(m[0], m[1], a) : 1.0 - SquareLower(m[0], m[1], 1.0 - a);
  else f = a <= 0.5 ? CubeLower(m, a) : 1.0 - CubeLower(m, 1.0 - a);
  return f * Vb;
}

double PSPlicOffset(int dim, const double n[3], double alpha, const double h[3])
{
  double       m[3];
  const double M = Canonical(dim, n, h, m);

  if (M == 0.0) return 0.0;
  if (!(alpha > 0.0)) return -0.5 * M;
  if (alpha >= 1.0) return 0.5 * M;
  if (alpha <= 0.5) return M * ((dim == 2 ? SquareLowerInverse(m[0], m[1], alpha) : CubeLowerInverse(m, alpha)) - 0.5);
  return M * (0.5 - (dim == 2 ? SquareLowerInverse(m[0], m[1], 1.0 - alpha) : CubeLowerInverse(m, 1.0 - alpha)));
}

/* ------------------------------------------------------- Youngs' normal ---- */

int PSPlicYoungsNormal(int dim, const double *a, ptrdiff_t sx, ptrdiff_t sy, ptrdiff_t sz, const double h[3], double n[3])
{
  double g[3] = {0.0, 0.0, 0.0}, len;
  int    j, k;

  if (dim == 2) {
    /* corner gradients averaged: (1,2,1) across, centred difference along, / 8h */
    for (j = -1; j <= 1; j++) {
      const double w = 2.0 - (double)(j * j);
      g[0] += w * (a[sx + j * sy] - a[-sx + j * sy]);
      g[1] += w * (a[j * sx + sy] - a[j * sx - sy]);
    }
    g[0] /= 8.0 * h[0];
    g[1] /= 8.0 * h[1];
  } else {
    /* (1,2,1) x (1,2,1) across, centred difference along, / 32h */
    for (k = -1; k <= 1; k++)
      for (j = -1; j <= 1; j++) {
        const double w = (2.0 - (double)(j * j)) * (2.0 - (double)(k * k));
        g[0] += w * (a[sx + j * sy + k * sz] - a[-sx + j * sy + k * sz]);
        g[1] += w * (a[j * sx + sy + k * sz] - a[j * sx - sy + k * sz]);
        g[2] += w * (a[j * sx + k * sy + sz] - a[j * sx + k * sy - sz]);
      }
    g[0] /= 32.0 * h[0];
    g[1] /= 32.0 * h[1];
    g[2] /= 32.0 * h[2];
  }
  if (fabs(g[0]) * h[0] <= PS_PLIC_FLAT && fabs(g[1]) * h[1] <= PS_PLIC_FLAT && (dim == 2 || fabs(g[2]) * h[2] <= PS_PLIC_FLAT)) {
    n[0] = 1.0;
    n[1] = n[2] = 0.0;
    return 1;
  }
  len  = sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
  n[0] = -g[0] / len;
  n[1] = -g[1] / len;
  n[2] = -g[2] / len;
  return 0;
}

/* ------------------------------------------- offsets on a polytope ---- */

/* The exact polynomial volume(u) on [u0, u1] (no vertex height inside) from its
   values y[0..deg] at u0 + i (u1 - u0)/deg, in Newton's forward-difference form
   in x = deg (u - u0)/(u1 - u0); the root of volume(u) = target by Newton's
   method safeguarded by bisection (volume is non-decreasing). */
static double PolynomialRoot(int deg, const double y[4], double u0, double u1, double target)
{
  const double D1 = y[1] - y[0], D2 = y[2] - 2.0 * y[1] + y[0];
  const double D3 = deg == 3 ? y[3] - 3.0 * y[2] + 3.0 * y[1] - y[0] : 0.0;
  const double X = (double)deg, yX = y[deg];
  double       lo = 0.0, hi = X, x;
  int          it;

  if (target <= y[0]) return u0;
  if (target >= yX) return u1;
  x = (target - y[0]) / (yX - y[0]) * X;
  for (it = 0; it < 60; it++) {
    /* p = y0 + D1 x + D2 x(x-1)/2 + D3 x(x-1)(x-2)/6 */
    const double p  = y[0] + x * (D1 + (x - 1.0) * (0.5 * D2 + (x - 2.0) * D3 / 6.0)) - target;
    const double dp = D1 + 0.5 * D2 * (2.0 * x - 1.0) + D3 * (3.0 * x * x - 6.0 * x + 2.0) / 6.0;
    double       xn;
    if (p < 0.0) lo = x;
    else hi = x;
    xn = dp > 0.0 ? x - p / dp : 0.5 * (lo + hi);
    if (!(xn > lo && xn < hi)) xn = 0.5 * (lo + hi);
    if (fabs(xn - x) <= 1e-15 * X || hi - lo <= 1e-15 * X) {
      x = xn;
      break;
    }
    x = xn;
  }
  return u0 + (u1 - u0) * (x / X);
}

/* Sort v[0..k-1] ascending and drop repeats; returns the new count. */
static int SortUnique(double *v, int k)
{
  int i, j, u = 0;
  for (i = 1; i < k; i++) {
    const double t = v[i];
    for (j = i; j > 0 && v[j - 1] > t; j--) v[j] = v[j - 1];
    v[j] = t;
  }
  for (i = 0; i < k; i++)
    if (u == 0 || v[i] > v[u - 1]) v[u++] = v[i];
  return u;
}

/* Volume of P ∩ {n.x <= u}; negative on a clipper overflow. */
static double CutVolume2(const PSPoly2 *P, const double n[3], double u)
{
  PSPoly2 T;
  PSPlane pl = {{n[0], n[1], 0.0}, u};
  double  mo[3];
  T.nv = P->nv;
  memcpy(T.x, P->x, sizeof(P->x[0]) * (size_t)P->nv);
  if (PSPoly2Clip(&T, &pl) < 0) return -1.0;
  PSPoly2Moments(&T, mo);
  return mo[0];
}

static double CutVolume3(const PSPoly3 *P, const double n[3], double u)
{
  PSPoly3 T;
  PSPlane pl = {{n[0], n[1], n[2]}, u};
  double  mo[4];
  T.nv = P->nv;
  memcpy(T.v, P->v, sizeof(P->v[0]) * (size_t)P->nv);
  if (PSPoly3Clip(&T, &pl) < 0) return -1.0;
  PSPoly3Moments(&T, mo);
  return mo[0];
}

/* The offset u with vol(P ∩ {n.x <= u}) = target, P (P2 in 2D, P3 in 3D) of
   volume VP, what the previous materials R left of the cell (sizes h, volume
   Vb = VP + |R|).  Since |B ∩ {n.x <= u}| - |R| <= vol(P ∩ {n.x <= u}) <=
   |B ∩ {n.x <= u}|, the closed-form offsets on the whole cell for the fractions
   (target + |R|)/Vb and target/Vb bracket u; each is the answer itself when R
   lies wholly below, or wholly above, the plane (layered materials), which one
   clip each tells.  Otherwise a binary search over the vertex heights inside
   the bracket finds the interval where the volume is one polynomial, and its
   exact interpolant gives u.  Returns 0, or -1 on a clipper overflow. */
static int PolytopeOffset(int dim, const PSPoly2 *P2, const PSPoly3 *P3, double VP, const double h[3], const double n[3], double target, double *u)
{
  const double Vb = BoxVolume(dim, h), tol = PS_PLIC_LAYER_TOL * Vb;
  double       hts[PS_MAXV3], y[4], ulo, uhi, flo, fhi;
  int          nv = dim == 2 ? P2->nv : P3->nv, nh, lo, hi, i;

  if (nv == 0) { /* nothing left: the plane through the cell's lowest vertex */
    *u = PSPlicOffset(dim, n, 0.0, h);
    return 0;
  }
  for (i = 0; i < nv; i++) {
    const double *x = dim == 2 ? P2->x[i] : P3->v[i].x;
    hts[i]          = dim == 2 ? n[0] * x[0] + n[1] * x[1] : n[0] * x[0] + n[1] * x[1] + n[2] * x[2];
  }
  nh = SortUnique(hts, nv);
  if (target <= 0.0) {
    *u = hts[0];
    return 0;
  }
  if (target >= VP) {
    *u = hts[nh - 1];
    return 0;
  }
  /* the bracket from the whole cell; R below the plane first (the usual order
     when material k's normal is that of materials 0..k together) */
  uhi = PSPlicOffset(dim, n, fmin((target + (Vb - VP)) / Vb, 1.0), h);
  fhi = dim == 2 ? CutVolume2(P2, n, uhi) : CutVolume3(P3, n, uhi);
  if (fhi < 0.0) return -1;
  if (fabs(fhi - target) <= tol) {
    *u = uhi;
    return 0;
  }
  ulo = PSPlicOffset(dim, n, target / Vb, h);
  flo = dim == 2 ? CutVolume2(P2, n, ulo) : CutVolume3(P3, n, ulo);
  if (flo < 0.0) return -1;
  if (fabs(flo - target) <= tol) {
    *u = ulo;
    return 0;
  }
  /* the vertex heights strictly inside (ulo, uhi), by binary search */
  for (lo = 0; lo < nh && hts[lo] <= ulo; lo++) {}
  for (hi = nh - 1; hi >= 0 && hts[hi] >= uhi; hi--) {}
  /* hts[lo..hi] are inside; search them keeping f(ulo) < target <= f(uhi) */
  while (lo <= hi) {
    const int    mid = (lo + hi) / 2;
    const double f   = dim == 2 ? CutVolume2(P2, n, hts[mid]) : CutVolume3(P3, n, hts[mid]);
    if (f < 0.0) return -1;
    if (f < target) {
      ulo = hts[mid];
      flo = f;
      lo  = mid + 1;
    } else {
      uhi = hts[mid];
      fhi = f;
      hi  = mid - 1;
    }
  }
  /* no vertex height inside (ulo, uhi): the volume is a polynomial of degree dim there */
  y[0]   = flo;
  y[dim] = fhi;
  for (i = 1; i < dim; i++) {
    const double ui = ulo + (uhi - ulo) * ((double)i / dim);
    y[i]            = dim == 2 ? CutVolume2(P2, n, ui) : CutVolume3(P3, n, ui);
    if (y[i] < 0.0) return -1;
  }
  *u = PolynomialRoot(dim, y, ulo, uhi, target);
  return 0;
}

/* ------------------------------------------------ nested dissection ---- */

int PSPlicReconstruct(int dim, const double h[3], int nmat, const double alpha[], const double n[][3], PSPlicCell *c)
{
  PSPoly2      P2;
  PSPoly3      P3;
  const double lo[3] = {-0.5 * h[0], -0.5 * h[1], -0.5 * (dim == 3 ? h[2] : 0.0)};
  const double hi[3] = {0.5 * h[0], 0.5 * h[1], 0.5 * (dim == 3 ? h[2] : 0.0)};
  double       Vb, mo[4];
  int          k;

  if ((dim != 2 && dim != 3) || nmat < 1 || nmat > PS_PLIC_MAXMAT) return -1;
  c->dim  = dim;
  c->nmat = nmat;
  c->h[0] = h[0];
  c->h[1] = h[1];
  c->h[2] = dim == 3 ? h[2] : 0.0;
  for (k = 0; k < nmat - 1; k++) {
    c->n[k][0] = n[k][0];
    c->n[k][1] = n[k][1];
    c->n[k][2] = dim == 3 ? n[k][2] : 0.0;
  }
  if (nmat == 1) return 0;
  /* the first plane cuts the whole box: closed form */
  c->d[0] = PSPlicOffset(dim, c->n[0], alpha[0], c->h);
  if (nmat == 2) return 0;
  /* the rest: on what the previous materials left, with the clipper */
  Vb = BoxVolume(dim, c->h);
  if (dim == 2) PSPoly2InitBox(&P2, lo, hi);
  else PSPoly3InitBox(&P3, lo, hi);
  for (k = 0; k < nmat - 1; k++) {
    const double *nk = c->n[k];
    if (k > 0) {
      const double target = fmax(alpha[k], 0.0) * Vb;
      if (dim == 2) PSPoly2Moments(&P2, mo);
      else PSPoly3Moments(&P3, mo);
      if (PolytopeOffset(dim, &P2, &P3, mo[0], c->h, nk, target, &c->d[k])) return -1;
    }
    if (k < nmat - 2) { /* keep the complement {n_k.x >= d_k} for the next material */
      const PSPlane comp = {{-nk[0], -nk[1], -nk[2]}, -c->d[k]};
      if ((dim == 2 ? PSPoly2Clip(&P2, &comp) : PSPoly3Clip(&P3, &comp)) < 0) return -1;
    }
  }
  return 0;
}

/* ------------------------------------------------------ slab volumes ---- */

int PSPlicSlabVolumes(const PSPlicCell *c, int axis, int side, double w, double vol[])
{
  const int dim = c->dim, nmat = c->nmat;
  double    lo[3], hi[3], Vs, sum = 0.0;
  int       i, k;

  if ((dim != 2 && dim != 3) || axis < 0 || axis >= dim || (side != -1 && side != 1) || nmat < 1 || nmat > PS_PLIC_MAXMAT) return -1;
  w  = fmin(fmax(w, 0.0), c->h[axis]);
  Vs = w;
  for (i = 0; i < dim; i++) {
    lo[i] = -0.5 * c->h[i];
    hi[i] = 0.5 * c->h[i];
    if (i != axis) Vs *= c->h[i];
  }
  if (side > 0) lo[axis] = hi[axis] - w;
  else hi[axis] = lo[axis] + w;
  if (nmat == 1) {
    vol[0] = Vs;
    return 0;
  }
  if (nmat == 2) {
    /* the slab is a box of sizes hs centred at cs: the closed form there */
    double       hs[3] = {c->h[0], c->h[1], c->h[2]};
    const double cs    = 0.5 * (lo[axis] + hi[axis]);
    hs[axis]           = w;
    vol[0]             = fmin(PSPlicVolume(dim, c->n[0], c->d[0] - c->n[0][axis] * cs, hs), Vs);
    vol[1]             = Vs - vol[0];
    return 0;
  }
  /* more planes: clip the slab by each material's region in turn */
  if (dim == 2) {
    PSPoly2 S, T;
    double  mo[3];
    PSPoly2InitBox(&S, lo, hi);
    for (k = 0; k < nmat - 1; k++) {
      const double *nk   = c->n[k];
      const PSPlane own  = {{nk[0], nk[1], 0.0}, c->d[k]};
      const PSPlane comp = {{-nk[0], -nk[1], 0.0}, -c->d[k]};
      T.nv               = S.nv;
      memcpy(T.x, S.x, sizeof(S.x[0]) * (size_t)S.nv);
      if (PSPoly2Clip(&T, &own) < 0) return -1;
      PSPoly2Moments(&T, mo);
      vol[k] = mo[0];
      sum += vol[k];
      if (k < nmat - 2 && PSPoly2Clip(&S, &comp) < 0) return -1;
    }
  } else {
    PSPoly3 S, T;
    double  mo[4];
    PSPoly3InitBox(&S, lo, hi);
    for (k = 0; k < nmat - 1; k++) {
      const double *nk   = c->n[k];
      const PSPlane own  = {{nk[0], nk[1], nk[2]}, c->d[k]};
      const PSPlane comp = {{-nk[0], -nk[1], -nk[2]}, -c->d[k]};
      T.nv               = S.nv;
      memcpy(T.v, S.v, sizeof(S.v[0]) * (size_t)S.nv);
      if (PSPoly3Clip(&T, &own) < 0) return -1;
      PSPoly3Moments(&T, mo);
      vol[k] = mo[0];
      sum += vol[k];
      if (k < nmat - 2 && PSPoly3Clip(&S, &comp) < 0) return -1;
    }
  }
  vol[nmat - 1] = fmax(Vs - sum, 0.0);
  return 0;
}
