/*
  clip.c - exact half-space clipping of boxes and their moments (see clip.h),
  and the closed form of a box cut by a slab (PSBoxSlabMoments).
*/
#include <math.h>
#include <string.h>
#include "clip.h"

/* ---------------------------------------------------------------- 2D ---- */

void PSPoly2InitBox(PSPoly2 *p, const double lo[2], const double hi[2])
{
  /* counter-clockwise */
  p->nv      = 4;
  p->x[0][0] = lo[0]; p->x[0][1] = lo[1];
  p->x[1][0] = hi[0]; p->x[1][1] = lo[1];
  p->x[2][0] = hi[0]; p->x[2][1] = hi[1];
  p->x[3][0] = lo[0]; p->x[3][1] = hi[1];
}

int PSPoly2Clip(PSPoly2 *p, const PSPlane *h)
{
  double sd[PS_MAXV2], out[PS_MAXV2][2];
  int    i, nin = 0, no = 0;

  /* signed distance, >= 0 kept: sd = d - n.x */
  for (i = 0; i < p->nv; i++) {
    sd[i] = h->d - (h->n[0] * p->x[i][0] + h->n[1] * p->x[i][1]);
    nin += (sd[i] >= 0.0);
  }
  if (nin == p->nv) return p->nv;
  if (nin == 0) return p->nv = 0;
  /* Sutherland-Hodgman: walk the edges (i -> j), keep inside vertices and crossings */
  for (i = 0; i < p->nv; i++) {
    const int j = (i + 1) % p->nv;
    if (sd[i] >= 0.0) {
      out[no][0] = p->x[i][0];
      out[no][1] = p->x[i][1];
      no++;
    }
    if ((sd[i] >= 0.0) != (sd[j] >= 0.0)) {
      const double t = sd[i] / (sd[i] - sd[j]);
      if (no >= PS_MAXV2) return -1;
      out[no][0] = p->x[i][0] + t * (p->x[j][0] - p->x[i][0]);
      out[no][1] = p->x[i][1] + t * (p->x[j][1] - p->x[i][1]);
      no++;
    }
  }
  memcpy(p->x, out, sizeof(double) * 2 * no);
  return p->nv = no;
}

void PSPoly2Moments(const PSPoly2 *p, double m[3])
{
  int i;

  /* shoelace: A = 1/2 sum cross, S_x = 1/6 sum cross (x_i + x_j) */
  /* about vertex 0, so that round-off scales with the piece, not the cell */
  const double ox = p->nv ? p->x[0][0] : 0.0, oy = p->nv ? p->x[0][1] : 0.0;
  m[0] = m[1] = m[2] = 0.0;
  for (i = 0; i < p->nv; i++) {
    const int    j  = (i + 1) % p->nv;
    const double xi = p->x[i][0] - ox, yi = p->x[i][1] - oy, xj = p->x[j][0] - ox, yj = p->x[j][1] - oy;
    const double c  = xi * yj - xj * yi;
    m[0] += c;
    m[1] += c * (xi + xj);
    m[2] += c * (yi + yj);
  }
  m[0] *= 0.5;
  m[1] = m[1] / 6.0 + m[0] * ox;
  m[2] = m[2] / 6.0 + m[0] * oy;
}

/* ---------------------------------------------------------------- 3D ---- */

/* Vertex v = i + 2j + 4k sits at (lo|hi)(i,j,k); its neighbours differ in one
   bit, ordered so that det(nb0 - v, nb1 - v, nb2 - v) has the same sign at
   every vertex: one orientation for all faces. */
static const int PSBoxNb[8][3] = {
  {1, 2, 4}, {0, 5, 3}, {3, 6, 0}, {2, 1, 7}, {5, 0, 6}, {4, 7, 1}, {7, 4, 2}, {6, 3, 5}
};

void PSPoly3InitBox(PSPoly3 *p, const double lo[3], const double hi[3])
{
  int v;
  p->nv = 8;
  for (v = 0; v < 8; v++) {
    p->v[v].x[0]  = v & 1 ? hi[0] : lo[0];
    p->v[v].x[1]  = v & 2 ? hi[1] : lo[1];
    p->v[v].x[2]  = v & 4 ? hi[2] : lo[2];
    p->v[v].nb[0] = PSBoxNb[v][0];
    p->v[v].nb[1] = PSBoxNb[v][1];
    p->v[v].nb[2] = PSBoxNb[v][2];
  }
}

