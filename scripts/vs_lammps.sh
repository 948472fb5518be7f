#!/usr/bin/env bash
# micromacro against LAMMPS on the same packing files, side by side in one run: the throughput
# benchmark (build/tests/benchmarks/throughput --packing) and LAMMPS (scripts/lammps/throughput.in:
# gran/hooke/history, nve/sphere) time the same particles, law (k = 1e5, k_t = 2e4 N/m, mu = 0.5,
# no dashpots), time step, skin and number of steps, alternating within each round; micromacro runs
# without its energy books (--no-energy: LAMMPS keeps none; they cost about 5%). The table gives
# each program's median particle-steps per second and the median of the rounds' ratios. Prints
# Markdown: docs/vs-lammps.md is its output.
#
# Packings (made once, kept in BUILD_DIR/vs_lammps): dense random polydisperse ones, radii 0.5-1.5 mm,
# prepared by the project's own preparation (examples/random_packing, a periodic box compressed to
# p/k = 5e-4 in 2D, p a/k = 5e-4 in 3D), in the order the preparation left them; and the throughput
# benchmark's jittered lattices (--write-packing). Two threads: micromacro's OpenMP threads against
# two MPI ranks of LAMMPS (Debian's LAMMPS has no OPENMP package; MPI domain decomposition is how it
# runs in parallel). Two ranks: micromacro's MPI layer (tests/benchmarks/throughput_mpi --packing)
# against LAMMPS's, both under mpirun on the same packing (skipped, and said so, in a build without MPI).
#
#   scripts/vs_lammps.sh > docs/vs-lammps.md   # 3 rounds, about 10 minutes on 2 cores (packings: 5 more, once)
#   RUNS=5 scripts/vs_lammps.sh
#   NATIVE=1 scripts/vs_lammps.sh        # also a LAMMPS built -O3 -march=native from Debian's source
#                                        # (apt-get source, built once into ~/.cache, about 15 minutes)
#   CASES=$'random3d_50000 3 1\nlattice2d_80000 2 2 ranks' scripts/vs_lammps.sh   # other cases, one per line:
#                                        # random2d_N, random3d_N, lattice2d_N or lattice3d_N, dim, threads,
#                                        # and "ranks" for MPI ranks instead of threads, or "sheared" for the
#                                        # box sheared at 1 /s (Lees-Edwards: micromacro's moving cell,
#                                        # throughput --cell-shear; LAMMPS's fix deform with remap v)
# Installs Debian's lammps if it is missing. Needs a build (scripts/setup.sh test).
set -euo pipefail
cd "$(dirname "$0")/.."
build=${BUILD_DIR:-build}
tp=$build/tests/benchmarks/throughput
tpm=$build/tests/benchmarks/throughput_mpi
rp=$build/examples/random_packing
for program in "$tp" "$rp"; do
  [ -x "$program" ] || { echo "vs_lammps.sh: no $program; build first (scripts/setup.sh test)" >&2; exit 1; }
done
rounds=${RUNS:-3}
[[ "$rounds" =~ ^[1-9][0-9]*$ ]] || { echo "vs_lammps.sh: RUNS must be a positive whole number, not '$rounds'" >&2; exit 2; }
# shellcheck source=scripts/lammps/environment.sh
source scripts/lammps/environment.sh
deck=scripts/lammps/throughput.in
density=2000 k=1e5 kt=2e4 mu=0.5

