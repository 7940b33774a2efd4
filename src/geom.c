/*
  geom.c - body geometry: bounding boxes, volumes, region half-spaces against a
  box, and the exact piece kernel

      piece = box  ∩  (every "in" region)  \  (every "sub" region)

  that insertion (one ply of one body, minus higher-priority bodies) and the
  overlap check (body a ∩ body b) share.  No PETSc objects are made here.
*/
#include <math.h>
#include <string.h>
#include "geom.h"

/* --------------------------------------------------------- half-spaces -- */

/* Test {n.x <= d} (absolute d) against the box with centre c and half sides
   a; a cutting plane is appended relative to c (the reference point of every
   clip).  PS_IN when the box lies inside (to PS_TOUCH_TOL of the box size),
   PS_OUT when outside. */
#define PS_INLINE static inline __attribute__((always_inline))
PS_INLINE PSCut PlaneTest(const int dim, const double n[3], double d, const double c[3], const double a[3], PSPlane *pl, int *np)
{
  double ext = 0.0, dr = d;
  int    i;
  for (i = 0; i < dim; i++) {
    ext += fabs(n[i]) * a[i];
    dr -= n[i] * c[i];
  }
  if (ext <= dr + PS_TOUCH_TOL * ext) return PS_IN;
  if (-ext >= dr - PS_TOUCH_TOL * ext) return PS_OUT;
  pl[*np].n[0] = n[0];
  pl[*np].n[1] = n[1];
  pl[*np].n[2] = dim == 3 ? n[2] : 0.0;
  pl[*np].d    = dr;
  (*np)++;
  return PS_CUT;
}

/* The axes of an oriented box that bound it in dim dimensions: 2D uses the
   frame's axes 1 and 3 (the 1-3 plane is the simulation plane). */
static inline int BoxAxes(PetscInt dim, int ax[3])
{
  if (dim == 2) {
    ax[0] = 0;
    ax[1] = 2;
    return 2;
  }
  ax[0] = 0;
  ax[1] = 1;
  ax[2] = 2;
  return 3;
}

/* Region against a box: flat planes exact (precomputed in PSRegionSetup), a
   curved surface by one plane (see PSPieceMoments for when it is used).
   *curved is set when the box is cut by a curved surface and is larger than the
   region's h_fine: the caller bisects.  The cutting planes are relative to the
   box centre. */
