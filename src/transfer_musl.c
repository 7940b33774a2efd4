/*
  transfer_musl.c - the MUSL transfers (Sulsky, Zhou & Schreyer 1995; solver.h
  steps 1-4 and the velocity gradient of step 5), in the paper's order:
    1. P2G        m_i = sum_p N_ip m_p, (mv)_i = sum_p N_ip m_p v_p,
                  f_i = -sum_p V_p (sigma_p - q_p I) grad N_ip                  (PSP2G)
    2. grid       v_i^new = v_i + dt f_i / m_i, boundary conditions            (PSGridUpdate, grid.c)
    3. G2P        v_p FLIP/PIC blend, dx_p = dt sum_i N_ip v_i^new               (PSG2P)
    4. re-project (mv)_i = sum_p N_ip m_p v_p^{n+1}, v_i = (mv)_i / m_i        (PSReproject)
    5. L_p = sum_i v_i (x) grad N_ip of the re-projected velocity, into S->Lp   (PSReproject)
  All use N_ip at x_p^n: P2G locates each marker (PSShapeLocate: its first
  node and offsets, S->at, 88 bytes) and the later passes (and contact.c)
  turn that into the weights again (PSShapeWeights, a few operations per
  direction, without the marker's size: storing the 160-byte weights cost
  P2G more).

  Axisymmetric 2D (x = r, y = z; S->axi): the weak form of the momentum
  equation in cylindrical coordinates with the full revolution's V_p and m_p
  (Sulsky & Schreyer, CMAME 139, 1996, eq. 28; Nairn, NairnMPM's
  axisymmetric MPM) adds the hoop stress to the radial force,
      f_ri = -sum_p V_p (sigma_rr dN/dr + sigma_rz dN/dz + sigma_tt N_ip / r_p)
      f_zi = -sum_p V_p (sigma_rz dN/dr + sigma_zz dN/dz)
  (sigma_tt is the stored out-of-plane component, sigma - q I as elsewhere),
  and the velocity gradient the hoop rate L_tt = v_r(x_p) / r_p, v_r(x_p) =
  sum_i N_ip v_ri of the re-projected velocity.  Masses and momenta need
  nothing new: m_p is the full revolution's.  The axisymmetric kernels are
  compiled apart (a constant flag), so the plane-strain ones are unchanged.

  Node layout (grid.c reads it through PSMUSLLayout): 3D nodes hold 8 reals,
  [m, mv_x, mv_y, mv_z | 0, f_x, f_y, f_z] (one cache line in the 64-byte
  aligned arrays), and the re-projection array 4 reals [0, mv_x, mv_y, mv_z];
  2D nodes [m, mv, f] and [mv].  The kernels are written once with the
  dimension dim and the nodes per direction N (2 linear, 3 GIMP and B-splines)
  as constants at each call (always inlined), and for GIMP (vs) the nodes
  that carry weight per marker and direction (PSShapeSupport, shape.h: 2 or
  3; a marker inside its cell along a direction skips the zero third node;
  the loops keep the bound N too, which lets them unroll: 1.05x).  Per row
  of nodes along x the y-z factors are applied once; in 3D each node then
  costs 4-wide multiply-adds only on the lanes it needs (P2G: one on the mass-momentum half, two on the force half; 8-wide
  registers would run the empty lanes too, at twice the cost on a CPU that
  splits them).  The arrays the passes after P2G store into are restrict.
*/
#include "step.h"
#include "cells/cells.h"

/* the shape function of a compiled kernel, a constant there: N = 2 linear,
   N = 3 GIMP (vs) or B-splines */
static inline __attribute__((always_inline)) PSShapeType KernelShape(const PetscInt N, const PetscBool vs)
{
  return N == 2 ? PS_SHAPE_LINEAR : vs ? PS_SHAPE_GIMP : PS_SHAPE_BSPLINE2;
}

