/*
  memory.c - the process's large arrays backed by transparent huge pages
  (Linux; option -run_hugepages, on by default; README "Speed").

  The step's passes walk arrays of tens to hundreds of MB: the cells' blocks,
  the nodes' values, the remap's planes.  With 4 KiB pages every 4 KiB of an
  array is its own entry in the translation lookaside buffer (TLB), which
  holds some thousands of them, and a sweep across rows (the remap along y
  reaches a row's cells a row of blocks apart) misses it again and again.  A
  2 MiB page holds 512 such entries' worth.  Where the machine's kernel gives
  huge pages to regions that ask for them only (transparent_hugepage
  "madvise", Debian's default), plyshock asks: every private anonymous
  writable mapping of the process (the heap, and each large allocation, which
  glibc maps on its own) that is at least half resident is advised
  MADV_HUGEPAGE for the pages it will touch and MADV_COLLAPSE (Linux >= 6.1)
  for those it has, on its 2 MiB-aligned part.  The advice changes no value
  (every result bitwise the same, tested); the kernel may decline it (no
  huge pages free, an older kernel: EINVAL), which costs nothing.  Measured:
  the quadrants' step at 512^2 took 0.90-0.93x the time, at 256^2
  0.96-0.98x; the collapse's copy costs about 0.5 s once for 150 MB here
  (README "Speed", docs/speed.md).

  Called by the step after the first step of a solver (every array of the
  step exists by then: the remap's scratch is made on first use) and every
  PS_HUGE_EVERY steps after it (arrays made since: the markers' fields after
  a migration that grew them).
*/
#define _DEFAULT_SOURCE /* madvise under -std=c99 */
#include <stdio.h>
#include <string.h>
#if defined(__linux__)
  #include <sys/mman.h>
#endif
#include "step.h"

#if defined(__linux__) && defined(MADV_HUGEPAGE)
  #if !defined(MADV_COLLAPSE)
    #define MADV_COLLAPSE 25 /* Linux 6.1 (not in Debian 12's glibc headers) */
  #endif
#endif

/* Advise the kernel to back this process's private anonymous writable
   mappings with huge pages, those at least half resident (a sparse one, a
   thread's stack or a reserved pool, the collapse would fill); *bytes: the
   bytes advised (0 off Linux) */
PetscErrorCode PSMemoryHugePages(PetscLogDouble *bytes)
{
  PetscFunctionBeginUser;
  *bytes = 0;
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  {
    const unsigned long H = 2UL << 20; /* a huge page (x86-64, aarch64 with 4 KiB pages) */
    FILE               *f = fopen("/proc/self/smaps", "r");
    char                line[1024];
    unsigned long       a = 0, b = 0, rss;
    PetscBool           candidate = PETSC_FALSE;
    if (!f) PetscFunctionReturn(PETSC_SUCCESS); /* no /proc: no advice */
    while (fgets(line, sizeof line, f)) {
      unsigned long off, ino, a2, b2;
      char          perm[8], dev[32], path[512] = "";
      /* a mapping's first line: a private writable mapping of no file is a
         candidate (the heap, an anonymous map; not the stack, nor a file's
         or a shared segment's pages: MPI's) */
      if (sscanf(line, "%lx-%lx %7s %lx %31s %lu %511s", &a, &b, perm, &off, dev, &ino, path) >= 6) {
        candidate = !strcmp(perm, "rw-p") && ino == 0 && (!path[0] || !strcmp(path, "[heap]")) ? PETSC_TRUE : PETSC_FALSE;
        continue;
      }
      /* its resident size: advise a candidate at least half resident, on its 2 MiB-aligned part */
      if (!candidate || sscanf(line, "Rss: %lu kB", &rss) != 1) continue;
      candidate = PETSC_FALSE;
      a2        = (a + H - 1) & ~(H - 1);
      b2        = b & ~(H - 1);
      if (b2 <= a2 || 2 * 1024 * rss < b - a) continue;
      (void)madvise((void *)a2, b2 - a2, MADV_HUGEPAGE); /* (advice: a refusal changes nothing) */
      (void)madvise((void *)a2, b2 - a2, MADV_COLLAPSE);
      *bytes += (PetscLogDouble)(b2 - a2);
    }
    fclose(f);
  }
#endif
  PetscFunctionReturn(PETSC_SUCCESS);
}
