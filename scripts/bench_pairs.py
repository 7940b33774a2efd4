"""The quadrants' speed against PyClaw's, from runs taken in pairs (scripts/bench).

    python scripts/bench_pairs.py [--sizes 256,512] [--pairs 4] [--efficiency]

For each size, --pairs times in turn: the peer (Clawpack PyClaw's
quadrants, Fortran kernels, second order, dimensional splitting, to t = 0.2,
1 core: scripts/peer_pyclaw), then plyshock (scripts/bench_cells.py, 1
rank, 100 steps at 256^2 and 40 at larger sizes after its 5 steps of
warm-up, as scripts/bench runs it) on the quadrants as one gas, as PyClaw
runs them (-bench_case quadrants1), then on the quadrants with a gas
material per quadrant (-bench_case quadrants: material interfaces at the
quadrants' edges, which PyClaw does not track), each set against the same
PyClaw run; each side the best of two runs in one process (a single run of the peer is its process's first, about 9%
slower at 256^2 here than its second, where plyshock's is warmed up); the
ratio of plyshock's rate to the peer's in each pair, and their median.  The main rows of scripts/bench
take each side's best of several runs minutes apart, so a disturbance of
this VM that lasts through one side's runs moves the ratio (on the same
code the thirty-fifth session's two bench runs read 1.68 and 1.91 at
256^2, plyshock's rate 17% apart, the peer's 2.5%); the median of the pairs
moves only when a disturbance lasts through half of them.

Prints each pair and the median, and the lines
    BENCH cells_pairs1_<n> <median ratio>  (one gas; cells_pairs_<n>: a material per quadrant)
    BENCH cells_pairs1_lo_<n> <lowest ratio>, BENCH cells_pairs1_hi_<n> <highest>
    BENCH cells_pairs1_k_<n> <pairs>
for scripts/bench_table.py.  Cell-updates per second per core; the ratios
are plyshock's rate over PyClaw's.  Where the peer cannot run (its venv
cannot be made), it says so and prints no BENCH line.

With --efficiency the pairs are plyshock's own: a run on 1 rank, then one
on 2 ranks (the same bench_cells.py runs), and the ratio is the 2-rank
rate per core over the 1-rank rate, the two-rank efficiency, against the
same disturbances as the ratios above (scripts/bench's main rows take the
two runs seconds apart, once); its lines are BENCH cells_effpairs_<n>,
cells_effpairs_lo_<n>, cells_effpairs_hi_<n> and cells_effpairs_k_<n>.
Each pair takes a third run, right after: the 2 ranks apart (bench_cells.py
-bench_apart: each rank its slab of the grid as a run of its own, the
machine shared but nothing exchanged and no rank waiting for the other),
whose rate per core over the 1-rank rate is the ceiling the machine sets the
two-rank efficiency (the shared L3 and memory, and the slabs' own work); the
efficiency over it is what the ranks' coupling keeps (halos, waits, the
phases a rank with a neighbour runs apart): BENCH cells_ceilpairs_<n> and
cells_couplepairs_<n>, each with its _lo_, _hi_ and _k_.  These are the
quadrants with a material per quadrant; each pair then takes the one gas's
1-rank and 2-rank runs too: BENCH cells_effpairs1_<n> (and _lo_, _hi_, _k_).
"""
import argparse
import os
import re
import statistics
import subprocess
import sys

from bench_table import PYCLAW_ROW  # (scripts/bench_table.py: the peer's rows)

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def sizes_arg(text):
    try:
        sizes = [int(s) for s in text.split(",") if s.strip()]
    except ValueError:
        raise argparse.ArgumentTypeError(f"a comma-separated list of grid sizes >= 16, got {text!r}")
    if not sizes or min(sizes) < 16:
        raise argparse.ArgumentTypeError(f"a comma-separated list of grid sizes >= 16, got {text!r}")
    return sizes


def pairs_arg(text):
    try:
        k = int(text)
    except ValueError:
        k = 0
    if k < 1:
        raise argparse.ArgumentTypeError(f"an integer >= 1, got {text!r}")
    return k


def run(cmd):
    """stdout of cmd, run in the repository (its stderr passed through)."""
    return subprocess.run(cmd, cwd=ROOT, stdout=subprocess.PIPE, text=True, check=False).stdout


def peer_rate(n):
    """PyClaw's rate (cell-updates/s) at n^2, the best of two runs in one process, or None where the peer did not run."""
    out = run(["bash", "scripts/peer_pyclaw", "--variants", "roe_split", "--sizes2d", str(n), "--sizes1d", "", "--reps", "2", "--tfinal2d", "0.2"])
    for line in out.splitlines():
        m = PYCLAW_ROW.match(line)
        if m and int(m.group(1)) == n:
            return float(m.group(3)) * 1e6
    print("\n".join(line for line in out.splitlines() if "peer_pyclaw" in line) or f"bench_pairs.py: no PyClaw row for {n}^2 in the peer's output")
    return None