PS_INLINE PSCut RegionPlanes(const int dim, const PSRegion *r, const double lo[3], const double hi[3], PSPlane *pl, int *np, int *curved)
{
  const PSBody *B = r->body;
  double        c[3] = {0, 0, 0}, a[3] = {0, 0, 0}, hmax = 0.0;
  int           i, k;

  *np     = 0;
  *curved = 0;
  for (i = 0; i < dim; i++) {
    c[i] = 0.5 * (lo[i] + hi[i]);
    a[i] = 0.5 * (hi[i] - lo[i]);
    hmax = PetscMax(hmax, hi[i] - lo[i]);
  }
  for (k = 0; k < r->nflat; k++)
    if (PlaneTest(dim, r->flat[k].n, r->flat[k].d, c, a, pl, np) == PS_OUT) return PS_OUT;
  switch (B->kind) {
  case PS_BODY_LAMINATE:
  case PS_BODY_BOX:
    return *np ? PS_CUT : PS_IN;
  case PS_BODY_SPHERE: {
    const double R = B->radius;
    double       dn2 = 0.0, df2 = 0.0, u[3] = {0, 0, 0}, un = 0.0, sag = 0.0;
    /* nearest point of the box by clamping, farthest at a corner */
    for (i = 0; i < dim; i++) {
      const double q = PetscMin(PetscMax(B->center[i], lo[i]), hi[i]) - B->center[i];
      const double f = PetscMax(fabs(lo[i] - B->center[i]), fabs(hi[i] - B->center[i]));
      dn2 += q * q;
      df2 += f * f;
      u[i] = c[i] - B->center[i];
      un += u[i] * u[i];
    }
    if (dn2 >= R * R) return PS_OUT;
    if (df2 <= R * R) return PS_IN;
    if (hmax > r->h_fine || un == 0.0) {
      /* too coarse for a plane (or the box holds the centre): bisect */
      *curved = 1;
      return PS_CUT;
    }
    /* the plane normal to the radius through the box centre, moved in from the
       tangent plane by the mean sag <rho^2>/(2R) over the box's lateral spread,
       <rho^2> = sum_i h_i^2 (1 - u_i^2) / 12 */
    un = sqrt(un);
    for (i = 0; i < dim; i++) {
      u[i] /= un;
      sag += 4.0 * a[i] * a[i] * (1.0 - u[i] * u[i]) / 12.0;
    }
    sag /= 2.0 * R;
    {
      double d = R - sag;
      for (i = 0; i < dim; i++) d += u[i] * B->center[i];
      if (PlaneTest(dim, u, d, c, a, pl, np) == PS_OUT) return PS_OUT;
    }
    return *np ? PS_CUT : PS_IN;
  }
  case PS_BODY_CYLINDER: {
    const double *ax = B->axis, R = B->radius;
    /* caps (and the 2D section's sides) were tested as flat planes above */
    if (dim == 2) {
      return *np ? PS_CUT : PS_IN;
    } else {
      /* mantle: distance to the axis line is convex, so its maximum over the
         box is at a corner; its minimum is bounded below by the centre's
         distance less the half diagonal */
      double dmax2 = 0.0, w[3], wa, dc, hd, u[3], un = 0.0, tt[3], sag = 0.0;
      int    v;
      for (v = 0; v < 8; v++) {
        double q[3], qa, d2 = 0.0;
        for (i = 0; i < 3; i++) q[i] = ((v >> i) & 1 ? hi[i] : lo[i]) - B->center[i];
        qa = q[0] * ax[0] + q[1] * ax[1] + q[2] * ax[2];
        for (i = 0; i < 3; i++) d2 += (q[i] - qa * ax[i]) * (q[i] - qa * ax[i]);
        dmax2 = PetscMax(dmax2, d2);
      }
      for (i = 0; i < 3; i++) w[i] = c[i] - B->center[i];
      wa = w[0] * ax[0] + w[1] * ax[1] + w[2] * ax[2];
      for (i = 0; i < 3; i++) {
        u[i] = w[i] - wa * ax[i];
        un += u[i] * u[i];
      }
      dc = sqrt(un);
      hd = sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
      if (dc - hd >= R) return PS_OUT;
      if (dmax2 <= R * R) return *np ? PS_CUT : PS_IN;
      if (hmax > r->h_fine || dc == 0.0) {
        *curved = 1;
        return PS_CUT;
      }
      /* plane normal to the radius through the box centre, moved in by the
         mean sag over the spread along the circumference t = axis x u */
      for (i = 0; i < 3; i++) u[i] /= dc;
      tt[0] = ax[1] * u[2] - ax[2] * u[1];
      tt[1] = ax[2] * u[0] - ax[0] * u[2];
      tt[2] = ax[0] * u[1] - ax[1] * u[0];
      for (i = 0; i < 3; i++) sag += 4.0 * a[i] * a[i] * tt[i] * tt[i] / 12.0;
      sag /= 2.0 * R;
      {
        double d = R - sag;
        for (i = 0; i < 3; i++) d += u[i] * B->center[i];
        if (PlaneTest(dim, u, d, c, a, pl, np) == PS_OUT) return PS_OUT;
      }
      return *np ? PS_CUT : PS_IN;
    }
  }
  }
  return PS_OUT;
}

/* OUT, IN or CUT of a region against a box, without the planes.  Flat
   regions need only the extent of the box along each face normal. */
