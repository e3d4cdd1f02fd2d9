#!/usr/bin/env bash
# Build the two tools ITK's Python wrapping needs, from their public sources (issue 31, item 2): SWIG >= 4.2
# (ITK 6.0 and 5.4 download a 2024 master build; Debian 12 has 4.1.0) and CastXML (ITK 6.0 downloads a 2026 build;
# Debian 12 has 0.5.1), built here against Debian's LLVM/Clang 14.
#
#   scripts/build-wrapping-tools.sh <swig source> <castxml source> <install prefix> [jobs]
#   e.g. git clone https://github.com/swig/swig && git -C swig checkout v4.3.1
#        git clone https://github.com/CastXML/CastXML castxml && git -C castxml checkout v0.7.0
#        bash scripts/build-wrapping-tools.sh swig castxml /work/itk/tools 2
#
# Then give ITK's configure (scripts/build-itk.sh) the tools:
#   -DITK_WRAP_PYTHON=ON -DITK_USE_SYSTEM_SWIG=ON -DSWIG_EXECUTABLE=<prefix>/bin/swig
#   -DITK_USE_SYSTEM_CASTXML=ON -DCASTXML_EXECUTABLE=<prefix>/bin/castxml
#
# Needs (Debian): bison, autoconf, automake, libpcre2-dev (SWIG), llvm-14-dev and libclang-14-dev (CastXML).
# How long here (2 shared cores): SWIG about 4 minutes, CastXML about 3.
set -euo pipefail

if [[ $# -lt 3 ]]; then
  sed -n '2,17p' "$0" | sed 's/^# \{0,1\}//'
  exit 2
fi
swig_src=$(realpath "$1")
castxml_src=$(realpath "$2")
prefix=$(realpath -m "$3")
jobs=${4:-2}
[[ -x "$swig_src/autogen.sh" ]] || {
  echo "build-wrapping-tools.sh: $swig_src is not a SWIG source folder" >&2
  exit 2
}
[[ -f "$castxml_src/src/castxml.cxx" ]] || {
  echo "build-wrapping-tools.sh: $castxml_src is not a CastXML source folder" >&2
  exit 2
}
llvm_dir=$(ls -d /usr/lib/llvm-*/lib/cmake/llvm 2>/dev/null | sort -V | tail -1)
[[ -n "$llvm_dir" && -f "$(dirname "$llvm_dir")/clang/ClangConfig.cmake" ]] || {
  echo "build-wrapping-tools.sh: no LLVM/Clang CMake package (apt-get install llvm-14-dev libclang-14-dev)" >&2
  exit 2
}
mkdir -p "$prefix"

echo "build-wrapping-tools.sh: $(date -u +%FT%TZ) SWIG $(git -C "$swig_src" describe --tags 2>/dev/null || echo '?')"
(
  cd "$swig_src"
  ./autogen.sh
  mkdir -p build && cd build
  ../configure --prefix="$prefix" --without-alllang --with-python=/usr/bin/python3
  make -j "$jobs"
  make install
)

echo "build-wrapping-tools.sh: $(date -u +%FT%TZ) CastXML $(git -C "$castxml_src" describe --tags 2>/dev/null || echo '?') on $llvm_dir"
cmake -S "$castxml_src" -B "$castxml_src/build" -DCMAKE_BUILD_TYPE=Release -DCMAKE_INSTALL_PREFIX="$prefix" \
  -DLLVM_DIR="$llvm_dir"
cmake --build "$castxml_src/build" -j "$jobs"
cmake --install "$castxml_src/build"

"$prefix/bin/swig" -version | grep -i version
"$prefix/bin/castxml" --version | sed -n 1p
echo "build-wrapping-tools.sh: $(date -u +%FT%TZ) done in $prefix"
