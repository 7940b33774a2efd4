"""The table scripts/bench ends with: every speed figure of one bench run as a
ratio to its reference, beside the goal the issues set.

    python3 scripts/bench_table.py out/bench.log

Reads the lines `BENCH <key> <value>` the bench scripts print (rates in units
per second; marker-steps, pieces or cell-updates) and the peers' rows (Taichi:
`PEER taichi_<threads> <rate>`; PyClaw: its own table, parsed here).  A figure
whose run did not happen (a peer that could not be installed) is shown as "-".
References measured in the same script are marked "same run"; the two quoted
constants (r3d's clipping rate and Karamelo's Taylor bar) are marked "quoted".
"""
import re
import sys

# PyClaw's rows: "2D quadrants roe_split 256x256 t=0.8  cells steps wall_med rate_med min..max ..."
# (n, steps, the best rate in M/s); bench_pairs.py reads its runs with it too
PYCLAW_ROW = re.compile(r"\s*2D quadrants roe_split (\d+)x\d+ t=\S+\s+\d+\s+(\d+)\s+\S+\s+\S+\s+\S+\.\.(\S+)")
# the cells' Lagrangian phases by their log events, as bench_cells.py prints
# them (a scene of cells alone runs the Lagrangian phase a unit behind the
# predictor, inside its event; PSCellsLagrange keeps the units after the halo)
# (on one rank, and on ranks split along y (z) alone, a scene of cells alone
# runs the first three as one pipeline of units, PSCellsPipeline: their
# events read 0 there, the pipeline's the sum;
# the table's rows leave out a phase that reads 0)
CELL_PHASES = [("P2G", "PSCellsP2G"), ("grid", "PSGridUpdate"), ("predictor+Lagrange", "PSCellsPredict"), ("Lagrange's rest", "PSCellsLagrange"),
               ("pipelined P2G+grid+predictor+Lagrange", "PSCellsPipeline")]
R3D = 1.4e6                         # r3d: a box clipped by a slab, first moments, pieces/s/core (quoted)
KARAMELO = {1: 0.50e6, 2: 0.87e6}   # Karamelo's copper Taylor bar, marker-steps/s on 1 and 2 ranks (quoted)


def read(path):
    b = {}
    for line in open(path, errors="replace"):
        f = line.split()
        if len(f) == 3 and f[0] in ("BENCH", "PEER"):
            b[f[1]] = float(f[2])
        # PyClaw's rows (PYCLAW_ROW): the best of its runs (max) over every
        # table (scripts/bench runs it before and after the quadrants), as
        # bench_cells.py reports its own best
        m = PYCLAW_ROW.match(line)
        if m:
            b[f"pyclaw_{m.group(1)}"] = max(b.get(f"pyclaw_{m.group(1)}", 0.0), float(m.group(3)) * 1e6)
            b[f"pyclaw_steps_{m.group(1)}"] = float(m.group(2))
    return b


