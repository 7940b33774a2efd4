/*
  Orthotropic ply: one marker's update over a step of length dt, given its
  velocity gradient L (1/s).  Stresses and strain rates of the ply are taken in
  its material axes a_1 (fiber), a_2, a_3, as Voigt vectors 11,22,33,23,13,12
  (engineering shear rates).

  1. F <- (I + dt L) F, J = det F, rho = rho0 / J (as the isotropic kernel).
  2. Axes turn with the material: a_k = R a_k^0, R from the polar decomposition
     F = R U (Green-Naghdi; the rotation the isotropic deviator uses), so they
     stay orthonormal to round-off.  The rate in material axes is
     d^ = (a_k . D a_l); a rigid rotation has D = 0 and leaves the stress in
     material axes unchanged (objective).
  3. Volumetric/deviatoric split for shock response, in the spirit of Anderson,
     Cox, Johnson & Maudlin (Comput. Mech. 15, 1994): sigma^ = s_r - p I, where
       s_r += dt (C d^ - K_R tr(D) I)        (stored, field "stress_material")
       p    = EOS(J, e)                       (Mie-Grueneisen, or without an EOS
                                               the linear dp = -K_R tr(D) dt)
     with K_R = 1 / sum_{i,j<=3} S_ij the Reuss bulk modulus.  Our choice of
     K_R (not the Voigt average) makes a hydrostatic strain rate, the one a
     pressure causes (d^ proportional to S:I), give s_r = 0 exactly, so a
     hydrostatic state is carried by the EOS alone; with the linear EOS the sum
     is exactly sigma^ = C : eps (the orthotropic stiffness alone).
  4. Failure (ply_failure_fn, e.g. Hashin 1980) sees the stress with the EOS
     pressure removed in compression: s_eff = s_r - min(p, 0) I, so a shocked
     ply does not fail from pressure alone (as in the orthotropic-with-EOS
     models of Clegg, Hayhurst et al., AUTODYN).  Each mode's index F >= 1
     initiates damage; with r = sqrt(F) (the strain over its initiation value
     for proportional loading) damage grows by linear softening in equivalent
     strain whose area is the mode's fracture energy over the cell size h
     (crack band, Bazant & Oh 1983; Lapczyk & Hurtado, Composites A 38, 2007):
       d = k (r - 1) / (r (k - 1)),  k = 2 G_c E / (X^2 h),  d never decreases.
     k <= 1 (cells too large for the energy) fails the mode at once; the run
     warns of it at set-up.
  5. Nominal stress: fiber terms scale by (1 - d_f) (d_ft or d_fc by the sign
     of s_eff,11), the transverse normal ones by (1 - d_m) (d_mt or d_mc by the
     sign of s_eff,22 + s_eff,33), shears by 1 - prod(1 - d_k) (Lapczyk &
     Hurtado 2007).  The EOS pressure is never degraded in compression (a
     shocked, damaged ply still carries pressure); in tension it is scaled by
     1 - max(d_ft, d_mt).
  6. Energy with the trapezoidal work of the nominal stress and the viscosity,
     solved exactly for p = A + B e as in the isotropic kernel.
  7. sigma = A^T sigma^ A (A: rows a_k); plane strain keeps xx, yy, zz, xy (the
     out-of-plane shears of an off-axis ply do no work in plane strain).
*/
#include "../materials.h"

/* a rate in the ply's axes A (rows a_k), Voigt with engineering shears:
   d^_kl = a_k . D a_l */
static void RateToMaterial(const PetscReal A[3][3], const PetscReal D[3][3], PetscReal v[6])
{
  PetscReal Y[3][3];
  PSTurn(A, PETSC_FALSE, D, Y);
  v[0] = Y[0][0];
  v[1] = Y[1][1];
  v[2] = Y[2][2];
  v[3] = 2.0 * Y[1][2];
  v[4] = 2.0 * Y[0][2];
  v[5] = 2.0 * Y[0][1];
}

/* degradation of the Voigt stress by the damage d (step 5); returns the
   tension factor of the pressure */
static PetscReal Degrade(const PetscReal *d, const PetscReal seff[6], const PetscReal s[6], PetscReal out[6])
{
  const PetscReal df = seff[0] >= 0.0 ? d[0] : d[1];
  const PetscReal dm = seff[1] + seff[2] >= 0.0 ? d[2] : d[3];
  const PetscReal ds = 1.0 - (1.0 - d[0]) * (1.0 - d[1]) * (1.0 - d[2]) * (1.0 - d[3]);
  out[0] = (1.0 - df) * s[0];
  out[1] = (1.0 - dm) * s[1];
  out[2] = (1.0 - dm) * s[2];
  out[3] = (1.0 - ds) * s[3];
  out[4] = (1.0 - ds) * s[4];
  out[5] = (1.0 - ds) * s[5];
  return 1.0 - PetscMax(d[0], d[2]);
}

/* linear softening in equivalent strain: damage at r = strain / initiation strain */
static PetscReal Softening(PetscReal r, PetscReal k)
{
  if (r <= 1.0) return 0.0;
  if (k <= 1.0) return 1.0;
  return PetscMin(1.0, k * (r - 1.0) / (r * (k - 1.0)));
}