PSCut PSRegionClassify(PetscInt dim, const PSRegion *r, const double lo[3], const double hi[3])
{
  PSPlane pl[PS_MAX_REGION_PLANES];
  int     np, curved, k, i, cut = 0;

  if (r->body->kind == PS_BODY_LAMINATE || r->body->kind == PS_BODY_BOX) {
    for (k = 0; k < r->nflat; k++) {
      double ext = 0.0, dr = r->flat[k].d;
      for (i = 0; i < dim; i++) {
        const double c = 0.5 * (lo[i] + hi[i]), a = 0.5 * (hi[i] - lo[i]);
        ext += fabs(r->flat[k].n[i]) * a;
        dr -= r->flat[k].n[i] * c;
      }
      if (-ext >= dr - PS_TOUCH_TOL * ext) return PS_OUT;
      if (ext > dr + PS_TOUCH_TOL * ext) cut = 1;
    }
    return cut ? PS_CUT : PS_IN;
  }
  return dim == 3 ? RegionPlanes(3, r, lo, hi, pl, &np, &curved) : RegionPlanes(2, r, lo, hi, pl, &np, &curved);
}

/* The size of box at which a curved cut is replaced by its plane.  With the
   sag-corrected plane the measured relative volume error falls as
   about 0.15 (h/R)^3.3 for spheres (doubly curved: the sag correction cancels
   most of the error) and as about 1e-3 (h/R)^2 for disks and cylinder mantles
   (singly curved).  The choices below keep it under tol with a margin of 4 or
   more (tests/test_insert.py checks tolerances 1e-3 to 1e-9). */
void PSRegionSetup(const PSScene *scene, const PSBody *B, PetscInt ply, PetscReal cell_h, PSRegion *r)
{
  const PetscInt dim = scene->dim;
  int            i, k;

  r->body   = B;
  r->ply    = ply;
  r->nflat  = 0;
  r->h_fine = PETSC_MAX_REAL;
  if (B->kind == PS_BODY_SPHERE || (B->kind == PS_BODY_CYLINDER && dim == 3)) {
    if (B->kind == PS_BODY_SPHERE && dim == 3) r->h_fine = 0.5 * B->radius * pow(B->volume_tolerance, 0.25);
    else r->h_fine = 0.5 * B->radius * sqrt(1e3 * B->volume_tolerance);
    /* never refine deeper than PS_MAX_LEVEL below the sub-cell */
    r->h_fine = PetscMax(r->h_fine, cell_h / (double)(1 << PS_MAX_LEVEL));
  }
  /* the flat faces, as half-spaces {n.x <= d} */
#define ADD_PLANE(nx, ny, nz, dd) \
  do { \
    r->flat[r->nflat].n[0] = (nx); \
    r->flat[r->nflat].n[1] = (ny); \
    r->flat[r->nflat].n[2] = (nz); \
    r->flat[r->nflat].d    = (dd); \
    r->nflat++; \
  } while (0)
  if (B->kind == PS_BODY_LAMINATE || B->kind == PS_BODY_BOX) {
    /* an oriented box: lb <= e_a.(x - origin) <= ub along its bounding axes;
       a ply replaces the axis-3 bounds by its interfaces */
    int ax[3], na = BoxAxes(dim, ax);
    for (k = na - 1; k >= 0; k--) { /* axis 3 first: the slab rejects most boxes */
      const double *e  = B->e[ax[k]];
      double        lb = 0.0, ub = B->size[ax[k]], eo = 0.0;
      if (ax[k] == 2 && ply >= 0) {
        lb = B->z[ply];
        ub = B->z[ply + 1];
      }
      for (i = 0; i < dim; i++) eo += e[i] * B->origin[i];
      ADD_PLANE(e[0], e[1], e[2], eo + ub);
      ADD_PLANE(-e[0], -e[1], -e[2], -(eo + lb));
    }
  } else if (B->kind == PS_BODY_CYLINDER) {
    /* caps: 0 <= a.(x - base) <= L; a 2D cylinder is its axial section, |t.(x - base)| <= R */
    const double *a  = B->axis;
    double        s0 = 0.0;
    for (i = 0; i < dim; i++) s0 += a[i] * B->center[i];
    ADD_PLANE(a[0], a[1], a[2], s0 + B->length);
    ADD_PLANE(-a[0], -a[1], -a[2], -s0);
    if (dim == 2) {
      const double tb = -a[1] * B->center[0] + a[0] * B->center[1];
      ADD_PLANE(-a[1], a[0], 0.0, tb + B->radius);
      ADD_PLANE(a[1], -a[0], 0.0, -(tb - B->radius));
    }
  }
#undef ADD_PLANE
}

