/*
  checkpoint.c - crash-safe checkpoints of a run, their verification, restart.

  OUTDIR/checkpoint.h5 (format 2); one writer per group of data, so a new kind
  of state (Eulerian cell data, say) is a new group with a writer of its own:

    /checkpoint/<field>  every registered marker field, N x block size, each
                         rank's markers a contiguous slab in rank order   (WriteMarkers)
    /checkpoint/ranks    per rank: marker count, booked lost mass, momentum
                         x, y, z, energy, marker count                    (WriteSolver)
    /checkpoint/state    t, dt, wave speed max, step, first dt (dt0)      (WriteSolver)
    /run/schedule        next output number, next output time, output
                         interval it was planned with                      (WriteSchedule)
    /run/gauges          ids of the markers the gauges follow (with gauges) (WriteSchedule)
    /cells/state         (scenes with cell materials) every cell's state, its
                         dof reals (cells/cells.h), natural order (x fastest)
    /cells/momentum      the cell materials' nodal momentum P^C, dim per node,
                         physical nodes in natural order
    /cells/ranks         per rank: remap heat, coupling work (J)
    /cells/sweep         the first sweep direction of the next remap     (WriteCells)
    /contact/ranks       (bodies in contact) per rank: friction work (J) (Checkpoint)
    root attributes      format, dim, cells, lower, upper (the grid it was
                         written for), complete = 1 (written last)
    every dataset        attribute checksum (uint64): the sum over its
                         elements k of mix(value_k xor mix(seed + k)), seed
                         from the dataset's path; a sum, so each rank adds
                         its own slab's share, on any rank count

  Crash safety: a checkpoint is written to OUTDIR/checkpoint.h5.tmp, closed
  collectively, then rank 0 flushes it to disk and renames it into place
  (atomic on POSIX): a run killed at any moment leaves the previous
  checkpoint whole.  PSCheckpointVerify checks a file before a restart
  (complete, same grid and fields, every checksum; every rank reads a share,
  HDF5's own error printing off) and returns what is wrong instead of failing.

  Restarting on the same rank count gives every rank back its own markers in
  their order, so the run continues bitwise as if uninterrupted; on another
  rank count the markers are read in equal slabs and migrated.  Cells and
  nodes are stored in natural order, each rank writing and reading the runs
  of its own box, so they restart on any rank count.
*/
#include <errno.h>
#include <fcntl.h>
#include <stdint.h>
#include <stdio.h>
#include <unistd.h>
#include <hdf5.h>
#include "cells/cells.h"
#include "contact.h"

#define PS_CHECKPOINT_FORMAT 2
#define PS_RANK_COLS         7 /* columns of /checkpoint/ranks */
#define PS_STATE_LEN         5 /* entries of /checkpoint/state (format 1 had 4: no dt0) */
#define PS_SCHEDULE_LEN      3 /* entries of /run/schedule */
#define PS_CHUNK             (1 << 20) /* elements read at a time when verifying */

#define H5CHK(e, what) PetscCheck((e) >= 0, PETSC_COMM_SELF, PETSC_ERR_FILE_UNEXPECTED, "checkpoint: HDF5 call %s failed", what)

static hid_t H5Type(PetscDataType t)
{
  return t == PETSC_REAL ? H5T_NATIVE_DOUBLE : t == PETSC_INT64 ? H5T_NATIVE_INT64 : (sizeof(PetscInt) == 8 ? H5T_NATIVE_INT64 : H5T_NATIVE_INT);
}

/* ------------------------------------------------------------ checksum -- */
/* splitmix64's finaliser (Steele, Lea & Flood 2014): every input bit moves every output bit */
static inline uint64_t Mix(uint64_t x)
{
  x ^= x >> 30;
  x *= 0xbf58476d1ce4e5b9ULL;
  x ^= x >> 27;
  x *= 0x94d049bb133111ebULL;
  x ^= x >> 31;
  return x;
}

/* FNV-1a of a dataset's path: its checksums differ from every other dataset's */
static uint64_t Seed(const char *path)
{
  uint64_t h = 0xcbf29ce484222325ULL;
  for (; *path; path++) h = (h ^ (unsigned char)*path) * 0x100000001b3ULL;
  return h;
}

/* this slab's share of a dataset's checksum: n elements from global element off */
static uint64_t ChecksumPart(PetscDataType type, const void *buf, PetscInt64 n, PetscInt64 off, uint64_t seed)
{
  uint64_t   sum = 0, v;
  PetscInt64 i;

  for (i = 0; i < n; i++) {
    if (type == PETSC_INT && sizeof(PetscInt) == 4) v = (uint64_t)(int64_t)((const int *)buf)[i]; /* by value: endian-free */
    else memcpy(&v, (const char *)buf + 8 * i, 8);
    sum += Mix(v ^ Mix(seed + (uint64_t)(off + i)));
  }
  return sum;
}

/* ---------------------------------------------------------------- write -- */
typedef struct {
  MPI_Comm    comm;
  PetscMPIInt rank, size;
  hid_t       file;
} PSCkptWriter;

/* One dataset of N x bs elements (bs = 0: N), written collectively; this rank
   writes n rows from row off.  Its checksum is summed over the ranks and
   attached as an attribute. */
