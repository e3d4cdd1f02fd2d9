#!/usr/bin/env bash
# The bias of the paper's unweighted estimators on real CT, against the exact (Siddon, 4 x 4 rays) reference:
#   level-alias (unbiased), level-alias --paper-count (perspective weight dropped), paper-hybrid (exact weights),
#   paper-hybrid --paper-count (the paper's Algorithm 1 as published: no weights at all).
# Usage: bash benchmark/paper_bias.sh [PBDRR] [OUTDIR]   (run scripts/demo.sh first for the head CT)
set -euo pipefail
cd "$(dirname "$0")/.."
pbdrr=${1:-build/apps/pbdrr/pbdrr}
out=${2:-out/paper_bias}
mkdir -p "$out"
chest=../shared/data/ct/lidc-idri-0314-chest
head=out/demo/head.mha
samples=1e8
render() { # name input geometry-flags...
  local name=$1 input=$2
  shift 2
  "$pbdrr" "$input" -o "$out/$name.ref.mha" --exact siddon --ss 4 -q "$@"
  "$pbdrr" "$input" -o "$out/$name.unbiased.mha" --samples $samples --seed 1 -q "$@"
  "$pbdrr" "$input" -o "$out/$name.count.mha" --samples $samples --seed 1 --paper-count -q "$@"
  "$pbdrr" "$input" -o "$out/$name.hybrid.mha" --samples $samples --seed 1 --sampler paper-hybrid -q "$@"
  "$pbdrr" "$input" -o "$out/$name.paper.mha" --samples $samples --seed 1 --sampler paper-hybrid --paper-count -q "$@"
}
[ -d "$chest" ] && render chest "$chest" --gantry 90 --size 256 256 --spacing 2.4 2.4
[ -f "$head" ] && render head "$head" --gantry 0 --size 256 256 --spacing 1.6 1.6
/usr/bin/python3 benchmark/paper_bias.py "$out"
