/*
  Mechanical Threshold Stress flow stress (P. S. Follansbee & U. F. Kocks,
  "A constitutive description of the deformation of copper based on the use
  of the mechanical threshold stress as an internal state variable", Acta
  Metall. 36 (1988) 81), in the notation of Uintah's MTS flow model
  (Banerjee; after Goto et al. 2000):

    Y = sigma_a + (S_i sigma_i + S_e sigma_e) mu(T)/mu_0
    mu(T) = mu_0 - D / (exp(T_0/T) - 1)                        (Varshni)
    S_x = [1 - (kT/(g_0x mu b^3) ln(eps_dot_0x/eps_dot))^(1/q_x)]^(1/p_x),  x = i, e
    d sigma_e / d eps_p = theta_0 [1 - tanh(alpha X)/tanh(alpha)],  X = sigma_e/sigma_es
    theta_0 = a_0 + a_1 ln eps_dot + a_2 sqrt(eps_dot) - a_3 T
    sigma_es = sigma_es0 (eps_dot/eps_dot_es0)^(kT/(g_0es mu b^3))

  Units: stresses and mu_0, D in Pa; k/b^3 (k_over_b3) in Pa/K; T_0 in K;
  rates in 1/s; a_0, a_1 in Pa, a_2 in Pa s^(1/2), a_3 in Pa/K; g, p, q,
  alpha dimensionless.  Stage-IV hardening (theta_IV) is not included (0, as
  for copper).

  The evolving threshold sigma_e is taken, as Uintah's MTS flow model takes it,
  at the current rate and temperature from the total plastic strain (no
  history of rate or temperature jumps: the strength function sees eps_p,
  eps_dot and T only).  For that the evolution law integrates in closed form:
  with w = alpha (1 - X),

    eps_p = sigma_es sinh(alpha) / (alpha theta_0)
            [cosh(alpha) ln(sinh(alpha)/sinh(w)) - (alpha - w) sinh(alpha)],

  solved here for w by Newton's method kept inside its bracket (bisection when
  a step leaves it), from the Voce guess w = alpha exp(-theta_0 eps_p/sigma_es).
  The rate is the marker's total equivalent deviatoric rate (as for the other
  models), at least MTS_RATE_MIN; theta_0 below 0 is taken as 0 (no hardening).
*/
#include "../materials.h"

#define MTS_RATE_MIN 1.0e-7 /* 1/s: a marker at rest would give ln(0) (Uintah uses the same floor) */

/* S = [1 - (c ln(eps_dot_0/eps_dot))^(1/q)]^(1/p), 1 above eps_dot_0, 0 where the bracket is <= 0 */
static inline PetscReal ThermalFactor(PetscReal c, PetscReal eps_dot0, PetscReal eps_dot, PetscReal p, PetscReal q)
{
  const PetscReal x = c * PetscLogReal(eps_dot0 / eps_dot);
  PetscReal       b;
  if (x <= 0.0) return 1.0;
  b = 1.0 - PetscPowReal(x, 1.0 / q);
  return b > 0.0 ? PetscPowReal(b, 1.0 / p) : 0.0;
}

/* sigma_e after plastic strain eps_p at constant theta_0, sigma_es (the closed form above) */
static PetscReal EvolvingThreshold(PetscReal eps_p, PetscReal theta0, PetscReal ses, PetscReal alpha)
{
  const PetscReal sa = PetscSinhReal(alpha), ca = PetscCoshReal(alpha), A = ses * sa / (alpha * theta0);
  PetscReal       w, lo = 0.0, hi = alpha;
  PetscInt        it;

  if (eps_p <= 0.0 || theta0 <= 0.0 || ses <= 0.0) return 0.0;
  w = alpha * PetscExpReal(-theta0 * eps_p / ses);
  for (it = 0; it < 100; it++) {
    /* g(w) = eps(w) - eps_p decreases in w: g > 0 means w is too small */
    const PetscReal g  = A * (ca * PetscLogReal(sa / PetscSinhReal(w)) - (alpha - w) * sa) - eps_p;
    const PetscReal dg = A * (sa - ca / PetscTanhReal(w));
    PetscReal       wn;
    if (g > 0.0) lo = w;
    else hi = w;
    wn = w - g / dg;
    if (!(wn > lo && wn < hi)) wn = 0.5 * (lo + hi);
    if (PetscAbsReal(wn - w) <= 1e-15 * alpha) {
      w = wn;
      break;
    }
    w = wn;
  }
  return ses * (1.0 - w / alpha);
}