# An -O3 -march=native LAMMPS (serial, GRANULAR only) from the source of Debian's package.
native=""
if [ "${NATIVE:-0}" = 1 ]; then
  home=${XDG_CACHE_HOME:-$HOME/.cache}/micromacro/lammps-native
  native=$home/build/lmp
  if [ ! -x "$native" ]; then
    version=$(dpkg-query -W -f '${Version}' lammps)
    echo "building an -O3 -march=native LAMMPS from Debian's source of lammps $version (once)" >&2
    rm -rf "$home" && mkdir -p "$home/apt/parts" "$home/apt/lists/partial" "$home/apt/cache" "$home/source"
    # apt-get source through a source list of its own, made from the machine's entries with
    # deb-src for deb and dropped afterwards: the machine's apt configuration is not touched.
    grep -hsE '^deb ' /etc/apt/sources.list /etc/apt/sources.list.d/*.list | sed 's/^deb /deb-src /' >"$home/apt/sources.list" || true
    for f in /etc/apt/sources.list.d/*.sources; do
      if [ -f "$f" ]; then sed -E 's/^Types:.*/Types: deb-src/' "$f" >"$home/apt/parts/$(basename "$f")"; fi
    done
    apt_own=(-o Dir::Etc::SourceList="$home/apt/sources.list" -o Dir::Etc::SourceParts="$home/apt/parts"
             -o Dir::State::Lists="$home/apt/lists" -o Dir::Cache="$home/apt/cache" -o Debug::NoLocking=1)
    apt-get "${apt_own[@]}" update -qq >&2
    (cd "$home/source" && apt-get "${apt_own[@]}" source -qq "lammps=$version" >&2)
    rm -rf "$home/apt"
    mv "$home/source"/lammps-*/ "$home/src"
    cmake -S "$home/src/cmake" -B "$home/build" -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_FLAGS_RELEASE="-O3 -march=native" \
      -DPKG_GRANULAR=on -DBUILD_MPI=off -DBUILD_OMP=off -DBUILD_SHARED_LIBS=off -DLAMMPS_EXCEPTIONS=off >&2
    cmake --build "$home/build" -j2 >&2
  fi
fi

cache=$build/vs_lammps
mkdir -p "$cache"
# packing NAME: the dump file of that packing, made if missing.
packing() {
  local file=$cache/$1.dump
  if [ ! -f "$file" ]; then
    case $1 in
      random2d_*) "$rp" --dim 2 --particles "${1#random2d_}" --seed 1 --out "$file" >&2 ;;
      random3d_*) "$rp" --dim 3 --particles "${1#random3d_}" --seed 1 --out "$file" >&2 ;;
      lattice2d_*) "$tp" --dim 2 --particles "${1#lattice2d_}" --steps 1 --write-packing "$file" >/dev/null ;;
      lattice3d_*) "$tp" --dim 3 --particles "${1#lattice3d_}" --steps 1 --write-packing "$file" >/dev/null ;;
    esac
  fi
  echo "$file"
}
# data DUMP: a LAMMPS data file (atom_style sphere) of the dump, next to it.
data() {
  local file=${1%.dump}.data
  [ -f "$file" ] || awk '
    /^ITEM: NUMBER OF ATOMS/ { getline; n = $1 }
    /^ITEM: BOX BOUNDS/ { for (a = 0; a < 3; a++) { getline; lo[a] = $1; hi[a] = $2 } }
    /^ITEM: ATOMS/ { for (c = 3; c <= NF; c++) col[$c] = c - 2; atoms = 1; next }
    atoms && NF { id = $col["id"]; r[id] = $col["radius"]; x[id] = $col["x"]; y[id] = $col["y"]; z[id] = ("z" in col) ? $col["z"] : 0 }
    END {
      printf "LAMMPS data file: a micromacro packing\n\n%d atoms\n1 atom types\n\n", n
      split("x y z", axis, " ")
      for (a = 0; a < 3; a++) printf "%s %s %slo %shi\n", lo[a], hi[a], axis[a + 1], axis[a + 1]
      printf "\nAtoms # sphere\n\n"
      for (i = 1; i <= n; i++) printf "%d 1 %.17g 1 %s %s %s\n", i, 2 * r[i], x[i], y[i], z[i]
    }' "$1" >"$file"
  echo "$file"
}
# The dump's total mass at the density (4/3 pi r^3 rho each), to check LAMMPS's.
total_mass() {
  awk -v rho=$density '/^ITEM: ATOMS/ { for (c = 3; c <= NF; c++) if ($c == "radius") rc = c - 2; atoms = 1; next }
    atoms && NF { m += 4 / 3 * 3.141592653589793 * rho * $rc ^ 3 } END { printf "%.12g", m }' "$1"
}
# micromacro DUMP DIM THREADS STEPS -> its JSON line
micromacro() {
  "$tp" --packing "$1" --dim "$2" --threads "$3" --steps "$4" --k $k --kt $kt --mu $mu --gamma-n 0 --gamma-t 0 \
    --density $density --no-energy --cell-shear "${shear:-0}" --json
}
# micromacro_ranks DUMP DIM RANKS STEPS -> its JSON line (throughput_mpi: the same law, t_c, skin)
micromacro_ranks() {
  mpirun -np "$3" "$tpm" --packing "$1" --dim "$2" --steps "$4" --k $k --kt $kt --mu $mu --gamma-n 0 --gamma-t 0 \
    --density $density --no-energy --json
}
# lammps BINARY RANKS DATA DIM DT SKIN STEPS -> "particle-steps/s total-mass"
lammps() {
  local launch=("$1")
  [ "$2" -gt 1 ] && launch=(mpirun -np "$2" "$1")
  "${launch[@]}" -log none -nocite -var dim "$4" -var data "$3" -var density $density -var kn $k -var kt $kt -var mu $mu \
    -var skin "$6" -var dt "$5" -var steps "$7" -var shear "${shear:-0}" -in $deck |
    awk '/^Loop time of/ { t = $4; s = $9; n = $12 } /^MASS/ { m = $2 } END { printf "%.6g %s\n", s * n / t, m }'
}
median() { sort -g | awk '{ v[NR] = $1 } END { printf "%.3g\n", v[int((NR + 1) / 2)] }'; }
json() { grep -o "\"$2\": [^,}]*" <<<"$1" | head -1 | cut -d' ' -f2 | tr -d '"'; }

