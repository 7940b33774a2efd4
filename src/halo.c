/*
  halo.c - the grid's ghost exchange on the ghosted local arrays alone.

  DMLocalToGlobal(ADD) and DMGlobalToLocal(INSERT) copy every owned node both
  ways on every step besides moving the ghosts.  Here a PetscSF links each
  ghost node of a rank's local array (a leaf) to the same node in its owner's
  local array (a root): Reduce(MPI_SUM) adds the ghosts' P2G contributions into
  the owners, Bcast(MPI_REPLACE) sends the owners' updated values back.  Only
  ghost nodes move; on one rank there are none.  The grid update runs on the
  owned part of the local array.

  Layout: the DMDA's (x fastest, ranks x fastest, stencil box of width sw,
  boundaries not periodic), ownership from the solver's node ranges lx; the
  same for the Eulerian cells' arrays (cells/, their own ranges and width).
*/
#include "solver.h"

/* rank k along one direction owning node i, and that rank's ghosted range */
static inline PetscInt Owner(const PetscInt *lx, PetscInt P, PetscInt i)
{
  PetscInt k = 0;
  while (k + 1 < P && i >= lx[k + 1]) k++;
  return k;
}

/* The ghost exchange of a box of N[d] points per direction split among
   nproc[d] ranks by the ranges lx[d] (rank k owns [lx[d][k], lx[d][k+1])),
   each rank holding its points and a ghost layer of width sw (clipped to the
   box), x fastest, in nb planes of bs reals per point, then nx planes of
   one real per point (a dof-per-point array: nb = 1, bs = dof, nx = 0; the
   cells' state: a plane per material, then one per per-cell value). */
static inline PetscInt PlaneIdx(PetscInt np, PetscInt nb, PetscInt bs, PetscInt p, PetscInt e)
{
  return e < nb * bs ? (e / bs) * np * bs + p * bs + e % bs : nb * np * bs + (e - nb * bs) * np + p;
}

PetscErrorCode PSHaloCreateBox(MPI_Comm comm, PetscInt dim, const PetscInt N0[3], const PetscInt nproc[3], PetscInt *const lx[3], PetscInt sw, PetscInt nb, PetscInt bs, PetscInt nx, PetscSF *sf)
{
  const PetscInt dof = nb * bs + nx;
  PetscInt     N[3], gs[3], ge[3], os[3], oe[3], me[3], i, j, k, d, n = 0, nroots;
  PetscInt    *ilocal;
  PetscSFNode *iremote;
  PetscMPIInt  rank;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  me[0] = rank % nproc[0];
  me[1] = (rank / nproc[0]) % nproc[1];
  me[2] = rank / (nproc[0] * nproc[1]);
  for (d = 0; d < 3; d++) {
    N[d]  = d < dim ? N0[d] : 1;
    os[d] = lx[d][me[d]];
    oe[d] = lx[d][me[d] + 1];
    gs[d] = d < dim ? PetscMax(os[d] - sw, 0) : 0;
    ge[d] = d < dim ? PetscMin(oe[d] + sw, N[d]) : 1;
  }
  nroots = dof * (ge[0] - gs[0]) * (ge[1] - gs[1]) * (ge[2] - gs[2]);
  /* leaves: the ghost points, dof entries each */
  for (k = gs[2]; k < ge[2]; k++)
    for (j = gs[1]; j < ge[1]; j++)
      for (i = gs[0]; i < ge[0]; i++)
        if (!(i >= os[0] && i < oe[0] && j >= os[1] && j < oe[1] && k >= os[2] && k < oe[2])) n++;
  PetscCall(PetscMalloc1(dof * n, &ilocal));
  PetscCall(PetscMalloc1(dof * n, &iremote));
  n = 0;
  for (k = gs[2]; k < ge[2]; k++)
    for (j = gs[1]; j < ge[1]; j++)
      for (i = gs[0]; i < ge[0]; i++) {
        const PetscInt ijk[3] = {i, j, k};
        PetscInt       r[3], rgs[3], rgm[3], e, ro;
        if (i >= os[0] && i < oe[0] && j >= os[1] && j < oe[1] && k >= os[2] && k < oe[2]) continue;
        /* the owner and the point's place in the owner's ghosted array */
        for (d = 0; d < 3; d++) {
          r[d]   = Owner(lx[d], nproc[d], ijk[d]);
          rgs[d] = d < dim ? PetscMax(lx[d][r[d]] - sw, 0) : 0;
          rgm[d] = (d < dim ? PetscMin(lx[d][r[d] + 1] + sw, N[d]) : 1) - rgs[d];
        }
        ro = ((k - rgs[2]) * rgm[1] + (j - rgs[1])) * rgm[0] + (i - rgs[0]);
        for (e = 0; e < dof; e++) {
          ilocal[n]        = PlaneIdx(nroots / dof, nb, bs, ((k - gs[2]) * (ge[1] - gs[1]) + (j - gs[1])) * (ge[0] - gs[0]) + (i - gs[0]), e);
          iremote[n].rank  = r[0] + nproc[0] * (r[1] + nproc[1] * r[2]);
          iremote[n].index = PlaneIdx(rgm[0] * rgm[1] * rgm[2], nb, bs, ro, e);
          n++;
        }
      }
  PetscCall(PetscSFCreate(comm, sf));
  PetscCall(PetscSFSetGraph(*sf, nroots, n, ilocal, PETSC_OWN_POINTER, iremote, PETSC_OWN_POINTER));
  PetscCall(PetscSFSetUp(*sf));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* the grid nodes' exchange: the node DMDA's sizes and stencil width */
PetscErrorCode PSHaloCreate(PSSolver *S, PetscInt dof, PetscSF *sf)
{
  PetscInt N[3], sw;

  PetscFunctionBeginUser;
  PetscCall(DMDAGetInfo(S->da, NULL, &N[0], &N[1], &N[2], NULL, NULL, NULL, NULL, &sw, NULL, NULL, NULL, NULL));
  PetscCall(PSHaloCreateBox(PetscObjectComm((PetscObject)S->da), S->dim, N, S->nproc, S->lx, sw, 1, dof, 0, sf));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* ghosts' contributions added into their owners (after P2G) */
PetscErrorCode PSHaloReduce(PetscSF sf, PetscReal *a)
{
  PetscFunctionBeginUser;
  PetscCall(PetscSFReduceBegin(sf, MPIU_REAL, a, a, MPIU_SUM));
  PetscCall(PetscSFReduceEnd(sf, MPIU_REAL, a, a, MPIU_SUM));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* owners' values copied to the ghosts (after the grid update) */
PetscErrorCode PSHaloBcast(PetscSF sf, PetscReal *a)
{
  PetscFunctionBeginUser;
  PetscCall(PetscSFBcastBegin(sf, MPIU_REAL, a, a, MPI_REPLACE));
  PetscCall(PetscSFBcastEnd(sf, MPIU_REAL, a, a, MPI_REPLACE));
  PetscFunctionReturn(PETSC_SUCCESS);
}
