/*
  contact.c - contact between marker bodies: one velocity field per body (or
  group of bonded bodies) at the nodes where two or more of them meet, and a
  contact law there (Bardenhagen, Brackbill & Sulsky, CMAME 187, 2000, 529-541;
  Bardenhagen et al., CMES 2, 2001, 509-522; as in Uintah's friction contact and
  NairnMPM's multimaterial mode).  MUSL transfer only (solver.h).

  Per field k and node i, besides the single field of the step (which holds the
  sum of all fields and every node's value where the bodies do not meet):
    P2G     m_ik = sum_{p in k} N_ip m_p,  (mv)_ik = sum_{p in k} N_ip m_p v_p,
            f_ik = -sum_{p in k} V_p (sigma_p - q_p I) grad N_ip,
            g_ik = sum_{p in k} m_p grad N_ip (grad N_ip = grad N_i at x_p, so g_ik
            is minus the gradient of the nodal mass: it points out of body k)  (PSContactP2G)
    grid    at a shared node (two or more fields heavier than mass_min):
            v_k = ((mv)_ik + dt f_ik) / m_ik with the boundary conditions;
            centre of mass v_cm = sum_k m_ik v_k / sum_k m_ik;
            normal of field k towards the others: the larger of g_ik and
              -sum_{j != k} g_ij, normalised (the field with the larger mass
              gradient defines the surface, like NairnMPM's maximum-volume-gradient
              normal option, here with mass gradients: a block's corners on a
              flat plate take the plate's normal;
              the difference g_a - g_b tilted them and slowed a frictionless
              block by 6.6%); two fields: n_a = -n_b (a tie goes to the lower
              field), so each node's exchange conserves momentum;
            a symmetry face mirrors the bodies: g has no component across it;
            approach  dn = (v_k - v_cm) . n_k > 0 (Bardenhagen et al. 2000);
            then the normal correction v_k -= dn n_k (no interpenetration) and
            Coulomb friction on the tangential rest t = v_k - v_cm - dn n_k:
              |t| <= mu dn: stick, v_k = v_cm;
              else slip,  v_k -= mu dn t/|t|          (Bardenhagen et al. 2001);
            dn <= 0: the field separates freely (no tension across a contact).
            The tangential correction dv_f (v_k after it minus v_k after the
            normal correction) is kept for G2P                        (PSContactGridSolve)
    G2P     each marker reads its field's v^new and dv at shared nodes, the
            single field elsewhere; the re-projection (mv) goes to both;
            friction work (history.csv friction_work): the impulse the
            tangential corrections gave the marker on its mean velocity
            over the step, -m_p sum_i N_ip dv_f,i . (v_p^n + v_p^n+1)/2
            (Nairn, Bardenhagen & Smith 2018)                        (PSContactG2P)
    re-project  the fields' re-projected velocity at shared nodes gets the
            same contact law where the grid phase applied it (not booked: it
            only sets L_p); L_p from the marker's field at shared nodes  (PSContactReproject)
  The friction coefficient of field k at a node is that of the pair of k and
  the heaviest other field there.
  Cell materials (src/cells/) put their nodal mass, momentum and force into the
  single field.  At a shared node where they have mass (m_c = m_i - sum_k m_ik
  > mass_min), that share (the single field's old and new momentum less the
  fields', which carries the boundary conditions) is shared among the fields
  in proportion to their masses, so each field feels the cells' force and
  the contact law acts on fields with the cells' mass in them (momentum
  conserved to round-off); the cells read the single field, the fields'
  centre of mass, and the cells' predictor's correction of it is added to
  every field there (PSContactCellsSync).  The cell material at such a node
  follows neither body, so what the markers crowd out of the cells around it
  is discarded and booked rather than crushed (src/cells/closure.c;
  docs/contact.md measures the alternatives).
*/
#include "contact.h"

/* one log event per kernel (registered by PSSolverSetContact) */
static PetscLogEvent PS_EV_ContactP2G = 0, PS_EV_ContactGrid, PS_EV_ContactG2P, PS_EV_ContactReproject;

/* zero the nodes of box in a dof-per-node ghosted local array */
static void ZeroBox(const PSIndex *ix, PetscReal *a, PetscInt dof, const PetscInt box[3][2])
{
  PetscInt lo[3], hi[3], j, k;

  Clip(box, ix->gs, ix->gm, lo, hi);
  if (hi[0] <= lo[0] || hi[1] <= lo[1] || hi[2] <= lo[2]) return;
  for (k = lo[2]; k < hi[2]; k++)
    for (j = lo[1]; j < hi[1]; j++) memset(&a[dof * Lidx(ix, lo[0], j, k)], 0, sizeof(PetscReal) * dof * (hi[0] - lo[0]));
}


/* The field of marker p: its body's, or its ply's in a laminate with cohesive
   ply interfaces */
static inline PetscInt MarkerField(const PSContact *C, const PSFields *f, PetscInt p)
{
  const PetscInt b = f->body[p];
  return C->field[b] + (C->split[b] ? f->ply[p] : 0);
}

/* psi below which a marker's interface is open (D = 1): the nodes' means of
   psi approach 0 only geometrically once they are all open */
#define PS_PSI_OPEN 1e-12

/* A cohesive pair's damage at a node, D = 1 - psi^1/2 from the mass-weighted
   mean psi of its two fields' (Pk: each field's (m psi)_k / m_k, psi_p =
   (1 - D_p)^2 the fraction of G_c a marker's interface still holds; see
   PSContactG2P for why psi, not D, is what the nodes average) */
static inline PetscReal PairDamage(const PetscReal *m, const PetscReal *Pk, PetscInt a, PetscInt b)
{
  return 1.0 - PetscSqrtReal(PetscMin(1.0, PetscMax(0.0, (m[a] * Pk[a] + m[b] * Pk[b]) / (m[a] + m[b]))));
}

/* axisymmetric: the radii [r0, r1] of node ip's ring, r_i -+ h/2 within the domain */
static inline void NodeRing(const PSSolver *S, const PetscInt ip[3], PetscReal *r0, PetscReal *r1)
{
  const PetscReal ri = S->scene->lower[0] + ip[0] * S->h[0];
  *r0 = PetscMax(S->scene->lower[0], ri - 0.5 * S->h[0]);
  *r1 = PetscMin(S->scene->upper[0], ri + 0.5 * S->h[0]);
}

/* A cohesive pair's interface area at node ip, (|g_a| V_a/m_a + |g_b| V_b/m_b)/2:
   the volume gradient of either ply, whose sum over a planar interface's nodes
   is its area.  Axisymmetric: g is the section's mass gradient (PSContactP2G),
   so that sum is the section's interface length, and the node's share of the
   revolution's area is it times 2 pi r_c, r_c the centroid radius of the
   node's ring [r_i - h/2, r_i + h/2] within the domain (r_i on the axis: h/4;
   with the half length such a node carries, the ring's area pi h^2/4) */