def main():
    b = read(sys.argv[1])
    rows = []

    def row(what, key, ref, refname, goal=None, unit="M/s", scale=1e-6, per=1):
        v = b.get(key)
        r = b.get(ref) if isinstance(ref, str) else ref
        val = f"{v * scale / per:.3g} {unit}" if v is not None else "-"
        ratio = f"{v / per / r:.2f}" if (v is not None and r) else "-"
        ok = "" if goal is None or ratio == "-" else ("yes" if float(ratio) >= goal else "no")
        rows.append((what, val, refname, ratio, f">= {goal:g}" if goal is not None else "", ok))

    # the default shock path (musl/gimp) and the others, elastic block 64^3, 74k markers, 1 core
    row("elastic block, default musl/gimp, 1 rank", "block_musl_1", "block_apic_1", "apic, same run", 0.7)
    row("elastic block, default musl/gimp, 1 rank", "block_musl_1", "taichi_1", "Taichi 1 thread, same run", 3.0)
    row("elastic block, musl/bspline2, 1 rank", "block_musl_bspline2_1", "block_apic_1", "apic, same run")
    row("elastic block, apic, 1 rank", "block_apic_1", "taichi_1", "Taichi 1 thread, same run", 2.0)
    row("elastic block, default, 2 ranks (per core)", "block_musl_2", "block_musl_1", "1 rank, same run: efficiency")
    row("elastic block, apic, 2 ranks (per core)", "block_apic_2", "block_apic_1", "1 rank, same run: efficiency")
    # the Taylor bar with full shock physics, default path
    row("Taylor bar, default musl/gimp, 1 rank", "taylor_gimp_1", KARAMELO[1], "Karamelo 0.50 M/s, quoted", 2.0)
    row("Taylor bar, default musl/gimp, 2 ranks", "taylor_gimp_2", KARAMELO[2], "Karamelo 0.87 M/s, quoted", 2.0)
    if "taylor_gimp_1" in b and "taylor_gimp_2" in b:
        b["taylor_gimp_2_core"] = b["taylor_gimp_2"] / 2
    row("Taylor bar, 2 ranks (per core)", "taylor_gimp_2_core", "taylor_gimp_1", "1 rank, same run: efficiency")
    # exact insertion, end to end (clipping + DMSwarm fill)
    row("insertion end to end, 1 rank (per core)", "insert_1", R3D, "r3d 1.4 M/s, quoted", 2.0)
    row("insertion end to end, 2 ranks (per core)", "insert_2", R3D, "r3d 1.4 M/s, quoted", 2.0)
    row("geometry kernel alone, 1 core", "insert_kernel_1", R3D, "r3d 1.4 M/s, quoted")
    # the Eulerian cells
    def pairs_row(label, key, ref, goal):
        """A row of bench_pairs.py's median over its pairs (BENCH cells_<key>, its _lo_, _hi_ and _k_ beside it)."""
        tag, n = key.rsplit("_", 1)
        if f"cells_{key}" not in b:
            return
        med, lo, hi, k = (b.get(f"cells_{tag}{s}_{n}", 0.0) for s in ("", "_lo", "_hi", "_k"))
        rows.append((label, f"{k:.0f} pairs", f"{ref}, range {lo:.2f}-{hi:.2f}", f"{med:.2f}", f">= {goal:g}" if goal else "", ("yes" if med >= goal else "no") if goal else ""))

    for n in (256, 512):
        # the quadrants as PyClaw runs them, one gas (each quadrant a body at
        # its own density): the goal's rows
        row(f"cells, quadrants (one gas) {n}^2, 1 rank", f"cells_quadrants1_{n}_1", f"pyclaw_{n}", "PyClaw 1 core, same run, best of 4 around it", 2.0)
        # the same ratio from runs taken in pairs (bench_pairs.py): their median
        pairs_row(f"cells, quadrants (one gas) {n}^2, 1 rank, in pairs with PyClaw", f"pairs1_{n}", "PyClaw 1 core right before each, same run: median of the ratios", 2.0)
        row(f"cells, quadrants (one gas) {n}^2, 2 ranks (per core)", f"cells_quadrants1_{n}_2", f"cells_quadrants1_{n}_1", "1 rank, same run: efficiency", 0.85)
        # the same efficiency from runs taken in pairs (bench_pairs.py --efficiency)
        pairs_row(f"cells, quadrants (one gas) {n}^2, 2 ranks (per core), in pairs with 1 rank", f"effpairs1_{n}", "1 rank right before each, same run: median of the efficiencies", 0.85)
        # the quadrants with a gas material per quadrant: material interfaces
        # at their edges (Youngs' PLIC, mixed cells), which PyClaw's one fluid
        # does not have (the goal's rows through the forty-fifth session, before
        # the body key `density` let one gas hold the four states)
        row(f"cells, quadrants (a material each) {n}^2, 1 rank", f"cells_quadrants_{n}_1", f"pyclaw_{n}", "PyClaw 1 core, same run, best of 4 around it")
        pairs_row(f"cells, quadrants (a material each) {n}^2, 1 rank, in pairs with PyClaw", f"pairs_{n}", "PyClaw 1 core right before each, same run: median of the ratios", None)
        row(f"cells, quadrants (a material each) {n}^2, 2 ranks (per core)", f"cells_quadrants_{n}_2", f"cells_quadrants_{n}_1", "1 rank, same run: efficiency")
        pairs_row(f"cells, quadrants (a material each) {n}^2, 2 ranks (per core), in pairs with 1 rank", f"effpairs_{n}", "1 rank right before each, same run: median of the efficiencies", None)
        # the same pairs' third run, the 2 ranks apart (each its slab alone, the
        # machine shared): the ceiling the machine sets, and what the coupling keeps
        pairs_row(f"cells, quadrants (a material each) {n}^2, 2 ranks apart (per core: each its slab alone), in the same pairs", f"ceilpairs_{n}", "1 rank, same pair: median (the machine's ceiling for the efficiency)", None)
        pairs_row(f"cells, quadrants (a material each) {n}^2, 2 ranks against 2 apart, in the same pairs", f"couplepairs_{n}", "2 ranks apart, same pair: median (what the coupling keeps)", None)
        # one gas in uniform flow, in the same bracket (no goal of its own: the
        # goal is the quadrants'; this says what their waves cost)
        row(f"cells, one gas in uniform flow {n}^2, 1 rank", f"cells_pure_{n}_1", f"pyclaw_{n}", "PyClaw's quadrants 1 core, same run, best of 4 around it")
    # the in-cache rate (128^2: the arrays, about 10 MB, sit in the caches), the ceiling of any reordering of the passes
    row("cells, quadrants (a material each) 128^2 (in cache), 1 rank", "cells_quadrants_128_1", "pyclaw_256", "PyClaw 256^2 1 core, same run, best of 4")
    row("cells, quadrants (a material each) 512^2 against 128^2 (in cache), 1 rank", "cells_quadrants_512_1", "cells_quadrants_128_1", "128^2, same run: what the caches cost")
    # what the quadrants' arrays hold (bench_cells.py: the resident growth over
    # setup and warm-up): beside the caches, what 512^2 against 128^2 costs
    for n in (128, 256, 512):
        k = f"cells_bytes_per_cell_quadrants_{n}_1"
        if k in b:
            rows.append((f"cells, quadrants (a material each) {n}^2, 1 rank: resident bytes per cell", f"{b[k]:.0f} B, {b[k] * n * n / 2**20:.0f} MiB",
                         "process's growth over setup and warm-up", "", "", ""))
    # a pass of the step's kind (scripts/pass_curve.c) over the smallest power
    # of two of MiB that holds each size's state: where 512^2 leaves the fast range
    def pass_rate(n):
        k = f"cells_bytes_per_cell_quadrants_{n}_1"
        if k not in b:
            return None, None
        mib = 1
        while mib < b[k] * n * n / 2**20 and mib < 512:
            mib *= 2
        return mib, b.get(f"pass_gbs_{mib}")
    (m2, r2), (m5, r5) = pass_rate(256), pass_rate(512)
    if r2 and r5:
        rows.append(("a pass of the step's kind over the 512^2 quadrants' state, 1 core", f"{r5 / 1e9:.3g} GB/s over {m5} MiB",
                     f"over the 256^2's, same run: {r2 / 1e9:.3g} GB/s over {m2} MiB", f"{r5 / r2:.2f}", "", ""))
    # the in-cache step's phases (a material per quadrant) against the time per
    # cell-update 2x PyClaw leaves (no goal of its own: a diagnosis)
    ph = CELL_PHASES + [("remap", "PSCellsRemap")]
    keys = [f"cells_phase_ns_{ev}_quadrants_128_1" for _, ev in ph]
    if all(k in b for k in keys) and "pyclaw_256" in b:
        budget = 1e9 / (2.0 * b["pyclaw_256"])
        tot = sum(b[k] for k in keys)
        rows.append(("cells, quadrants (a material each) 128^2, ns per cell-update: " + ", ".join(f"{lab} {b[k]:.0f}" for (lab, _), k in zip(ph, keys) if b[k] != 0.0),
                     f"{tot:.0f} ns (the phases)", f"2x PyClaw 256^2 leaves {budget:.0f} ns", f"{budget / tot:.2f}", "", ""))
    for n in (256,):
        if f"cells_mixed_{n}_1" in b and f"cells_pure_{n}_1" in b:
            b[f"cells_mixed_cost_{n}"] = b[f"cells_pure_{n}_1"] / b[f"cells_mixed_{n}_1"]
        rows.append((f"cells, mixed cell against pure ({n}^2, 1 rank)",
                     f"{b[f'cells_pure_{n}_1'] / 1e6:.3g} / {b[f'cells_mixed_{n}_1'] / 1e6:.3g} M/s" if f"cells_mixed_cost_{n}" in b else "-",
                     "cost ratio mixed / pure", f"{b[f'cells_mixed_cost_{n}']:.2f}" if f"cells_mixed_cost_{n}" in b else "-", "", ""))
    # the pure case's flux phase against the same scheme's sweep stripped of generality (sweep_floor.c)
    if "cells_flux_ns_pure_256_1" in b and "sweep_floor_ns_256" in b:
        rows.append(("cells, remap flux phase, pure gas 256^2, 1 rank", f"{b['cells_flux_ns_pure_256_1']:.3g} ns/cell/sweep",
                     f"stripped one-gas sweep in SIMD passes, same run: {b['sweep_floor_ns_256']:.3g} ns"
                     + (f" (one pass {b['sweep_floor_onepass_ns_256']:.3g}, interleaved {b['sweep_floor_interleaved_ns_256']:.3g})" if "sweep_floor_interleaved_ns_256" in b else ""), f"{b['cells_flux_ns_pure_256_1'] / b['sweep_floor_ns_256']:.2f}", "", ""))
    # the pure case's Lagrangian phases against the same arithmetic stripped of generality (lagrange_floor.c)
    # (the floor's phases, each beside plyshock's event: CELL_PHASES)
    floor = [("P2G", "p2g"), ("grid", "grid"), ("predictor", "predictor"), ("Lagrange", "lagrange")]
    keys = [f"cells_phase_ns_{ev}_pure_256_1" for _, ev in CELL_PHASES]
    if all(k in b for k in keys) and "lagrange_floor_ns_256" in b:
        tot = sum(b[k] for k in keys)
        rows.append(("cells, Lagrangian phases, pure gas 256^2, 1 rank, ns per cell-update: " + ", ".join(f"{lab} {b[k]:.3g}" for (lab, _), k in zip(CELL_PHASES, keys) if b[k] != 0.0),
                     f"{tot:.3g} ns", "stripped one-gas phases in SIMD passes, same run: " + ", ".join(f"{lab} {b[f'lagrange_floor_{fk}_ns_256']:.3g}" for lab, fk in floor)
                     + f" = {b['lagrange_floor_ns_256']:.3g} ns (one pass {b['lagrange_floor_onepass_ns_256']:.3g}"
                     + (f", interleaved {b['lagrange_floor_interleaved_ns_256']:.3g})" if "lagrange_floor_interleaved_ns_256" in b else ")"), f"{tot / b['lagrange_floor_ns_256']:.2f}", "", ""))
    # the same step counted in instructions (scripts/bench_instructions): no ratio, a figure that does not move with the machine's load
    if "cells_instructions_quadrants_128" in b:
        rows.append(("cells, quadrants (a material each) 128^2, 1 rank: instructions per cell-update", f"{b['cells_instructions_quadrants_128']:.0f}",
                     "valgrind callgrind, the same on every run", "", "", ""))
    # what the quadrants' four materials and their interfaces cost, without their
    # waves: the pure case's flow with four gases in the quadrants' boxes, and in
    # columns (three interfaces across every row), against one gas, in time (same
    # run) and in instructions (valgrind): the time's ratio above the
    # instructions' is what the seams between runs of one gas cost beyond their
    # instructions
    for c, lab in (("boxes", "the quadrants' boxes"), ("columns", "four columns")):
        if f"cells_{c}_128_1" in b and "cells_pure_128_1" in b:
            rt = b["cells_pure_128_1"] / b[f"cells_{c}_128_1"]
            ki = f"cells_instructions_{c}_128"
            ri = b[ki] / b["cells_instructions_pure_128"] if ki in b and "cells_instructions_pure_128" in b else None
            rows.append((f"cells, four gases in {lab} against one gas, uniform flow 128^2, 1 rank: time", f"{rt:.2f}x",
                         f"instructions, same run: {ri:.2f}x" if ri else "-", f"{rt / ri:.2f}" if ri else "-", "", ""))
    # time to a solution: the quadrants at 128^2 to t = 0.3 at run.cfl 0.8 against the default 0.4 (scripts/bench_cfl.py)
    if "cfl_wall_0.8_0.4" in b:
        rows.append(("cells, quadrants (a material each) 128^2 to t = 0.3, run.cfl 0.8 against 0.4, 1 rank", f"{b['cfl_wall_0.8_0.4']:.2f}x the wall time",
                     f"density L1 error against 256^2: {b['cfl_err_0.8']:.3g} against {b['cfl_err_0.4']:.3g}", f"{b['cfl_err_0.8'] / b['cfl_err_0.4']:.3f}", "", ""))
    # time to PyClaw's end time t = 0.2 at 256^2 (its best run's time: cells x steps / its best rate), as a speed ratio (> 1: faster)
    for cfl in ("0.4", "0.8"):
        k = f"cfl_t02_wall_256_{cfl}"
        if k in b and "pyclaw_steps_256" in b:
            pw = 256 * 256 * b["pyclaw_steps_256"] / b["pyclaw_256"]
            rows.append((f"cells, quadrants (a material each) 256^2 to t = 0.2, run.cfl {cfl}, 1 rank: time to it", f"{b[k]:.2f} s, {b[f'cfl_t02_steps_256_{cfl}']:.0f} steps",
                         f"PyClaw's best run, same run: {pw:.2f} s, {b['pyclaw_steps_256']:.0f} steps", f"{pw / b[k]:.2f}", "", ""))
    if "nocells_calls" in b:
        rows.append(("elastic block (no cells): cells' phases entered", f"{b['nocells_calls']:.0f} times", "", "", "0", "yes" if b["nocells_calls"] == 0 else "no"))
    # contact (multi-field) against bonded, the oblique plate
    row("oblique plate, contact, 1 rank", "contact_multi_1", "contact_bonded_1", "bonded, same run")
    row("oblique plate, contact, 2 ranks (per core)", "contact_multi_2", "contact_bonded_2", "bonded, same run")
    row("oblique plate, cohesive plies, 1 rank", "contact_cohesive_1", "contact_bonded_1", "bonded, same run")
    row("oblique plate, cohesive plies, 2 ranks (per core)", "contact_cohesive_2", "contact_bonded_2", "bonded, same run")
    # the coupled blast example against the same panel without its cell bodies
    for r in (1, 2):
        if f"blast_seconds_{r}" in b and f"blast_vacuum_seconds_{r}" in b:
            rows.append((f"blast panel example (cells + markers), {r} rank(s)", f"{b[f'blast_seconds_{r}']:.1f} s",
                         f"panel alone (markers only), same run: {b[f'blast_vacuum_seconds_{r}']:.1f} s",
                         f"{b[f'blast_seconds_{r}'] / b[f'blast_vacuum_seconds_{r}']:.2f}", "", ""))

    w = [max(len(r[i]) for r in rows + [("figure", "measured", "reference", "ratio", "goal", "met")]) for i in range(6)]
    head = ("figure", "measured", "reference", "ratio", "goal", "met")
    print("  ".join(h.ljust(w[i]) for i, h in enumerate(head)))
    print("  ".join("-" * w[i] for i in range(6)))
    for r in rows:
        print("  ".join(c.ljust(w[i]) for i, c in enumerate(r)))


if __name__ == "__main__":
    main()
