#!/usr/bin/env python3
"""The weak-scaling model of docs/PERFORMANCE.md ("Distributed meshes: the command line on 1, 2
and 4 ranks, and a weak-scaling model"): one conjugate-gradient iteration of the distributed
biharmonic (a W-cycle of the distributed multigrid) at P ranks of n fine vertices each, from the
levels and halo values that `scripts/bench-ranks.sh` measured.

    scripts/ranks-model.py OUT/ranks.csv [CASE]

CASE (default box-hex-3d) names the rows to read: its 2-rank biharmonic row gives the levels'
coarsening ratios, the halo values per unknown of a cut face and the iterations of a solve; the
rest is read from the code (degrees, visits, exchanges per smoothing step, the agglomeration rule)
and printed with the projection at 1 000 and 10 000 ranks of 50k, 100k and 200k vertices.
"""
import csv
import math
import sys

# The biharmonic's smoothing degrees (finest level, coarse levels): 8 on every level without
# lines, the serial degrees under wall layers in 3D (the graded sphere's lines).
DEGREES = {"box-hex-3d": (8, 8), "graded-sphere-3d": (10, 16)}
VISITS = 2  # W-cycle: two visits of every coarse level but a gathered one
PER_RANK = 200  # a level with fewer unknowns per rank moves onto halved ranks
GATHER = 400  # a level of at most this many unknowns is the coarsest, gathered on one rank
NEIGHBOURS = 26  # partners of a part in a 3D arrangement of parts
T_VERTEX = 2.0e-6  # s per fine vertex and iteration on one core, all levels (serial bench)


def measured(path, case):
    """The 2-rank biharmonic row: levels (unknowns), halo values per exchange and iterations (of
    the moving component, the largest of the components' counts)."""
    with open(path) as f:
        for row in csv.DictReader(f):
            if row["case"] == case and row["method"] == "Biharmonic" and row["ranks"] == "2":
                levels = [int(v) for v in row["level_unknowns"].split(";")]
                halo = [int(v) for v in row["level_halo_values"].split(";")]
                iterations = max(int(v) for v in row["iterations"].split(";"))
                return int(row["vertices"]), levels, halo, iterations
    sys.exit(f"no 2-rank biharmonic row of {case} in {path}")


def hierarchy(n_fine, ratios, ranks):
    """Unknowns and ranks per level: coarsened by the measured ratios (the last repeated) down
    to the first level of at most GATHER unknowns; each level on the ranks the rule leaves."""
    sizes, holders = [], []
    size, held = n_fine * ratios[0], ranks
    k = 1
    while True:
        while held > 1 and size / held < PER_RANK:
            held = math.ceil(held / 2)
        if size <= GATHER:
            held = 1
        sizes.append(size)
        holders.append(held)
        if size <= GATHER:
            return sizes, holders
        size *= ratios[min(k, len(ratios) - 1)]
        k += 1


def model(n, ranks, ratios, faces, alpha, beta, degrees, v_moved=False):
    """Per level: (unknowns per rank, ranks, cycles, exchanges, compute s, communication s);
    `v_moved`: the levels moved onto fewer ranks visited once (a V-cycle below the W)."""
    sizes, holders = hierarchy(n * ranks, ratios, ranks)
    depth = len(sizes)
    cycles = [1]
    for l in range(1, depth):
        once = l == depth - 1 or (v_moved and holders[l] < ranks)
        cycles.append(cycles[-1] * (1 if once else VISITS))
    # one cycle of a smoothed level: d-1 + 1 (residual) + d exchanges of its own; the level
    # above adds 2 of this level's layout per its cycle (restriction's sum, prolongation's
    # refresh), a second visit one residual; the finest adds the PCG's K V⁻¹ K (2).
    rows = []
    for l in range(depth):
        u = sizes[l] / holders[l]
        if l == depth - 1:
            exchanges = 0
        else:
            exchanges = cycles[l] * 2 * degrees[min(l, 1)] + (cycles[l] - (cycles[l - 1] if l else 1))
        if l == 0:
            exchanges += 2
        if l:
            exchanges += 2 * cycles[l - 1]
        parts = holders[l]
        m = min(NEIGHBOURS, parts - 1)
        face = faces[min(l, len(faces) - 1)]
        h = min(6 * face * u ** (2 / 3), 3 * u) if parts > 1 else 0
        comm = exchanges * (alpha * m + 8 * h / beta)
        if l == depth - 1 or (l and holders[l] < holders[l - 1]):
            # a moved or gathered level: each sender's message to its receiving rank, which
            # takes them one after another, and the answers back, per cycle of the level above
            senders = holders[l - 1] / holders[l]
            comm += 2 * cycles[l - 1] * (alpha * senders + 8 * u / beta)
        rows.append([u, parts, cycles[l], exchanges, cycles[l] * u, comm])
    return rows


