#!/usr/bin/env bash
# Installs the Debian packages PointBasedDRR needs to build, test and run its demo (as root, Debian bookworm).
set -euo pipefail
packages=(build-essential cmake libinsighttoolkit5-dev libgdcm-dev libgtest-dev invesalius-examples
  libxrl-dev                    # xraylib 4.0: cross sections and NIST compounds (DRRMaterialTable, DRRXRaySpectrum)
  clang libclang-rt-14-dev llvm # clang, libFuzzer and the sanitizers' runtimes, llvm-symbolizer: test/fuzz
  doxygen clang-format          # the docs target and its test, the formatting test (docs/, test/format)
  python3-numpy python3-matplotlib # the benchmarks' tables and plots (benchmark/*.py, /usr/bin/python3)
  slurm-wlm munge parallel      # batches on a Slurm cluster or GNU parallel, the test's own cluster (docs/slurm.md, test/slurm)
  util-linux)                   # prlimit: the full-disk test's file size limit (test/cli/FullDiskResume.cmake)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "Installing: ${missing[*]}"
  apt-get update -qq
  DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi
