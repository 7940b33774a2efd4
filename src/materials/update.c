/*
  One marker's constitutive update over a step of length dt, given its
  velocity gradient L (1/s).

  1. F <- (I + dt L) F, J = det F, V = J V0, rho = rho0 / J.
  2. Rotation R of the polar decomposition F = R U (Higham's Newton iteration).
  3. Deviator, Green-Naghdi rate: the unrotated deviator s~ = R^T s R takes
     s~ += 2 G dt R^T D' R; J2 radial return against the flow stress Y (plastic
     strain, temperature by chi * plastic work / c_v, damage by the failure strain).
  4. Artificial viscosity q = rho h (c_q h tr(D)^2 + c_l c |tr D|) in compression
     only (von Neumann-Richtmyer quadratic + linear, Wilkins 1980).
  5. Energy with trapezoidal work, solved exactly for p = A + B e:
       e1 = e0 + dt/rho (s~0 + s~1)/2 : D~' - dt trD/rho ((p0 + p1)/2 + q)
  6. sigma = R s~ R^T - p I (q is kept apart, added only in the force).
  Plane strain (2D): F_zz = 1, L_zz = 0; sigma_zz from the deviator.
*/
#include <math.h>
#include "../materials.h"

/* stored components (3D xx,yy,zz,yz,xz,xy; 2D xx,yy,zz,xy) <-> the kernel's 6 (materials.h) */
static inline void Unpack(const PetscInt dim, const PetscReal *v, PetscReal S[6])
{
  S[0] = v[0];
  S[1] = v[1];
  S[2] = v[2];
  S[3] = dim == 3 ? v[3] : 0.0;
  S[4] = dim == 3 ? v[4] : 0.0;
  S[5] = dim == 3 ? v[5] : v[3];
}

static inline void Pack(const PetscInt dim, const PetscReal S[6], PetscReal *v)
{
  v[0] = S[0];
  v[1] = S[1];
  v[2] = S[2];
  if (dim == 3) {
    v[3] = S[3];
    v[4] = S[4];
    v[5] = S[5];
  } else v[3] = S[5];
}

/* R of F = R U: X <- (X + X^-T)/2 (Higham 1986).  The iteration converges
   quadratically: once a step changes X by less than 1e-8 (sum of |changes|)
   X is within ~1e-16 of R, so it stops there. */
void PSPolarRotation(const PetscReal F[3][3], PetscReal R[3][3])
{
  PetscReal X[3][3], C[3][3];
  PetscInt  it, i, j;
  for (i = 0; i < 3; i++)
    for (j = 0; j < 3; j++) X[i][j] = F[i][j];
  for (it = 0; it < 40; it++) {
    PetscReal di, diff = 0.0;
    /* X^-T = cofactor(X) / det X */
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
        const PetscReal y = 0.5 * (X[i][j] + C[i][j] * di);
        diff += PetscAbsReal(y - X[i][j]);
        X[i][j] = y;
      }
    if (diff < 1e-8) break;
  }
  for (i = 0; i < 3; i++)
    for (j = 0; j < 3; j++) R[i][j] = X[i][j];
}

/* A step that would invert a marker is an error naming it, never a silent NaN. */
PetscErrorCode PSMarkerCheckJ(PetscReal J, PetscInt64 id, PetscInt material, PetscInt step, PetscReal t)
{
  PetscFunctionBeginUser;
  PetscCheck(J > 0.0, PETSC_COMM_SELF, PETSC_ERR_NOT_CONVERGED, "marker %lld (material %" PetscInt_FMT ") would reach J = det F = %g <= 0 at step %" PetscInt_FMT ", t = %g s: the step inverts it; lower run.cfl or refine the grid",
             (long long)id, material, (double)J, step, (double)t);
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode PSMarkerSoundSpeed(const PSMaterial *M, PetscReal J, PetscReal e, PetscReal p, PetscReal *c)
{
  PetscReal A, B, c2;

  PetscFunctionBeginUser;
  (void)e;
  PetscCall(M->eos_fn(M, J, p, 0.0, &A, &B, &c2));
  if (M->aniso) *c = PetscSqrtReal(M->ply.c2max * J + PetscMax(0.0, c2 - M->ply.K_R * J / M->rho0)); /* see orthotropic.c */
  else *c = PetscSqrtReal(c2 + 4.0 * M->G * J / (3.0 * M->rho0));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* the kernel's body, inlined with a constant dim (a 2D and a 3D kernel) */
static inline __attribute__((always_inline)) PetscErrorCode Update(const PSMaterial *M, const PetscInt dim, const PetscReal L[3][3], PetscReal dt, PetscReal h, PetscReal c_linear, PetscReal c_quadratic, PSMarkerState *s, PetscReal *Jout, PetscReal *cout)
{
  PetscReal Fn[3][3], R[3][3], D[3][3], Dp[6], Dt[6], S[6];
  PetscReal J, rho, irho, trD, A, B, c2, q, wdev = 0.0, p0 = *s->p, p1, e1;
  PetscBool failed = (s->D && *s->D >= 1.0) ? PETSC_TRUE : PETSC_FALSE;
  PetscInt  a;

  PetscFunctionBeginUser;
  /* 1. deformation gradient, volume, rate of deformation */
  J     = PSKinematics(dim, L, dt, s, Fn, D, &trD);
  *Jout = J;
  if (J <= 0.0) PetscFunctionReturn(PETSC_SUCCESS);
  rho  = M->rho0 / J;
  irho = J / M->rho0; /* 1/rho without a second division */
  for (a = 0; a < 6; a++) Dp[a] = D[PS_SYM_I[a]][PS_SYM_J[a]];
  for (a = 0; a < 3; a++) Dp[a] -= trD / 3.0; /* D' */

  /* 2-3. unrotated deviator with J2 return */
  PSPolarRotation(Fn, R);
  Unpack(dim, s->sdev, S);
  if (M->G > 0.0 && !failed) {
    PetscReal seq2, Dd2, S0[6], Sm[6];
    for (a = 0; a < 6; a++) S0[a] = S[a];
    PSTurnSym(R, PETSC_TRUE, Dp, Dt); /* D~' = R^T D' R */
    for (a = 0; a < 6; a++) S[a] += 2.0 * M->G * dt * Dt[a];
    seq2 = PSSymDot(S, S);
    Dd2  = PSSymDot(Dt, Dt);
    if (M->strength_fn) {
      const PetscReal seq = PetscSqrtReal(1.5 * seq2), eps_dot = PetscSqrtReal(2.0 / 3.0 * Dd2);
      PetscReal       Y;
      PetscCall(M->strength_fn(M, s->eps_p ? *s->eps_p : 0.0, eps_dot, s->T ? *s->T : M->T_room, &Y));
      if (seq > Y) {
        const PetscReal dep = (seq - Y) / (3.0 * M->G);
        for (a = 0; a < 6; a++) S[a] *= Y / seq;
        if (s->eps_p) *s->eps_p += dep;
        if (s->T && M->cv > 0.0) *s->T += M->chi * Y * dep / (rho * M->cv);
        if (s->D && M->failure_fn) {
          PetscReal ef;
          PetscCall(M->failure_fn(M, -p0 / PetscMax(Y, 1.0), dep / dt, s->T ? *s->T : M->T_room, &ef));
          *s->D += dep / ef;
          if (*s->D >= 1.0) failed = PETSC_TRUE;
        }
      }
    }
    /* failing in this step: it ends with no deviator */
    if (failed)
      for (a = 0; a < 6; a++) S[a] = 0.0;
    /* deviatoric work with the mid-step stress (trapezoidal, like the pressure
       work; (S0 + 0)/2 in the step a marker fails) */
    for (a = 0; a < 6; a++) Sm[a] = S0[a] + S[a];
    wdev = 0.5 * PSSymDot(Sm, Dt);
  }
  /* a marker failed before this step skipped the block: its stored deviator
     is 0 (zeroed in the step it failed) and wdev stays 0 */
  Pack(dim, S, s->sdev);

  /* 4-5. pressure, viscosity, energy */
  PetscCall(M->eos_fn(M, J, p0, trD * dt, &A, &B, &c2));
  q = trD < 0.0 ? PSViscosity(rho, h, trD, PetscSqrtReal(c2), c_linear, c_quadratic) : 0.0; /* compression only */
  PSPressureEnergy(M, failed, *s->e, dt * wdev * irho, dt * trD * irho, p0, A, B, q, &e1, &p1);
  *s->e = e1;
  *s->p = p1;
  *s->q = q;

  /* 6. Cauchy stress sigma = R s~ R^T - p I */
  PSTurnSym(R, PETSC_FALSE, S, Dt);
  for (a = 0; a < 3; a++) Dt[a] -= p1;
  Pack(dim, Dt, s->sig);
  *cout = PetscSqrtReal(c2 + (4.0 / 3.0) * M->G * irho);
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode PSMarkerUpdate(const PSMaterial *M, PetscInt dim, const PetscReal L[3][3], PetscReal dt, PetscReal h, PetscReal c_linear, PetscReal c_quadratic, PSMarkerState *s, PetscReal *Jout, PetscReal *cout)
{
  return dim == 3 ? Update(M, 3, L, dt, h, c_linear, c_quadratic, s, Jout, cout) : Update(M, 2, L, dt, h, c_linear, c_quadratic, s, Jout, cout);
}