/* ---------------------------------------------------------- piece kernel -- */

typedef struct {
  int     np;
  PSPlane pl[PS_MAX_REGION_PLANES];
} PSPlaneSet;

/* 2D: clip P by the planes of sub[j..], keep only what lies outside all of them */
static void Subtract2(PSPoly2 *P, int j, int nsub, const PSPlaneSet *sub, const double ref[3], double m[4])
{
  PSPoly2 Q;
  int     i;
  if (j == nsub) {
    double mm[3];
    PSPoly2Moments(P, mm);
    m[0] += mm[0];
    m[1] += mm[1] + mm[0] * ref[0];
    m[2] += mm[2] + mm[0] * ref[1];
    return;
  }
  /* P \ S = union over i of P ∩ h_1 ∩ ... ∩ h_{i-1} ∩ not h_i (disjoint) */
  for (i = 0; i < sub[j].np; i++) {
    PSPlane flip = sub[j].pl[i];
    flip.n[0] = -flip.n[0];
    flip.n[1] = -flip.n[1];
    flip.d    = -flip.d;
    Q         = *P;
    if (PSPoly2Clip(&Q, &flip) > 0) Subtract2(&Q, j + 1, nsub, sub, ref, m);
    if (PSPoly2Clip(P, &sub[j].pl[i]) <= 0) return;
  }
}

static void Subtract3(PSPoly3 *P, int j, int nsub, const PSPlaneSet *sub, const double ref[3], double m[4])
{
  PSPoly3 Q;
  int     i;
  if (j == nsub) {
    double mm[4];
    PSPoly3Moments(P, mm);
    m[0] += mm[0];
    m[1] += mm[1] + mm[0] * ref[0];
    m[2] += mm[2] + mm[0] * ref[1];
    m[3] += mm[3] + mm[0] * ref[2];
    return;
  }
  for (i = 0; i < sub[j].np; i++) {
    PSPlane flip = sub[j].pl[i];
    flip.n[0] = -flip.n[0];
    flip.n[1] = -flip.n[1];
    flip.n[2] = -flip.n[2];
    flip.d    = -flip.d;
    Q         = *P;
    if (PSPoly3Clip(&Q, &flip) > 0) Subtract3(&Q, j + 1, nsub, sub, ref, m);
    if (PSPoly3Clip(P, &sub[j].pl[i]) <= 0) return;
  }
}

static void PieceMoments2(const double lo[3], const double hi[3], int nin, const PSRegion *in, int nsub, const PSRegion *sub, double m[4]);
static void PieceMoments3(const double lo[3], const double hi[3], int nin, const PSRegion *in, int nsub, const PSRegion *sub, double m[4]);

/* Adds to m[0] the area/volume and to m[1..dim] the first moment of
   box ∩ in[0] ∩ ... ∩ in[nin-1] \ (sub[0] ∪ ... ∪ sub[nsub-1]).
   Curved regions bisect the box until it is no larger than their h_fine.
   Written once for both dimensions, compiled twice with dim a constant. */
