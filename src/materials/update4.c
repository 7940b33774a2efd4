/*
  The isotropic kernel of update.c for four 3D markers of one material at
  once: one 4-wide vector (PSv4) per tensor component, so the deformation
  gradient, the polar rotation and both frame changes run on all four markers
  in the same instructions.  The scalar kernel is latency-bound (a chain of
  dependent 3x3 products per marker); four independent chains fill the FMA
  units.  Each lane performs the scalar kernel's operations in the same order,
  so a marker's result is bitwise the one PSMarkerUpdate gives (the tests
  compare the two paths); the EOS, viscosity, energy and flow-stress steps are
  done lane by lane with the scalar code's expressions.

  Used for isotropic materials without metal failure (registry.c); a batch in
  which any marker would reach J <= 0 is redone by the scalar kernel, which
  reports the marker.
*/
#include <math.h>
#include <stdint.h>
#include "../materials.h"

static inline PSv4 Abs4(PSv4 x)
{
  const PSm4 magnitude = {INT64_MAX, INT64_MAX, INT64_MAX, INT64_MAX};
  return (PSv4)((PSm4)x & magnitude);
}

/* lane-wise a where m, else b */
static inline PSv4 Select4(PSm4 m, PSv4 a, PSv4 b)
{
  return (PSv4)(((PSm4)a & m) | ((PSm4)b & ~m));
}

static inline PetscBool Any4(PSm4 m)
{
  return (m[0] | m[1] | m[2] | m[3]) ? PETSC_TRUE : PETSC_FALSE;
}

/* Y = Q X Q^T, or Q^T X Q when transpose (PSTurn, lane-wise) */
static inline void Turn4(const PSv4 Q[3][3], PetscBool transpose, const PSv4 X[3][3], PSv4 Y[3][3])
{
  PSv4     T[3][3];
  PetscInt i, j, k;
  for (i = 0; i < 3; i++)
    for (j = 0; j < 3; j++) {
      T[i][j] = (PSv4){0, 0, 0, 0};
      for (k = 0; k < 3; k++) T[i][j] += X[i][k] * (transpose ? Q[k][j] : Q[j][k]);
    }
  for (i = 0; i < 3; i++)
    for (j = 0; j < 3; j++) {
      Y[i][j] = (PSv4){0, 0, 0, 0};
      for (k = 0; k < 3; k++) Y[i][j] += (transpose ? Q[k][i] : Q[i][k]) * T[k][j];
    }
}

/* R of F = R U (PSPolarRotation, lane-wise): a lane stops changing once its
   own iteration has converged, exactly where the scalar loop breaks */
static inline void Polar4(const PSv4 F[3][3], PSv4 R[3][3])
{
  PSv4     X[3][3], C[3][3];
  PSm4     active = {-1, -1, -1, -1};
  PetscInt it, i, j;
  for (i = 0; i < 3; i++)
    for (j = 0; j < 3; j++) X[i][j] = F[i][j];
  for (it = 0; it < 40 && Any4(active); it++) {
    PSv4 di, diff = {0, 0, 0, 0};
    C[0][0] = X[1][1] * X[2][2] - X[1][2] * X[2][1];
    C[0][1] = X[1][2] * X[2][0] - X[1][0] * X[2][2];
    C[0][2] = X[1][0] * X[2][1] - X[1][1] * X[2][0];
    C[1][0] = X[0][2] * X[2][1] - X[0][1] * X[2][2];
    C[1][1] = X[0][0] * X[2][2] - X[0][2] * X[2][0];
    C[1][2] = X[0][1] * X[2][0] - X[0][0] * X[2][1];
    C[2][0] = X[0][1] * X[1][2] - X[0][2] * X[1][1];
    C[2][1] = X[0][2] * X[1][0] - X[0][0] * X[1][2];
    C[2][2] = X[0][0] * X[1][1] - X[0][1] * X[1][0];
    di = 1.0 / (X[0][0] * C[0][0] + X[0][1] * C[0][1] + X[0][2] * C[0][2]);
    for (i = 0; i < 3; i++)
      for (j = 0; j < 3; j++) {
        const PSv4 y = 0.5 * (X[i][j] + C[i][j] * di);
        diff += Abs4(y - X[i][j]);
        X[i][j] = Select4(active, y, X[i][j]);
      }
    active &= ~(PSm4)(diff < 1e-8);
  }
  for (i = 0; i < 3; i++)
    for (j = 0; j < 3; j++) R[i][j] = X[i][j];
}

