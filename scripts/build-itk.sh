#!/usr/bin/env bash
# Build ITK from a source folder with only the modules PointBasedDRR needs (issue 31: check the module against ITK 6.0
# and 5.4.4, not only Debian's 5.2.1).
#
#   scripts/build-itk.sh <ITK source folder> <build folder> [jobs] [extra CMake arguments...]
#   e.g. nohup nice -n 19 bash scripts/build-itk.sh /work/itk/src-6.0 /work/itk/build-6.0 2 > /work/itk/build-6.0.log 2>&1 &
#
# What it builds: ITK (shared libraries, Release, BUILD_TESTING=OFF, BUILD_EXAMPLES=OFF, ITK_BUILD_DEFAULT_MODULES=OFF)
# with the modules of CMake/PointBasedDRRProgramITK.cmake's find_package(ITK ... COMPONENTS ...) and of itk-module.cmake (the TEST_DEPENDS
# ITKTestKernel and ITKGoogleTest, for the in-ITK test driver and PointBasedDRR.ITKModuleTestConfigure), plus ITKIOXML
# (issue 31, item 4) and whatever ITK adds as their dependencies. ITK 6 (ITK_VERSION_MAJOR >= 6 in the source) also gets
# ITK_LEGACY_REMOVE=ON, so that removed 5.x spellings are errors. zlib, PNG, TIFF, JPEG, expat and
# GoogleTest come from Debian's packages (scripts/install-dependencies.sh), which saves their compilation; GDCM, HDF5,
# Eigen, VNL, MetaIO, NIFTI, NrrdIO and double-conversion (ITK 6 asks >= 3.1.6, Debian 12 has 3.1.5) are ITK's own
# copies (system GDCM is not needed and its CMake config is fragile).
# Extra arguments (e.g. -DITK_LEGACY_REMOVE=OFF, -DCMAKE_BUILD_TYPE=RelWithDebInfo) are appended to the configure line.
#
# It is re-runnable: a second run re-configures the existing build folder (cheap) and lets the build tool resume where
# it stopped. Compilation runs under `nice -n 19` (and `ionice -c3` where available), so it takes only idle CPU.
#
# How long: configuration about 30 seconds; v6.0b02 is 1583 Ninja steps, built here (2 shared cores, nice -n 19 beside
# other sessions' builds and tests, 2 jobs) in 46 minutes (2026-11-27, 15:53 to 16:39 UTC; 140 MB), v5.4.4 1582 steps
# in 25 minutes (18:45 to 19:10 UTC; 136 MB). Progress: the [n/N] counter in the log. Do not edit this script while
# it runs: bash reads it as it goes.
#
# Then point this project at the result:
#   cmake -S . -B build-itk6 -DCMAKE_BUILD_TYPE=Release -DITK_DIR=<build folder>
set -euo pipefail

if [[ $# -lt 2 ]]; then
  sed -n '2,27p' "$0" | sed 's/^# \{0,1\}//'
  exit 2
fi
src=$(realpath "$1")
build=$2
jobs=${3:-2}
shift 2
[[ $# -gt 0 ]] && shift
[[ -f "$src/CMakeLists.txt" && -d "$src/Modules/Core/Common" ]] || {
  echo "build-itk.sh: $src is not an ITK source folder" >&2
  exit 2
}
[[ "$jobs" =~ ^[0-9]+$ ]] || {
  echo "build-itk.sh: jobs must be a number, not '$jobs'" >&2
  exit 2
}
mkdir -p "$build"

# The modules of CMake/PointBasedDRRProgramITK.cmake's find_package(ITK ... COMPONENTS) and of itk-module.cmake.
modules=(ITKCommon ITKTransform ITKImageFunction ITKImageGrid ITKImageIntensity ITKOptimizers ITKOptimizersv4 ITKRegistrationCommon
  ITKIOImageBase ITKIOGDCM ITKGDCM ITKIOMeta ITKIONRRD ITKIONIFTI ITKIOPNG ITKIOTIFF ITKIOTransformBase ITKIOTransformInsightLegacy
  ITKTestKernel ITKGoogleTest ITKIOXML ITKZLIB)

major=$(sed -n 's/^ *set(ITK_VERSION_MAJOR "\{0,1\}\([0-9]*\).*/\1/p' "$src/CMake/itkVersion.cmake" 2>/dev/null | head -1)
legacy=()
if [[ "${major:-5}" -ge 6 ]]; then
  legacy=(-DITK_LEGACY_REMOVE=ON)
fi

generator=()
if [[ ! -f "$build/CMakeCache.txt" ]] && command -v ninja >/dev/null; then
  generator=(-G Ninja)
fi

args=(-S "$src" -B "$build" "${generator[@]}"
  -DCMAKE_BUILD_TYPE=Release
  -DBUILD_SHARED_LIBS=ON
  -DBUILD_TESTING=OFF
  -DBUILD_EXAMPLES=OFF
  -DITK_BUILD_DEFAULT_MODULES=OFF
  -DITK_WRAP_PYTHON=OFF
  -DITK_USE_SYSTEM_ZLIB=ON
  -DITK_USE_SYSTEM_PNG=ON
  -DITK_USE_SYSTEM_TIFF=ON
  -DITK_USE_SYSTEM_JPEG=ON
  -DITK_USE_SYSTEM_EXPAT=ON
  -DITK_USE_SYSTEM_GOOGLETEST=ON
  "${legacy[@]}")
for m in "${modules[@]}"; do
  args+=("-DModule_$m=ON")
done
args+=("$@")

echo "build-itk.sh: $(date -u +%FT%TZ) ITK ${major:-?} from $src ($(git -C "$src" describe --tags 2>/dev/null || echo '?'))"
echo "build-itk.sh: cmake ${args[*]}"
cmake "${args[@]}"

nicer=(nice -n 19)
if command -v ionice >/dev/null; then
  nicer+=(ionice -c3)
fi
echo "build-itk.sh: $(date -u +%FT%TZ) building with $jobs jobs"
"${nicer[@]}" cmake --build "$build" -j "$jobs"
echo "build-itk.sh: $(date -u +%FT%TZ) done; configure this project with -DITK_DIR=$build"