PS_INLINE void PieceMomentsT(const int dim, const double lo[3], const double hi[3], int nin, const PSRegion *in, int nsub, const PSRegion *sub, double m[4])
{
  PSPlane    pin[PS_MAX_REGION_PLANES * 2];
  PSPlaneSet ps[PS_MAX_SUB];
  PSRegion   in2[2], sub2[PS_MAX_SUB];
  double     ref[3] = {0, 0, 0};
  int        i, k, npin = 0, nin2 = 0, nsub2 = 0, refine = 0;

  for (i = 0; i < dim; i++) ref[i] = 0.5 * (lo[i] + hi[i]);
  /* classify; keep only the regions that cut this box */
  for (k = 0; k < nin; k++) {
    int   np, curved;
    PSCut s = RegionPlanes(dim, &in[k], lo, hi, pin + npin, &np, &curved);
    if (s == PS_OUT) return;
    if (s == PS_IN) continue;
    npin += np;
    refine |= curved;
    in2[nin2++] = in[k];
  }
  for (k = 0; k < nsub; k++) {
    int   curved;
    PSCut s = RegionPlanes(dim, &sub[k], lo, hi, ps[nsub2].pl, &ps[nsub2].np, &curved);
    if (s == PS_IN) return;
    if (s == PS_OUT) continue;
    refine |= curved;
    sub2[nsub2++] = sub[k];
  }
  if (refine) {
    /* bisect in every direction and recurse on the children */
    double clo[3] = {0, 0, 0}, chi[3] = {0, 0, 0};
    int    c, nc = 1 << dim;
    for (c = 0; c < nc; c++) {
      for (i = 0; i < dim; i++) {
        const double mid = 0.5 * (lo[i] + hi[i]);
        clo[i]           = (c >> i) & 1 ? mid : lo[i];
        chi[i]           = (c >> i) & 1 ? hi[i] : mid;
      }
      if (dim == 2) PieceMoments2(clo, chi, nin2, in2, nsub2, sub2, m);
      else PieceMoments3(clo, chi, nin2, in2, nsub2, sub2, m);
    }
    return;
  }
  /* a slab (a ply's two faces, or one face) through the box and nothing to
     take away: the closed form (clip.c), where it keeps its digits */
  if (!nsub2 && (npin == 1 || (npin == 2 && pin[1].n[0] == -pin[0].n[0] && pin[1].n[1] == -pin[0].n[1] && pin[1].n[2] == -pin[0].n[2]))) {
    double A[3] = {0, 0, 0}, mm[4];
    for (i = 0; i < dim; i++) A[i] = 0.5 * (hi[i] - lo[i]);
    if (PSBoxSlabMoments(dim, A, pin[0].n, npin == 2 ? -pin[1].d : -INFINITY, pin[0].d, mm)) {
      m[0] += mm[0];
      for (i = 0; i < dim; i++) m[1 + i] += mm[1 + i] + mm[0] * ref[i];
      return;
    }
  }
  /* planar: clip the box by the in-planes, then take away the sub regions */
  {
    double rlo[3] = {0, 0, 0}, rhi[3] = {0, 0, 0};
    for (i = 0; i < dim; i++) {
      rlo[i] = lo[i] - ref[i];
      rhi[i] = hi[i] - ref[i];
    }
    if (dim == 2) {
      PSPoly2 P;
      PSPoly2InitBox(&P, rlo, rhi);
      for (k = 0; k < npin; k++)
        if (PSPoly2Clip(&P, &pin[k]) <= 0) return;
      if (!nsub2 && !npin) {
        const double V = (hi[0] - lo[0]) * (hi[1] - lo[1]);
        m[0] += V;
        m[1] += V * ref[0];
        m[2] += V * ref[1];
        return;
      }
      Subtract2(&P, 0, nsub2, ps, ref, m);
    } else {
      PSPoly3 P;
      if (!nsub2 && !npin) {
        const double V = (hi[0] - lo[0]) * (hi[1] - lo[1]) * (hi[2] - lo[2]);
        m[0] += V;
        m[1] += V * ref[0];
        m[2] += V * ref[1];
        m[3] += V * ref[2];
        return;
      }
      PSPoly3InitBox(&P, rlo, rhi);
      for (k = 0; k < npin; k++)
        if (PSPoly3Clip(&P, &pin[k]) <= 0) return;
      Subtract3(&P, 0, nsub2, ps, ref, m);
    }
  }
}