static inline PetscReal PairArea(const PSSolver *S, const PetscInt ip[3], const PetscReal *m, const PetscReal (*gm)[3], const PetscReal *V, PetscInt a, PetscInt b)
{
  const PetscReal ga = PetscSqrtReal(gm[a][0] * gm[a][0] + gm[a][1] * gm[a][1] + gm[a][2] * gm[a][2]);
  const PetscReal gb = PetscSqrtReal(gm[b][0] * gm[b][0] + gm[b][1] * gm[b][1] + gm[b][2] * gm[b][2]);
  const PetscReal A  = 0.5 * (ga * V[a] / m[a] + gb * V[b] / m[b]);
  PetscReal       r0, r1;
  if (!S->axi) return A;
  NodeRing(S, ip, &r0, &r1);
  return A * PETSC_PI * (r0 + r1);
}

/* The cohesive law between two adjacent plies' fields (Nairn, CMES 92, 2013,
   271-299: imperfect interfaces between the velocity fields of multimaterial
   MPM), on field k of mass mk whose heaviest neighbour is field o; n from k
   towards o, dn = (v_k - v_cm).n (> 0: approach), A the interface area at the
   node, Dn the node's damage.  The law is rigid until it breaks, then softens
   linearly (its rising branch rigid: a penalty stiffness would read the
   grid's strain across a ply, eps h, as opening):
     tension      the pair sticks (v_k = v_cm, as in the single field) while
                  the traction that takes, t = m_k (v_cm - v_k) / (dt A), lies
                  inside the strength ellipse r = (t_n/(N s))^2 + (t_s/(S s))^2
                  <= 1 (quadratic initiation: Camanho, Davila & de Moura,
                  J. Compos. Mater. 37, 2003, 1415-1438), s = 1 - D; beyond
                  it the traction is cut back onto the ellipse: v_k moves the
                  fraction r^-1/2 of the way to v_cm;
     compression  no interpenetration (contact's normal correction) and the
                  tangential traction capped by max(S s, mu p): once open
                  (D = 1) the interface is Coulomb contact with the scene's
                  friction. */
static PetscReal CohesiveLaw(const PSSolver *S, const PSContact *C, PetscInt k, PetscInt o, PetscReal mk, const PetscReal n[3], PetscReal dn, PetscReal A, PetscReal Dn, PetscReal dt, const PetscReal vcm[3], PetscReal vk[3], PetscReal dvf[3])
{
  const PetscInt   dim = S->dim, nf = C->nfield;
  const PetscReal *cp = &C->cohp[4 * C->coh[k * nf + o]], s = 1.0 - Dn, tf = mk / (dt * A); /* traction per unit velocity change (Pa s/m) */
  PetscReal        t[3], tt = 0.0, r, alpha, cap, ts;
  PetscInt         d;

  for (d = 0; d < dim; d++) {
    t[d] = vk[d] - vcm[d] - dn * n[d]; /* tangential rest */
    tt += t[d] * t[d];
  }
  tt = PetscSqrtReal(tt);
  ts = tf * tt;
  if (dn > 0.0) { /* compression */
    for (d = 0; d < dim; d++) vk[d] -= dn * n[d];
    cap = PetscMax(cp[1] * s, C->mu[k * nf + o] * tf * dn);
    alpha = ts <= cap ? 1.0 : cap / ts;
    /* the part of the tangential correction beyond the cohesive traction S s
       (whose work CohesiveDamage books) is friction's */
    if (dvf && cap > cp[1] * s)
      for (d = 0; d < dim; d++) dvf[d] = -(1.0 - cp[1] * s / cap) * alpha * t[d];
    for (d = 0; d < dim; d++) vk[d] = alpha < 1.0 ? vk[d] - alpha * t[d] : vcm[d]; /* stuck: exactly v_cm */
    return alpha;
  }
  if (s <= 0.0) return 0.0; /* open: the fields separate freely */
  r     = PetscSqr(tf * -dn / (cp[0] * s)) + PetscSqr(ts / (cp[1] * s));
  alpha = r <= 1.0 ? 1.0 : 1.0 / PetscSqrtReal(r);
  for (d = 0; d < dim; d++) vk[d] = alpha < 1.0 ? vk[d] - alpha * (vk[d] - vcm[d]) : vcm[d]; /* stuck: exactly v_cm */
  return alpha;
}

/* The damage of a cohesive pair (a, b) after the law (velocities v): the
   opening d = dt (v_b - v_a) of this step, normal part d_n = <d.n_a>, shear
   d_s, grows D by |d| / lambda_f with lambda_f = 2 G_c / T_eff, so that a full
   opening at one mode mix absorbs G_c per unit area under the linear
   softening; G_c from the linear power law G_I/G_Ic + G_II/G_IIc = 1 at the
   mix B = d_s^2/|d|^2 (Reeder, ASTM STP 1110, 1992: the power law with
   exponent 1), T_eff the strength ellipse's radius in the opening's
   direction.  *W gets the energy the law takes on the area A meanwhile,
   the integral of T_eff (1 - D) dlambda = A G_c ((1 - D0)^2 - (1 - D1)^2)
   (J; >= 0, and A G_c over a whole opening). */
static PetscReal CohesiveDamage(const PSSolver *S, const PSContact *C, PetscInt a, PetscInt b, const PetscReal na[3], PetscReal Dn, PetscReal A, PetscReal dt, PetscReal (*v)[3], PetscReal *W)
{
  const PetscInt   dim = S->dim;
  const PetscReal *cp  = &C->cohp[4 * C->coh[a * C->nfield + b]];
  PetscReal        dd[3], dnn = 0.0, ds2 = 0.0, dl2, B, Gc, c2, s2, Teff, D1;
  PetscInt         d;

  *W = 0.0;
  for (d = 0; d < dim; d++) {
    dd[d] = dt * (v[b][d] - v[a][d]);
    dnn += dd[d] * na[d];
  }
  for (d = 0; d < dim; d++) ds2 += PetscSqr(dd[d] - dnn * na[d]);
  dnn = PetscMax(dnn, 0.0); /* closing is not opening */
  dl2 = dnn * dnn + ds2;
  if (!(dl2 > 0.0) || Dn >= 1.0) return Dn;
  B    = ds2 / dl2;
  Gc   = 1.0 / ((1.0 - B) / cp[2] + B / cp[3]);
  c2   = dnn * dnn / dl2;
  s2   = ds2 / dl2;
  Teff = 1.0 / PetscSqrtReal(c2 / PetscSqr(cp[0]) + s2 / PetscSqr(cp[1]));
  D1   = PetscMin(1.0, Dn + PetscSqrtReal(dl2) * Teff / (2.0 * Gc));
  *W   = A * Gc * (PetscSqr(1.0 - Dn) - PetscSqr(1.0 - D1));
  return D1;
}