PetscErrorCode PSStrengthMTS(const PSMaterial *M, PetscReal eps_p, PetscReal eps_dot, PetscReal T, PetscReal *Y)
{
  const PSMTS    *c    = &M->mts;
  const PetscReal rate = PetscMax(eps_dot, MTS_RATE_MIN);
  const PetscReal mu   = c->mu_0 - c->D / (PetscExpReal(c->T_0 / T) - 1.0);
  const PetscReal CC   = c->k_over_b3 * T / mu;
  const PetscReal Se   = ThermalFactor(CC / c->g_0e, c->eps_dot_0e, rate, c->p_e, c->q_e);
  const PetscReal Si   = c->sigma_i > 0.0 ? ThermalFactor(CC / c->g_0i, c->eps_dot_0i, rate, c->p_i, c->q_i) : 0.0;
  const PetscReal th0  = c->a_0 + c->a_1 * PetscLogReal(rate) + c->a_2 * PetscSqrtReal(rate) - c->a_3 * T;
  const PetscReal ses  = c->sigma_es0 * PetscPowReal(rate / c->eps_dot_es0, CC / c->g_0es);

  PetscFunctionBeginUser;
  *Y = c->sigma_a + (Si * c->sigma_i + Se * EvolvingThreshold(eps_p, PetscMax(th0, 0.0), ses, c->alpha)) * mu / c->mu_0;
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Constants (the front end checks them first, naming the deck key). */
PetscErrorCode PSStrengthMTSCheck(const PSMaterial *M)
{
  const PSMTS *c = &M->mts;

  PetscFunctionBeginUser;
  PetscCheck(c->mu_0 > 0.0 && c->D >= 0.0 && c->T_0 >= 0.0, PETSC_COMM_SELF, PETSC_ERR_ARG_OUTOFRANGE, "MTS shear modulus: mu_0 %g Pa must be > 0, D %g Pa and T_0 %g K >= 0",
             (double)c->mu_0, (double)c->D, (double)c->T_0);
  PetscCheck(c->k_over_b3 > 0.0 && c->g_0e > 0.0 && c->g_0es > 0.0, PETSC_COMM_SELF, PETSC_ERR_ARG_OUTOFRANGE, "MTS k_over_b3 %g Pa/K, g_0e %g, g_0es %g must be > 0", (double)c->k_over_b3,
             (double)c->g_0e, (double)c->g_0es);
  PetscCheck(c->p_e > 0.0 && c->q_e > 0.0 && c->eps_dot_0e > 0.0 && c->eps_dot_es0 > 0.0, PETSC_COMM_SELF, PETSC_ERR_ARG_OUTOFRANGE,
             "MTS p_e %g, q_e %g, eps_dot_0e %g 1/s, eps_dot_es0 %g 1/s must be > 0", (double)c->p_e, (double)c->q_e, (double)c->eps_dot_0e, (double)c->eps_dot_es0);
  PetscCheck(c->sigma_a >= 0.0 && c->sigma_es0 > 0.0 && c->sigma_i >= 0.0, PETSC_COMM_SELF, PETSC_ERR_ARG_OUTOFRANGE, "MTS sigma_a %g Pa, sigma_i %g Pa must be >= 0 and sigma_es0 %g Pa > 0",
             (double)c->sigma_a, (double)c->sigma_i, (double)c->sigma_es0);
  PetscCheck(c->sigma_i == 0.0 || (c->g_0i > 0.0 && c->p_i > 0.0 && c->q_i > 0.0 && c->eps_dot_0i > 0.0), PETSC_COMM_SELF, PETSC_ERR_ARG_OUTOFRANGE,
             "MTS with sigma_i %g Pa needs g_0i %g, p_i %g, q_i %g, eps_dot_0i %g 1/s > 0", (double)c->sigma_i, (double)c->g_0i, (double)c->p_i, (double)c->q_i, (double)c->eps_dot_0i);
  PetscCheck(c->alpha >= 0.01 && c->alpha <= 50.0, PETSC_COMM_SELF, PETSC_ERR_ARG_OUTOFRANGE, "MTS alpha %g must be in [0.01, 50]", (double)c->alpha);
  PetscFunctionReturn(PETSC_SUCCESS);
}