static void PieceMoments2(const double lo[3], const double hi[3], int nin, const PSRegion *in, int nsub, const PSRegion *sub, double m[4])
{
  PieceMomentsT(2, lo, hi, nin, in, nsub, sub, m);
}

static void PieceMoments3(const double lo[3], const double hi[3], int nin, const PSRegion *in, int nsub, const PSRegion *sub, double m[4])
{
  PieceMomentsT(3, lo, hi, nin, in, nsub, sub, m);
}

void PSPieceMoments(PetscInt dim, const double lo[3], const double hi[3], int nin, const PSRegion *in, int nsub, const PSRegion *sub, double m[4])
{
  if (dim == 2) PieceMoments2(lo, hi, nin, in, nsub, sub, m);
  else PieceMoments3(lo, hi, nin, in, nsub, sub, m);
}

/* ------------------------------------------------------- whole bodies -- */

/* Where a point lies in a body, for the lattice fill: -2 outside, -1 inside a
   body without plies, else the ply containing it.  Faces are half-open
   (lower bound in, upper bound out; a curved surface's points on it are out),
   so two bodies that touch, or two plies that share an interface, never both
   claim a point; with the same expressions on every rank the answer does not
   depend on the rank count. */
PetscInt PSBodyLocatePoint(PetscInt dim, const PSBody *B, const double x[3])
{
  double   r[3] = {0, 0, 0}, q, r2 = 0.0;
  PetscInt i;

  switch (B->kind) {
  case PS_BODY_LAMINATE:
  case PS_BODY_BOX: {
    int      ax[3], na = BoxAxes(dim, ax), k;
    PetscInt ply = -1;
    for (i = 0; i < dim; i++) r[i] = x[i] - B->origin[i];
    for (k = 0; k < na; k++) {
      const double *e = B->e[ax[k]];
      q               = 0.0;
      for (i = 0; i < dim; i++) q += e[i] * r[i];
      if (q < 0.0 || q >= B->size[ax[k]]) return -2;
      if (ax[k] == 2 && B->kind == PS_BODY_LAMINATE) {
        /* the ply with z_p <= q < z_{p+1} (z_0 = 0 <= q < z_nply = size[2]
           holds here): bisection over the interfaces */
        PetscInt hi = B->nply;
        ply         = 0;
        while (hi - ply > 1) {
          const PetscInt mid = (ply + hi) / 2;
          if (q >= B->z[mid]) ply = mid;
          else hi = mid;
        }
      }
    }
    return ply;
  }
  case PS_BODY_SPHERE:
    for (i = 0; i < dim; i++) r2 += (x[i] - B->center[i]) * (x[i] - B->center[i]);
    return r2 < B->radius * B->radius ? -1 : -2;
  case PS_BODY_CYLINDER: {
    const double *a = B->axis;
    for (i = 0; i < dim; i++) r[i] = x[i] - B->center[i];
    q = 0.0;
    for (i = 0; i < dim; i++) q += a[i] * r[i];
    if (q < 0.0 || q >= B->length) return -2;
    if (dim == 2) {
      /* the axial section: -R <= t.(x - base) < R, t the in-plane normal */
      const double t = -a[1] * r[0] + a[0] * r[1];
      return (t >= -B->radius && t < B->radius) ? -1 : -2;
    }
    for (i = 0; i < 3; i++) r2 += (r[i] - q * a[i]) * (r[i] - q * a[i]);
    return r2 < B->radius * B->radius ? -1 : -2;
  }
  }
  return -2;
}