PetscErrorCode PSMarkerUpdateOrthotropic(const PSMaterial *M, PetscInt dim, const PetscReal L[3][3], PetscReal dt, PetscReal h, PetscReal c_linear, PetscReal c_quadratic, PSMarkerState *s, PetscReal *Jout, PetscReal *cout)
{
  const PSPly    *P     = &M->ply;
  const PetscReal zero4[4] = {0, 0, 0, 0};
  PetscReal       Fn[3][3], R[3][3], A[3][3], D[3][3], Sg[3][3];
  PetscReal       d[6], sr0[6], sr[6], sn0[6], sn[6], seff[6], dold[4], J, rho, trD, Aeos, Beos, c2, c, q, wdev = 0.0, p0 = *s->p, ptrial, p1, e1, f0, f1;
  PetscInt        i, j, k;

  PetscFunctionBeginUser;
  /* 1. deformation gradient, volume, rate of deformation */
  J     = PSKinematics(dim, L, dt, s, Fn, D, &trD);
  *Jout = J;
  if (J <= 0.0) PetscFunctionReturn(PETSC_SUCCESS);
  rho = M->rho0 / J;

  /* 2. axes a_k = R a_k^0 and the rate in material axes */
  PSPolarRotation(Fn, R);
  for (k = 0; k < 3; k++)
    for (i = 0; i < 3; i++) {
      A[k][i] = 0.0;
      for (j = 0; j < 3; j++) A[k][i] += R[i][j] * s->axes0[3 * k + j];
      s->axes[3 * k + i] = A[k][i];
    }
  RateToMaterial(A, D, d);

  /* 3. remainder stress s_r and the EOS's pressure p = Aeos + Beos e */
  for (i = 0; i < 6; i++) {
    PetscReal Cd = 0.0;
    for (j = 0; j < 6; j++) Cd += P->C[6 * i + j] * d[j];
    sr0[i] = s->smat[i];
    sr[i]  = sr0[i] + dt * (Cd - (i < 3 ? P->K_R * trD : 0.0));
  }
  PetscCall(M->eos_fn(M, J, p0, trD * dt, &Aeos, &Beos, &c2));

  /* 4. failure of the stress with the EOS pressure removed in compression */
  for (k = 0; k < 4; k++) dold[k] = s->D ? s->D[k] : 0.0;
  for (i = 0; i < 6; i++) seff[i] = sr0[i] - (i < 3 ? PetscMin(p0, 0.0) : 0.0);
  f0 = Degrade(s->D ? dold : zero4, seff, sr0, sn0);
  ptrial = Aeos + Beos * (*s->e);
  for (i = 0; i < 6; i++) seff[i] = sr[i] - (i < 3 ? PetscMin(ptrial, 0.0) : 0.0);
  if (M->ply_failure_fn && s->D) {
    PetscReal Fi[4];
    PetscCall(M->ply_failure_fn(M, seff, Fi));
    for (k = 0; k < 4; k++) {
      const PetscReal X = P->X[k], kk = 2.0 * P->Gc[k] * P->E[k] / (X * X * h);
      s->D[k] = PetscMax(s->D[k], Softening(PetscSqrtReal(PetscMax(Fi[k], 0.0)), kk));
    }
  }

  /* 5-6. nominal stress, viscosity, energy */
  f1 = Degrade(s->D ? s->D : zero4, seff, sr, sn);
  if (p0 >= 0.0) f0 = 1.0;
  if (ptrial >= 0.0) f1 = 1.0;
  if (M->spall < 0.0 && p0 < M->spall) f0 = 0.0; /* spalled at the start: it carried no tension */
  for (i = 0; i < 6; i++) wdev += 0.5 * (sn0[i] + sn[i]) * d[i];
  c = PetscSqrtReal(P->c2max * J + PetscMax(0.0, c2 - P->K_R * J / M->rho0));
  q = PSViscosity(rho, h, trD, c, c_linear, c_quadratic);
  {
    const PetscReal a = dt * trD / rho;
    e1 = (*s->e + dt * wdev / rho - a * (0.5 * f0 * p0 + 0.5 * f1 * Aeos + q)) / (1.0 + 0.5 * a * f1 * Beos);
    p1 = Aeos + Beos * e1;
    /* spalled (below spall_pressure) at the end: no tension, so the step's
       pressure work is that of (f0 p0 + 0)/2, as in update.c */
    if (M->spall < 0.0 && p1 < M->spall) {
      f1 = 0.0;
      e1 = *s->e + dt * wdev / rho - a * (0.5 * f0 * p0 + q);
      p1 = Aeos + Beos * e1;
    }
  }
  *s->e = e1;
  *s->p = p1;
  *s->q = q;
  for (i = 0; i < 6; i++) s->smat[i] = sr[i];

  /* 7. Cauchy stress sigma = A^T (s_n - f p I) A */
  Sg[0][0] = sn[0] - f1 * p1;
  Sg[1][1] = sn[1] - f1 * p1;
  Sg[2][2] = sn[2] - f1 * p1;
  Sg[1][2] = Sg[2][1] = sn[3];
  Sg[0][2] = Sg[2][0] = sn[4];
  Sg[0][1] = Sg[1][0] = sn[5];
  PSTurn(A, PETSC_TRUE, Sg, D);
  PSStressPack(dim, D, s->sig);
  *cout = c;
  PetscFunctionReturn(PETSC_SUCCESS);
}
