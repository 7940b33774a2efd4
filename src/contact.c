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
            The kinetic energy the tangential correction removes,
            sum_k m_ik (|v_k after the normal correction|^2 - |v_k|^2)/2, is
            booked as friction work (history.csv friction_work)       (PSContactGridSolve)
    G2P     each marker reads its field's v^new and dv at shared nodes, the
            single field elsewhere; the re-projection (mv) goes to both  (PSContactG2P)
    re-project  the fields' re-projected velocity at shared nodes gets the
            same contact law (not booked: it only sets L_p); L_p from the
            marker's field at shared nodes                             (PSContactReproject)
  The friction coefficient of field k at a node is that of the pair of k and
  the heaviest other field there.  Cell materials join the single field only
  (docs/contact.md).
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

/* fields heavier than mass_min at a node of g: shared when >= 2 */
static inline PetscInt HeavyFields(const PSContact *C, const PetscReal *gn, PetscReal mmin)
{
  PetscInt k, n = 0;
  for (k = 0; k < C->nfield; k++) n += gn[k * C->fs] > mmin;
  return n;
}

/* The contact law on the fields' velocities v[k] (dim each, with the boundary
   conditions) at one node, with masses m[k] and g[k] (layout above); returns
   the kinetic energy the tangential (friction) correction removed (J). */
static PetscReal ContactLaw(const PSSolver *S, const PSContact *C, const PetscInt ip[3], const PetscReal *m, const PetscReal (*gm)[3], PetscReal (*v)[3])
{
  const PetscInt dim = S->dim, nf = C->nfield;
  PetscReal      M = 0.0, vcm[3] = {0, 0, 0}, work = 0.0;
  PetscInt       k, j, d;

  for (k = 0; k < nf; k++) {
    if (m[k] <= S->mass_min) continue;
    M += m[k];
    for (d = 0; d < dim; d++) vcm[d] += m[k] * v[k][d];
  }
  for (d = 0; d < dim; d++) vcm[d] /= M;
  for (k = 0; k < nf; k++) {
    PetscReal n[3] = {0, 0, 0}, nn = 0.0, dn = 0.0, t[3] = {0, 0, 0}, tt = 0.0, mu, mo = 0.0, e0 = 0.0, e1 = 0.0, gk2 = 0.0, go2 = 0.0;
    PetscInt  other = -1;
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
    for (d = 0; d < dim; d++) {
      gk2 += gm[k][d] * gm[k][d];
      go2 += n[d] * n[d];
    }
    if (gk2 > go2 || (gk2 == go2 && k < other)) /* a tie goes to the lower field, the same for both */
      for (d = 0; d < dim; d++) n[d] = gm[k][d];
    for (d = 0; d < dim; d++) nn += n[d] * n[d];
    if (!(nn > 0.0)) continue; /* no direction: the fields move freely */
    nn = PetscSqrtReal(nn);
    for (d = 0; d < dim; d++) {
      n[d] /= nn;
      dn += (v[k][d] - vcm[d]) * n[d];
    }
    if (dn <= 0.0) continue; /* separating: free */
    mu = C->mu[k * nf + other];
    for (d = 0; d < dim; d++) {
      v[k][d] -= dn * n[d]; /* normal correction: v_k . n = v_cm . n */
      t[d] = v[k][d] - vcm[d];
      tt += t[d] * t[d];
      e0 += v[k][d] * v[k][d];
    }
    tt = PetscSqrtReal(tt);
    if (tt <= mu * dn) { /* stick */
      for (d = 0; d < dim; d++) v[k][d] = vcm[d];
    } else { /* slip: the tangential velocity loses mu dn */
      for (d = 0; d < dim; d++) v[k][d] -= mu * dn * t[d] / tt;
    }
    for (d = 0; d < dim; d++) e1 += v[k][d] * v[k][d];
    work += 0.5 * m[k] * (e0 - e1);
    PSNodeBC(S, ip, v[k]); /* the normal may lean into a direction a face holds */
  }
  return work;
}