/* 1. P2G of one marker, dim and N constant */
static inline __attribute__((always_inline)) void P2GMarker(const PSSolver *S, const PSFields *f, PetscInt p, const PSIndex *ix, const PetscInt dim, const PetscInt N, const PetscBool vs, const PetscBool axi, const PSShape *sh, PetscReal *g)
{
  const PetscInt   dof = dim == 3 ? 8 : 5, nz = dim == 3 ? N : 1, sy = dof * ix->gm[0], sz = sy * ix->gm[1];
  const PetscReal *x = &f->x[p * dim], *v = &f->v[p * dim], m = f->mass[p], V = f->vol[p];
  PetscReal        s[3][3], *g0;
  PetscInt         a, b, c, d, e, n[3];
  PSShapeSupport(sh, dim, N, vs, n);
  ForceStress(dim, &f->sig[p * PSStressComponents(dim)], f->q[p], s);
  g0 = &g[dof * Lidx(ix, sh->i0[0], sh->i0[1], sh->i0[2])]; /* first node; rows sy, planes sz apart */
  if (dim == 3) {
    /* T = (m, m v), S_e = (0, -V (sigma - q I) e_e); per plane c and row b
       the y-z factors: node a adds w_x,a T_bc to its first half and
       w_x,a F1_bc + dw_x,a F0_bc to its second, with
       T_bc = w_y w_z T, F1_bc = dw_y w_z S1 + w_y dw_z S2, F0_bc = w_y w_z S0
       (f_i = -V (sigma - q I) grad N_ip, grad N = (dw_x w_y w_z, w_x dw_y w_z, w_x w_y dw_z)) */
    const PSv4 T  = {m, m * v[0], m * v[1], m * v[2]};
    const PSv4 S0 = {0.0, -V * s[0][0], -V * s[1][0], -V * s[2][0]};
    const PSv4 S1 = {0.0, -V * s[0][1], -V * s[1][1], -V * s[2][1]};
    const PSv4 S2 = {0.0, -V * s[0][2], -V * s[1][2], -V * s[2][2]};
    for (c = 0; c < N && c < n[2]; c++) {
      const PSv4 Tc = sh->w[2][c] * T, S0c = sh->w[2][c] * S0, S1c = sh->w[2][c] * S1, S2c = sh->dw[2][c] * S2;
      for (b = 0; b < N && b < n[1]; b++) {
        const PSv4 Tb = sh->w[1][b] * Tc, F1 = sh->dw[1][b] * S1c + sh->w[1][b] * S2c, F0 = sh->w[1][b] * S0c;
        PetscReal *gr = g0 + c * sz + b * sy;
        for (a = 0; a < N && a < n[0]; a++) {
          /* the marker's sum first, then one add into the node: the chain
             through memory to the next marker at the same node is one add */
          Store4(gr + 8 * a, Load4(gr + 8 * a) + sh->w[0][a] * Tb);
          Store4(gr + 8 * a + 4, Load4(gr + 8 * a + 4) + (sh->w[0][a] * F1 + sh->dw[0][a] * F0));
        }
      }
    }
  } else {
    PetscReal       mv[2], Vs[2][2];
    const PetscReal Vtt = axi ? V * s[2][2] / x[0] : 0.0; /* V_p sigma_tt / r_p (axisymmetric) */
    for (d = 0; d < 2; d++) {
      mv[d] = m * v[d];
      for (e = 0; e < 2; e++) Vs[d][e] = V * s[d][e];
    }
    for (c = 0; c < nz; c++)
      for (b = 0; b < N && b < n[1]; b++) {
        const PetscReal wy = sh->w[1][b], dy = sh->dw[1][b];
        PetscReal      *gr = g0 + c * sz + b * sy;
        for (a = 0; a < N && a < n[0]; a++) {
          const PetscReal w = sh->w[0][a] * wy, g_x = sh->dw[0][a] * wy, g_y = sh->w[0][a] * dy;
          PetscReal      *gn = gr + 5 * a;
          gn[0] += w * m;
          gn[1] += w * mv[0];
          gn[2] += w * mv[1];
          if (axi) gn[3] -= Vs[0][0] * g_x + Vs[0][1] * g_y + Vtt * w;
          else gn[3] -= Vs[0][0] * g_x + Vs[0][1] * g_y;
          gn[4] -= Vs[1][0] * g_x + Vs[1][1] * g_y;
        }
      }
  }
}