def plyshock_rate(n, ranks=1, apart=False, case="quadrants"):
    """plyshock's rate (cell-updates/s per core) for the quadrants at n^2 on `ranks` ranks, the best of two runs in one process
    (apart: each rank its slab alone, bench_cells.py -bench_apart; case quadrants1: one gas)."""
    steps = 100 if n <= 256 else 40
    out = run(["mpiexec", "-n", str(ranks), os.path.join(ROOT, ".venv", "bin", "python"), "scripts/bench_cells.py", "-bench_case", case,
               "-bench_n", str(n), "-bench_steps", str(steps), "-bench_reps", "2"] + (["-bench_apart"] if apart else []))
    tag = ("apart1" if case == "quadrants1" else "apart") if apart else case  # (bench_cells.py's BENCH lines' name)
    m = re.search(rf"^BENCH cells_{tag}_{n}_{ranks} (\S+)$", out, re.M)
    if not m:
        sys.exit(f"bench_pairs.py: bench_cells.py printed no rate for {n}^2:\n{out}")
    return float(m.group(1))


def report(key, n, what, values):
    """The median and range of one size's pairs, and their BENCH lines cells_<key>_<n> (the median), _lo_, _hi_ and _k_."""
    med = statistics.median(values)
    print(f"  median {what} {med:.3f} (range {min(values):.3f}-{max(values):.3f})")
    print(f"BENCH cells_{key}_{n} {med:.6e}")
    print(f"BENCH cells_{key}_lo_{n} {min(values):.6e}")
    print(f"BENCH cells_{key}_hi_{n} {max(values):.6e}")
    print(f"BENCH cells_{key}_k_{n} {len(values)}", flush=True)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--sizes", type=sizes_arg, default=[256, 512], help="grid sizes n (n^2 cells), comma-separated (default 256,512)")
    ap.add_argument("--pairs", type=pairs_arg, default=4, help="pairs per size, >= 1 (default 4)")
    ap.add_argument("--efficiency", action="store_true", help="pairs of plyshock on 1 rank, then on 2: the two-rank efficiency")
    args = ap.parse_args()
    if args.efficiency:
        for n in args.sizes:
            print(f"quadrants {n}^2, 2 ranks against 1, in {args.pairs} pair{'s' if args.pairs != 1 else ''} (1 rank's run, then 2 ranks', then 2 ranks apart)", flush=True)
            effs, ceils, couples, effs1 = [], [], [], []
            for i in range(args.pairs):
                r1, r2, ra = plyshock_rate(n, 1), plyshock_rate(n, 2), plyshock_rate(n, 2, apart=True)
                g1, g2 = plyshock_rate(n, 1, case="quadrants1"), plyshock_rate(n, 2, case="quadrants1")
                effs.append(r2 / r1)
                ceils.append(ra / r1)
                couples.append(r2 / ra)
                effs1.append(g2 / g1)
                print(f"  pair {i + 1}: 1 rank {r1 / 1e6:.3f} M/s, 2 ranks {r2 / 1e6:.3f} M/s per core, efficiency {r2 / r1:.3f}; "
                      f"apart {ra / 1e6:.3f} M/s per core, ceiling {ra / r1:.3f}, coupling {r2 / ra:.3f}; "
                      f"one gas 1 rank {g1 / 1e6:.3f} M/s, 2 ranks {g2 / 1e6:.3f} M/s per core, efficiency {g2 / g1:.3f}", flush=True)
            report("effpairs", n, "efficiency", effs)
            report("ceilpairs", n, "ceiling (2 ranks apart against 1)", ceils)
            report("couplepairs", n, "coupling (2 ranks against 2 apart)", couples)
            report("effpairs1", n, "efficiency, one gas", effs1)
        return
    for n in args.sizes:
        print(f"quadrants {n}^2 against PyClaw, in {args.pairs} pair{'s' if args.pairs != 1 else ''} (PyClaw's runs, then plyshock's: one gas, then a material per quadrant; 1 core each)", flush=True)
        ratios, ratios1 = [], []
        for i in range(args.pairs):
            rp = peer_rate(n)
            if rp is None:
                return
            rg = plyshock_rate(n, case="quadrants1")
            rc = plyshock_rate(n)
            ratios1.append(rg / rp)
            ratios.append(rc / rp)
            print(f"  pair {i + 1}: PyClaw {rp / 1e6:.3f} M/s, plyshock one gas {rg / 1e6:.3f} M/s, ratio {rg / rp:.3f}; "
                  f"a material per quadrant {rc / 1e6:.3f} M/s, ratio {rc / rp:.3f}", flush=True)
        report("pairs1", n, "ratio, one gas", ratios1)
        report("pairs", n, "ratio, a material per quadrant", ratios)


if __name__ == "__main__":
    main()
