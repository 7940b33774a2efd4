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
  glibc maps on its own) is advised MADV_HUGEPAGE for the pages it will touch
  and MADV_COLLAPSE (Linux >= 6.1) for those it has, on its 2 MiB-aligned
  part.  The advice changes no value (every result bitwise the same, tested);
  the kernel may decline it (no huge pages free, an older kernel: EINVAL),
  which costs nothing.  Measured: the quadrants' step at 512^2 took
  0.93x the time and at 256^2 0.95x (README "Speed").

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
   mappings with huge pages; *bytes: the bytes advised (0 off Linux) */
PetscErrorCode PSMemoryHugePages(PetscLogDouble *bytes)
{
  PetscFunctionBeginUser;
  *bytes = 0;
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  {
    const unsigned long H = 2UL << 20; /* a huge page (x86-64, aarch64 with 4 KiB pages) */
    FILE               *f = fopen("/proc/self/maps", "r");
    char                line[1024];
    if (!f) PetscFunctionReturn(PETSC_SUCCESS); /* no /proc: no advice */
    while (fgets(line, sizeof line, f)) {
      unsigned long a, b, off, ino, a2, b2;
      char          perm[8], dev[32], path[512] = "";
      int           n = sscanf(line, "%lx-%lx %7s %lx %31s %lu %511s", &a, &b, perm, &off, dev, &ino, path);
      /* a private writable mapping of no file: the heap, an anonymous map
         (not the stack, nor a file's or a shared segment's pages: MPI's) */
      if (n < 6 || strcmp(perm, "rw-p") || ino != 0 || (path[0] && strcmp(path, "[heap]"))) continue;
      a2 = (a + H - 1) & ~(H - 1);
      b2 = b & ~(H - 1);
      if (b2 <= a2) continue;
      (void)madvise((void *)a2, b2 - a2, MADV_HUGEPAGE); /* (advice: a refusal changes nothing) */
      (void)madvise((void *)a2, b2 - a2, MADV_COLLAPSE);
      *bytes += (PetscLogDouble)(b2 - a2);
    }
    fclose(f);
  }
#endif
  PetscFunctionReturn(PETSC_SUCCESS);
}
