#!/usr/bin/env bash
# Writes the outputs of a fixed list of commands (every front end's main paths) into DIR
# and their checksums into DIR/SHA256SUMS, so that two builds can be compared byte for byte:
#   benches/same_bytes.sh target/release/stillpoint /tmp/before
#   (change, rebuild)
#   benches/same_bytes.sh target/release/stillpoint /tmp/after
#   diff /tmp/before/SHA256SUMS /tmp/after/SHA256SUMS
# Lines of the headers that record times, and the version lines (`# stillpoint X.Y.Z`,
# `# version: "X.Y.Z"`), are
# dropped before hashing; nothing else is.
set -euo pipefail
bin=$(realpath "${1:?usage: same_bytes.sh BIN OUTDIR}")
out=${2:?usage: same_bytes.sh BIN OUTDIR}
mkdir -p "$out"
out=$(realpath "$out")
cd "$out"
run() { # NAME ARGS...: generate into NAME.csv
    local name=$1; shift
    "$bin" --threads 2 generate -q "$@" -o "$name.csv" 2>/dev/null
}
run paper-s2-n50 --method paper -n 50 -s 2 --seed 3
run paper-s4-n30 --method paper -n 30 -s 4 --seed 3
for s in 2 8 15 20; do
    for n in 100 1500 100000; do
        run "default-s$s-n$n" -n "$n" -s "$s" --seed 1
    done
done
run ball --shape ball:1 -n 60 -s 2 --seed 2
run ellipsoid --shape ellipsoid:1,0.5,0.3 -n 50 -s 3 --seed 2
run box --shape box:0,2,-1,1 -n 40 -s 2 --seed 2
run simplex --shape simplex -n 40 -s 3 --seed 2
printf '1 1 1\n-1 0 0\n0 -1 0\n' > polytope.txt
run polytope --shape polytope:polytope.txt --box 0,1,0,1 -n 40 -s 2 --seed 2
run region --region '|x| + 2*|y| - 1' --box -1,1,-1,1 -n 50 -s 2 --seed 2
run constraint --constraint 'x1 + 2*x2 <= 1.5' --box 0,1,0,1 -n 40 -s 2 --seed 2
run mixture --mixture -s 3 -n 30 --seed 2
run space-filling --goal space-filling -n 40 -s 3 --seed 2
run randomize-tent -n 64 -s 4 --randomize tent --seed 5
run randomize-cells -n 64 -s 4 --randomize cells --seed 5
run randomize-shift -n 64 -s 4 --randomize shift --seed 5
run bounds -n 32 -s 2 --bounds 0,10,-1,1 --seed 4
run space --var 'a=normal(0,1)' --var 'b=int(1,5)' --var 'c={red,green,blue}' \
    --var 'd=beta(2,3)' --var 'e=ordered{low,mid,high}' -n 30 --seed 6
run space-corr --var 'a=normal(0,1)' --var 'b=lognormal(0,0.5)' --correlation '1,0.5;0.5,1' -n 25 --seed 6
run extend --extend default-s2-n100.csv -n 20 --seed 7
run nested --nested 16,32,64 -s 3 --seed 8
"$bin" baseline sobol -n 64 -s 3 --seed 1 -o baseline-sobol.csv 2>/dev/null || true
for f in default-s8-n100 paper-s2-n50 randomize-tent default-s8-n1500; do
    "$bin" eval "$f.csv" --json > "eval-$f.json" 2>/dev/null
done
rm -f SHA256SUMS
for f in *.csv *.json; do
    printf '%s  %s\n' "$(grep -v -e '^# time' -e '"seconds"' -e '^# stillpoint [0-9]' -e '^# version: ' "$f" | sha256sum | cut -d' ' -f1)" "$f"
done > SHA256SUMS
wc -l < SHA256SUMS