/* GIMP's size of marker p into *G (other shapes: nothing).  Axisymmetric:
   from the marker's own section; otherwise from V0, left in *G while V0
   repeats (*V0c: the V0 it was set for; uniform insertion repeats it, so
   cbrt and the divisions run once per run of equal V0).  The caller's *V0c
   starts at -1. */
static inline __attribute__((always_inline)) void MarkerGimpSize(const PSSolver *S, const PSFields *f, PetscInt p, PetscInt dim, PetscBool axi, PetscReal *V0c, PSGimpSize *G)
{
  if (S->run.shape != PS_SHAPE_GIMP) return;
  if (axi) {
    /* the initial section area A0 = V0 / (2 pi r0), r0 = r_p / F_tt and
       F_tt = V / (V0 det F_rz): A0 = V / (2 pi r_p det F_rz) */
    const PetscReal *F = &f->F[4 * p];
    PSGimpSizeSet(0.5 * PetscSqrtReal(f->vol[p] / (2.0 * PETSC_PI * f->x[2 * p] * (F[0] * F[3] - F[1] * F[2]))), S->ih, G);
  } else if (f->V0[p] != *V0c) {
    *V0c = f->V0[p];
    PSGimpSizeSet(HalfSize(dim, *V0c), S->ih, G);
  }
}

static inline __attribute__((always_inline)) void P2GAll(PSSolver *S, const PSFields *f, const PSIndex *ix, const PetscInt dim, const PetscInt N, const PetscBool vs, const PetscBool axi, PetscReal *g)
{
  PetscReal  V0 = -1.0;
  PSGimpSize G = {{0}, {0}, {0}};
  PetscInt   p;
  for (p = 0; p < f->n; p++) {
    PSShapeAt at;
    PSShape   sh; /* locals: stores into g cannot alias them */
    MarkerGimpSize(S, f, p, dim, axi, &V0, &G);
    PSShapeLocate(KernelShape(N, vs), dim, S->scene->lower, S->ih, &f->x[p * dim], &G, &at);
    PSShapeWeights(KernelShape(N, vs), dim, S->ih, &at, &sh);
    P2GMarker(S, f, p, ix, dim, N, vs, axi, &sh, g);
    S->at[p] = at; /* after the scatter, when the stores just made have reached the cache */
  }
}

/* 3. G2P: v_p = (1 - a)(v_p + sum N dv) + a sum N v_new, dx_p = dt sum N v_new;
   4. and in the same pass the re-projection (mv)_i += N_ip m_p v_p^{n+1} */
