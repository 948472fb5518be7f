#!/usr/bin/env bash
# Compares this build's tests/benchmarks/throughput with another commit's, side by side: the
# other commit is built in a temporary git worktree, the two binaries alternate REPS times
# (the machines are shared and noisy, so only runs taken together compare), and the medians
# and their ratio are printed. How the README's and the notes' "side by side" figures were taken.
#   scripts/side_by_side.sh COMMIT "--dim 3 --particles 100000 --steps 60" [REPS=5]
set -euo pipefail
cd "$(dirname "$0")/.."
commit=$1 args=$2 reps=${3:-5}
new=${BUILD_DIR:-build}/tests/benchmarks/throughput
[ -x "$new" ] || { echo "side_by_side.sh: no $new; build first (scripts/setup.sh test)" >&2; exit 1; }
tree=$(mktemp -d)
trap 'git worktree remove --force "$tree" >/dev/null 2>&1 || true' EXIT
git worktree add -q -f --detach "$tree" "$commit"
cmake -S "$tree" -B "$tree/build" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$tree/build" -j2 --target throughput >/dev/null
old=$tree/build/tests/benchmarks/throughput
rate() { "$1" $args --json | grep -o '"particle_steps_per_second": [0-9.e+]*' | awk '{print $2}'; }
median() { sort -g | awk '{a[NR] = $1} END {print a[int((NR + 1) / 2)]}'; }
o=() n=()
for _ in $(seq "$reps"); do o+=("$(rate "$old")"); n+=("$(rate "$new")"); done
mo=$(printf '%s\n' "${o[@]}" | median) mn=$(printf '%s\n' "${n[@]}" | median)
echo "throughput $args: $commit $mo, this build $mn, ratio $(awk -v a="$mn" -v b="$mo" 'BEGIN {printf "%.3f", a / b}') (medians of $reps)"
