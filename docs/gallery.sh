#!/usr/bin/env bash
# Remakes every picture of the front page and of docs/gallery.md from the command line:
#
#     docs/gallery.sh                      # with `stillpoint` on the PATH
#     STILLPOINT=target/release/stillpoint docs/gallery.sh
#
# The pictures go to docs/gallery/; the point files to a scratch directory that is
# removed afterwards. Every run is seeded, so the pictures come out the same for a given
# version. About half a minute on 2 cores.
set -euo pipefail
cd "$(dirname "$0")"
sp=${STILLPOINT:-stillpoint}
case "$sp" in /*) ;; */*) sp="$PWD/../$sp" ;; esac
out="$PWD/gallery"
mkdir -p "$out"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"

# The modified L2 discrepancy of a point file, for the titles.
dmd() { "$sp" eval --json "$1" | sed -n 's/.*"modified_l2": *\([0-9.e+-]*\).*/\1/p' | xargs printf '%.4f'; }

# The front page: the default set beside scrambled Sobol' and random points, n = 128.
"$sp" generate -n 128 -s 2 -q -o ours.csv
"$sp" baseline sobol -n 128 -s 2 --seed 1 -o sobol.csv
"$sp" baseline random -n 128 -s 2 --seed 1 -o random.csv
"$sp" plot ours.csv -o "$out/front-stillpoint.png" --title "stillpoint: D_MD $(dmd ours.csv)"
"$sp" plot sobol.csv -o "$out/front-sobol.png" --title "scrambled Sobol': D_MD $(dmd sobol.csv)"
"$sp" plot random.csv -o "$out/front-random.png" --title "random: D_MD $(dmd random.csv)"

# The paper's four regions (eq. 58), 100 points each for integration over the region.
region() { # name, expression, box
    "$sp" generate --region "$2" --box "$3" --goal integration -n 100 -q -o "$1.csv"
    "$sp" plot "$1.csv" --region "$2" --box "$3" -o "$out/region-$1.png" --title "$1: $2 <= 0"
}
region g1 "17*x^2 - 16*|x|*y + 17*y^2 - 225" -4.3,4.3,-4.3,4.3
region g2 "x^2*|x| + 10*y^2 - 100" -4.8,4.8,-3.3,3.3
region g3 "y^2 + 2*|x| - 20" -10.4,10.4,-4.65,4.65
region g4 "|x| + 2*|y| - 5" -5.2,5.2,-2.6,2.6

# A design in a mixed space: a uniform, a normal and an integer variable, 60 runs.
"$sp" generate -n 60 --var 'x=uniform(0,1)' --var 'T=normal(350,5)' --var 'layers=int(1,5)' -q -o mixed.csv
"$sp" plot mixed.csv -o "$out/mixed.png" --title "x uniform(0,1), T normal(350,5), layers int(1,5); n = 60"

# Every 2-D projection of a default set at s = 8.
"$sp" generate -n 128 -s 8 -q -o s8.csv
"$sp" plot s8.csv --dims 8 -o "$out/projections-s8.png" --title "n = 128, s = 8: every 2-D projection"

# A set that grows: 32 points, extended to 64, then to 128 (old points in one colour).
"$sp" generate -n 32 -s 2 -q -o grow32.csv
"$sp" generate --extend grow32.csv -n 32 -q -o grow64.csv
"$sp" generate --extend grow64.csv -n 64 -q -o grow128.csv
"$sp" plot grow32.csv -o "$out/grow-32.png" --title "32 points"
"$sp" plot grow64.csv --split 32 -o "$out/grow-64.png" --title "extended to 64 (the first 32 kept)"
"$sp" plot grow128.csv --split 64 -o "$out/grow-128.png" --title "extended to 128 (the first 64 kept)"

echo "pictures written to $out"