static inline __attribute__((always_inline)) void G2PAll(PSSolver *S, PSFields *f, const PSIndex *ix, PetscReal dt, const PetscInt dim, const PetscInt N, const PetscBool vs, const PetscReal *restrict g, PetscReal *restrict hv)
{
  const PetscInt  dof = dim == 3 ? 8 : 5, hdof = dim == 3 ? 4 : 2, nz = dim == 3 ? N : 1;
  const PetscInt  sy = dof * ix->gm[0], sz = sy * ix->gm[1], hy = hdof * ix->gm[0], hz = hy * ix->gm[1];
  const PetscReal apic = S->run.pic_fraction;
  PetscInt        p, a, b, c, d;

  for (p = 0; p < f->n; p++) {
    PSShape          shl, *sh = &shl; /* a local: stores into hv cannot alias it */
    PSShapeWeights(KernelShape(N, vs), dim, S->ih, &S->at[p], &shl);
    const PetscInt   o  = Lidx(ix, sh->i0[0], sh->i0[1], sh->i0[2]);
    const PetscReal *g0 = &g[dof * o];
    PetscReal       *h0 = &hv[hdof * o], *v = &f->v[p * dim], m = f->mass[p];
    PetscInt         n[3];
    PSShapeSupport(sh, dim, N, vs, n);
    if (dim == 3) {
      /* acc = (sum N v_new | sum N dv), 8-wide over the node's two halves,
         summed by row, then plane, then the planes (short add chains: the
         marker's velocity and its scatter wait on this sum) */
      PSv8 acc = {0, 0, 0, 0, 0, 0, 0, 0};
      PSv4 MV;
      for (c = 0; c < N && c < n[2]; c++) {
        PSv8 ac = {0, 0, 0, 0, 0, 0, 0, 0};
        for (b = 0; b < N && b < n[1]; b++) {
          const PetscReal *gr = g0 + c * sz + b * sy;
          PSv8             sr = sh->w[0][0] * Load8(gr);
          for (a = 1; a < N && a < n[0]; a++) sr += sh->w[0][a] * Load8(gr + 8 * a);
          ac += sh->w[1][b] * sr;
        }
        acc += sh->w[2][c] * ac;
      }
      for (d = 0; d < 3; d++) {
        v[d]               = (1.0 - apic) * (v[d] + acc[5 + d]) + apic * acc[1 + d];
        S->dx[p * dim + d] = dt * acc[1 + d];
      }
      MV = (PSv4){0.0, m * v[0], m * v[1], m * v[2]};
      for (c = 0; c < N && c < n[2]; c++)
        for (b = 0; b < N && b < n[1]; b++) {
          const PSv4 W  = (sh->w[1][b] * sh->w[2][c]) * MV;
          PetscReal *hr = h0 + c * hz + b * hy;
          for (a = 0; a < N && a < n[0]; a++) Store4(hr + 4 * a, Load4(hr + 4 * a) + sh->w[0][a] * W);
        }
    } else {
      PetscReal vpic[2] = {0, 0}, dv[2] = {0, 0}, mv[2];
      for (c = 0; c < nz; c++)
        for (b = 0; b < N && b < n[1]; b++) {
          const PetscReal  wy = sh->w[1][b];
          const PetscReal *gr = g0 + c * sz + b * sy;
          for (a = 0; a < N && a < n[0]; a++) {
            const PetscReal  w  = sh->w[0][a] * wy;
            const PetscReal *gn = gr + 5 * a;
            vpic[0] += w * gn[1];
            vpic[1] += w * gn[2];
            dv[0] += w * gn[3];
            dv[1] += w * gn[4];
          }
        }
      for (d = 0; d < 2; d++) {
        v[d]               = (1.0 - apic) * (v[d] + dv[d]) + apic * vpic[d];
        S->dx[p * dim + d] = dt * vpic[d];
        mv[d]              = m * v[d];
      }
      for (c = 0; c < nz; c++)
        for (b = 0; b < N && b < n[1]; b++) {
          const PetscReal wy = sh->w[1][b];
          PetscReal      *hr = h0 + c * hz + b * hy;
          for (a = 0; a < N && a < n[0]; a++) {
            const PetscReal w = sh->w[0][a] * wy;
            hr[2 * a] += w * mv[0];
            hr[2 * a + 1] += w * mv[1];
          }
        }
    }
  }
}

/* 5. L_p = sum_i v_i (x) grad N_ip from the re-projected velocities, into
   S->Lp (9 reals per marker, row major) */