# packing dim threads [ranks]
cases=(
  "random2d_1950 2 1" "random2d_20000 2 1" "lattice2d_20000 2 1" "random2d_20000 2 2"
  "random3d_13824 3 1" "lattice3d_13824 3 1" "random3d_13824 3 2"
  "lattice2d_200000 2 2 ranks" "lattice3d_100000 3 2 ranks"
  "random2d_20000 2 1 sheared" "random3d_13824 3 1 sheared"
)
[ -z "${CASES:-}" ] || mapfile -t cases <<<"$CASES"
help=$(lmp -h 2>/dev/null || true)
version=$(awk -F' - ' '/^Large-scale Atomic/ { print $2; exit }' <<<"$help")
echo "# micromacro and LAMMPS side by side"
echo
echo "Made by \`${native:+NATIVE=1 }RUNS=$rounds scripts/vs_lammps.sh > docs/vs-lammps.md\` on $(awk -F': ' '/model name/ { print $2; exit }' /proc/cpuinfo),"
echo "$(nproc) cores; LAMMPS ${version:-(version unknown)} from Debian${native:+ and the same source built -O3 -march=native}."
echo "Each program's median particle-steps per second over $rounds rounds, the two run alternately within a"
echo "round, and the median of the rounds' ratios (micromacro / LAMMPS). The same law (k = 1e5 N/m, k_t = 2e4 N/m,"
echo "mu = 0.5, no dashpots), time step (t_c/50 of two mean particles), skin (a fifth of the mean radius) and steps;"
echo "micromacro without its energy books (\`--no-energy\`), as LAMMPS keeps none. Two threads: micromacro's"
echo "threads against two MPI ranks of LAMMPS; two ranks: two MPI ranks of each (micromacro's \`throughput_mpi\`);"
echo "sheared: the periodic box sheared at 1 /s by Lees-Edwards images, the particles starting with the flow"
echo "(micromacro's moving cell, \`throughput --cell-shear 1\`; LAMMPS's triclinic box under \`fix deform ... remap v\`)."
echo
header="| packing | particles | contacts per particle | threads | micromacro | LAMMPS (Debian) | ratio |"
rule="|---|---|---|---|---|---|---|"
if [ -n "$native" ]; then header="$header LAMMPS -O3 -march=native | ratio |"; rule="$rule---|---|"; fi
echo "$header"
echo "$rule"
for c in "${cases[@]}"; do
  read -r name dim threads over <<<"$c"
  shear=0
  [ "$over" != sheared ] || shear=1
  if [ "$over" = ranks ] && [ ! -x "$tpm" ]; then
    echo "| ${name%%_*} | ${name#*_} | | $threads ranks | (no $tpm: a build without MPI) | | |${native:+ | |}"
    continue
  fi
  dump=$(packing "$name")
  file=$(data "$dump")
  probe=$(micromacro "$dump" "$dim" 1 1)
  n=$(json "$probe" particles)
  steps=$(( (dim == 2 ? 100000000 : 40000000) / n ))
  dt=$(json "$probe" dt) skin=$(json "$probe" skin) contacts=$(json "$probe" contacts)
  expected=$(total_mass "$dump")
  mm=() lm=() ln=() rl=() rn=()
  ours() {  # this case's micromacro run: threads, or MPI ranks (whose time step must be the probe's, LAMMPS's)
    if [ "$over" != ranks ]; then micromacro "$dump" "$dim" "$threads" "$steps"; return; fi
    local line
    line=$(micromacro_ranks "$dump" "$dim" "$threads" "$steps")
    [ "$(json "$line" dt)" = "$dt" ] ||
      { echo "vs_lammps.sh: throughput_mpi took dt $(json "$line" dt), LAMMPS $dt: the two would run different scenes" >&2; exit 1; }
    echo "$line"
  }
  for round in $(seq "$rounds"); do
    if (( round % 2 )); then
      a=$(json "$(ours)" particle_steps_per_second); read -r b mass < <(lammps lmp "$threads" "$file" "$dim" "$dt" "$skin" "$steps")
    else
      read -r b mass < <(lammps lmp "$threads" "$file" "$dim" "$dt" "$skin" "$steps"); a=$(json "$(ours)" particle_steps_per_second)
    fi
    awk -v m="$mass" -v e="$expected" 'BEGIN { exit !(m / e - 1 < 1e-9 && 1 - m / e < 1e-9) }' ||
      { echo "vs_lammps.sh: LAMMPS's total mass $mass is not the packing's $expected: the two would run different scenes" >&2; exit 1; }
    mm+=("$a") lm+=("$b") rl+=("$(awk -v a="$a" -v b="$b" 'BEGIN { print a / b }')")
    if [ -n "$native" ] && [ "$threads" = 1 ]; then
      read -r b _ < <(lammps "$native" 1 "$file" "$dim" "$dt" "$skin" "$steps")
      ln+=("$b") rn+=("$(awk -v a="$a" -v b="$b" 'BEGIN { print a / b }')")
    fi
  done
  row="| ${name%%_*} | $n | $(awk -v c="$contacts" -v n="$n" 'BEGIN { printf "%.2f", 2 * c / n }') | $threads${over:+ $over}"
  row="$row | $(printf '%s\n' "${mm[@]}" | median) | $(printf '%s\n' "${lm[@]}" | median) | $(printf '%s\n' "${rl[@]}" | median | awk '{ printf "%.2f", $1 }') |"
  if [ -n "$native" ]; then
    if [ "${#ln[@]}" -gt 0 ]; then
      row="$row $(printf '%s\n' "${ln[@]}" | median) | $(printf '%s\n' "${rn[@]}" | median | awk '{ printf "%.2f", $1 }') |"
    else
      row="$row (serial build) | |"
    fi
  fi
  echo "$row"
done