static PetscErrorCode WriteTable(PSCkptWriter *w, hid_t loc, const char *group, const char *name, PetscDataType type, const void *buf, PetscInt64 n, PetscInt bs, PetscInt64 off, PetscInt64 N)
{
  const int rk   = bs ? 2 : 1;
  hsize_t   gd[2] = {(hsize_t)N, (hsize_t)bs}, ld[2] = {(hsize_t)n, (hsize_t)bs}, st[2] = {(hsize_t)off, 0}, one = 1;
  hid_t     fs, ms, ds, xfer, as, at;
  char      path[256];
  uint64_t  part, sum;
  static const double none = 0.0;

  PetscFunctionBeginUser;
  PetscCall(PetscSNPrintf(path, sizeof(path), "/%s/%s", group, name));
  part = ChecksumPart(type, buf, n * PetscMax(bs, 1), off * PetscMax(bs, 1), Seed(path));
  PetscCallMPI(MPI_Allreduce(&part, &sum, 1, MPI_UINT64_T, MPI_SUM, w->comm));
  fs = H5Screate_simple(rk, gd, NULL);
  H5CHK(fs, "H5Screate_simple");
  ds = H5Dcreate2(loc, name, H5Type(type), fs, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  H5CHK(ds, path);
  ms = H5Screate_simple(rk, ld, NULL);
  if (n > 0) H5CHK(H5Sselect_hyperslab(fs, H5S_SELECT_SET, st, NULL, ld, NULL), "H5Sselect_hyperslab");
  else {
    H5CHK(H5Sselect_none(fs), "H5Sselect_none");
    H5CHK(H5Sselect_none(ms), "H5Sselect_none");
  }
  xfer = H5Pcreate(H5P_DATASET_XFER);
  H5CHK(H5Pset_dxpl_mpio(xfer, H5FD_MPIO_COLLECTIVE), "H5Pset_dxpl_mpio");
  /* N = 0 (every marker has left): nothing to write, and HDF5 fails on an empty dataset */
  if (N > 0) H5CHK(H5Dwrite(ds, H5Type(type), ms, fs, xfer, buf ? buf : (const void *)&none), path); /* a rank without rows still joins */
  as = H5Screate_simple(1, &one, NULL);
  at = H5Acreate2(ds, "checksum", H5T_NATIVE_UINT64, as, H5P_DEFAULT, H5P_DEFAULT);
  H5CHK(at, "checksum");
  H5CHK(H5Awrite(at, H5T_NATIVE_UINT64, &sum), "checksum");
  H5Aclose(at);
  H5Sclose(as);
  H5Pclose(xfer);
  H5Sclose(ms);
  H5Dclose(ds);
  H5Sclose(fs);
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* a small table every rank knows: rank 0 writes it */
static PetscErrorCode WriteShared(PSCkptWriter *w, hid_t loc, const char *group, const char *name, PetscDataType type, const void *buf, PetscInt64 N)
{
  PetscFunctionBeginUser;
  PetscCall(WriteTable(w, loc, group, name, type, buf, w->rank ? 0 : N, 0, 0, N));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* A table of N rows of bs reals in natural order of a box grid (n[3] points,
   x fastest); this rank holds the points [lo, hi) of it, contiguous in buf
   (x fastest).  Written (or read, write = PETSC_FALSE) collectively as the
   runs along x of its box; the checksum is each element's at its natural
   place, so it is the same on any rank count. */
static PetscErrorCode BoxTable(PSCkptWriter *w, hid_t loc, const char *group, const char *name, const PetscInt n[3], const PetscInt lo[3], const PetscInt hi[3], PetscInt bs, PetscReal *buf, PetscBool write)
{
  const hsize_t N = (hsize_t)n[0] * n[1] * n[2];
  hsize_t       gd[2] = {N, (hsize_t)bs}, cnt = 0;
  hid_t         fs, ms, ds, xfer, as, at;
  char          path[256];
  uint64_t      part = 0, sum;
  PetscInt      j, k;
  PetscBool     any = PETSC_FALSE;
  static double none;

  PetscFunctionBeginUser;
  PetscCall(PetscSNPrintf(path, sizeof(path), "/%s/%s", group, name));
  fs = H5Screate_simple(2, gd, NULL);
  H5CHK(fs, "H5Screate_simple");
  if (write) ds = H5Dcreate2(loc, name, H5T_NATIVE_DOUBLE, fs, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  else ds = H5Dopen2(loc, name, H5P_DEFAULT);
  H5CHK(ds, path);
  H5CHK(H5Sselect_none(fs), "H5Sselect_none");
  for (k = lo[2]; k < hi[2]; k++)
    for (j = lo[1]; j < hi[1]; j++) {
      const hsize_t row = ((hsize_t)k * n[1] + j) * n[0] + lo[0], st[2] = {row, 0}, ct[2] = {(hsize_t)(hi[0] - lo[0]), (hsize_t)bs};
      if (ct[0] == 0) continue;
      H5CHK(H5Sselect_hyperslab(fs, H5S_SELECT_OR, st, NULL, ct, NULL), "H5Sselect_hyperslab");
      if (write) part += ChecksumPart(PETSC_REAL, buf + cnt * bs, (PetscInt64)ct[0] * bs, (PetscInt64)row * bs, Seed(path));
      cnt += ct[0];
      any = PETSC_TRUE;
    }
  {
    hsize_t md[2] = {PetscMax(cnt, 1), (hsize_t)bs};
    ms = H5Screate_simple(2, md, NULL);
    if (!any) H5CHK(H5Sselect_none(ms), "H5Sselect_none");
  }
  xfer = H5Pcreate(H5P_DATASET_XFER);
  H5CHK(H5Pset_dxpl_mpio(xfer, H5FD_MPIO_COLLECTIVE), "H5Pset_dxpl_mpio");
  if (write) H5CHK(H5Dwrite(ds, H5T_NATIVE_DOUBLE, ms, fs, xfer, any ? buf : &none), path);
  else H5CHK(H5Dread(ds, H5T_NATIVE_DOUBLE, ms, fs, xfer, any ? buf : &none), path);
  if (write) {
    PetscCallMPI(MPI_Allreduce(&part, &sum, 1, MPI_UINT64_T, MPI_SUM, w->comm));
    {
      const hsize_t one = 1;
      as = H5Screate_simple(1, &one, NULL);
      at = H5Acreate2(ds, "checksum", H5T_NATIVE_UINT64, as, H5P_DEFAULT, H5P_DEFAULT);
      H5CHK(at, "checksum");
      H5CHK(H5Awrite(at, H5T_NATIVE_UINT64, &sum), "checksum");
      H5Aclose(at);
      H5Sclose(as);
    }
  }
  H5Pclose(xfer);
  H5Sclose(ms);
  H5Dclose(ds);
  H5Sclose(fs);
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* the boxes of this rank's cells and physical nodes, and their sizes */
static void CellBoxes(const PSSolver *S, PetscInt nc[3], PetscInt clo[3], PetscInt chi[3], PetscInt nn[3], PetscInt nlo[3], PetscInt nhi[3])
{
  const PSCells *C = S->cells;
  PSIndex        ix;
  PetscInt       d;
  (void)PSGridIndex(S->da, &ix);
  for (d = 0; d < 3; d++) {
    nc[d]  = C->nc[d];
    clo[d] = C->cs[d];
    chi[d] = C->ce[d];
    nn[d]  = d < S->dim ? C->nc[d] + 1 : 1;
    nlo[d] = d < S->dim ? PetscMax(ix.os[d] - PS_PAD, 0) : 0;
    nhi[d] = d < S->dim ? PetscMin(ix.os[d] + ix.om[d] - PS_PAD, nn[d]) : 1;
  }
}

/* copy between the owned cells (or physical nodes) and a contiguous buffer */
static void CellsPack(PSSolver *S, PetscReal *cb, PetscReal *nb, PetscBool pack)
{
  PSCells *C = S->cells;
  PetscInt nc[3], clo[3], chi[3], nn[3], nlo[3], nhi[3], i, j, k, n = 0;
  PSIndex  ix;
  (void)PSGridIndex(S->da, &ix);
  CellBoxes(S, nc, clo, chi, nn, nlo, nhi);
  for (k = clo[2]; k < chi[2]; k++)
    for (j = clo[1]; j < chi[1]; j++)
      for (i = clo[0]; i < chi[0]; i++, n++) {
        if (pack) PSCellsCopyOut(C, PSCellIdx(C, i, j, k), &cb[n * C->dof]);
        else PSCellsCopyIn(C, PSCellIdx(C, i, j, k), &cb[n * C->dof]);
      }
  n = 0;
  for (k = nlo[2]; k < nhi[2]; k++)
    for (j = nlo[1]; j < nhi[1]; j++)
      for (i = nlo[0]; i < nhi[0]; i++, n++) {
        PetscReal *P = &C->P[S->dim * Lidx(&ix, i + PS_PAD, j + PS_PAD, S->dim == 3 ? k + PS_PAD : 0)];
        if (pack) memcpy(&nb[n * S->dim], P, S->dim * sizeof(PetscReal));
        else memcpy(P, &nb[n * S->dim], S->dim * sizeof(PetscReal));
      }
}

/* /cells: the Eulerian cells' state, their nodal momentum, books, sweep order */
static PetscErrorCode WriteCells(PSSolver *S, PSCkptWriter *w, hid_t grp)
{
  PSCells  *C = S->cells;
  PetscInt  nc[3], clo[3], chi[3], nn[3], nlo[3], nhi[3];
  PetscReal *cb, *nb, row[2] = {C->remap_heat, C->coupling_work}, sweep = (PetscReal)C->sweep0;

  PetscFunctionBeginUser;
  CellBoxes(S, nc, clo, chi, nn, nlo, nhi);
  PetscCall(PetscMalloc2(PetscMax(1, (chi[0] - clo[0]) * (chi[1] - clo[1]) * (chi[2] - clo[2]) * C->dof), &cb, PetscMax(1, (nhi[0] - nlo[0]) * (nhi[1] - nlo[1]) * (nhi[2] - nlo[2]) * S->dim), &nb));
  CellsPack(S, cb, nb, PETSC_TRUE);
  PetscCall(BoxTable(w, grp, "cells", "state", nc, clo, chi, C->dof, cb, PETSC_TRUE));
  PetscCall(BoxTable(w, grp, "cells", "momentum", nn, nlo, nhi, S->dim, nb, PETSC_TRUE));
  PetscCall(PetscFree2(cb, nb));
  PetscCall(WriteTable(w, grp, "cells", "ranks", PETSC_REAL, row, 1, 2, w->rank, w->size));
  PetscCall(WriteShared(w, grp, "cells", "sweep", PETSC_REAL, &sweep, 1));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode WriteAttr(hid_t loc, const char *name, hid_t type, hsize_t n, const void *buf)
{
  hid_t sp, at;

  PetscFunctionBeginUser;
  sp = H5Screate_simple(1, &n, NULL);
  at = H5Acreate2(loc, name, type, sp, H5P_DEFAULT, H5P_DEFAULT);
  H5CHK(at, name);
  H5CHK(H5Awrite(at, type, buf), name);
  H5Aclose(at);
  H5Sclose(sp);
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* /checkpoint/<field>: every registered marker field, each rank's slab in rank order */
static PetscErrorCode WriteMarkers(PSSolver *S, PSCkptWriter *w, hid_t grp)
{
  PetscInt      nf, bs[PS_MAX_FIELDS], n, f;
  const char   *names[PS_MAX_FIELDS];
  PetscDataType types[PS_MAX_FIELDS];
  PetscInt64    nl, off = 0, N = 0;

  PetscFunctionBeginUser;
  PetscCall(PSMarkersFieldList(S->scene, &nf, names, bs, types));
  PetscCall(DMSwarmGetLocalSize(S->sw, &n));
  nl = n;
  PetscCallMPI(MPI_Exscan(&nl, &off, 1, MPIU_INT64, MPI_SUM, w->comm));
  if (!w->rank) off = 0;
  PetscCallMPI(MPI_Allreduce(&nl, &N, 1, MPIU_INT64, MPI_SUM, w->comm));
  for (f = 0; f < nf; f++) {
    void *buf;
    PetscCall(DMSwarmGetField(S->sw, names[f], NULL, NULL, &buf));
    PetscCall(WriteTable(w, grp, "checkpoint", names[f], types[f], buf, n, bs[f], off, N));
    PetscCall(DMSwarmRestoreField(S->sw, names[f], NULL, NULL, &buf));
  }
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* /checkpoint/ranks and /checkpoint/state: each rank's count and books, the solver's clock */
static PetscErrorCode WriteSolver(PSSolver *S, PSCkptWriter *w, hid_t grp)
{
  PetscInt  n;
  PetscReal row[PS_RANK_COLS], state[PS_STATE_LEN] = {S->t, S->dt, S->smax, (PetscReal)S->step, S->dt0};

  PetscFunctionBeginUser;
  PetscCall(DMSwarmGetLocalSize(S->sw, &n));
  row[0] = (PetscReal)n;
  row[1] = S->lost_local.mass;
  row[2] = S->lost_local.p[0];
  row[3] = S->lost_local.p[1];
  row[4] = S->lost_local.p[2];
  row[5] = S->lost_local.kinetic + S->lost_local.internal;
  row[6] = (PetscReal)S->lost_local.markers;
  PetscCall(WriteTable(w, grp, "checkpoint", "ranks", PETSC_REAL, row, 1, PS_RANK_COLS, w->rank, w->size));
  /* column 5's two books apart (kinetic, internal), so that a restart sums
     them in the same order as the run it continues, bitwise; a checkpoint
     without them restarts with column 5 as kinetic */
  {
    const PetscReal ki[2] = {S->lost_local.kinetic, S->lost_local.internal};
    PetscCall(WriteTable(w, grp, "checkpoint", "lost_energies", PETSC_REAL, ki, 1, 2, w->rank, w->size));
  }
  PetscCall(WriteShared(w, grp, "checkpoint", "state", PETSC_REAL, state, PS_STATE_LEN));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* /run/schedule and /run/gauges: where the outputs stand, what the gauges follow */
static PetscErrorCode WriteSchedule(PSSolver *S, PSCkptWriter *w, hid_t grp)
{
  PetscReal sched[PS_SCHEDULE_LEN] = {(PetscReal)S->out.index, S->out.t_next, S->out.interval};

  PetscFunctionBeginUser;
  PetscCall(WriteShared(w, grp, "run", "schedule", PETSC_REAL, sched, PS_SCHEDULE_LEN));
  if (S->ngauge) PetscCall(WriteShared(w, grp, "run", "gauges", PETSC_INT64, S->gauge_id, S->ngauge));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* root attributes: what the file is and which grid it belongs to */
static PetscErrorCode WriteIdentity(PSSolver *S, hid_t file)
{
  const int format = PS_CHECKPOINT_FORMAT, dim = (int)S->scene->dim;
  int       cells[3];
  PetscInt  d;

  PetscFunctionBeginUser;
  for (d = 0; d < 3; d++) cells[d] = (int)S->scene->cells[d];
  PetscCall(WriteAttr(file, "format", H5T_NATIVE_INT, 1, &format));
  PetscCall(WriteAttr(file, "dim", H5T_NATIVE_INT, 1, &dim));
  PetscCall(WriteAttr(file, "cells", H5T_NATIVE_INT, 3, cells));
  PetscCall(WriteAttr(file, "lower", H5T_NATIVE_DOUBLE, 3, S->scene->lower));
  PetscCall(WriteAttr(file, "upper", H5T_NATIVE_DOUBLE, 3, S->scene->upper));
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode Checkpoint(PSSolver *S, const char filename[])
{
  PSCkptWriter w;
  hid_t        fapl, grp;
  char         tmp[PETSC_MAX_PATH_LEN + 8];
  const int    complete = 1;
  int          err = 0;

  PetscFunctionBeginUser;
  w.comm = PetscObjectComm((PetscObject)S->sw);
  PetscCallMPI(MPI_Comm_rank(w.comm, &w.rank));
  PetscCallMPI(MPI_Comm_size(w.comm, &w.size));
  PetscCall(PetscSNPrintf(tmp, sizeof(tmp), "%s.tmp", filename));
  fapl = H5Pcreate(H5P_FILE_ACCESS);
  H5CHK(H5Pset_fapl_mpio(fapl, w.comm, MPI_INFO_NULL), "H5Pset_fapl_mpio");
  w.file = H5Fcreate(tmp, H5F_ACC_TRUNC, H5P_DEFAULT, fapl);
  H5Pclose(fapl);
  PetscCheck(w.file >= 0, w.comm, PS_ERR_RUN, "cannot create the checkpoint %s (is the output directory writable?)", tmp);
  PetscCall(WriteIdentity(S, w.file));
  grp = H5Gcreate2(w.file, "/checkpoint", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  H5CHK(grp, "/checkpoint");
  PetscCall(WriteMarkers(S, &w, grp));
  PetscCall(WriteSolver(S, &w, grp));
  H5Gclose(grp);
  grp = H5Gcreate2(w.file, "/run", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  H5CHK(grp, "/run");
  PetscCall(WriteSchedule(S, &w, grp));
  H5Gclose(grp);
  if (S->cells) {
    grp = H5Gcreate2(w.file, "/cells", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    H5CHK(grp, "/cells");
    PetscCall(WriteCells(S, &w, grp));
    H5Gclose(grp);
  }
  if (S->contact) {
    grp = H5Gcreate2(w.file, "/contact", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    H5CHK(grp, "/contact");
    PetscCall(WriteTable(&w, grp, "contact", "ranks", PETSC_REAL, &S->contact->friction_work, 1, 1, w.rank, w.size));
    PetscCall(WriteTable(&w, grp, "contact", "interface", PETSC_REAL, &S->contact->interface_energy, 1, 1, w.rank, w.size));
    H5Gclose(grp);
  }
  PetscCall(WriteAttr(w.file, "complete", H5T_NATIVE_INT, 1, &complete)); /* last: everything above is in */
  H5CHK(H5Fclose(w.file), "H5Fclose");
  PetscCallMPI(MPI_Barrier(w.comm));
  if (!w.rank) {
    /* on disk before it takes the old one's place; then the directory entry */
    int  fd = open(tmp, O_RDONLY);
    char dir[PETSC_MAX_PATH_LEN], *slash;
    if (fd < 0 || fsync(fd) != 0) err = errno;
    if (fd >= 0) close(fd);
    if (!err && rename(tmp, filename) != 0) err = errno;
    PetscCall(PetscStrncpy(dir, filename, sizeof(dir)));
    slash = strrchr(dir, '/');
    if (slash) *slash = 0;
    else PetscCall(PetscStrncpy(dir, ".", sizeof(dir)));
    fd = open(dir, O_RDONLY);
    if (fd >= 0) {
      (void)fsync(fd);
      close(fd);
    }
  }
  PetscCallMPI(MPI_Bcast(&err, 1, MPI_INT, 0, w.comm));
  PetscCheck(!err, w.comm, PS_ERR_RUN, "cannot move the checkpoint %s into place as %s: %s", tmp, filename, strerror(err));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Write the checkpoint: collective; filename appears whole or not at all. */
PetscErrorCode PSSolverCheckpoint(PSSolver *S, const char filename[])
{
  H5E_auto2_t    func;
  void          *data;
  PetscErrorCode ierr;

  PetscFunctionBeginUser;
  H5Eget_auto2(H5E_DEFAULT, &func, &data);
  H5Eset_auto2(H5E_DEFAULT, NULL, NULL); /* failures are our errors, not HDF5's dumps on every rank */
  ierr = Checkpoint(S, filename);
  H5Eset_auto2(H5E_DEFAULT, func, data);
  PetscCall(ierr);
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* --------------------------------------------------------------- verify -- */
/* a dataset to check: its path, element type, rows and block size */
typedef struct {
  char          path[128];
  PetscDataType type;
  PetscInt64    N;
  PetscInt      bs;
} PSCkptTable;

/* Open a dataset and check its shape (N x bs; bs = 0: N; N < 0: any). */
static PetscBool TableShape(hid_t file, const char *path, PetscDataType type, PetscInt64 N, PetscInt bs, PetscInt64 *Nout, char msg[], size_t len)
{
  hid_t   ds, sp, ty;
  hsize_t d[2] = {0, 0};
  int     rk;
  PetscBool ok = PETSC_TRUE;

  if (H5Lexists(file, path, H5P_DEFAULT) <= 0 || (ds = H5Dopen2(file, path, H5P_DEFAULT)) < 0) {
    snprintf(msg, len, "has no dataset %s: was it written for this deck (transfer, materials, gauges)?", path);
    return PETSC_FALSE;
  }
  sp = H5Dget_space(ds);
  rk = sp >= 0 ? H5Sget_simple_extent_ndims(sp) : -1;
  if (rk >= 1 && rk <= 2) H5Sget_simple_extent_dims(sp, d, NULL);
  ty = H5Dget_type(ds);
  if (rk != (bs ? 2 : 1) || (bs > 0 && d[1] != (hsize_t)bs) || (N >= 0 && d[0] != (hsize_t)N)) { /* bs < 0: any block size */
    snprintf(msg, len, "dataset %s has shape %llu x %llu, expected %lld x %d: was it written for this deck?", path, (unsigned long long)d[0], (unsigned long long)(rk == 2 ? d[1] : 1), (long long)N, (int)PetscMax(bs, 1));
    ok = PETSC_FALSE;
  } else if (ty < 0 || H5Tget_class(ty) != (type == PETSC_REAL ? H5T_FLOAT : H5T_INTEGER) || H5Tget_size(ty) != H5Tget_size(H5Type(type))) {
    snprintf(msg, len, "dataset %s has the wrong element type: was it written for this deck?", path);
    ok = PETSC_FALSE;
  }
  if (Nout) *Nout = (PetscInt64)d[0];
  if (ty >= 0) H5Tclose(ty);
  if (sp >= 0) H5Sclose(sp);
  H5Dclose(ds);
  return ok;
}

static PetscBool ReadAttrInt(hid_t loc, const char *name, int n, int *v)
{
  hid_t     at;
  hsize_t   d = 0;
  hid_t     sp;
  PetscBool ok = PETSC_FALSE;

  if (H5Aexists(loc, name) <= 0 || (at = H5Aopen(loc, name, H5P_DEFAULT)) < 0) return PETSC_FALSE;
  sp = H5Aget_space(at);
  if (sp >= 0 && H5Sget_simple_extent_npoints(sp) == n) ok = H5Aread(at, H5T_NATIVE_INT, v) >= 0 ? PETSC_TRUE : PETSC_FALSE;
  (void)d;
  if (sp >= 0) H5Sclose(sp);
  H5Aclose(at);
  return ok;
}

static PetscBool ReadAttrReal(hid_t loc, const char *name, int n, double *v)
{
  hid_t     at, sp;
  PetscBool ok = PETSC_FALSE;

  if (H5Aexists(loc, name) <= 0 || (at = H5Aopen(loc, name, H5P_DEFAULT)) < 0) return PETSC_FALSE;
  sp = H5Aget_space(at);
  if (sp >= 0 && H5Sget_simple_extent_npoints(sp) == n) ok = H5Aread(at, H5T_NATIVE_DOUBLE, v) >= 0 ? PETSC_TRUE : PETSC_FALSE;
  if (sp >= 0) H5Sclose(sp);
  H5Aclose(at);
  return ok;
}

/* read rows [r0, r1) of a table in chunks and add up their checksum share; PETSC_FALSE on a read failure */
static PetscBool TableChecksum(hid_t file, const PSCkptTable *t, PetscInt64 r0, PetscInt64 r1, uint64_t *sum)
{
  const PetscInt   bs = PetscMax(t->bs, 1), rk = t->bs ? 2 : 1;
  const PetscInt64 rows = PetscMax(1, PS_CHUNK / bs);
  const uint64_t   seed = Seed(t->path);
  PetscInt64       r;
  hid_t            ds, fs, ms;
  void            *buf;
  PetscBool        ok = PETSC_TRUE;

  *sum = 0;
  if (r1 <= r0) return PETSC_TRUE;
  if ((ds = H5Dopen2(file, t->path, H5P_DEFAULT)) < 0) return PETSC_FALSE;
  if (!(buf = malloc((size_t)(PetscMin(rows, r1 - r0) * bs) * 8))) {
    H5Dclose(ds);
    return PETSC_FALSE;
  }
  fs = H5Dget_space(ds);
  for (r = r0; r < r1 && ok; r += rows) {
    hsize_t st[2] = {(hsize_t)r, 0}, ct[2] = {(hsize_t)PetscMin(rows, r1 - r), (hsize_t)bs};
    ms = H5Screate_simple(rk, ct, NULL);
    if (H5Sselect_hyperslab(fs, H5S_SELECT_SET, st, NULL, ct, NULL) < 0 || H5Dread(ds, H5Type(t->type), ms, fs, H5P_DEFAULT, buf) < 0) ok = PETSC_FALSE;
    else *sum += ChecksumPart(t->type, buf, (PetscInt64)ct[0] * bs, r * bs, seed);
    H5Sclose(ms);
  }
  H5Sclose(fs);
  free(buf);
  H5Dclose(ds);
  return ok;
}

static PetscBool StoredChecksum(hid_t file, const char *path, uint64_t *sum)
{
  hid_t     ds, at;
  PetscBool ok = PETSC_FALSE;

  if ((ds = H5Dopen2(file, path, H5P_DEFAULT)) < 0) return PETSC_FALSE;
  if (H5Aexists(ds, "checksum") > 0 && (at = H5Aopen(ds, "checksum", H5P_DEFAULT)) >= 0) {
    ok = H5Aread(at, H5T_NATIVE_UINT64, sum) >= 0 ? PETSC_TRUE : PETSC_FALSE;
    H5Aclose(at);
  }
  H5Dclose(ds);
  return ok;
}

/* the first rank with a message gives it to all (msg empty: all passed) */
static PetscErrorCode Agree(MPI_Comm comm, char msg[], size_t len)
{
  PetscMPIInt rank, size, mine, first;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCallMPI(MPI_Comm_size(comm, &size));
  mine = msg[0] ? rank : size;
  PetscCallMPI(MPI_Allreduce(&mine, &first, 1, MPI_INT, MPI_MIN, comm));
  if (first < size) PetscCallMPI(MPI_Bcast(msg, (PetscMPIInt)len, MPI_CHAR, first, comm));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* the checks that need no other rank: what the file is, its grid, its datasets' shapes */
static PetscErrorCode VerifyLayout(const PSScene *scene, hid_t file, PSCkptTable *t, PetscInt *nt, char msg[], size_t len)
{
  int           format = 0, complete = 0, dim = 0, cells[3];
  double        lo[3], hi[3];
  PetscInt      nf, bs[PS_MAX_FIELDS], f, d, ns = 0;
  const char   *names[PS_MAX_FIELDS];
  PetscDataType types[PS_MAX_FIELDS];
  PetscInt64    N = 0, R, r;
  double       *rows;

  PetscFunctionBeginUser;
  *nt = 0;
  if (!ReadAttrInt(file, "format", 1, &format)) {
    snprintf(msg, len, "is not a plyshock checkpoint, or one written before checkpoints carried a checksum (no format attribute)");
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  if (format != PS_CHECKPOINT_FORMAT) {
    snprintf(msg, len, "has checkpoint format %d; this plyshock reads format %d", format, PS_CHECKPOINT_FORMAT);
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  if (!ReadAttrInt(file, "complete", 1, &complete) || complete != 1) {
    snprintf(msg, len, "is incomplete: its writer stopped before the end (a kill during the write?); restart from an earlier copy");
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  if (!ReadAttrInt(file, "dim", 1, &dim) || !ReadAttrInt(file, "cells", 3, cells) || !ReadAttrReal(file, "lower", 3, lo) || !ReadAttrReal(file, "upper", 3, hi)) {
    snprintf(msg, len, "is damaged: its grid attributes (dim, cells, lower, upper) cannot be read");
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  if (dim != scene->dim) {
    snprintf(msg, len, "was written for a %dD scene; this deck is %dD", dim, (int)scene->dim);
    PetscFunctionReturn(PETSC_SUCCESS);
  }
  for (d = 0; d < scene->dim; d++)
    if (cells[d] != scene->cells[d] || lo[d] != scene->lower[d] || hi[d] != scene->upper[d]) {
      snprintf(msg, len, "was written for another grid (along %c: %d cells on [%g, %g] m; this deck: %d cells on [%g, %g] m)", "xyz"[d], cells[d], lo[d], hi[d], (int)scene->cells[d], (double)scene->lower[d], (double)scene->upper[d]);
      PetscFunctionReturn(PETSC_SUCCESS);
    }
  /* per-rank rows: the marker count */
  if (!TableShape(file, "/checkpoint/ranks", PETSC_REAL, -1, PS_RANK_COLS, &R, msg, len)) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(PetscMalloc1(PS_RANK_COLS * PetscMax(R, 1), &rows));
  {
    hid_t ds = H5Dopen2(file, "/checkpoint/ranks", H5P_DEFAULT);
    if (ds < 0 || H5Dread(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, rows) < 0) snprintf(msg, len, "is damaged: /checkpoint/ranks cannot be read");
    if (ds >= 0) H5Dclose(ds);
  }
  for (r = 0; r < R && !msg[0]; r++) {
    const double c = rows[PS_RANK_COLS * r];
    if (!(c >= 0 && c < 9.0e15 && c == floor(c))) snprintf(msg, len, "is damaged: rank %lld's marker count reads %g", (long long)r, c);
    else N += (PetscInt64)c;
  }
  PetscCall(PetscFree(rows));
  if (msg[0]) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(PetscSNPrintf(t[ns].path, sizeof(t[ns].path), "/checkpoint/ranks"));
  t[ns].type = PETSC_REAL, t[ns].N = R, t[ns].bs = PS_RANK_COLS, ns++;
  /* every marker field this deck needs */
  PetscCall(PSMarkersFieldList(scene, &nf, names, bs, types));
  for (f = 0; f < nf; f++) {
    PetscCall(PetscSNPrintf(t[ns].path, sizeof(t[ns].path), "/checkpoint/%s", names[f]));
    t[ns].type = types[f], t[ns].N = N, t[ns].bs = bs[f];
    if (!TableShape(file, t[ns].path, types[f], N, bs[f], NULL, msg, len)) PetscFunctionReturn(PETSC_SUCCESS);
    ns++;
  }
  if (!TableShape(file, "/checkpoint/state", PETSC_REAL, PS_STATE_LEN, 0, NULL, msg, len)) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(PetscSNPrintf(t[ns].path, sizeof(t[ns].path), "/checkpoint/state"));
  t[ns].type = PETSC_REAL, t[ns].N = PS_STATE_LEN, t[ns].bs = 0, ns++;
  if (!TableShape(file, "/run/schedule", PETSC_REAL, PS_SCHEDULE_LEN, 0, NULL, msg, len)) PetscFunctionReturn(PETSC_SUCCESS);
  PetscCall(PetscSNPrintf(t[ns].path, sizeof(t[ns].path), "/run/schedule"));
  t[ns].type = PETSC_REAL, t[ns].N = PS_SCHEDULE_LEN, t[ns].bs = 0, ns++;
  if (H5Lexists(file, "/run/gauges", H5P_DEFAULT) > 0) {
    PetscInt64 ng;
    if (!TableShape(file, "/run/gauges", PETSC_INT64, -1, 0, &ng, msg, len)) PetscFunctionReturn(PETSC_SUCCESS);
    PetscCall(PetscSNPrintf(t[ns].path, sizeof(t[ns].path), "/run/gauges"));
    t[ns].type = PETSC_INT64, t[ns].N = ng, t[ns].bs = 0, ns++;
  }
  /* the Eulerian cells' tables */
  if (scene->ncellmat > 0) {
    const PetscInt ncell = scene->cells[0] * scene->cells[1] * (scene->dim == 3 ? scene->cells[2] : 1);
    const PetscInt nnode = (scene->cells[0] + 1) * (scene->cells[1] + 1) * (scene->dim == 3 ? scene->cells[2] + 1 : 1);
    PetscInt64     Nc = 0, Rr = 0;
    if (!TableShape(file, "/cells/state", PETSC_REAL, ncell, -1, &Nc, msg, len)) PetscFunctionReturn(PETSC_SUCCESS);
    PetscCall(PetscSNPrintf(t[ns].path, sizeof(t[ns].path), "/cells/state"));
    {
      hid_t   ds = H5Dopen2(file, "/cells/state", H5P_DEFAULT), sp = H5Dget_space(ds);
      hsize_t dd[2] = {0, 0};
      H5Sget_simple_extent_dims(sp, dd, NULL);
      H5Sclose(sp);
      H5Dclose(ds);
      t[ns].type = PETSC_REAL, t[ns].N = ncell, t[ns].bs = (PetscInt)dd[1], ns++;
    }
    if (!TableShape(file, "/cells/momentum", PETSC_REAL, nnode, scene->dim, NULL, msg, len)) PetscFunctionReturn(PETSC_SUCCESS);
    PetscCall(PetscSNPrintf(t[ns].path, sizeof(t[ns].path), "/cells/momentum"));
    t[ns].type = PETSC_REAL, t[ns].N = nnode, t[ns].bs = scene->dim, ns++;
    if (!TableShape(file, "/cells/ranks", PETSC_REAL, -1, 2, &Rr, msg, len)) PetscFunctionReturn(PETSC_SUCCESS);
    PetscCall(PetscSNPrintf(t[ns].path, sizeof(t[ns].path), "/cells/ranks"));
    t[ns].type = PETSC_REAL, t[ns].N = Rr, t[ns].bs = 2, ns++;
    if (!TableShape(file, "/cells/sweep", PETSC_REAL, 1, 0, NULL, msg, len)) PetscFunctionReturn(PETSC_SUCCESS);
    PetscCall(PetscSNPrintf(t[ns].path, sizeof(t[ns].path), "/cells/sweep"));
    t[ns].type = PETSC_REAL, t[ns].N = 1, t[ns].bs = 0, ns++;
    (void)Nc;
  }
  /* the contact's books (a run with bodies in contact) */
  if (H5Lexists(file, "/contact", H5P_DEFAULT) > 0) {
    PetscInt64 Rc = 0;
    if (!TableShape(file, "/contact/ranks", PETSC_REAL, -1, 1, &Rc, msg, len)) PetscFunctionReturn(PETSC_SUCCESS);
    PetscCall(PetscSNPrintf(t[ns].path, sizeof(t[ns].path), "/contact/ranks"));
    t[ns].type = PETSC_REAL, t[ns].N = Rc, t[ns].bs = 1, ns++;
  }
  for (f = 0; f < ns; f++) {
    uint64_t c;
    if (!StoredChecksum(file, t[f].path, &c)) {
      snprintf(msg, len, "is damaged: dataset %s has no readable checksum", t[f].path);
      PetscFunctionReturn(PETSC_SUCCESS);
    }
  }
  *nt = ns;
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscErrorCode Verify(MPI_Comm comm, const PSScene *scene, const char filename[], char msg[], size_t len)
{
  PetscMPIInt rank, size;
  hid_t       file = -1;
  PSCkptTable t[PS_MAX_FIELDS + 8];
  PetscInt    nt = 0, k;
  uint64_t    part[PS_MAX_FIELDS + 8], sum[PS_MAX_FIELDS + 8];
  int         bad[PS_MAX_FIELDS + 8], gbad[PS_MAX_FIELDS + 8], ntg;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCallMPI(MPI_Comm_size(comm, &size));
  msg[0] = 0;
  /* every rank reads on its own (no collective I/O: a damaged file cannot hang one) */
  file = H5Fopen(filename, H5F_ACC_RDONLY, H5P_DEFAULT);
  if (file < 0) snprintf(msg, len, "is not a readable HDF5 file (truncated, damaged, or not a checkpoint)");
  else PetscCall(VerifyLayout(scene, file, t, &nt, msg, len));
  PetscCall(Agree(comm, msg, len));
  if (!msg[0]) {
    /* the same tables on every rank now; each reads an equal share of each and adds up its checksum */
    ntg = (int)nt;
    for (k = 0; k < nt; k++) {
      const PetscInt64 r0 = t[k].N * rank / size, r1 = t[k].N * (rank + 1) / size;
      bad[k] = TableChecksum(file, &t[k], r0, r1, &part[k]) ? 0 : 1;
    }
    PetscCallMPI(MPI_Allreduce(part, sum, ntg, MPI_UINT64_T, MPI_SUM, comm));
    PetscCallMPI(MPI_Allreduce(bad, gbad, ntg, MPI_INT, MPI_MAX, comm));
    for (k = 0; k < nt && !msg[0]; k++) {
      uint64_t stored = 0;
      (void)StoredChecksum(file, t[k].path, &stored);
      if (gbad[k]) snprintf(msg, len, "is damaged: dataset %s cannot be read", t[k].path);
      else if (stored != sum[k]) snprintf(msg, len, "is damaged: dataset %s fails its checksum (stored %016llx, read %016llx)", t[k].path, (unsigned long long)stored, (unsigned long long)sum[k]);
    }
  }
  if (file >= 0) H5Fclose(file);
  PetscCall(Agree(comm, msg, len));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Check a checkpoint before a restart, on every rank of comm: complete, written
   for this scene's grid and fields, every dataset's checksum.  msg is empty
   when it passes, else says what is wrong (the same on every rank).  HDF5
   prints nothing. */
PetscErrorCode PSCheckpointVerify(MPI_Comm comm, const PSScene *scene, const char filename[], char msg[], size_t len)
{
  H5E_auto2_t    func;
  void          *data;
  PetscErrorCode ierr;

  PetscFunctionBeginUser;
  H5Eget_auto2(H5E_DEFAULT, &func, &data);
  H5Eset_auto2(H5E_DEFAULT, NULL, NULL);
  ierr = Verify(comm, scene, filename, msg, len);
  H5Eset_auto2(H5E_DEFAULT, func, data);
  PetscCall(ierr);
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* -------------------------------------------------------------- restart -- */
/* collective slab read of an (N, bs) dataset */
static PetscErrorCode ReadSlab(hid_t loc, const char *name, hid_t type, void *buf, PetscInt n, PetscInt bs, PetscInt64 off)
{
  hsize_t ld[2] = {(hsize_t)n, (hsize_t)bs}, st[2] = {(hsize_t)off, 0};
  hid_t   ds, fs, ms, xfer;
  int     rk;
  static double none;

  PetscFunctionBeginUser;
  ds = H5Dopen2(loc, name, H5P_DEFAULT);
  H5CHK(ds, name);
  fs = H5Dget_space(ds);
  rk = H5Sget_simple_extent_ndims(fs);
  ms = H5Screate_simple(rk, ld, NULL);
  if (n > 0) H5CHK(H5Sselect_hyperslab(fs, H5S_SELECT_SET, st, NULL, ld, NULL), "select");
  else {
    H5CHK(H5Sselect_none(fs), "select");
    H5CHK(H5Sselect_none(ms), "select");
  }
  xfer = H5Pcreate(H5P_DATASET_XFER);
  H5CHK(H5Pset_dxpl_mpio(xfer, H5FD_MPIO_COLLECTIVE), "dxpl");
  if (H5Sget_simple_extent_npoints(fs) > 0) H5CHK(H5Dread(ds, type, ms, fs, xfer, buf ? buf : (void *)&none), name);
  H5Pclose(xfer);
  H5Sclose(ms);
  H5Sclose(fs);
  H5Dclose(ds);
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* a small dataset every rank reads whole */
static PetscErrorCode ReadAll(hid_t loc, const char *name, hid_t type, void *buf)
{
  hid_t ds;

  PetscFunctionBeginUser;
  ds = H5Dopen2(loc, name, H5P_DEFAULT);
  H5CHK(ds, name);
  H5CHK(H5Dread(ds, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, buf), name);
  H5Dclose(ds);
  PetscFunctionReturn(PETSC_SUCCESS);
}

static PetscInt64 Rows(hid_t loc, const char *name)
{
  hid_t   ds = H5Dopen2(loc, name, H5P_DEFAULT), sp;
  hsize_t d[2] = {0, 0};

  if (ds < 0) return -1;
  sp = H5Dget_space(ds);
  H5Sget_simple_extent_dims(sp, d, NULL);
  H5Sclose(sp);
  H5Dclose(ds);
  return (PetscInt64)d[0];
}

static PetscErrorCode Restart(PSSolver *S, const char filename[])
{
  MPI_Comm      comm = PetscObjectComm((PetscObject)S->sw);
  PetscMPIInt   rank, size;
  PetscInt      nf, bs[PS_MAX_FIELDS], n, f, r, nranks;
  const char   *names[PS_MAX_FIELDS];
  PetscDataType types[PS_MAX_FIELDS];
  PetscInt64    off = 0, N, ng;
  hid_t         fapl, file, grp;
  PetscReal     state[PS_STATE_LEN] = {0}, sched[PS_SCHEDULE_LEN], *rows, *lki;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCallMPI(MPI_Comm_size(comm, &size));
  fapl = H5Pcreate(H5P_FILE_ACCESS);
  H5CHK(H5Pset_fapl_mpio(fapl, comm, MPI_INFO_NULL), "fapl");
  file = H5Fopen(filename, H5F_ACC_RDONLY, fapl);
  H5Pclose(fapl);
  PetscCheck(file >= 0, comm, PS_ERR_RUN, "cannot open checkpoint %s", filename);
  grp = H5Gopen2(file, "/checkpoint", H5P_DEFAULT);
  PetscCheck(grp >= 0, comm, PS_ERR_RUN, "checkpoint %s has no /checkpoint group", filename);
  nranks = (PetscInt)Rows(grp, "ranks");
  PetscCheck(nranks > 0 && Rows(grp, "state") == PS_STATE_LEN, comm, PS_ERR_RUN, "checkpoint %s is damaged or of another format (check it with PSCheckpointVerify)", filename);
  PetscCall(PetscMalloc2(PS_RANK_COLS * nranks, &rows, 2 * nranks, &lki));
  PetscCall(ReadAll(grp, "ranks", H5T_NATIVE_DOUBLE, rows));
  if (H5Lexists(grp, "lost_energies", H5P_DEFAULT) > 0 && Rows(grp, "lost_energies") == nranks) PetscCall(ReadAll(grp, "lost_energies", H5T_NATIVE_DOUBLE, lki));
  else
    for (r = 0; r < nranks; r++) {
      lki[2 * r]     = rows[PS_RANK_COLS * r + 5];
      lki[2 * r + 1] = 0.0;
    }
  PetscCall(ReadAll(grp, "state", H5T_NATIVE_DOUBLE, state));
  N = 0;
  for (r = 0; r < nranks; r++) N += (PetscInt64)rows[PS_RANK_COLS * r];
  PetscCall(PetscMemzero(&S->lost_local, sizeof(S->lost_local)));
  if (nranks == size) {
    /* same rank count: every rank its own slab, its own order, its own books */
    const PetscReal *row = &rows[PS_RANK_COLS * rank];
    for (r = 0; r < rank; r++) off += (PetscInt64)rows[PS_RANK_COLS * r];
    n                     = (PetscInt)row[0];
    S->lost_local.mass    = row[1];
    S->lost_local.p[0]    = row[2];
    S->lost_local.p[1]    = row[3];
    S->lost_local.p[2]    = row[4];
    S->lost_local.kinetic  = lki[2 * rank];
    S->lost_local.internal = lki[2 * rank + 1];
    S->lost_local.markers  = (PetscInt64)row[6];
  } else {
    /* another rank count: equal slabs, books summed on rank 0, then migrate */
    off = N * rank / size;
    n   = (PetscInt)(N * (rank + 1) / size - off);
    if (!rank)
      for (r = 0; r < nranks; r++) {
        const PetscReal *row = &rows[PS_RANK_COLS * r];
        S->lost_local.mass += row[1];
        S->lost_local.p[0] += row[2];
        S->lost_local.p[1] += row[3];
        S->lost_local.p[2] += row[4];
        S->lost_local.kinetic += lki[2 * r];
        S->lost_local.internal += lki[2 * r + 1];
        S->lost_local.markers += (PetscInt64)row[6];
      }
  }
  PetscCall(PetscFree2(rows, lki));
  PetscCall(DMSwarmSetLocalSizes(S->sw, n, PetscMax(16, n / 16)));
  PetscCall(PSMarkersFieldList(S->scene, &nf, names, bs, types));
  for (f = 0; f < nf; f++) {
    void *buf;
    PetscCheck(Rows(grp, names[f]) == N, comm, PS_ERR_RUN, "checkpoint %s has no field %s of %lld markers: was it written for this deck?", filename, names[f], (long long)N);
    PetscCall(DMSwarmGetField(S->sw, names[f], NULL, NULL, &buf));
    PetscCall(ReadSlab(grp, names[f], H5Type(types[f]), buf, n, bs[f], off));
    PetscCall(DMSwarmRestoreField(S->sw, names[f], NULL, NULL, &buf));
  }
  H5Gclose(grp);
  grp = H5Gopen2(file, "/run", H5P_DEFAULT);
  PetscCheck(grp >= 0, comm, PS_ERR_RUN, "checkpoint %s has no /run group", filename);
  PetscCall(ReadAll(grp, "schedule", H5T_NATIVE_DOUBLE, sched));
  ng = Rows(grp, "gauges");
  if (ng > 0) {
    PetscInt64 *ids;
    PetscCall(PetscMalloc1(ng, &ids));
    PetscCall(ReadAll(grp, "gauges", H5T_NATIVE_INT64, ids));
    PetscCall(PSSolverSetGauges(S, (PetscInt)ng, ids));
    PetscCall(PetscFree(ids));
  }
  H5Gclose(grp);
  if (S->cells) {
    PSCells  *C = S->cells;
    PetscInt  nc[3], clo[3], chi[3], nn[3], nlo[3], nhi[3], R;
    PetscReal *cb, *nb, *books, sweep;
    PSCkptWriter w;
    PSIndex      ix;
    w.comm = comm;
    w.rank = rank;
    w.size = size;
    grp    = H5Gopen2(file, "/cells", H5P_DEFAULT);
    PetscCheck(grp >= 0, comm, PS_ERR_RUN, "checkpoint %s has no /cells group: was it written for this deck?", filename);
    CellBoxes(S, nc, clo, chi, nn, nlo, nhi);
    PetscCall(PetscMalloc2(PetscMax(1, (chi[0] - clo[0]) * (chi[1] - clo[1]) * (chi[2] - clo[2]) * C->dof), &cb, PetscMax(1, (nhi[0] - nlo[0]) * (nhi[1] - nlo[1]) * (nhi[2] - nlo[2]) * S->dim), &nb));
    PetscCall(BoxTable(&w, grp, "cells", "state", nc, clo, chi, C->dof, cb, PETSC_FALSE));
    PetscCall(BoxTable(&w, grp, "cells", "momentum", nn, nlo, nhi, S->dim, nb, PETSC_FALSE));
    PetscCall(PetscArrayzero(C->P, C->nnl * S->dim));
    CellsPack(S, cb, nb, PETSC_FALSE);
    PetscCall(PetscFree2(cb, nb));
    R = (PetscInt)Rows(grp, "ranks");
    PetscCall(PetscMalloc1(2 * PetscMax(R, 1), &books));
    PetscCall(ReadAll(grp, "ranks", H5T_NATIVE_DOUBLE, books));
    C->remap_heat = C->coupling_work = 0.0;
    if (R == size) {
      C->remap_heat    = books[2 * rank];
      C->coupling_work = books[2 * rank + 1];
    } else if (!rank)
      for (r = 0; r < R; r++) {
        C->remap_heat += books[2 * r];
        C->coupling_work += books[2 * r + 1];
      }
    PetscCall(PetscFree(books));
    PetscCall(ReadAll(grp, "sweep", H5T_NATIVE_DOUBLE, &sweep));
    C->sweep0 = (PetscInt)sweep;
    H5Gclose(grp);
    /* ghosts, nodal masses */
    PetscCall(PSHaloBcast(C->sfp, C->P));
    PetscCall(PSCellsExchange(C));
    PetscCall(PSGridIndex(S->da, &ix));
    PetscCall(PSCellsNodalMass(S, &ix, PETSC_FALSE));
  }
  /* the contact's friction work: each rank its own on the same rank count, else all on rank 0 */
  if (S->contact) {
    S->contact->friction_work = 0.0;
    if (H5Lexists(file, "/contact", H5P_DEFAULT) > 0) {
      PetscInt   R;
      PetscReal *books;
      grp = H5Gopen2(file, "/contact", H5P_DEFAULT);
      R   = (PetscInt)Rows(grp, "ranks");
      PetscCall(PetscMalloc1(PetscMax(R, 1), &books));
      PetscCall(ReadAll(grp, "ranks", H5T_NATIVE_DOUBLE, books));
      if (R == size) S->contact->friction_work = books[rank];
      else if (!rank)
        for (r = 0; r < R; r++) S->contact->friction_work += books[r];
      S->contact->interface_energy = 0.0;
      if (H5Lexists(grp, "interface", H5P_DEFAULT) > 0) {
        PetscCheck(Rows(grp, "interface") == R, PETSC_COMM_SELF, PETSC_ERR_FILE_UNEXPECTED, "checkpoint: /contact/interface has %lld rows, /contact/ranks %lld", (long long)Rows(grp, "interface"), (long long)R);
        PetscCall(ReadAll(grp, "interface", H5T_NATIVE_DOUBLE, books));
        if (R == size) S->contact->interface_energy = books[rank];
        else if (!rank)
          for (r = 0; r < R; r++) S->contact->interface_energy += books[r];
      }
      PetscCall(PetscFree(books));
      H5Gclose(grp);
    }
  }
  H5Fclose(file);
  S->t            = state[0];
  S->dt           = state[1];
  S->smax         = state[2];
  S->step         = (PetscInt)state[3];
  S->dt0          = state[4];
  S->out.index    = (PetscInt)sched[0];
  S->out.t_next   = sched[1];
  S->out.interval = sched[2];
  S->restarted    = PETSC_TRUE;
  if (nranks != size) PetscCall(PSSolverMigrate(S));
  PetscFunctionReturn(PETSC_SUCCESS);
}

/* Read a checkpoint (checked by PSCheckpointVerify) into an empty swarm whose
   fields are registered. */
PetscErrorCode PSSolverRestart(PSSolver *S, const char filename[])
{
  H5E_auto2_t    func;
  void          *data;
  PetscErrorCode ierr;

  PetscFunctionBeginUser;
  H5Eget_auto2(H5E_DEFAULT, &func, &data);
  H5Eset_auto2(H5E_DEFAULT, NULL, NULL);
  ierr = Restart(S, filename);
  H5Eset_auto2(H5E_DEFAULT, func, data);
  PetscCall(ierr);
  PetscFunctionReturn(PETSC_SUCCESS);
}