static inline __attribute__((always_inline)) void GradientAll(PSSolver *S, const PSFields *f, const PSIndex *ix, const PetscInt dim, const PetscInt N, const PetscBool vs, const PetscBool axi, const PetscReal *restrict hv)
{
  const PetscInt hdof = dim == 3 ? 4 : 2, nz = dim == 3 ? N : 1, hy = hdof * ix->gm[0], hz = hy * ix->gm[1];
  PetscInt       p, a, b, c, d;

  for (p = 0; p < f->n; p++) {
    PSShape          shl, *sh = &shl;
    PSShapeWeights(KernelShape(N, vs), dim, S->ih, &S->at[p], &shl);
    const PetscReal *h0 = &hv[hdof * Lidx(ix, sh->i0[0], sh->i0[1], sh->i0[2])];
    PetscReal       *L  = &S->Lp[9 * p];
    PetscInt         n[3];
    PSShapeSupport(sh, dim, N, vs, n);
    if (dim == 3) {
      /* columns of L: c0 = sum dN/dx v, c1 = sum dN/dy v, c2 = sum dN/dz v.
         Per row, sw = sum_a w_x,a v_a and sd = sum_a dw_x,a v_a; per plane
         t0 = sum_b w_y sd, t1 = sum_b dw_y sw, t2 = sum_b w_y sw; then
         c0 += w_z t0, c1 += w_z t1, c2 += dw_z t2 (4-wide) */
      PSv4 c0 = {0, 0, 0, 0}, c1 = {0, 0, 0, 0}, c2 = {0, 0, 0, 0};
      for (c = 0; c < N && c < n[2]; c++) {
        PSv4 t0 = {0, 0, 0, 0}, t1 = {0, 0, 0, 0}, t2 = {0, 0, 0, 0};
        for (b = 0; b < N && b < n[1]; b++) {
          const PetscReal *hr = h0 + c * hz + b * hy;
          const PSv4       v0 = Load4(hr);
          PSv4             sw = sh->w[0][0] * v0, sd = sh->dw[0][0] * v0;
          for (a = 1; a < N && a < n[0]; a++) {
            const PSv4 va = Load4(hr + 4 * a);
            sw += sh->w[0][a] * va;
            sd += sh->dw[0][a] * va;
          }
          t0 += sh->w[1][b] * sd;
          t1 += sh->dw[1][b] * sw;
          t2 += sh->w[1][b] * sw;
        }
        c0 += sh->w[2][c] * t0;
        c1 += sh->w[2][c] * t1;
        c2 += sh->dw[2][c] * t2;
      }
      for (d = 0; d < 3; d++) {
        L[3 * d + 0] = c0[1 + d];
        L[3 * d + 1] = c1[1 + d];
        L[3 * d + 2] = c2[1 + d];
      }
    } else {
      PetscReal l00 = 0, l01 = 0, l10 = 0, l11 = 0, vr = 0;
      for (c = 0; c < nz; c++)
        for (b = 0; b < N && b < n[1]; b++) {
          const PetscReal  wy = sh->w[1][b], dy = sh->dw[1][b];
          const PetscReal *hr = h0 + c * hz + b * hy;
          for (a = 0; a < N && a < n[0]; a++) {
            const PetscReal g_x = sh->dw[0][a] * wy, g_y = sh->w[0][a] * dy, *vn = hr + 2 * a;
            l00 += vn[0] * g_x;
            l01 += vn[0] * g_y;
            l10 += vn[1] * g_x;
            l11 += vn[1] * g_y;
            if (axi) vr += sh->w[0][a] * wy * vn[0];
          }
        }
      L[0] = l00;
      L[1] = l01;
      L[2] = 0.0;
      L[3] = l10;
      L[4] = l11;
      L[5] = L[6] = L[7] = 0.0;
      L[8] = axi ? vr / f->x[2 * p] : 0.0; /* the hoop rate v_r / r_p (axisymmetric) */
    }
  }
}

/* the compiled forms of each kernel: 2D and 3D x linear (N = 2), B-splines
   (N = 3) and GIMP (N = 3, the support per marker, vs); P2G and the gradient
   have three more, the axisymmetric 2D ones (call2a) */
#define PS_MUSL_DISPATCH1(call) \
  do { \
    if (S->run.shape == PS_SHAPE_GIMP) call(3, PETSC_TRUE); \
    else if (N == 3) call(3, PETSC_FALSE); \
    else call(2, PETSC_FALSE); \
  } while (0)
#define PS_MUSL_DISPATCH(call3, call2) \
  do { \
    if (S->dim == 3) PS_MUSL_DISPATCH1(call3); \
    else PS_MUSL_DISPATCH1(call2); \
  } while (0)
