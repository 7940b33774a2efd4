/*
  The isotropic kernel of update.c for four 3D markers of one material at
  once: one 4-wide vector (PSv4) per tensor component, so the deformation
  gradient, the polar rotation and both frame changes run on all four markers
  in the same instructions.  The scalar kernel is latency-bound (a chain of
  dependent 3x3 products per marker); four independent chains fill the FMA
  units.  Each lane performs the scalar kernel's operations in the same order,
  so a marker's result is bitwise the one PSMarkerUpdate gives (the tests
  compare the two paths).  Symmetric tensors are 6 components (materials.h).
  The flow stress, and the EOS with viscosity and energy of materials with
  an EOS model, go lane by lane through the scalar code's functions; the
  elastic materials' (no EOS model: PSEOSHydroelastic, no spall) are written
  out in lanes in a second compiled form, PSMarkerUpdate4Elastic, since a
  call spills every lane.

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

/* Y = Q X Q^T, or Q^T X Q when transpose, X and Y symmetric (PSTurnSym, lane-wise) */
static inline void TurnSym4(const PSv4 Q[3][3], PetscBool transpose, const PSv4 X[6], PSv4 Y[6])
{
  PSv4     T[3][3];
  PetscInt a, k, j;
  for (k = 0; k < 3; k++)
    for (j = 0; j < 3; j++) T[k][j] = X[PS_SYM[k][0]] * (transpose ? Q[0][j] : Q[j][0]) + X[PS_SYM[k][1]] * (transpose ? Q[1][j] : Q[j][1]) + X[PS_SYM[k][2]] * (transpose ? Q[2][j] : Q[j][2]);
  for (a = 0; a < 6; a++) {
    const PetscInt i = PS_SYM_I[a];
    j                = PS_SYM_J[a];
    Y[a]             = (transpose ? Q[0][i] : Q[i][0]) * T[0][j] + (transpose ? Q[1][i] : Q[i][1]) * T[1][j] + (transpose ? Q[2][i] : Q[i][2]) * T[2][j];
  }
}