PetscErrorCode PSBodyBoundingBox(const PSScene *scene, PetscInt b, PetscReal lo[3], PetscReal hi[3])
{
  const PSBody *B   = &scene->bodies[b];
  PetscInt      dim = scene->dim, i;

  PetscFunctionBeginUser;
  for (i = 0; i < 3; i++) {
    lo[i] = i < dim ? PETSC_MAX_REAL : 0.0;
    hi[i] = i < dim ? -PETSC_MAX_REAL : 0.0;
  }
  switch (B->kind) {
  case PS_BODY_LAMINATE:
  case PS_BODY_BOX: {
    int ax[3], na = BoxAxes(dim, ax), v, k;
    for (v = 0; v < (1 << na); v++) {
      double x[3] = {B->origin[0], B->origin[1], B->origin[2]};
      for (k = 0; k < na; k++)
        if ((v >> k) & 1)
          for (i = 0; i < dim; i++) x[i] += B->size[ax[k]] * B->e[ax[k]][i];
      for (i = 0; i < dim; i++) {
        lo[i] = PetscMin(lo[i], x[i]);
        hi[i] = PetscMax(hi[i], x[i]);
      }
    }
  } break;
  case PS_BODY_SPHERE:
    for (i = 0; i < dim; i++) {
      lo[i] = B->center[i] - B->radius;
      hi[i] = B->center[i] + B->radius;
    }
    break;
  case PS_BODY_CYLINDER:
    for (i = 0; i < dim; i++) {
      const double e0 = B->center[i], e1 = B->center[i] + B->length * B->axis[i];
      /* 3D: a disk of radius R normal to the axis spans R sqrt(1 - a_i^2); 2D: the
         section's half width R along the in-plane normal spans R |a_j| */
      const double w = dim == 3 ? B->radius * sqrt(PetscMax(0.0, 1.0 - B->axis[i] * B->axis[i])) : B->radius * fabs(B->axis[1 - i]);
      lo[i]          = PetscMin(e0, e1) - w;
      hi[i]          = PetscMax(e0, e1) + w;
    }
    break;
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscReal PSBodyVolume(const PSScene *scene, PetscInt b)
{
  const PSBody *B = &scene->bodies[b];
  switch (B->kind) {
  case PS_BODY_LAMINATE:
  case PS_BODY_BOX:
    return scene->dim == 3 ? B->size[0] * B->size[1] * B->size[2] : B->size[0] * B->size[2];
  case PS_BODY_SPHERE:
    return scene->dim == 3 ? 4.0 / 3.0 * PETSC_PI * PetscPowReal(B->radius, 3) : PETSC_PI * B->radius * B->radius;
  case PS_BODY_CYLINDER:
    return scene->dim == 3 ? PETSC_PI * B->radius * B->radius * B->length : 2.0 * B->radius * B->length;
  }
  return 0.0;
}

/* Bounds of sub-cell q (0 <= q_d < s) of cell idx.  Every bound is computed
   from the same expression on every rank, and sub-cell s-1 ends exactly where
   its cell ends, so the sub-cells tile the cells and the cells the domain. */
void PSSubCellBounds(const PSScene *scene, const PetscInt idx[3], PetscInt s, const PetscInt q[3], double lo[3], double hi[3])
{
  PetscInt d;
  for (d = 0; d < scene->dim; d++) {
    const double h  = (scene->upper[d] - scene->lower[d]) / scene->cells[d];
    const double c0 = scene->lower[d] + idx[d] * h;
    const double c1 = idx[d] + 1 == scene->cells[d] ? scene->upper[d] : scene->lower[d] + (idx[d] + 1) * h;
    if (s == 1) {
      lo[d] = c0;
      hi[d] = c1;
      continue;
    }
    lo[d] = q[d] == 0 ? c0 : c0 + q[d] * ((c1 - c0) / s);
    hi[d] = q[d] + 1 == s ? c1 : c0 + (q[d] + 1) * ((c1 - c0) / s);
  }
}

/* Cells [cs, ce) of the grid that the box [lo, hi] touches. */
void PSCellRange(const PSScene *scene, const PetscReal lo[3], const PetscReal hi[3], PetscInt cs[3], PetscInt ce[3])
{
  PetscInt i;
  for (i = 0; i < 3; i++) {
    if (i >= scene->dim) {
      cs[i] = 0;
      ce[i] = 1;
      continue;
    }
    {
      const double h = (scene->upper[i] - scene->lower[i]) / scene->cells[i];
      double       a = floor((lo[i] - scene->lower[i]) / h), z = ceil((hi[i] - scene->lower[i]) / h);
      cs[i]          = (PetscInt)PetscMax(0.0, PetscMin(a, (double)scene->cells[i]));
      ce[i]          = (PetscInt)PetscMax(0.0, PetscMin(z, (double)scene->cells[i]));
    }
  }
}

/* Volume of (body a ∩ body b) inside the domain, cell by cell at the finer of
   the two subdivisions.  Serial: called in validation on every rank alike. */
PetscErrorCode PSOverlapVolume(const PSScene *scene, PetscInt a, PetscInt b, PetscReal *vol)
{
  PetscReal loa[3], hia[3], lob[3], hib[3], lo[3], hi[3], h[3] = {0, 0, 0}, m[4] = {0, 0, 0, 0};
  PetscInt  cs[3], ce[3], i, j, k, s, dim = scene->dim;
  PSRegion  r[2];

  PetscFunctionBeginUser;
  PetscCall(PSBodyBoundingBox(scene, a, loa, hia));
  PetscCall(PSBodyBoundingBox(scene, b, lob, hib));
  *vol = 0.0;
  for (i = 0; i < dim; i++) {
    lo[i] = PetscMax(loa[i], lob[i]);
    hi[i] = PetscMin(hia[i], hib[i]);
    if (hi[i] <= lo[i]) PetscFunctionReturn(PETSC_SUCCESS);
  }
  s = PetscMax(scene->bodies[a].subdivision, scene->bodies[b].subdivision);
  for (i = 0; i < dim; i++) h[i] = (scene->upper[i] - scene->lower[i]) / scene->cells[i];
  PSRegionSetup(scene, &scene->bodies[a], -1, PetscMax(PetscMax(h[0], h[1]), h[2]) / s, &r[0]);
  PSRegionSetup(scene, &scene->bodies[b], -1, PetscMax(PetscMax(h[0], h[1]), h[2]) / s, &r[1]);
  PSCellRange(scene, lo, hi, cs, ce);
  for (k = cs[2]; k < ce[2]; k++)
    for (j = cs[1]; j < ce[1]; j++)
      for (i = cs[0]; i < ce[0]; i++) {
        PetscInt idx[3] = {i, j, k}, q, nsc = dim == 3 ? s * s * s : s * s;
        for (q = 0; q < nsc; q++) {
          double   clo[3] = {0, 0, 0}, chi[3] = {0, 0, 0};
          PetscInt qi[3] = {q % s, (q / s) % s, q / (s * s)};
          PSSubCellBounds(scene, idx, s, qi, clo, chi);
          PSPieceMoments(dim, clo, chi, 2, r, 0, NULL, m);
        }
      }
  *vol = m[0];
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Volume of body b inside the grid domain: the kernel applied once to the
   whole domain box (one exact clip for flat bodies; curved ones bisect down to
   their h_fine along the surface only). */
PetscErrorCode PSBodyDomainVolume(const PSScene *scene, PetscInt b, PetscReal *vol)
{
  double   lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0}, m[4] = {0, 0, 0, 0}, h = 0.0;
  PetscInt d;
  PSRegion r;

  PetscFunctionBeginUser;
  for (d = 0; d < scene->dim; d++) {
    lo[d] = scene->lower[d];
    hi[d] = scene->upper[d];
    h     = PetscMax(h, (hi[d] - lo[d]) / scene->cells[d]);
  }
  PSRegionSetup(scene, &scene->bodies[b], -1, h, &r);
  PSPieceMoments(scene->dim, lo, hi, 1, &r, 0, NULL, m);
  *vol = m[0];
  PetscFunctionReturn(PETSC_SUCCESS);
}