def main():
    path = sys.argv[1]
    case = sys.argv[2] if len(sys.argv) > 2 else "box-hex-3d"
    vertices, levels, halo, iterations = measured(path, case)
    degrees = DEGREES.get(case, DEGREES["box-hex-3d"])
    ratios = [levels[0] / vertices] + [levels[i + 1] / levels[i] for i in range(len(levels) - 2)]
    # values per unknown of the cut face: both ranks' sends over 2 N_l^(2/3)
    faces = [h / (2 * s ** (2 / 3)) for h, s in zip(halo[:-1], levels[:-1])]
    print(f"{case}: ratios {', '.join(f'{r:.3f}' for r in ratios)}; "
          f"halo values per face unknown {', '.join(f'{f:.2f}' for f in faces)}")
    # the time per unknown-cycle from one rank of the measured size
    one = model(vertices, 1, ratios, faces, 0.0, 1.0, degrees)
    t_u = T_VERTEX * vertices / sum(r[4] for r in one)
    print("| ranks | vertices per rank | levels | ranks per level | latency exceeds work from level | "
          f"compute ms | latency ms | bandwidth ms | ms / iteration | s per solve ({iterations} iterations) | "
          "finest level's share |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for ranks in (1, 1000, 10000):
        for n in (50_000, 100_000, 200_000):
            for alpha, beta in ((1.5e-6, 10e9),):
                rows = model(n, ranks, ratios, faces, alpha, beta, degrees)
                lat = model(n, ranks, ratios, faces, alpha, math.inf, degrees)
                comp = [r[4] * t_u for r in rows]
                latency = [r[5] for r in lat]
                comm = [r[5] for r in rows]
                first = next((l for l in range(len(rows)) if latency[l] > comp[l]), None)
                # the iteration's one collective: an allgather of 3 sums from every rank
                dot = alpha * math.log2(ranks) + 24 * ranks / beta if ranks > 1 else 0.0
                comm.append(dot)
                latency.append(alpha * math.log2(ranks) if ranks > 1 else 0.0)
                total = sum(comp) + sum(comm)
                print(f"| {ranks} | {n // 1000}k | {len(rows)} | {', '.join(str(r[1]) for r in rows)} | "
                      f"{'—' if first is None else first} | {1e3 * sum(comp):.1f} | {1e3 * sum(latency):.1f} | "
                      f"{1e3 * (sum(comm) - sum(latency)):.1f} | {1e3 * total:.1f} | "
                      f"{iterations * total:.2f} | {100 * (comp[0] + comm[0]) / total:.0f} % |")
    print()
    print("Per level at 10 000 ranks of 100k vertices (alpha 1.5 us, beta 10 GB/s):")
    print("| level | unknowns per rank | ranks | cycles | exchanges | messages per exchange per rank | "
          "compute ms | communication ms |")
    print("|---|---|---|---|---|---|---|---|")
    rows = model(100_000, 10000, ratios, faces, 1.5e-6, 10e9, degrees)
    for l, r in enumerate(rows):
        print(f"| {l} | {r[0]:.0f} | {r[1]} | {r[2]} | {r[3]} | {min(NEIGHBOURS, r[1] - 1)} | "
              f"{1e3 * r[4] * t_u:.2f} | {1e3 * r[5]:.2f} |")
    print()
    print("The moved levels visited once (W-cycle on the levels every rank holds, V below), "
          "alpha 1.5 us, beta 10 GB/s, at the same iterations:")
    for ranks in (1000, 10000):
        for n in (50_000, 100_000, 200_000):
            rows = model(n, ranks, ratios, faces, 1.5e-6, 10e9, degrees, v_moved=True)
            comp = sum(r[4] for r in rows) * t_u
            comm = sum(r[5] for r in rows)
            print(f"| {ranks} | {n // 1000}k | {1e3 * comp:.1f} | {1e3 * comm:.1f} | {1e3 * (comp + comm):.1f} | "
                  f"{iterations * (comp + comm):.2f} |")
    print()
    for alpha, beta in ((1e-6, 25e9), (2e-6, 10e9)):
        for ranks in (1000, 10000):
            rows = model(100_000, ranks, ratios, faces, alpha, beta, degrees)
            total = sum(r[4] * t_u + r[5] for r in rows)
            print(f"alpha {alpha * 1e6:.0f} us, beta {beta / 1e9:.0f} GB/s, {ranks} ranks of 100k: "
                  f"{1e3 * total:.1f} ms / iteration, communication {1e3 * sum(r[5] for r in rows):.1f} ms")


if __name__ == "__main__":
    main()