/* Whether the fields at a node touch: their volumes V_k = sum N_ip V_p fill at
   least PS_CONTACT_FILL of the node's own volume (the cell volume, halved per
   domain face the node lies on).  Two bodies a gap apart already share the
   nodes between them (GIMP reaches 1.5 cells), where the approach check alone
   would let them meet a cell early; that early contact created energy: a
   flyer (1 x 0.5 mm, aluminium, 50 m/s) two cells before an aluminium plate
   rebounded at -31 m/s with the total +55% (+21% at CFL 0.1); with this check
   -2.7%, as when the flyer starts in contact (-2.0%: contact's inelastic
   loss, tests/test_contact.py).  The
   check is NairnMPM's volume-based contact test in spirit (Nairn, CMES 92,
   2013). */
#define PS_CONTACT_FILL 0.9
static inline PetscBool Filled(const PSSolver *S, const PetscInt ip[3], const PetscReal *m, const PetscReal *V)
{
  const PSContact *C  = S->contact;
  PetscReal        Vn = 1.0, Vs = 0.0;
  PetscInt         d, k;

  for (d = 0; d < S->dim; d++) {
    if (d == 0 && S->axi) { /* axisymmetric: the node's ring (marker volumes are the full revolution's) */
      PetscReal r0, r1;
      NodeRing(S, ip, &r0, &r1);
      Vn *= PETSC_PI * (r1 * r1 - r0 * r0);
    } else Vn *= S->h[d] * ((ip[d] <= 0 || ip[d] >= S->scene->cells[d]) ? 0.5 : 1.0);
  }
  for (k = 0; k < C->nfield; k++)
    if (m[k] > S->mass_min) Vs += V[k];
  return Vs >= PS_CONTACT_FILL * Vn ? PETSC_TRUE : PETSC_FALSE;
}

/* The contact law on the fields' velocities v[k] (dim each, with the boundary
   conditions) at one node, with masses m[k], g[k] (layout above), nodal
   volumes V[k] and psi Pk[k] (PairDamage).  In the grid phase (iwork !=
   NULL): dvf[k] gets field k's tangential (friction) correction, alpha_k[k]
   1 where the contact corrected field k (friction pairs) or the fraction of
   the way to v_cm the cohesive law moved it (1: stuck), *iwork the energy
   the cohesive law took at the node (CohesiveDamage; J) and *dD the
   decrement of psi (the fraction of G_c taken) of the pair of the two
   heaviest fields (-1: not a cohesive pair).  In the re-projection (iwork,
   Pk, dvf, dD NULL) alpha_k holds those values: a friction pair is
   corrected where the grid phase corrected it; a cohesive pair that stuck
   sticks again, any other keeps each ply's own velocity (no
   interpenetration), so that L_p
   strains a ply by its own motion, not by the opening (measured on the
   mode-I spall, tests/test_cohesive.py: re-applying the fraction left
   4% of the energy the interface took in the plies as strain, taking each
   ply's own velocity everywhere made the intact interface 2% too energetic
   against bonded plies; this rule matches bonded plies while intact and
   keeps the total within 2%). */
static void ContactLaw(const PSSolver *S, const PSContact *C, const PetscInt ip[3], PetscReal dt, const PetscReal *m, const PetscReal (*gm)[3], const PetscReal *V, const PetscReal *Pk, PetscReal (*v)[3], PetscReal (*dvf)[3], PetscReal *alpha_k, PetscReal *iwork, PetscReal *dD, PetscInt *pair)
{
  const PetscInt dim = S->dim, nf = C->nfield;
  PetscReal      M = 0.0, vcm[3] = {0, 0, 0}, nk[16][3], P0[3] = {0, 0, 0}, dP[3] = {0, 0, 0};
  PetscInt       k, j, d, a = -1, b = -1, nh = 0;
  PetscBool      filled;

  if (iwork) *iwork = 0.0;
  if (dD) *dD = -1.0;
  for (k = 0; k < nf; k++) {
    if (m[k] <= S->mass_min) continue;
    M += m[k];
    nh++;
    for (d = 0; d < dim; d++) vcm[d] += m[k] * v[k][d];
    if (a < 0 || m[k] > m[a]) {
      b = a;
      a = k;
    } else if (b < 0 || m[k] > m[b]) b = k;
  }
  for (d = 0; d < dim; d++) {
    P0[d]  = vcm[d];
    vcm[d] /= M;
  }
  filled = Filled(S, ip, m, V);
  for (k = 0; k < nf; k++) {
    PetscReal n[3] = {0, 0, 0}, nn = 0.0, dn = 0.0, t[3] = {0, 0, 0}, tt = 0.0, mu, mo = 0.0, vn[3] = {0, 0, 0}, gk2 = 0.0, go2 = 0.0;
    PetscInt  other = -1, coh;
    for (d = 0; d < 3; d++) nk[k][d] = 0.0;
    if (dvf)
      for (d = 0; d < 3; d++) dvf[k][d] = 0.0;
    if (m[k] <= S->mass_min) continue;
    /* n_k: g = -grad m points out of its field; the larger of g_k and
       -sum_{j != k} g_j, normalised, points from k towards the others */
    for (j = 0; j < nf; j++) {
      if (j == k || m[j] <= S->mass_min) continue;
      for (d = 0; d < dim; d++) n[d] -= gm[j][d];
      if (m[j] > mo) {
        mo    = m[j];
        other = j;
      }
    }
    coh = C->coh ? C->coh[k * nf + other] : -1;
    for (d = 0; d < dim; d++) {
      gk2 += gm[k][d] * gm[k][d];
      go2 += n[d] * n[d];
    }
    if (gk2 > go2 || (gk2 == go2 && k < other)) /* a tie goes to the lower field, the same for both */
      for (d = 0; d < dim; d++) n[d] = gm[k][d];
    for (d = 0; d < dim; d++) nn += n[d] * n[d];
    if (coh >= 0) { /* adjacent plies of a laminate with cohesive interfaces */
      PetscReal alpha;
      if (nn > 0.0) {
        nn = PetscSqrtReal(nn);
        for (d = 0; d < dim; d++) {
          n[d] /= nn;
          nk[k][d] = n[d];
          dn += (v[k][d] - vcm[d]) * n[d];
        }
      }
      if (iwork) { /* the grid phase: the law */
        const PetscReal Dn = PairDamage(m, Pk, k, other), A = PairArea(S, ip, m, gm, V, k, other);
        if (!(nn > 0.0) || !(A > 0.0)) { /* no surface here: intact plies stay together */
          alpha = Dn < 1.0 ? 1.0 : 0.0;
          if (alpha > 0.0)
            for (d = 0; d < dim; d++) v[k][d] = vcm[d];
        } else alpha = CohesiveLaw(S, C, k, other, m[k], n, dn, A, Dn, dt, vcm, v[k], dvf[k]);
        PSNodeBC(S, ip, v[k]);
        alpha_k[k] = alpha;
      } else { /* the re-projection: where the grid phase stuck, stick; else each ply its own velocity, no interpenetration */
        if (alpha_k[k] >= 1.0)
          for (d = 0; d < dim; d++) v[k][d] = vcm[d];
        else if (dn > 0.0)
          for (d = 0; d < dim; d++) v[k][d] -= dn * n[d];
        PSNodeBC(S, ip, v[k]);
      }
      continue;
    }
    if (!(nn > 0.0)) continue; /* no direction: the fields move freely */
    if (!filled) continue;     /* a gap: the fields do not touch yet */
    nn = PetscSqrtReal(nn);
    for (d = 0; d < dim; d++) {
      n[d] /= nn;
      dn += (v[k][d] - vcm[d]) * n[d];
    }
    /* the grid phase corrects an approaching field (dn > 0) and notes it in
       alpha_k; the re-projection corrects exactly those fields, whatever the
       re-projected velocities' approach: L_p then strains the bodies as the
       grid phase moved them.  (Re-deciding on the re-projected approach let
       the strain return more energy than the correction took: a flyer
       striking a bar's end in 2D ended +1.8% and +1.9% at 50 and 25 um cells;
       this way -2.4% and -1.2%: an inelastic loss of first order in h, as a
       grid contact's.) */
    if (!iwork) {
      if (alpha_k[k] < 1.0) continue; /* the grid phase left it free */
    } else if (dn <= 0.0) continue;   /* separating: free */
    else alpha_k[k] = 1.0;
    mu = C->mu[k * nf + other];
    for (d = 0; d < dim; d++) {
      v[k][d] -= dn * n[d]; /* normal correction: v_k . n = v_cm . n */
      t[d] = v[k][d] - vcm[d];
      tt += t[d] * t[d];
      vn[d] = v[k][d];
    }
    tt = PetscSqrtReal(tt);
    if (tt <= mu * dn) { /* stick */
      for (d = 0; d < dim; d++) v[k][d] = vcm[d];
    } else { /* slip: the tangential velocity loses mu dn */
      for (d = 0; d < dim; d++) v[k][d] -= mu * dn * t[d] / tt;
    }
    if (dvf)
      for (d = 0; d < dim; d++) dvf[k][d] = v[k][d] - vn[d]; /* the tangential correction, booked by the markers' impulse (PSContactG2P) */
    PSNodeBC(S, ip, v[k]); /* the normal may lean into a direction a face holds */
  }
  /* three or more fields: each field's correction towards v_cm along its own
     normal does not cancel as two fields' (n_a = -n_b) do; the momentum it
     leaves over is taken back by one velocity shift of all fields, which keeps
     their relative velocities (the contact and the cohesive law) */
  if (nh > 2) {
    for (k = 0; k < nf; k++)
      if (m[k] > S->mass_min)
        for (d = 0; d < dim; d++) dP[d] += m[k] * v[k][d];
    for (k = 0; k < nf; k++)
      if (m[k] > S->mass_min) {
        for (d = 0; d < dim; d++) v[k][d] -= (dP[d] - P0[d]) / M;
        PSNodeBC(S, ip, v[k]);
      }
  }
  /* the damage of the node's cohesive pair, its two heaviest fields, and the
     energy its law took */
  if (dD && b >= 0 && C->coh && C->coh[a * nf + b] >= 0) {
    const PetscReal Dn = PairDamage(m, Pk, a, b);
    const PetscReal D1 = (nk[a][0] != 0.0 || nk[a][1] != 0.0 || nk[a][2] != 0.0) ? CohesiveDamage(S, C, a, b, nk[a], Dn, PairArea(S, ip, m, gm, V, a, b), dt, v, iwork) : Dn;
    *dD                = PetscSqr(1.0 - Dn) - PetscSqr(1.0 - D1); /* the fraction of G_c taken: psi0 - psi1 >= 0 */
    pair[0]            = a;
    pair[1]            = b;
  }
}