#define PS_MUSL_DISPATCH_AXI(call3, call2, call2a) \
  do { \
    if (S->dim == 2 && S->axi) PS_MUSL_DISPATCH1(call2a); \
    else PS_MUSL_DISPATCH(call3, call2); \
  } while (0)

/* 1. P2G of the markers into S->g (the grid phase sums the ghosts) */
PetscErrorCode PSMUSLP2G(PSSolver *S, PSFields *f, const PSIndex *ix)
{
  const PetscInt N = PSShapeNodes(S->run.shape);
  PetscReal     *g = S->g;

  PetscFunctionBeginUser;
  PetscCall(PetscLogEventBegin(PS_EV_P2G, 0, 0, 0, 0));
#define P2G3(n, vs)  P2GAll(S, f, ix, 3, n, vs, PETSC_FALSE, g)
#define P2G2(n, vs)  P2GAll(S, f, ix, 2, n, vs, PETSC_FALSE, g)
#define P2G2A(n, vs) P2GAll(S, f, ix, 2, n, vs, PETSC_TRUE, g)
  PS_MUSL_DISPATCH_AXI(P2G3, P2G2, P2G2A);
  PetscCall(PetscLogEventEnd(PS_EV_P2G, 0, 0, 0, 0));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* 3. G2P and 4. the re-projection's P2G into S->hv */
PetscErrorCode PSMUSLG2P(PSSolver *S, PSFields *f, const PSIndex *ix, PetscReal dt)
{
  const PetscInt N = PSShapeNodes(S->run.shape);
  PetscReal     *g = S->g, *hv = S->hv;

  PetscFunctionBeginUser;
  PetscCall(PetscLogEventBegin(PS_EV_G2P, 0, 0, 0, 0));
#define G2P3(n, vs) G2PAll(S, f, ix, dt, 3, n, vs, g, hv)
#define G2P2(n, vs) G2PAll(S, f, ix, dt, 2, n, vs, g, hv)
  PS_MUSL_DISPATCH(G2P3, G2P2);
  PetscCall(PetscLogEventEnd(PS_EV_G2P, 0, 0, 0, 0));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* 4. the re-projected velocity v_i = (mv)_i / m_i with the boundary
   conditions (the cell materials' momentum P^C_i joins the markers' on the
   owned nodes), then 5. each marker's L_p from it into S->Lp */
PetscErrorCode PSMUSLReproject(PSSolver *S, PSFields *f, const PSIndex *ix)
{
  const PetscInt dim = S->dim, N = PSShapeNodes(S->run.shape), hdof = PSReprojectDof(S);
  PetscReal     *hv = S->hv;

  PetscFunctionBeginUser;
  PetscCall(PetscLogEventBegin(PS_EV_Reproject, 0, 0, 0, 0));
  PetscCall(PSHaloReduce(S->sfh, hv));
  if (S->cells) PSGridAddOwned(S, ix, S->cells->P, dim, hv + hdof - dim, hdof);
  PSGridVelocity(S, ix, S->g, PSGridDof(S), hv + hdof - dim, hdof);
  PetscCall(PSHaloBcast(S->sfh, hv));
  /* with bodies in contact, contact.c then gives the markers next to a node
     where fields meet their L_p from their field (plane strain and 3D only) */
#define GRAD3(n, vs)  GradientAll(S, f, ix, 3, n, vs, PETSC_FALSE, hv)
#define GRAD2(n, vs)  GradientAll(S, f, ix, 2, n, vs, PETSC_FALSE, hv)
#define GRAD2A(n, vs) GradientAll(S, f, ix, 2, n, vs, PETSC_TRUE, hv)
  PS_MUSL_DISPATCH_AXI(GRAD3, GRAD2, GRAD2A);
  PetscCall(PetscLogEventEnd(PS_EV_Reproject, 0, 0, 0, 0));
  PetscFunctionReturn(PETSC_SUCCESS);
}