int PSPoly3Clip(PSPoly3 *p, const PSPlane *h)
{
  double sd[PS_MAXV3];
  int    remap[PS_MAXV3];
  int    v, k, nin = 0;
  const int onv = p->nv;

  for (v = 0; v < onv; v++) {
    const double *x = p->v[v].x;
    sd[v]           = h->d - (h->n[0] * x[0] + h->n[1] * x[1] + h->n[2] * x[2]);
    nin += (sd[v] >= 0.0);
  }
  if (nin == onv) return onv;
  if (nin == 0) return p->nv = 0;

  /* one new vertex on every edge from a kept vertex v to a clipped one w; it
     takes w's place in v's neighbour list, and v becomes its neighbour 0 */
  for (v = 0; v < onv; v++) {
    if (sd[v] < 0.0) continue;
    for (k = 0; k < 3; k++) {
      const int w = p->v[v].nb[k];
      double    a, b;
      if (sd[w] >= 0.0) continue;
      if (p->nv >= PS_MAXV3) return -1;
      a                    = sd[v] / (sd[v] - sd[w]); /* weight of w */
      b                    = 1.0 - a;
      p->v[p->nv].x[0]     = b * p->v[v].x[0] + a * p->v[w].x[0];
      p->v[p->nv].x[1]     = b * p->v[v].x[1] + a * p->v[w].x[1];
      p->v[p->nv].x[2]     = b * p->v[v].x[2] + a * p->v[w].x[2];
      p->v[p->nv].nb[0]    = v;
      p->v[v].nb[k]        = p->nv;
      p->nv++;
    }
  }
  /* link the new vertices into the cap: walk each new vertex's face through
     kept vertices until the next new vertex is met */
  for (v = onv; v < p->nv; v++) {
    int cur = v, next = p->v[v].nb[0], np;
    do {
      for (np = 0; np < 3; np++)
        if (p->v[next].nb[np] == cur) break;
      cur  = next;
      next = p->v[cur].nb[(np + 1) % 3];
    } while (cur < onv);
    p->v[v].nb[2]   = cur;
    p->v[cur].nb[1] = v;
  }
  /* compact: drop the clipped vertices */
  {
    int nn = 0;
    for (v = 0; v < p->nv; v++) {
      if (v < onv && sd[v] < 0.0) {
        remap[v] = -1;
        continue;
      }
      remap[v] = nn;
      if (nn != v) p->v[nn] = p->v[v];
      nn++;
    }
    for (v = 0; v < nn; v++)
      for (k = 0; k < 3; k++) p->v[v].nb[k] = remap[p->v[v].nb[k]];
    p->nv = nn;
  }
  return p->nv;
}

void PSPoly3Moments(const PSPoly3 *p, double m[4])
{
  unsigned char mark[PS_MAXV3][3];
  int           vs, ps;
  double        o[3] = {0, 0, 0}, y[PS_MAXV3][3];

  /* about vertex 0, so that round-off scales with the piece, not the cell */
  if (p->nv) {
    o[0] = p->v[0].x[0];
    o[1] = p->v[0].x[1];
    o[2] = p->v[0].x[2];
  }
  for (vs = 0; vs < p->nv; vs++) {
    y[vs][0] = p->v[vs].x[0] - o[0];
    y[vs][1] = p->v[vs].x[1] - o[1];
    y[vs][2] = p->v[vs].x[2] - o[2];
  }

  m[0] = m[1] = m[2] = m[3] = 0.0;
  memset(mark, 0, sizeof(mark[0]) * (size_t)p->nv);
  /* walk each face once (each directed edge marked), fan it into triangles
     (v0, v1, v2) and add the tetrahedron they make with the origin:
     V = det/6, first moment = det (v0 + v1 + v2) / 24 */
  for (vs = 0; vs < p->nv; vs++) {
    for (ps = 0; ps < 3; ps++) {
      const double *x0;
      int           cur, next, np;
      if (mark[vs][ps]) continue;
      cur            = vs;
      mark[cur][ps]  = 1;
      next           = p->v[cur].nb[ps];
      x0             = y[vs];
      for (np = 0; np < 3; np++)
        if (p->v[next].nb[np] == cur) break;
      cur                     = next;
      mark[cur][(np + 1) % 3] = 1;
      next                    = p->v[cur].nb[(np + 1) % 3];
      while (next != vs) {
        const double *x2 = y[cur], *x1 = y[next];
        const double  det = x0[0] * (x1[1] * x2[2] - x1[2] * x2[1]) - x0[1] * (x1[0] * x2[2] - x1[2] * x2[0]) + x0[2] * (x1[0] * x2[1] - x1[1] * x2[0]);
        m[0] += det;
        m[1] += det * (x0[0] + x1[0] + x2[0]);
        m[2] += det * (x0[1] + x1[1] + x2[1]);
        m[3] += det * (x0[2] + x1[2] + x2[2]);
        for (np = 0; np < 3; np++)
          if (p->v[next].nb[np] == cur) break;
        cur                     = next;
        mark[cur][(np + 1) % 3] = 1;
        next                    = p->v[cur].nb[(np + 1) % 3];
      }
    }
  }
  /* the face walk turns clockwise seen from outside: flip the sign once */
  m[0] /= -6.0;
  m[1] = m[1] / -24.0 + m[0] * o[0];
  m[2] = m[2] / -24.0 + m[0] * o[1];
  m[3] = m[3] / -24.0 + m[0] * o[2];
}