/* 1. the fields' P2G (after the single field's: it located the markers, S->at).
   First the fields' masses alone, summed over the ranks, mark the shared
   nodes and the markers near them (touching one); then the near markers put
   their full fields.  At a shared node every marker touching it is near, so
   the fields there are whole (the same sums, in the same order, as from all
   markers); elsewhere they are partial and unused. */
PetscErrorCode PSContactP2G(PSSolver *S, PSFields *f, const PSIndex *ix)
{
  PSContact     *C   = S->contact;
  const PetscInt dim = S->dim, N = PSShapeNodes(S->run.shape), nz = dim == 3 ? N : 1, fs = C->fs, nf = C->nfield;
  PetscInt       p, a, b, c, d, e, lo[3], hi[3], i, j, k, n[3];

  PetscFunctionBeginUser;
  PetscCall(PetscLogEventBegin(PS_EV_ContactP2G, 0, 0, 0, 0));
  ZeroBox(ix, C->g, C->gdof, C->zbox);
  ZeroBox(ix, C->h, C->hdof, C->zbox);
  ZeroBox(ix, C->mk, nf, C->zbox);
  PetscCall(PetscArraycpy(&C->zbox[0][0], &S->zbox[0][0], 6));
  if (f->n > C->nnear) {
    PetscCall(PetscFree2(C->near, C->vold));
    C->nnear = (PetscInt)(1.2 * f->n) + 16;
    PetscCall(PetscMalloc2(C->nnear, &C->near, C->nnear * dim, &C->vold));
  }
  /* the fields' masses */
  for (p = 0; p < f->n; p++) {
    PSShape          shl, *sh = &shl;
    PSMarkerWeights(S, p, dim, &shl);
    const PetscInt  kf = MarkerField(C, f, p);
    const PetscReal m  = f->mass[p];
    PetscCheck(kf >= 0 && kf < nf, PETSC_COMM_SELF, PETSC_ERR_PLIB, "marker %lld of body %" PetscInt_FMT " has no velocity field", (long long)f->id[p], f->body[p]);
    PSShapeSupport(sh, dim, N, PETSC_TRUE, n); /* the nodes that carry weight (shape.h) */
    for (c = 0; c < n[2]; c++)
      for (b = 0; b < n[1]; b++)
        for (a = 0; a < n[0]; a++) C->mk[nf * Lidx(ix, sh->i0[0] + a, sh->i0[1] + b, dim == 3 ? sh->i0[2] + c : 0) + kf] += sh->w[0][a] * sh->w[1][b] * (dim == 3 ? sh->w[2][c] : 1.0) * m;
  }
  PetscCall(PetscLogEventEnd(PS_EV_ContactP2G, 0, 0, 0, 0));
  PetscCall(PSHaloReduce(C->sfm, C->mk));
  PetscCall(PSHaloBcast(C->sfm, C->mk));
  PetscCall(PetscLogEventBegin(PS_EV_ContactP2G, 0, 0, 0, 0));
  /* the shared nodes of the box, ghosts included */
  Clip(C->zbox, ix->gs, ix->gm, lo, hi);
  for (k = lo[2]; k < hi[2]; k++)
    for (j = lo[1]; j < hi[1]; j++)
      for (i = lo[0]; i < hi[0]; i++) {
        const PetscInt   o  = Lidx(ix, i, j, k);
        const PetscReal *mo = &C->mk[nf * o];
        PetscInt         nh = 0, q;
        for (q = 0; q < nf; q++) nh += mo[q] > S->mass_min;
        C->shared[o] = nh >= 2;
      }
  /* the near markers, and their full fields */
  for (p = 0; p < f->n; p++) {
    PSShape          shl, *sh = &shl;
    PSMarkerWeights(S, p, dim, &shl);
    const PetscInt   kf = MarkerField(C, f, p);
    const PetscReal *v = &f->v[p * dim], m = f->mass[p], V = f->vol[p], mD = f->Di ? m * PetscSqr(1.0 - f->Di[p]) : 0.0; /* m psi_p */
    PetscReal        s[3][3], mg;
    char             nr = 0;
    for (c = 0; c < nz && !nr; c++)
      for (b = 0; b < N && !nr; b++)
        for (a = 0; a < N; a++)
          if (C->shared[Lidx(ix, sh->i0[0] + a, sh->i0[1] + b, dim == 3 ? sh->i0[2] + c : 0)]) {
            nr = 1;
            break;
          }
    C->near[p] = nr;
    if (!nr) continue;
    for (d = 0; d < dim; d++) C->vold[p * dim + d] = v[d];
    ForceStress(dim, &f->sig[p * PSStressComponents(dim)], f->q[p], s);
    /* the normals' mass gradient: axisymmetric, of the section's mass
       m_p / (2 pi r_p) (the full revolution's grows with r, and its
       gradient would tilt every normal towards +r: a flat interface across
       the axis pushed its bodies sideways and lost 12% of a trap's energy) */
    mg = S->axi ? m / (2.0 * PETSC_PI * f->x[2 * p]) : m;
    PSShapeSupport(sh, dim, N, PETSC_TRUE, n);
    for (c = 0; c < n[2]; c++)
      for (b = 0; b < n[1]; b++)
        for (a = 0; a < n[0]; a++) {
          const PetscReal wz = dim == 3 ? sh->w[2][c] : 1.0, w = sh->w[0][a] * sh->w[1][b] * wz;
          const PetscReal gN[3] = {sh->dw[0][a] * sh->w[1][b] * wz, sh->w[0][a] * sh->dw[1][b] * wz, dim == 3 ? sh->w[0][a] * sh->w[1][b] * sh->dw[2][c] : 0.0};
          PetscReal      *gk = &C->g[C->gdof * Lidx(ix, sh->i0[0] + a, sh->i0[1] + b, dim == 3 ? sh->i0[2] + c : 0) + kf * fs];
          gk[0] += w * m;
          gk[1 + 3 * dim] += w * V;
          gk[2 + 3 * dim] += w * mD;
          for (d = 0; d < dim; d++) {
            gk[1 + d] += w * m * v[d];
            for (e = 0; e < dim; e++) gk[1 + dim + d] -= V * s[d][e] * gN[e];
            gk[1 + 2 * dim + d] += mg * gN[d];
          }
          if (S->axi) gk[1 + dim] -= V * s[2][2] * w / f->x[2 * p]; /* the hoop force, as transfer_musl.c's P2G */
        }
  }
  PetscCall(PetscLogEventEnd(PS_EV_ContactP2G, 0, 0, 0, 0));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* 2. the fields' grid update, the cells' share joined to them, and the
   contact law at shared nodes (after the single field's grid solve) */
PetscErrorCode PSContactGridSolve(PSSolver *S, const PSIndex *ix, PetscReal dt)
{
  PSContact     *C   = S->contact;
  const PetscInt dim = S->dim, nf = C->nfield, fs = C->fs;
  const PetscInt dof = PSGridDof(S), fo = dof - dim;
  PetscInt       a, b, c, k, d, lo[3], hi[3], pair[2];
  PetscReal      m[16], gm[16][3], v[16][3], vo[16][3], V[16], psi[16], al[16], dvf[16][3], iwork, dD;

  PetscFunctionBeginUser;
  PetscCall(PSHaloReduce(C->sfg, C->g));
  PetscCall(PetscLogEventBegin(PS_EV_ContactGrid, 0, 0, 0, 0));
  Clip(S->zbox, ix->os, ix->om, lo, hi);
  for (c = lo[2]; c < hi[2]; c++)
    for (b = lo[1]; b < hi[1]; b++)
      for (a = lo[0]; a < hi[0]; a++) {
        const PetscInt o     = Lidx(ix, a, b, c);
        PetscReal     *gn    = &C->g[C->gdof * o];
        const PetscInt ip[3] = {a - S->pad, b - S->pad, dim == 3 ? c - S->pad : 0};
        if (!C->shared[o]) continue; /* the single field serves this node */
        for (k = 0; k < nf; k++) {
          PetscReal *gk = gn + k * fs;
          m[k]          = gk[0];
          V[k]          = gk[1 + 3 * dim];
          psi[k]        = m[k] > 0.0 ? gk[2 + 3 * dim] / m[k] : 1.0;
          al[k]         = 0.0;
          for (d = 0; d < 3; d++) v[k][d] = vo[k][d] = gm[k][d] = 0.0;
          if (m[k] <= S->mass_min) continue;
          for (d = 0; d < dim; d++) {
            vo[k][d] = gk[1 + d] / m[k];
            v[k][d]  = vo[k][d] + dt * gk[1 + dim + d] / m[k];
            gm[k][d] = gk[1 + 2 * dim + d];
          }
          PSNodeBC(S, ip, v[k]);
          PSNodeBC(S, ip, gm[k]); /* a symmetry face mirrors the body: no gradient across it */
        }
        /* the cells' share of the node, by mass among the fields present */
        if (S->cells) {
          const PetscReal *gs = &S->g[dof * o];
          PetscReal        mc = gs[0], pn[3], po[3], mm = 0.0;
          for (d = 0; d < dim; d++) {
            pn[d]              = gs[0] * gs[1 + d];
            po[d]              = gs[0] * (gs[1 + d] - gs[fo + d]);
            C->vs[dim * o + d] = gs[1 + d];
          }
          for (k = 0; k < nf; k++) {
            mc -= m[k];
            for (d = 0; d < dim; d++) {
              pn[d] -= m[k] * v[k][d];
              po[d] -= m[k] * vo[k][d];
            }
            if (m[k] > S->mass_min) mm += m[k];
          }
          if (mc > S->mass_min) {
            for (k = 0; k < nf; k++) {
              PetscReal w, ma;
              if (m[k] <= S->mass_min) continue;
              w  = m[k] / mm;
              ma = m[k] + w * mc;
              for (d = 0; d < dim; d++) {
                v[k][d]  = (m[k] * v[k][d] + w * pn[d]) / ma;
                vo[k][d] = (m[k] * vo[k][d] + w * po[d]) / ma;
              }
              m[k] = ma;
            }
          }
        }
        ContactLaw(S, C, ip, dt, m, (const PetscReal(*)[3])gm, V, psi, v, dvf, al, &iwork, &dD, pair);
        C->interface_energy += iwork;
        for (k = 0; k < nf; k++) {
          for (d = 0; d < dim; d++) {
            gn[k * fs + 1 + d]       = v[k][d];
            gn[k * fs + 1 + dim + d] = v[k][d] - vo[k][d];
          }
          gn[k * fs + 3 + 3 * dim] = al[k]; /* the cohesive law's fraction alpha, for the re-projection */
          for (d = 0; d < dim; d++) gn[k * fs + 4 + 3 * dim + d] = dvf[k][d]; /* friction's correction, for G2P's book */
          gn[k * fs + 2 + 3 * dim] = dD >= 0.0 && (k == pair[0] || k == pair[1]) ? dD : -1.0; /* the node's decrement of psi for G2P */
        }
      }
  PetscCall(PetscLogEventEnd(PS_EV_ContactGrid, 0, 0, 0, 0));
  PetscCall(PSHaloBcast(C->sfg, C->g));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* 2b. (bodies in cells, after PSCellsPredict) the predictor's correction of
   the single field's v^new at a shared node with cell mass, added to each
   field there: each holds its share of the cells, and the shares' centre of
   mass is the single field (PSContactGridSolve) */
PetscErrorCode PSContactCellsSync(PSSolver *S, const PSIndex *ix)
{
  PSContact     *C   = S->contact;
  const PetscInt dim = S->dim, fs = C->fs, dof = PSGridDof(S);
  PetscInt       a, b, c, d, k, lo[3], hi[3];

  PetscFunctionBeginUser;
  PetscCall(PetscLogEventBegin(PS_EV_ContactGrid, 0, 0, 0, 0));
  Clip(S->zbox, ix->os, ix->om, lo, hi);
  for (c = lo[2]; c < hi[2]; c++)
    for (b = lo[1]; b < hi[1]; b++)
      for (a = lo[0]; a < hi[0]; a++) {
        const PetscInt   o  = Lidx(ix, a, b, c);
        const PetscReal *gs = &S->g[dof * o];
        PetscReal        mc = gs[0]; /* the cells' mass here, as PSContactGridSolve found it */
        if (!C->shared[o]) continue;
        for (k = 0; k < C->nfield; k++) mc -= C->g[C->gdof * o + k * fs];
        if (mc <= S->mass_min) continue;
        for (k = 0; k < C->nfield; k++) {
          PetscReal *gk = &C->g[C->gdof * o + k * fs];
          if (gk[0] <= S->mass_min) continue;
          for (d = 0; d < dim; d++) {
            const PetscReal dv = gs[1 + d] - C->vs[dim * o + d];
            gk[1 + d] += dv;
            gk[1 + dim + d] += dv;
          }
        }
      }
  PetscCall(PetscLogEventEnd(PS_EV_ContactGrid, 0, 0, 0, 0));
  PetscCall(PSHaloBcast(C->sfg, C->g));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* 3. G2P of the near markers, redone after the single field's (PSMUSLG2P, every
   marker) from their velocity before it: v_p = (1 - a)(v_p + sum N dv) + a
   sum N v_new, dx_p = dt sum N v_new from the marker's field at shared nodes,
   the single field elsewhere; 4. the re-projection's P2G into the field (C->h),
   and into the single field (S->hv) the difference from what PSMUSLG2P put */
PetscErrorCode PSContactG2P(PSSolver *S, PSFields *f, const PSIndex *ix, PetscReal dt)
{
  PSContact      *C   = S->contact;
  const PetscInt  dim = S->dim, N = PSShapeNodes(S->run.shape), fs = C->fs;
  const PetscInt  dof = PSGridDof(S), fo = dof - dim, hdof = PSReprojectDof(S), ho = hdof - dim;
  const PetscReal apic = S->run.pic_fraction;
  PetscInt        p, a, b, c, d, n[3];

  PetscFunctionBeginUser;
  PetscCall(PetscLogEventBegin(PS_EV_ContactG2P, 0, 0, 0, 0));
  for (p = 0; p < f->n; p++) {
    if (!C->near[p]) continue; /* away from shared nodes: the single field's G2P is its own */
    PSShape          shl, *sh = &shl;
    PSMarkerWeights(S, p, dim, &shl);
    const PetscInt k  = MarkerField(C, f, p);
    PetscReal     *v = &f->v[p * dim], m = f->mass[p], vpic[3] = {0, 0, 0}, dv[3] = {0, 0, 0}, wD = 0.0, sD = 0.0, vs[3] = {0, 0, 0}, dm[3], df[3] = {0, 0, 0}, wf = 0.0;
    for (d = 0; d < dim; d++) { /* PSMUSLG2P's velocity (its re-projection momentum is replaced below), and the one before */
      vs[d] = v[d];
      v[d]  = C->vold[p * dim + d];
    }
    PSShapeSupport(sh, dim, N, PETSC_TRUE, n);
    for (c = 0; c < n[2]; c++)
      for (b = 0; b < n[1]; b++)
        for (a = 0; a < n[0]; a++) {
          const PetscInt   o = Lidx(ix, sh->i0[0] + a, sh->i0[1] + b, dim == 3 ? sh->i0[2] + c : 0);
          const PetscReal  w = sh->w[0][a] * sh->w[1][b] * (dim == 3 ? sh->w[2][c] : 1.0);
          const PetscReal *cn = &C->g[C->gdof * o], *vn, *dn;
          if (C->shared[o]) {
            vn = cn + k * fs + 1;
            dn = vn + dim;
            if (cn[k * fs + 2 + 3 * dim] >= 0.0) { /* a cohesive pair of this marker's ply meets here: its decrement of psi */
              wD += w;
              sD += w * cn[k * fs + 2 + 3 * dim];
            }
            for (d = 0; d < dim; d++) df[d] += w * cn[k * fs + 4 + 3 * dim + d];
          } else {
            vn = &S->g[dof * o + 1];
            dn = &S->g[dof * o + fo];
          }
          for (d = 0; d < dim; d++) {
            vpic[d] += w * vn[d];
            dv[d] += w * dn[d];
          }
        }
    for (d = 0; d < dim; d++) {
      v[d]               = (1.0 - apic) * (v[d] + dv[d]) + apic * vpic[d];
      S->dx[p * dim + d] = dt * vpic[d];
    }
    /* friction work: the impulse m dv_f (dv_f = sum N dv_f,i, which entered
       v_p in both the FLIP and the PIC part) on the marker's mean velocity
       over the step, -m dv_f . (v_p^n + v_p^n+1)/2; summed over the two
       bodies at a node, the friction impulse on their mean relative slip
       (Nairn, Bardenhagen & Smith 2018, "Generalized contact and improved
       frictional heating in the MPM", Comp. Part. Mech. 5:285).  Not the
       kinetic energy the correction took, m (|v_p - dv_f|^2 - |v_p|^2)/2:
       its trial velocity holds this step's internal force, which friction
       takes back where it holds the slip, so that book counts f dv_f dt in
       addition, about S^2/m per node and step (S = mu dn), a sum that does
       not fall with h (dt ~ h): the sliding block's total rose +0.6% and
       +1.3% at 0.25 and 0.125 mm, now -1.1% and -0.6% as its frictionless
       twin's -1.0 and -0.5% (the normal correction's loss).  Nor the nodes'
       m_i |dv|^2, which over-counts what the markers lose (+5%) */
    for (d = 0; d < dim; d++) wf -= m * df[d] * 0.5 * (C->vold[p * dim + d] + v[d]);
    C->friction_work += wf;
    /* the marker carries the interface's history: psi_p = (1 - D_p)^2, the
       fraction of G_c its piece of interface still holds, loses the mean
       decrement of the nodes where its ply meets a cohesive neighbour (an
       increment, not the nodes' value, so that markers farther from the
       interface, which the nodes' mean also counts, do not hold it back).
       Why psi and not D: the round trip node -> markers -> node smooths (at
       a node of a front, GIMP with 2 markers per cell gives back 5/8 of its
       increment and 3/16 to each neighbour); the energy left in the law,
       sum A G_c psi, is linear in psi, so smoothing psi keeps it, while
       smoothing D, under the convex (1 - D)^2, loses it unbooked: a shear
       crack running along a lap-shear strip took 0.62 G_II per unit area
       when markers carried D (mode I opens everywhere at once and was
       right either way) */
    if (wD > 0.0 && f->Di) {
      const PetscReal psi = PetscSqr(1.0 - f->Di[p]) - sD / wD;
      f->Di[p] = psi > PS_PSI_OPEN ? 1.0 - PetscSqrtReal(psi) : 1.0;
    }
    for (d = 0; d < dim; d++) dm[d] = m * (v[d] - vs[d]);
    for (c = 0; c < n[2]; c++)
      for (b = 0; b < n[1]; b++)
        for (a = 0; a < n[0]; a++) {
          const PetscInt  o = Lidx(ix, sh->i0[0] + a, sh->i0[1] + b, dim == 3 ? sh->i0[2] + c : 0);
          const PetscReal w = sh->w[0][a] * sh->w[1][b] * (dim == 3 ? sh->w[2][c] : 1.0);
          for (d = 0; d < dim; d++) {
            S->hv[hdof * o + ho + d] += w * dm[d]; /* the single field's re-projection had m v_s */
            C->h[C->hdof * o + k * dim + d] += w * m * v[d];
          }
        }
  }
  PetscCall(PetscLogEventEnd(PS_EV_ContactG2P, 0, 0, 0, 0));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* 4. the fields' re-projected velocity with the contact law at shared nodes
   (after the single field's, PSMUSLReproject, which gave every marker an L_p),
   then 5. the near markers' L_p, redone from their field at shared nodes and
   the single field elsewhere, into S->Lp */
PetscErrorCode PSContactReproject(PSSolver *S, PSFields *f, const PSIndex *ix)
{
  PSContact     *C   = S->contact;
  const PetscInt dim = S->dim, nf = C->nfield, fs = C->fs, N = PSShapeNodes(S->run.shape);
  const PetscInt hdof = PSReprojectDof(S), ho = hdof - dim;
  PetscInt       p, a, b, c, k, d, e, lo[3], hi[3];
  PetscReal      m[16], gm[16][3], v[16][3], V[16], al[16];

  PetscFunctionBeginUser;
  PetscCall(PSHaloReduce(C->sfh, C->h));
  PetscCall(PetscLogEventBegin(PS_EV_ContactReproject, 0, 0, 0, 0));
  Clip(S->zbox, ix->os, ix->om, lo, hi);
  for (c = lo[2]; c < hi[2]; c++)
    for (b = lo[1]; b < hi[1]; b++)
      for (a = lo[0]; a < hi[0]; a++) {
        const PetscInt   o = Lidx(ix, a, b, c), ip[3] = {a - S->pad, b - S->pad, dim == 3 ? c - S->pad : 0};
        const PetscReal *gn = &C->g[C->gdof * o];
        PetscReal       *hn = &C->h[C->hdof * o];
        if (!C->shared[o]) continue;
        for (k = 0; k < nf; k++) {
          m[k]  = gn[k * fs];
          V[k]  = gn[k * fs + 1 + 3 * dim];
          al[k] = gn[k * fs + 3 + 3 * dim];
          for (d = 0; d < 3; d++) v[k][d] = gm[k][d] = 0.0;
          if (m[k] <= S->mass_min) continue;
          for (d = 0; d < dim; d++) {
            v[k][d]  = hn[k * dim + d] / m[k];
            gm[k][d] = gn[k * fs + 1 + 2 * dim + d];
          }
          PSNodeBC(S, ip, v[k]);
          PSNodeBC(S, ip, gm[k]);
        }
        ContactLaw(S, C, ip, S->dt, m, (const PetscReal(*)[3])gm, V, NULL, v, NULL, al, NULL, NULL, NULL); /* not booked: sets L_p only */
        for (k = 0; k < nf; k++)
          for (d = 0; d < dim; d++) hn[k * dim + d] = v[k][d];
      }
  PetscCall(PetscLogEventEnd(PS_EV_ContactReproject, 0, 0, 0, 0));
  PetscCall(PSHaloBcast(C->sfh, C->h));
  PetscCall(PetscLogEventBegin(PS_EV_ContactReproject, 0, 0, 0, 0));
  for (p = 0; p < f->n; p++) {
    if (!C->near[p]) continue; /* away from shared nodes: PSMUSLReproject's L_p is its own */
    PSShape          shl, *sh = &shl;
    PSMarkerWeights(S, p, dim, &shl);
    const PetscInt k  = MarkerField(C, f, p);
    PetscReal      L[3][3] = {{0}};
    PetscInt       n[3];
    PSShapeSupport(sh, dim, N, PETSC_TRUE, n);
    for (c = 0; c < n[2]; c++)
      for (b = 0; b < n[1]; b++)
        for (a = 0; a < n[0]; a++) {
          const PetscInt   o = Lidx(ix, sh->i0[0] + a, sh->i0[1] + b, dim == 3 ? sh->i0[2] + c : 0);
          const PetscReal  wz = dim == 3 ? sh->w[2][c] : 1.0;
          const PetscReal  gN[3] = {sh->dw[0][a] * sh->w[1][b] * wz, sh->w[0][a] * sh->dw[1][b] * wz, dim == 3 ? sh->w[0][a] * sh->w[1][b] * sh->dw[2][c] : 0.0};
          const PetscReal *vn = C->shared[o] ? &C->h[C->hdof * o + k * dim] : &S->hv[hdof * o + ho];
          for (d = 0; d < dim; d++)
            for (e = 0; e < dim; e++) L[d][e] += vn[d] * gN[e];
          if (S->axi) L[2][2] += sh->w[0][a] * sh->w[1][b] * vn[0]; /* v_r(x_p), divided by r_p below */
        }
    if (S->axi) L[2][2] /= f->x[2 * p]; /* the hoop rate v_r / r_p, as transfer_musl.c's gradient */
    for (d = 0; d < 3; d++)
      for (e = 0; e < 3; e++) S->Lp[9 * p + 3 * d + e] = L[d][e];
  }
  PetscCall(PetscLogEventEnd(PS_EV_ContactReproject, 0, 0, 0, 0));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Contact between marker bodies: field[b] is body b's velocity field (-1 for
   bodies in cells), or with split[b] its first ply's (ply j: field[b] + j; a
   laminate with cohesive ply interfaces); mu the nfield x nfield friction
   coefficients; coh the nfield x nfield cohesive law of a pair of fields (-1:
   none), cohp its ncoh x 4 constants (N, S in Pa; G_I, G_II in J/m^2).
   nfield < 2: none (the single field). */
PetscErrorCode PSSolverSetContact(PSSolver *S, PetscInt nbody, const PetscInt field[], const PetscInt split[], PetscInt nfield, const PetscReal mu[], const PetscInt coh[], PetscInt ncoh, const PetscReal cohp[])
{
  MPI_Comm   comm = PetscObjectComm((PetscObject)S->da);
  PSContact *C;
  PSIndex    ix;
  PetscInt   b, k;

  PetscFunctionBeginUser;
  PetscCall(PSContactDestroy(&S->contact));
  if (nfield < 2) PetscFunctionReturn(PETSC_SUCCESS);
  if (!PS_EV_ContactP2G) {
    PetscClassId cid;
    PetscCall(PetscClassIdRegister("plyshock contact", &cid));
    PetscCall(PetscLogEventRegister("PSContactP2G", cid, &PS_EV_ContactP2G));
    PetscCall(PetscLogEventRegister("PSContactGrid", cid, &PS_EV_ContactGrid));
    PetscCall(PetscLogEventRegister("PSContactG2P", cid, &PS_EV_ContactG2P));
    PetscCall(PetscLogEventRegister("PSContactReproject", cid, &PS_EV_ContactReproject));
  }
  PetscCheck(S->run.transfer == PS_TRANSFER_MUSL, comm, PETSC_ERR_SUP, "contact: friction needs run.transfer: musl (got %s); or set contact: {type: bonded}", PSTransferTypes[S->run.transfer]);
  PetscCheck(nbody == S->scene->nbody, comm, PETSC_ERR_ARG_SIZ, "contact: %" PetscInt_FMT " bodies given, the scene has %" PetscInt_FMT, nbody, S->scene->nbody);
  PetscCheck(nfield <= 16, comm, PETSC_ERR_ARG_OUTOFRANGE, "contact: %" PetscInt_FMT " velocity fields; at most 16 (group bodies with bonded pairs; plies with cohesive interfaces take one each)", nfield);
  for (b = 0; b < nbody; b++) {
    const PetscInt last = field[b] + (split[b] ? S->scene->bodies[b].nply - 1 : 0);
    PetscCheck(field[b] >= -1 && last < nfield, comm, PETSC_ERR_ARG_OUTOFRANGE, "contact: body %" PetscInt_FMT " has fields [%" PetscInt_FMT ", %" PetscInt_FMT "]; allowed [-1, %" PetscInt_FMT ")", b, field[b], last, nfield);
    PetscCheck(!split[b] || (S->has_ply && S->scene->bodies[b].kind == PS_BODY_LAMINATE), comm, PETSC_ERR_ARG_WRONG, "contact: body %" PetscInt_FMT " has a field per ply but is not a laminate", b);
  }
  PetscCheck(!ncoh || S->scene->need_interface, comm, PETSC_ERR_ARG_WRONG, "contact: cohesive interfaces need the interface damage field (scene need_interface)");
  for (k = 0; k < nfield * nfield; k++) {
    PetscCheck(mu[k] >= 0.0 && mu[k] < PETSC_INFINITY, comm, PETSC_ERR_ARG_OUTOFRANGE, "contact: friction %g is out of range; allowed [0, inf)", (double)mu[k]);
    PetscCheck(coh[k] >= -1 && coh[k] < ncoh, comm, PETSC_ERR_ARG_OUTOFRANGE, "contact: cohesive law %" PetscInt_FMT " of a pair; allowed [-1, %" PetscInt_FMT ")", coh[k], ncoh);
  }
  for (k = 0; k < 4 * ncoh; k++) PetscCheck(cohp[k] > 0.0 && cohp[k] < PETSC_INFINITY, comm, PETSC_ERR_ARG_OUTOFRANGE, "contact: cohesive constant %g (law %" PetscInt_FMT ", %s) is out of range; allowed (0, inf)", (double)cohp[k], k / 4, (const char *[]){"normal_strength", "shear_strength", "G_I", "G_II"}[k % 4]);
  PetscCall(PetscNew(&C));
  C->nfield = nfield;
  C->nbody  = nbody;
  C->fs     = 4 + 4 * S->dim;
  C->gdof   = nfield * C->fs;
  C->hdof   = nfield * S->dim;
  C->ncoh   = ncoh;
  PetscCall(PetscMalloc2(nbody, &C->field, nbody, &C->split));
  PetscCall(PetscMalloc1(nfield * nfield, &C->mu));
  PetscCall(PetscArraycpy(C->field, field, nbody));
  PetscCall(PetscArraycpy(C->split, split, nbody));
  PetscCall(PetscArraycpy(C->mu, mu, nfield * nfield));
  if (ncoh) {
    PetscCall(PetscMalloc2(nfield * nfield, &C->coh, 4 * ncoh, &C->cohp));
    PetscCall(PetscArraycpy(C->coh, coh, nfield * nfield));
    PetscCall(PetscArraycpy(C->cohp, cohp, 4 * ncoh));
  }
  PetscCall(PSGridIndex(S->da, &ix));
  C->nl = ix.gm[0] * ix.gm[1] * ix.gm[2];
  PetscCall(PetscCalloc2(C->nl * C->gdof, &C->g, C->nl * C->hdof, &C->h));
  PetscCall(PetscCalloc3(C->nl * nfield, &C->mk, C->nl, &C->shared, C->nl * S->dim, &C->vs));
  PetscCall(PSHaloCreate(S, C->gdof, &C->sfg));
  PetscCall(PSHaloCreate(S, C->hdof, &C->sfh));
  PetscCall(PSHaloCreate(S, nfield, &C->sfm));
  S->contact = C;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode PSContactDestroy(PSContact **C)
{
  PetscFunctionBeginUser;
  if (!*C) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(PetscFree2((*C)->field, (*C)->split));
  PetscCall(PetscFree((*C)->mu));
  PetscCall(PetscFree2((*C)->coh, (*C)->cohp));
  PetscCall(PetscFree2((*C)->g, (*C)->h));
  PetscCall(PetscFree3((*C)->mk, (*C)->shared, (*C)->vs));
  PetscCall(PetscFree2((*C)->near, (*C)->vold));
  PetscCall(PetscSFDestroy(&(*C)->sfm));
  PetscCall(PetscSFDestroy(&(*C)->sfg));
  PetscCall(PetscSFDestroy(&(*C)->sfh));
  PetscCall(PetscFree(*C));
  PetscFunctionReturn(PETSC_SUCCESS);
}