/* 1. the fields' P2G (after the single field's: it evaluated S->shape) */
PetscErrorCode PSContactP2G(PSSolver *S, PSFields *f, const PSIndex *ix)
{
  PSContact     *C   = S->contact;
  const PetscInt dim = S->dim, N = PSShapeNodes(S->run.shape), nz = dim == 3 ? N : 1, fs = C->fs;
  PetscInt       p, a, b, c, d, e;

  PetscFunctionBeginUser;
  PetscCall(PetscLogEventBegin(PS_EV_ContactP2G, 0, 0, 0, 0));
  ZeroBox(ix, C->g, C->gdof, C->zbox);
  ZeroBox(ix, C->h, C->hdof, C->zbox);
  PetscCall(PetscArraycpy(&C->zbox[0][0], &S->zbox[0][0], 6));
  for (p = 0; p < f->n; p++) {
    const PSShape   *sh = &S->shape[p];
    const PetscInt   k  = C->field[f->body[p]];
    const PetscReal *v = &f->v[p * dim], m = f->mass[p], V = f->vol[p];
    PetscReal        s[3][3];
    PetscCheck(k >= 0, PETSC_COMM_SELF, PETSC_ERR_PLIB, "marker %lld of body %" PetscInt_FMT " has no velocity field", (long long)f->id[p], f->body[p]);
    ForceStress(dim, &f->sig[p * PSStressComponents(dim)], f->q[p], s);
    for (c = 0; c < nz; c++)
      for (b = 0; b < N; b++)
        for (a = 0; a < N; a++) {
          const PetscReal wz = dim == 3 ? sh->w[2][c] : 1.0, w = sh->w[0][a] * sh->w[1][b] * wz;
          const PetscReal gN[3] = {sh->dw[0][a] * sh->w[1][b] * wz, sh->w[0][a] * sh->dw[1][b] * wz, dim == 3 ? sh->w[0][a] * sh->w[1][b] * sh->dw[2][c] : 0.0};
          PetscReal      *gk = &C->g[C->gdof * Lidx(ix, sh->i0[0] + a, sh->i0[1] + b, dim == 3 ? sh->i0[2] + c : 0) + k * fs];
          gk[0] += w * m;
          for (d = 0; d < dim; d++) {
            gk[1 + d] += w * m * v[d];
            for (e = 0; e < dim; e++) gk[1 + dim + d] -= V * s[d][e] * gN[e];
            gk[1 + 2 * dim + d] += m * gN[d];
          }
        }
  }
  PetscCall(PetscLogEventEnd(PS_EV_ContactP2G, 0, 0, 0, 0));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* 2. the fields' grid update and the contact law at shared nodes (after the
   single field's grid solve) */
PetscErrorCode PSContactGridSolve(PSSolver *S, const PSIndex *ix, PetscReal dt)
{
  PSContact     *C   = S->contact;
  const PetscInt dim = S->dim, nf = C->nfield, fs = C->fs;
  PetscInt       a, b, c, k, d, lo[3], hi[3];
  PetscReal      m[16], gm[16][3], v[16][3], vo[16][3];

  PetscFunctionBeginUser;
  PetscCall(PSHaloReduce(C->sfg, C->g));
  PetscCall(PetscLogEventBegin(PS_EV_ContactGrid, 0, 0, 0, 0));
  Clip(S->zbox, ix->os, ix->om, lo, hi);
  for (c = lo[2]; c < hi[2]; c++)
    for (b = lo[1]; b < hi[1]; b++)
      for (a = lo[0]; a < hi[0]; a++) {
        PetscReal     *gn    = &C->g[C->gdof * Lidx(ix, a, b, c)];
        const PetscInt ip[3] = {a - S->pad, b - S->pad, dim == 3 ? c - S->pad : 0};
        if (HeavyFields(C, gn, S->mass_min) < 2) continue; /* the single field serves this node */
        for (k = 0; k < nf; k++) {
          PetscReal *gk = gn + k * fs;
          m[k]          = gk[0];
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
        C->friction_work += ContactLaw(S, C, ip, m, (const PetscReal(*)[3])gm, v);
        for (k = 0; k < nf; k++)
          for (d = 0; d < dim; d++) {
            gn[k * fs + 1 + d]       = v[k][d];
            gn[k * fs + 1 + dim + d] = v[k][d] - vo[k][d];
          }
      }
  PetscCall(PetscLogEventEnd(PS_EV_ContactGrid, 0, 0, 0, 0));
  PetscCall(PSHaloBcast(C->sfg, C->g));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* 3. G2P: v_p = (1 - a)(v_p + sum N dv) + a sum N v_new, dx_p = dt sum N v_new
   from the marker's field at shared nodes, the single field elsewhere;
   4. the re-projection's P2G into the single field (S->hv) and the field (C->h) */
PetscErrorCode PSContactG2P(PSSolver *S, PSFields *f, const PSIndex *ix, PetscReal dt)
{
  PSContact      *C   = S->contact;
  const PetscInt  dim = S->dim, N = PSShapeNodes(S->run.shape), nz = dim == 3 ? N : 1, fs = C->fs;
  const PetscInt  dof = PSGridDof(S), fo = dof - dim, hdof = PSReprojectDof(S), ho = hdof - dim;
  const PetscReal apic = S->run.pic_fraction;
  PetscInt        p, a, b, c, d;

  PetscFunctionBeginUser;
  PetscCall(PetscLogEventBegin(PS_EV_ContactG2P, 0, 0, 0, 0));
  for (p = 0; p < f->n; p++) {
    const PSShape *sh = &S->shape[p];
    const PetscInt k  = C->field[f->body[p]];
    PetscReal     *v = &f->v[p * dim], m = f->mass[p], vpic[3] = {0, 0, 0}, dv[3] = {0, 0, 0};
    for (c = 0; c < nz; c++)
      for (b = 0; b < N; b++)
        for (a = 0; a < N; a++) {
          const PetscInt   o = Lidx(ix, sh->i0[0] + a, sh->i0[1] + b, dim == 3 ? sh->i0[2] + c : 0);
          const PetscReal  w = sh->w[0][a] * sh->w[1][b] * (dim == 3 ? sh->w[2][c] : 1.0);
          const PetscReal *cn = &C->g[C->gdof * o], *vn, *dn;
          if (HeavyFields(C, cn, S->mass_min) >= 2) {
            vn = cn + k * fs + 1;
            dn = vn + dim;
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
    for (c = 0; c < nz; c++)
      for (b = 0; b < N; b++)
        for (a = 0; a < N; a++) {
          const PetscInt  o = Lidx(ix, sh->i0[0] + a, sh->i0[1] + b, dim == 3 ? sh->i0[2] + c : 0);
          const PetscReal w = sh->w[0][a] * sh->w[1][b] * (dim == 3 ? sh->w[2][c] : 1.0);
          for (d = 0; d < dim; d++) {
            S->hv[hdof * o + ho + d] += w * m * v[d];
            C->h[C->hdof * o + k * dim + d] += w * m * v[d];
          }
        }
  }
  PetscCall(PetscLogEventEnd(PS_EV_ContactG2P, 0, 0, 0, 0));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* 4. the fields' re-projected velocity with the contact law at shared nodes
   (after the single field's, PSMUSLReproject), then 5. L_p from the marker's
   field at shared nodes and the single field elsewhere, into S->Lp */
PetscErrorCode PSContactReproject(PSSolver *S, PSFields *f, const PSIndex *ix)
{
  PSContact     *C   = S->contact;
  const PetscInt dim = S->dim, nf = C->nfield, fs = C->fs, N = PSShapeNodes(S->run.shape), nz = dim == 3 ? N : 1;
  const PetscInt hdof = PSReprojectDof(S), ho = hdof - dim;
  PetscInt       p, a, b, c, k, d, e, lo[3], hi[3];
  PetscReal      m[16], gm[16][3], v[16][3];

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
        if (HeavyFields(C, gn, S->mass_min) < 2) continue;
        for (k = 0; k < nf; k++) {
          m[k] = gn[k * fs];
          for (d = 0; d < 3; d++) v[k][d] = gm[k][d] = 0.0;
          if (m[k] <= S->mass_min) continue;
          for (d = 0; d < dim; d++) {
            v[k][d]  = hn[k * dim + d] / m[k];
            gm[k][d] = gn[k * fs + 1 + 2 * dim + d];
          }
          PSNodeBC(S, ip, v[k]);
          PSNodeBC(S, ip, gm[k]);
        }
        (void)ContactLaw(S, C, ip, m, (const PetscReal(*)[3])gm, v); /* not booked: sets L_p only */
        for (k = 0; k < nf; k++)
          for (d = 0; d < dim; d++) hn[k * dim + d] = v[k][d];
      }
  PetscCall(PetscLogEventEnd(PS_EV_ContactReproject, 0, 0, 0, 0));
  PetscCall(PSHaloBcast(C->sfh, C->h));
  PetscCall(PetscLogEventBegin(PS_EV_ContactReproject, 0, 0, 0, 0));
  for (p = 0; p < f->n; p++) {
    const PSShape *sh = &S->shape[p];
    const PetscInt k  = C->field[f->body[p]];
    PetscReal      L[3][3] = {{0}};
    for (c = 0; c < nz; c++)
      for (b = 0; b < N; b++)
        for (a = 0; a < N; a++) {
          const PetscInt   o = Lidx(ix, sh->i0[0] + a, sh->i0[1] + b, dim == 3 ? sh->i0[2] + c : 0);
          const PetscReal  wz = dim == 3 ? sh->w[2][c] : 1.0;
          const PetscReal  gN[3] = {sh->dw[0][a] * sh->w[1][b] * wz, sh->w[0][a] * sh->dw[1][b] * wz, dim == 3 ? sh->w[0][a] * sh->w[1][b] * sh->dw[2][c] : 0.0};
          const PetscReal *vn = HeavyFields(C, &C->g[C->gdof * o], S->mass_min) >= 2 ? &C->h[C->hdof * o + k * dim] : &S->hv[hdof * o + ho];
          for (d = 0; d < dim; d++)
            for (e = 0; e < dim; e++) L[d][e] += vn[d] * gN[e];
        }
    for (d = 0; d < 3; d++)
      for (e = 0; e < 3; e++) S->Lp[9 * p + 3 * d + e] = L[d][e];
  }
  PetscCall(PetscLogEventEnd(PS_EV_ContactReproject, 0, 0, 0, 0));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Contact between marker bodies: field[b] is body b's velocity field (-1 for
   bodies in cells), mu the nfield x nfield friction coefficients.  nfield < 2:
   none (the single field). */
PetscErrorCode PSSolverSetContact(PSSolver *S, PetscInt nbody, const PetscInt field[], PetscInt nfield, const PetscReal mu[])
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
  PetscCheck(nfield <= 16, comm, PETSC_ERR_ARG_OUTOFRANGE, "contact: %" PetscInt_FMT " velocity fields; at most 16 (group bodies with bonded pairs)", nfield);
  for (b = 0; b < nbody; b++) PetscCheck(field[b] >= -1 && field[b] < nfield, comm, PETSC_ERR_ARG_OUTOFRANGE, "contact: body %" PetscInt_FMT " has field %" PetscInt_FMT "; allowed [-1, %" PetscInt_FMT ")", b, field[b], nfield);
  for (k = 0; k < nfield * nfield; k++) PetscCheck(mu[k] >= 0.0 && mu[k] < PETSC_INFINITY, comm, PETSC_ERR_ARG_OUTOFRANGE, "contact: friction %g is out of range; allowed [0, inf)", (double)mu[k]);
  PetscCall(PetscNew(&C));
  C->nfield = nfield;
  C->nbody  = nbody;
  C->fs     = 1 + 3 * S->dim;
  C->gdof   = nfield * C->fs;
  C->hdof   = nfield * S->dim;
  PetscCall(PetscMalloc2(nbody, &C->field, nfield * nfield, &C->mu));
  PetscCall(PetscArraycpy(C->field, field, nbody));
  PetscCall(PetscArraycpy(C->mu, mu, nfield * nfield));
  PetscCall(PSGridIndex(S->da, &ix));
  C->nl = ix.gm[0] * ix.gm[1] * ix.gm[2];
  PetscCall(PetscCalloc2(C->nl * C->gdof, &C->g, C->nl * C->hdof, &C->h));
  PetscCall(PSHaloCreate(S, C->gdof, &C->sfg));
  PetscCall(PSHaloCreate(S, C->hdof, &C->sfh));
  S->contact = C;
  PetscFunctionReturn(PETSC_SUCCESS);
}

PetscErrorCode PSContactDestroy(PSContact **C)
{
  PetscFunctionBeginUser;
  if (!*C) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(PetscFree2((*C)->field, (*C)->mu));
  PetscCall(PetscFree2((*C)->g, (*C)->h));
  PetscCall(PetscSFDestroy(&(*C)->sfg));
  PetscCall(PetscSFDestroy(&(*C)->sfh));
  PetscCall(PetscFree(*C));
  PetscFunctionReturn(PETSC_SUCCESS);
}