/* ------------------------------------------------- a box cut by a slab ---- */

/* Moments of {y in [0, L]^k : an.y <= s} in the k directions ax[] where
   an > 0, by inclusion-exclusion over the box's corners c_v: the corner's
   simplex {y >= c_v, an.y <= s} has the volume t^k / (k! prod an) and its
   centroid at c_v + t / ((k + 1) an), t = s - an.c_v (Scardovelli & Zaleski,
   J. Comput. Phys. 164 (2000) 228, for the volume).  M[0] the k-volume,
   M[1 + i] its first moment along axis i; not yet divided by k! prod an. */
static void CornerSum(int k, const int ax[3], const double L[3], const double an[3], double s, double M[4])
{
  int v, j;
  M[0] = M[1] = M[2] = M[3] = 0.0;
  for (v = 0; v < (1 << k); v++) {
    double t = s, tk = 1.0, sg = 1.0;
    for (j = 0; j < k; j++)
      if (v >> j & 1) {
        t -= an[ax[j]] * L[ax[j]];
        sg = -sg;
      }
    if (t <= 0.0) continue;
    for (j = 0; j < k; j++) tk *= t;
    tk *= sg;
    M[0] += tk;
    for (j = 0; j < k; j++) M[1 + ax[j]] += tk * ((v >> j & 1 ? L[ax[j]] : 0.0) + t / ((k + 1) * an[ax[j]]));
  }
}

/* box ∩ {an.y <= s} of the cut directions, divided out (F(s) of PSBoxSlabMoments):
   the whole box exactly once s reaches S = an.L */
static void CutMoments(int k, const int ax[3], const double L[3], const double A[3], const double an[3], double S, double s, double M[4])
{
  int    j;
  double q = 1.0;
  if (s >= S) {
    M[1] = M[2] = M[3] = 0.0;
    for (j = 0; j < k; j++) q *= L[ax[j]];
    M[0] = q;
    for (j = 0; j < k; j++) M[1 + ax[j]] = q * A[ax[j]];
    return;
  }
  CornerSum(k, ax, L, an, s, M);
  for (j = 0; j < k; j++) q *= (j + 1) * an[ax[j]];
  for (j = 0; j < 4; j++) M[j] /= q;
}

int PSBoxSlabMoments(int dim, const double A[3], const double n[3], double dlo, double dhi, double m[4])
{
  double an[3] = {0, 0, 0}, sg[3] = {1, 1, 1}, L[3] = {0, 0, 0}, nA = 0.0, S = 0.0, P = 1.0, kappa = 1.0, box = 1.0, s0, s1, V, M[4], Mlo[4];
  int    ax[3], k = 0, i, j;

  /* reflect the axes where n < 0 and move the origin to the box's corner:
     y_i = sg_i x_i + A_i in [0, L_i], and n.x = an.y - an.A */
  for (i = 0; i < dim; i++) {
    an[i] = fabs(n[i]);
    sg[i] = n[i] < 0.0 ? -1.0 : 1.0;
    L[i]  = 2.0 * A[i];
    nA += an[i] * A[i];
    if (an[i] > 0.0) {
      ax[k++] = i;
      S += an[i] * L[i];
      P *= k * an[i] * L[i];
      box *= L[i];
    }
  }
  if (!k) return 0;
  /* conditioning: the largest corner term against the box, S^k / (k! prod an L);
     past 30 (a normal close to a face's) the clipper does it */
  for (j = 0; j < k; j++) kappa *= S;
  kappa /= P;
  if (kappa > 30) return 0;
  s1 = dhi + nA;
  s0 = dlo + nA;
  if (s1 <= 0.0 || s0 >= S || s1 <= s0) return 0; /* no piece: the clipper's answer, whatever it is */
  CutMoments(k, ax, L, A, an, S, s1, M);
  if (s0 > 0.0) {
    CutMoments(k, ax, L, A, an, S, s0, Mlo);
    for (j = 0; j < 4; j++) M[j] -= Mlo[j];
  }
  /* a piece small against the corner terms' round-off (about 2^(k+1) kappa
     eps of the box) would lose its centroid's digits: the clipper does it */
  if (M[0] < (double)(2 << k) * kappa * 2.2e-4 * box) return 0;
  /* the directions the slab does not cut: extrude */
  V = M[0];
  for (i = 0; i < dim; i++)
    if (an[i] == 0.0) {
      for (j = 0; j < 4; j++) M[j] *= L[i];
      V *= L[i];
      M[1 + i] = V * A[i];
    }
  /* back to the box centre and the original axes */
  m[0] = V;
  for (i = 0; i < 3; i++) m[1 + i] = i < dim ? sg[i] * (M[1 + i] - A[i] * V) : 0.0;
  return 1;
}
