#!/usr/bin/env python3
"""The scaling model of docs/mpi.md: the time of a step of mpi::DistributedRun on P ranks from
figures measured on one machine (docs/performance.md, "Over MPI ranks"), printed as the
document's tables. Plain Python, no modules:

    python3 scripts/mpi_scaling_model.py

A rank's step, with n = N / P particles on a cubic (square in 2D) subdomain:

    T(n, P) = t_p n (1 + g) + b * ghosts / beta + (messages + log2 P) * alpha

- t_p: the serial engine's time per particle-step (one rank, measured);
- g = ghosts / n: a ghost costs what an owned particle costs (its pairs with the owned particles
  are computed on both ranks, it is integrated and its record copied);
- ghosts: the particle layers within the halo (contact range plus skin, `layers` particle
  spacings, measured from the ghost count of two ranks) around the subdomain on the split axes;
- b bytes per ghost and step (one refresh of its motion: 40 in 2D, 72 in 3D), at bandwidth beta; 2 messages per split axis per
  step and one MPI_Allreduce (the largest move) of log2 P latencies alpha;
- redistributions (every tens of steps, about one halo build each) and load imbalance left out.
"""
import math

# Measured on the 2-core AMD EPYC of docs/performance.md (one rank = the serial engine).
T_P = {2: 1 / 3.93e7, 3: 1 / 1.90e7}   # s per particle-step: 2D N = 200 000, 3D N = 100 000 lattices
LAYERS = {2: 1.0, 3: 1.26}              # halo depth in particle layers: 2 ranks held 894 and 5 350 ghosts
RECORD = {2: 40.0, 3: 72.0}             # bytes per ghost per refresh (mpi::Motion)
# Fitted to the two-rank runs: 3D spent 0.12 ms per step beyond its ghosts' compute while sending
# 555 kB (in 104-byte records, before a refresh sent the motion only), so about 5 GB/s between the
# two ranks of this machine (shared memory).
BETA_NODE = 5e9
# Assumptions for a cluster (not measured here): InfiniBand HDR-class links.
ALPHA = 2e-6                            # s per message
BETA = 10e9                             # bytes/s per rank pair


def split(P, dim):
    """MPI_Dims_create's near-cubic split of P ranks."""
    dims = [1] * dim
    f, rest = 2, P
    factors = []
    while rest > 1:
        while rest % f == 0:
            factors.append(f)
            rest //= f
        f += 1
    for f in sorted(factors, reverse=True):
        dims[dims.index(min(dims))] *= f
    return sorted(dims, reverse=True)


def step_time(N, P, dim, beta=BETA, alpha=ALPHA):
    n = N / P
    dims = split(P, dim)
    side = (N ** (1 / dim))              # particles per box side
    sub = [side / d for d in dims]       # particles per subdomain side
    grown = 1.0
    for a in range(dim):
        grown *= sub[a] + (2 * LAYERS[dim] if dims[a] > 1 else 0.0)
    ghosts = max(0.0, grown - n)  # zero on one rank (rounding aside)
    split_axes = sum(1 for d in dims if d > 1)
    compute = T_P[dim] * (n + ghosts)
    comm = RECORD[dim] * ghosts / beta + (2 * split_axes + (math.log2(P) if P > 1 else 0)) * alpha
    return compute + comm, ghosts / n, comm


def row(N, P, dim, T1):
    T, g, comm = step_time(N, P, dim)
    speedup = T1 / T
    return f"| {P} | {'x'.join(map(str, split(P, dim)))} | {N / P:.3g} | {g:.3f} | {comm / T:.3f} | {speedup:.3g} | {speedup / P:.2f} |"


def main():
    head = "| ranks | split | particles per rank | ghosts per particle | share of the step in messages | speed-up | efficiency |\n|---|---|---|---|---|---|---|"
    print("Check against the two-rank runs of this machine (beta = 5 GB/s, alpha = 2 us):")
    for dim, N, measured in ((2, 200_000, "1.95-1.96x"), (3, 100_000, "1.73-1.76x")):
        T1 = step_time(N, 1, dim, BETA_NODE)[0]
        T2 = step_time(N, 2, dim, BETA_NODE)[0]
        print(f"- {dim}D N = {N}: model {T1 / T2:.2f}x, measured {measured}")
    for title, dim, N in (("Strong scaling, 3D, N = 1e6", 3, 10**6), ("Strong scaling, 3D, N = 1e8", 3, 10**8),
                          ("Strong scaling, 2D, N = 1e6", 2, 10**6)):
        print(f"\n{title}:\n\n{head}")
        T1 = step_time(N, 1, dim)[0]
        for P in (1, 8, 64, 1024):
            print(row(N, P, dim, T1))
    for dim, n in ((3, 100_000), (2, 100_000)):
        print(f"\nWeak scaling, {dim}D, {n} particles per rank (efficiency = one rank's step / P ranks' step):\n")
        print("| ranks | split | particles | ghosts per particle | share of the step in messages | efficiency |\n|---|---|---|---|---|---|")
        T1 = step_time(n, 1, dim)[0]
        for P in (1, 8, 64, 1024):
            T, g, comm = step_time(n * P, P, dim)
            print(f"| {P} | {'x'.join(map(str, split(P, dim)))} | {n * P:.3g} | {g:.3f} | {comm / T:.3f} | {T1 / T:.2f} |")


if __name__ == "__main__":
    main()
