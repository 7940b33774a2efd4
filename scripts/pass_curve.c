/*
  pass_curve.c - how fast one core streams a pass of the step's kind over a
  working set of a given size (scripts/bench; docs/speed.md, twenty-eighth
  session).

  The pass is b[i] += s a[i] over two arrays of doubles that together take
  the working set (a read of two, a write of one, per element): the shape of
  most of the cells' loops, which read a few arrays and write one.  For each
  working set from 1 to 512 MiB it prints the rate in GB/s (three reals per
  element counted, the best of five repeats, each repeat enough passes to
  move at least 512 MiB) as

    BENCH pass_gbs_<MiB> <rate in bytes/s>

  The bench's table sets the rate over the 512^2 quadrants' resident state
  beside the rate over the 256^2's (their sizes: bench_cells.py's resident
  bytes per cell): where the state leaves the caches' fast range, each pass
  of the step slows down, and PyClaw, whose state is four reals per cell,
  does not.  Not plyshock's solver: a yardstick of this machine.

    cc -O3 -march=native -std=c99 scripts/pass_curve.c -o out/pass_curve
    out/pass_curve
*/
#define _POSIX_C_SOURCE 199309L
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

static double Now(void)
{
  struct timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

int main(void)
{
  size_t mib;
  for (mib = 1; mib <= 512; mib *= 2) {
    const size_t n = mib * 1024 * 1024 / (2 * sizeof(double));
    const int    passes = (int)(512 / mib) + 1;
    double      *a = malloc(n * sizeof(double)), *b = malloc(n * sizeof(double)), best = 1e30, sum = 0.0;
    size_t       i;
    int          r, p;
    if (!a || !b) {
      fprintf(stderr, "pass_curve: no memory for %zu MiB\n", mib);
      return 1;
    }
    for (i = 0; i < n; i++) {
      a[i] = (double)i;
      b[i] = 0.0;
    }
    for (r = 0; r < 5; r++) {
      const double t0 = Now();
      for (p = 0; p < passes; p++)
        for (i = 0; i < n; i++) b[i] += 1.0001 * a[i];
      const double t = (Now() - t0) / passes;
      if (t < best) best = t;
    }
    for (i = 0; i < n; i += 4096) sum += b[i]; /* (the passes' result is used) */
    printf("  a pass over %4zu MiB: %6.1f GB/s%s\n", mib, 3.0 * (double)n * sizeof(double) / best / 1e9, sum < 0.0 ? " (?)" : "");
    printf("BENCH pass_gbs_%zu %.6e\n", mib, 3.0 * (double)n * sizeof(double) / best);
    free(a);
    free(b);
  }
  return 0;
}
