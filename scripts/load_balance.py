#!/usr/bin/python3
"""Load balance of a Cartesian split over MPI ranks on a biaxial run as its box deforms.

    /usr/bin/python3 scripts/load_balance.py RUN_DIR [RANKS ...]

Reads the particle frames of a `biaxial` run (RUN_DIR/vtk/particles.pvd, written with
--vtk-every) and, for each rank count (default 2 4 8), splits the box into equal slabs per axis as
mpi::DistributedRun does (MPI_Dims_create's counts, the most slabs along the longest axis of the
first frame's extent, of equal ones the last) in three ways:
  fixed:     equal slabs over the particles' extent in the first frame, kept (particles outside
             it belong to the end slabs);
  following: equal slabs over the particles' extent in each frame (what DistributedRun does with
             Split::equal along the axes that walls alone bound, at every redistribution);
  balanced:  in each frame each boundary where an equal share of the particles' centres lies
             below it along its axis (what DistributedRun does by default, Split::balanced, up
             to its histogram's bins).
It prints, per frame, the strain eps_zz and the imbalance max/mean - 1 of the particles per rank,
and the largest imbalance over the run. Needs Debian's python3-vtk9 (hence /usr/bin/python3).
"""
import bisect
import os
import sys
import xml.etree.ElementTree as ET

import vtk


def dims_create(ranks, dim):
    """MPI_Dims_create's balanced split: prime factors, largest first, onto the smallest axis."""
    factors, n, p = [], ranks, 2
    while n > 1:
        while n % p == 0:
            factors.append(p)
            n //= p
        p += 1
    dims = [1] * dim
    for f in sorted(factors, reverse=True):
        dims[dims.index(min(dims))] *= f
    return sorted(dims, reverse=True)


def dims_for(ranks, dim, lo, hi):
    """The slabs per axis mpi::CartesianComm gives the box lo..hi: MPI_Dims_create's counts,
    largest first, onto the axes, longest first (of equal ones, the last)."""
    axes = sorted(range(dim), key=lambda a: (hi[a] - lo[a], a), reverse=True)
    dims = [1] * dim
    for a, d in zip(axes, dims_create(ranks, dim)):
        dims[a] = d
    return dims


def cell_counts(x, dims, slab):
    """Particles per rank: slab(a, coordinate) along each axis, then per cell."""
    total = 1
    for d in dims:
        total *= d
    c = [0] * total
    for p in x:
        cell = 0
        for a, d in enumerate(dims):
            cell = cell * d + slab(a, p[a])
        c[cell] += 1
    return c


def counts(x, lo, hi, dims):
    """Particles per rank over equal slabs of lo..hi (clamped to the end slabs)."""
    return cell_counts(x, dims, lambda a, v: min(max(int((v - lo[a]) / (hi[a] - lo[a]) * dims[a] // 1), 0), dims[a] - 1))


def balanced_counts(x, dims):
    """Particles per rank with each axis's boundaries at the quantiles of the centres."""
    cuts = []
    for a, d in enumerate(dims):
        coords = sorted(p[a] for p in x)
        cuts.append([coords[min(len(coords) - 1, (c * len(coords)) // d)] for c in range(1, d)])
    return cell_counts(x, dims, lambda a, v: bisect.bisect_right(cuts[a], v))


def imbalance(c):
    return max(c) / (sum(c) / len(c)) - 1.0


def extent(x, r, dim):
    lo = [min(p[a] - q for p, q in zip(x, r)) for a in range(dim)]
    hi = [max(p[a] + q for p, q in zip(x, r)) for a in range(dim)]
    return lo, hi


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    run = sys.argv[1]
    ranks = [int(r) for r in sys.argv[2:]] or [2, 4, 8]
    pvd = os.path.join(run, "vtk", "particles.pvd")
    if not os.path.exists(pvd):
        sys.exit(f"load_balance.py: no {pvd}; run biaxial with --vtk-every N (N > 0)")
    files = [os.path.join(run, "vtk", d.get("file")) for d in ET.parse(pvd).getroot().iter("DataSet")]
    frames = []
    for f in files:
        reader = vtk.vtkXMLPolyDataReader()
        reader.SetFileName(f)
        reader.Update()
        out = reader.GetOutput()
        radius = out.GetPointData().GetArray("radius")
        r = [radius.GetValue(i) for i in range(out.GetNumberOfPoints())]
        x = [out.GetPoint(i) for i in range(out.GetNumberOfPoints())]
        strain = out.GetFieldData().GetArray("eps_zz").GetValue(0)
        frames.append((strain, x, r))
    dim = 3 if any(p[2] != frames[0][1][0][2] for p in frames[0][1]) else 2
    first_lo, first_hi = extent(frames[0][1], frames[0][2], dim)
    print(f"{run}: {dim}D, {len(frames[0][2])} particles, {len(frames)} frames")
    split = {R: dims_for(R, dim, first_lo, first_hi) for R in ranks}
    header = "eps_zz " + " ".join(f"{R}({'x'.join(map(str, split[R]))}):fixed/following/balanced" for R in ranks)
    print(header)
    worst = {R: [0.0, 0.0, 0.0] for R in ranks}
    for strain, x, r in frames:
        lo, hi = extent(x, r, dim)
        cells = []
        for R in ranks:
            dims = split[R]
            fixed, following = imbalance(counts(x, first_lo, first_hi, dims)), imbalance(counts(x, lo, hi, dims))
            balanced = imbalance(balanced_counts(x, dims))
            worst[R] = [max(worst[R][0], fixed), max(worst[R][1], following), max(worst[R][2], balanced)]
            cells.append(f"{fixed:.3f}/{following:.3f}/{balanced:.3f}")
        print(f"{strain:.3f} " + " ".join(cells))
    print("largest imbalance, fixed / following / balanced: " +
          ", ".join(f"{R} ranks {w[0]:.3f} / {w[1]:.3f} / {w[2]:.3f}" for R, w in worst.items()))


if __name__ == "__main__":
    main()