/* A : B (PSSymDot, lane-wise) */
static inline PSv4 SymDot4(const PSv4 A[6], const PSv4 B[6])
{
  return (A[0] * B[0] + A[1] * B[1] + A[2] * B[2]) + 2.0 * (A[3] * B[3] + A[4] * B[4] + A[5] * B[5]);
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

/* the kernel's body, compiled twice (registry.c picks one per material):
   elastic, a constant, writes the hydroelastic EOS (no EOS model, no spall)
   with the viscosity and energy out in lanes */
static inline __attribute__((always_inline)) PetscErrorCode Update4(const PSMaterial *M, const PetscBool elastic, const PetscReal L[4][3][3], PetscReal dt, PetscReal h, PetscReal c_linear, PetscReal c_quadratic, PSMarkerState s[4], PetscReal Jout[4], PetscReal cout[4])
{
  PSv4     Fn[3][3], R[3][3], Dp[6], Dt[6], S[6];
  PSv4     J, rho, irho, trD, wdev = {0, 0, 0, 0}, p1v, c2v;
  PetscInt i, j, k, l, a;

  PetscFunctionBeginUser;
  /* 1. deformation gradient, volume, rate of deformation (PSKinematics) */
  {
    PSv4 F[3][3], Lv[3][3];
    for (i = 0; i < 3; i++)
      for (j = 0; j < 3; j++) {
        F[i][j]  = (PSv4){s[0].F[3 * i + j], s[1].F[3 * i + j], s[2].F[3 * i + j], s[3].F[3 * i + j]};
        Lv[i][j] = (PSv4){L[0][i][j], L[1][i][j], L[2][i][j], L[3][i][j]};
      }
    for (i = 0; i < 3; i++)
      for (j = 0; j < 3; j++) {
        Fn[i][j] = F[i][j];
        for (k = 0; k < 3; k++) Fn[i][j] += dt * Lv[i][k] * F[k][j];
      }
    for (a = 0; a < 6; a++) Dp[a] = 0.5 * (Lv[PS_SYM_I[a]][PS_SYM_J[a]] + Lv[PS_SYM_J[a]][PS_SYM_I[a]]);
  }
  trD = Dp[0] + Dp[1] + Dp[2];
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
  for (a = 0; a < 3; a++) Dp[a] -= trD / 3.0; /* D' */

  /* 2-3. unrotated deviator with J2 return */
  Polar4(Fn, R);
  for (a = 0; a < 6; a++) S[a] = (PSv4){s[0].sdev[a], s[1].sdev[a], s[2].sdev[a], s[3].sdev[a]};
  if (M->G > 0.0) {
    PSv4 S0[6], seq2, Dd2;
    for (a = 0; a < 6; a++) S0[a] = S[a];
    TurnSym4(R, PETSC_TRUE, Dp, Dt); /* D~' = R^T D' R */
    for (a = 0; a < 6; a++) S[a] += 2.0 * M->G * dt * Dt[a];
    seq2 = SymDot4(S, S);
    Dd2  = SymDot4(Dt, Dt);
    if (M->strength_fn) {
      PSv4 scale = {1, 1, 1, 1};
      for (l = 0; l < 4; l++) {
        const PetscReal seq = PetscSqrtReal(1.5 * seq2[l]), eps_dot = PetscSqrtReal(2.0 / 3.0 * Dd2[l]);
        PetscReal       Y;
        PetscCall(M->strength_fn(M, s[l].eps_p ? *s[l].eps_p : 0.0, eps_dot, s[l].T ? *s[l].T : M->T_room, &Y));
        if (seq > Y) {
          const PetscReal dep = (seq - Y) / (3.0 * M->G);
          scale[l]            = Y / seq;
          if (s[l].eps_p) *s[l].eps_p += dep;
          if (s[l].T && M->cv > 0.0) *s[l].T += M->chi * Y * dep / (rho[l] * M->cv);
        }
      }
      for (a = 0; a < 6; a++) S[a] *= scale; /* x 1 exactly where elastic */
    }
    for (a = 0; a < 6; a++) S0[a] += S[a];
    wdev = 0.5 * SymDot4(S0, Dt);
  }
  for (l = 0; l < 4; l++)
    for (a = 0; a < 6; a++) s[l].sdev[a] = S[a][l];

  /* 4-5. pressure, viscosity, energy (update.c) */
  if (elastic) {
    /* PSEOSHydroelastic, PSViscosity and PSPressureEnergy (no spall) in
       lanes: the same expressions, with no call that would spill the lanes */
    const PSv4 p0 = {*s[0].p, *s[1].p, *s[2].p, *s[3].p}, e0 = {*s[0].e, *s[1].e, *s[2].e, *s[3].e};
    const PSv4 zero = {0, 0, 0, 0}, A = p0 - M->K * (trD * dt), B = zero;
    const PSv4 c2 = M->K * J / M->rho0, w = dt * wdev * irho, av = dt * trD * irho;
    const PSm4 comp = (PSm4)(trD < 0.0);
    PSv4       q = zero, e1, p1;
    if (Any4(comp)) {
      const PSv4 c = {PetscSqrtReal(c2[0]), PetscSqrtReal(c2[1]), PetscSqrtReal(c2[2]), PetscSqrtReal(c2[3])};
      q            = Select4(comp, rho * h * (c_quadratic * h * trD * trD + c_linear * c * Abs4(trD)), zero);
    }
    e1 = (e0 + w - av * (0.5 * p0 + 0.5 * A + q)) / (1.0 + 0.5 * av * B);
    p1 = A + B * e1;
    for (l = 0; l < 4; l++) {
      *s[l].e = e1[l];
      *s[l].p = p1[l];
      *s[l].q = q[l];
    }
    p1v = p1;
    c2v = c2;
  } else
    for (l = 0; l < 4; l++) { /* lane by lane */
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
  TurnSym4(R, PETSC_FALSE, S, Dt);
  for (a = 0; a < 3; a++) Dt[a] -= p1v;
  for (l = 0; l < 4; l++) {
    for (a = 0; a < 6; a++) s[l].sig[a] = Dt[a][l];
    cout[l] = PetscSqrtReal(c2v[l] + (4.0 / 3.0) * M->G * irho[l]);
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode PSMarkerUpdate4(const PSMaterial *M, const PetscReal L[4][3][3], PetscReal dt, PetscReal h, PetscReal c_linear, PetscReal c_quadratic, PSMarkerState s[4], PetscReal J[4], PetscReal c[4])
{
  return Update4(M, PETSC_FALSE, L, dt, h, c_linear, c_quadratic, s, J, c);
}

PetscErrorCode PSMarkerUpdate4Elastic(const PSMaterial *M, const PetscReal L[4][3][3], PetscReal dt, PetscReal h, PetscReal c_linear, PetscReal c_quadratic, PSMarkerState s[4], PetscReal J[4], PetscReal c[4])
{
  return Update4(M, PETSC_TRUE, L, dt, h, c_linear, c_quadratic, s, J, c);
}
