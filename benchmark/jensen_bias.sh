#!/bin/bash
# The Jensen bias of transmission from a noisy estimate (docs/design.md section 14): on one chest view, the mean
# over the body's pixels (0.001 < T < 0.9) of exp(-L_hat) and of the 120 kVp transmission, uncorrected and with
# --jensen-correction, against the exact projector's (16 x 16 rays per pixel, converged to 0.03% there), for 10^5,
# 10^6 and 10^7 points without the control variate, 4 seeds each; beside the bias the second-order prediction
# T se^2 / 2 from the renders' own standard errors.
#
#   bash benchmark/jensen_bias.sh [CT] [PBDRR]     (defaults: the LIDC chest, build/apps/pbdrr/pbdrr)
set -euo pipefail
HERE=$(cd "$(dirname "$0")" && pwd)
CT=${1:-/work/shared/data/ct/lidc-idri-0314-chest}
PBDRR=${2:-$HERE/../build/apps/pbdrr/pbdrr}
O=$(mktemp -d)
trap 'rm -rf "$O"' EXIT
V="--gantry 90 --size 128 128 --spacing 4.8 4.8 -q"
# shellcheck disable=SC2086
{
  "$PBDRR" "$CT" $V --exact siddon --ss 16 -o "$O/exact.mha"
  "$PBDRR" "$CT" $V --exact siddon --ss 16 --kvp 120 -o "$O/exact_kvp.mha"
  for n in 1e5 1e6 1e7; do
    for s in 1 2 3 4; do
      P="$V --output-mode transmission --control-variate off --samples $n --seed $s"
      "$PBDRR" "$CT" $P -o "$O/mono_${n}_$s.mha" --stderr "$O/mono_se_${n}_$s.mha"
      "$PBDRR" "$CT" $P --kvp 120 -o "$O/kvp_${n}_$s.mha" --stderr "$O/kvp_se_${n}_$s.mha"
      "$PBDRR" "$CT" $P --kvp 120 --jensen-correction -o "$O/jensen_${n}_$s.mha"
    done
  done
}
/usr/bin/python3 - "$O" "$HERE/../docs/figures/scene_chest_ap.py" <<'PY'
import sys

import numpy as np

out, reader = sys.argv[1], sys.argv[2]
exec(open(reader).read().split("prefix, output")[0])  # read_mha()
exact = np.exp(-read_mha(f"{out}/exact.mha").astype(float))
exact_kvp = np.exp(-read_mha(f"{out}/exact_kvp.mha").astype(float))
body = (exact < 0.9) & (exact > 1e-3)


def relative(image, reference):
    return np.mean(image[body] - reference[body]) / np.mean(reference[body])


def mean_and_error(values):
    values = np.array(values)
    return f"{100 * values.mean():+.3f}% +- {100 * values.std(ddof=1) / np.sqrt(len(values)):.3f}"


print("| points | median se_L | T = exp(-L): bias | predicted T se^2 / 2 | 120 kVp: bias | predicted | "
      "120 kVp, --jensen-correction |")
print("|---|---:|---:|---:|---:|---:|---:|")
for n in ["1e5", "1e6", "1e7"]:
    mono, mono_predicted, kvp, kvp_predicted, corrected, se = [], [], [], [], [], []
    for s in range(1, 5):
        t = read_mha(f"{out}/mono_{n}_{s}.mha").astype(float)
        se_t = read_mha(f"{out}/mono_se_{n}_{s}.mha").astype(float)
        se_l = se_t / np.maximum(t, 1e-12)
        se.append(np.median(se_l[body]))
        mono.append(relative(t, exact))
        mono_predicted.append(np.mean((t * se_l**2 / 2)[body]) / np.mean(exact[body]))
        k = read_mha(f"{out}/kvp_{n}_{s}.mha").astype(float)
        se_k = read_mha(f"{out}/kvp_se_{n}_{s}.mha").astype(float)
        kvp.append(relative(k, exact_kvp))
        kvp_predicted.append(np.mean((se_k**2 / np.maximum(k, 1e-12) / 2)[body]) / np.mean(exact_kvp[body]))
        corrected.append(relative(read_mha(f"{out}/jensen_{n}_{s}.mha").astype(float), exact_kvp))
    print(f"| {n} | {np.median(se):.3f} | {mean_and_error(mono)} | {100 * np.mean(mono_predicted):+.3f}% | "
          f"{mean_and_error(kvp)} | {100 * np.mean(kvp_predicted):+.3f}% | {mean_and_error(corrected)} |")
PY