PetscErrorCode PSMarkerUpdate4(const PSMaterial *M, const PetscReal L[4][3][3], PetscReal dt, PetscReal h, PetscReal c_linear, PetscReal c_quadratic, PSMarkerState s[4], PetscReal Jout[4], PetscReal cout[4])
{
  PSv4     F[3][3], Fn[3][3], Lv[3][3], D[3][3], Dt[3][3], R[3][3], S[3][3], S0[3][3];
  PSv4     J, rho, irho, trD, wdev = {0, 0, 0, 0};
  PetscInt i, j, k, l;

  PetscFunctionBeginUser;
  /* 1. deformation gradient, volume, rate of deformation (PSKinematics) */
  for (i = 0; i < 3; i++)
    for (j = 0; j < 3; j++) {
      F[i][j]  = (PSv4){s[0].F[3 * i + j], s[1].F[3 * i + j], s[2].F[3 * i + j], s[3].F[3 * i + j]};
      Lv[i][j] = (PSv4){L[0][i][j], L[1][i][j], L[2][i][j], L[3][i][j]};
    }
  for (i = 0; i < 3; i++)
    for (j = 0; j < 3; j++) {
      Fn[i][j] = F[i][j];
      for (k = 0; k < 3; k++) Fn[i][j] += dt * Lv[i][k] * F[k][j];
      D[i][j] = 0.5 * (Lv[i][j] + Lv[j][i]);
    }
  trD = D[0][0] + D[1][1] + D[2][2];
  J   = Fn[0][0] * (Fn[1][1] * Fn[2][2] - Fn[1][2] * Fn[2][1]) - Fn[0][1] * (Fn[1][0] * Fn[2][2] - Fn[1][2] * Fn[2][0]) + Fn[0][2] * (Fn[1][0] * Fn[2][1] - Fn[1][1] * Fn[2][0]);
  if (Any4((PSm4)(J <= 0.0))) { /* the scalar kernel names the marker */
    for (l = 0; l < 4; l++) PetscCall(PSMarkerUpdate(M, 3, L[l], dt, h, c_linear, c_quadratic, &s[l], &Jout[l], &cout[l]));
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  for (l = 0; l < 4; l++) {
    for (i = 0; i < 3; i++)
      for (j = 0; j < 3; j++) s[l].F[3 * i + j] = Fn[i][j][l];
    *s[l].vol = J[l] * s[l].V0;
    Jout[l]   = J[l];
  }
  rho  = M->rho0 / J;
  irho = J / M->rho0;
  for (i = 0; i < 3; i++) D[i][i] -= trD / 3.0; /* D' */

  /* 2-3. unrotated deviator with J2 return */
  Polar4(Fn, R);
  {
    const PetscInt u[3][3] = {{0, 5, 4}, {5, 1, 3}, {4, 3, 2}}; /* xx,yy,zz,yz,xz,xy */
    for (i = 0; i < 3; i++)
      for (j = 0; j < 3; j++) S[i][j] = (PSv4){s[0].sdev[u[i][j]], s[1].sdev[u[i][j]], s[2].sdev[u[i][j]], s[3].sdev[u[i][j]]};
  }
  if (M->G > 0.0) {
    PSv4 seq2 = {0, 0, 0, 0}, Dd = {0, 0, 0, 0};
    for (i = 0; i < 3; i++)
      for (j = 0; j < 3; j++) S0[i][j] = S[i][j];
    Turn4(R, PETSC_TRUE, D, Dt); /* D~' = R^T D' R */
    for (i = 0; i < 3; i++)
      for (j = 0; j < 3; j++) {
        S[i][j] += 2.0 * M->G * dt * Dt[i][j];
        seq2 += S[i][j] * S[i][j];
        Dd += Dt[i][j] * Dt[i][j];
      }
    if (M->strength_fn) {
      PSv4 scale = {1, 1, 1, 1};
      for (l = 0; l < 4; l++) {
        const PetscReal seq = PetscSqrtReal(1.5 * seq2[l]), eps_dot = PetscSqrtReal(2.0 / 3.0 * Dd[l]);
        PetscReal       Y;
        PetscCall(M->strength_fn(M, s[l].eps_p ? *s[l].eps_p : 0.0, eps_dot, s[l].T ? *s[l].T : M->T_room, &Y));
        if (seq > Y) {
          const PetscReal dep = (seq - Y) / (3.0 * M->G);
          scale[l]            = Y / seq;
          if (s[l].eps_p) *s[l].eps_p += dep;
          if (s[l].T && M->cv > 0.0) *s[l].T += M->chi * Y * dep / (rho[l] * M->cv);
        }
      }
      for (i = 0; i < 3; i++)
        for (j = 0; j < 3; j++) S[i][j] *= scale; /* x 1 exactly where elastic */
    }
    {
      PSv4 w[3] = {{0, 0, 0, 0}, {0, 0, 0, 0}, {0, 0, 0, 0}};
      for (i = 0; i < 3; i++)
        for (j = 0; j < 3; j++) w[i] += (S0[i][j] + S[i][j]) * Dt[i][j];
      wdev = 0.5 * (w[0] + w[1] + w[2]);
    }
  }
  for (l = 0; l < 4; l++) {
    PetscReal *v = s[l].sdev;
    v[0]         = S[0][0][l];
    v[1]         = S[1][1][l];
    v[2]         = S[2][2][l];
    v[3]         = 0.5 * (S[1][2][l] + S[2][1][l]);
    v[4]         = 0.5 * (S[0][2][l] + S[2][0][l]);
    v[5]         = 0.5 * (S[0][1][l] + S[1][0][l]);
  }

  /* 4-5. pressure, viscosity, energy, lane by lane (update.c) */
  PSv4 p1v, c2v;
  for (l = 0; l < 4; l++) {
    const PetscReal p0 = *s[l].p;
    PetscReal       A, B, c2, q, e1, p1;
    PetscCall(M->eos_fn(M, J[l], p0, trD[l] * dt, &A, &B, &c2));
    q = trD[l] < 0.0 ? PSViscosity(rho[l], h, trD[l], PetscSqrtReal(c2), c_linear, c_quadratic) : 0.0;
    PSPressureEnergy(M, PETSC_FALSE, *s[l].e, dt * wdev[l] * irho[l], dt * trD[l] * irho[l], p0, A, B, q, &e1, &p1);
    *s[l].e = e1;
    *s[l].p = p1;
    *s[l].q = q;
    p1v[l]  = p1;
    c2v[l]  = c2;
  }

  /* 6. Cauchy stress sigma = R s~ R^T - p I */
  Turn4(R, PETSC_FALSE, S, Dt);
  for (i = 0; i < 3; i++) Dt[i][i] -= p1v;
  for (l = 0; l < 4; l++) {
    PetscReal *v = s[l].sig;
    v[0]         = Dt[0][0][l];
    v[1]         = Dt[1][1][l];
    v[2]         = Dt[2][2][l];
    v[3]         = 0.5 * (Dt[1][2][l] + Dt[2][1][l]);
    v[4]         = 0.5 * (Dt[0][2][l] + Dt[2][0][l]);
    v[5]         = 0.5 * (Dt[0][1][l] + Dt[1][0][l]);
    cout[l]      = PetscSqrtReal(c2v[l] + (4.0 / 3.0) * M->G * irho[l]);
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}
