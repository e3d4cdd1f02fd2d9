#!/usr/bin/env bash
# pbdrr against `plastimatch drr` (Debian package plastimatch) on a real CT: same picture, same geometry, and time.
#
#   bash benchmark/compare_plastimatch.sh [PBDRR_BINARY] [CT_DIR]
#
# defaults: build/apps/pbdrr/pbdrr and ../shared/data/ct/lidc-idri-0314-chest (relative to the repository root);
# CT_DIR is a DICOM series directory (or any volume `plastimatch convert` reads). Prints Markdown on stdout.
# Environment: OUT (scratch dir, default /tmp/pbdrr_vs_plastimatch), RUNS (timing runs, default 5), SAMPLES
# (points of the picture, default 1e8), MATCH=0 skips timing pbdrr at the sample count that matches plastimatch's
# accuracy (about 10 minutes on 2 cores), PNG (picture path, default $OUT/pbdrr_vs_plastimatch.png).
#
# 1. Convention check on a synthetic asymmetric volume: which plastimatch flags reproduce pbdrr (gantry unit,
#    row/column order of -r -z -c, the output scale, the exit voxel, the default HU conversion). The flags found
#    are the ones used below; the script stops if none reproduces pbdrr.
# 2. The chest: `plastimatch convert` turns the series into ct.mha (HU); mu = 0.02059 max(0, 1 + HU/1000) (1/mm)
#    goes to mu.mha, which BOTH tools read (pbdrr --input-units mu, plastimatch -P none), so the HU -> mu step
#    cannot differ. AP view (pbdrr --gantry 90), 256 x 256 pixels of 2.4 mm, SAD 1000, SID 1500, isocenter at the
#    volume centre (pbdrr's default, passed to plastimatch with -o).
# 3. Whole-process wall time, median of RUNS interleaved runs on the same mu.mha.
set -euo pipefail

root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
abspath() { case "$1" in /*) echo "$1" ;; *) echo "$PWD/$1" ;; esac; }
PBDRR=$(abspath "${1:-$root/build/apps/pbdrr/pbdrr}")
CT=$(abspath "${2:-$root/../shared/data/ct/lidc-idri-0314-chest}")
OUT=${OUT:-/tmp/pbdrr_vs_plastimatch}
RUNS=${RUNS:-5}
SAMPLES=${SAMPLES:-1e8}
MATCH=${MATCH:-1}
PNG=${PNG:-$OUT/pbdrr_vs_plastimatch.png}
PY=/usr/bin/python3                      # Debian's python3 (numpy, matplotlib)
HELP="$root/benchmark/compare_plastimatch.py"

# the geometry (pbdrr flags; plastimatch's are derived from the convention check)
GANTRY=90 COLS=256 ROWS=256 DU=2.4 DV=2.4 SAD=1000 SID=1500

skip() { echo "SKIP: $*"; exit 0; }
command -v plastimatch >/dev/null || skip "plastimatch is not installed (Debian: apt-get install plastimatch)"
[ -e "$CT" ] || skip "no CT data at $CT"
[ -x "$PY" ] && "$PY" -c "import numpy, matplotlib" 2>/dev/null || skip "$PY with numpy and matplotlib is needed"
[ -x "$PBDRR" ] || { echo "error: no pbdrr binary at $PBDRR (build it: cmake --build build --target pbdrr)" >&2; exit 1; }
mkdir -p "$OUT"
cd "$OUT"

PLM_VERSION=$(plastimatch --version 2>&1 | awk '{print $NF; exit}')
export PLM_VERSION SAMPLES
log() { echo "$*" >&2; }

plm() { plastimatch drr -A cpu --sad "$SAD" --sid "$SID" -t pfm "$@" >>"$OUT/plastimatch.log" 2>&1; }
pb() { "$PBDRR" -q "$@"; }

echo "# pbdrr vs plastimatch drr"
echo
echo "plastimatch $PLM_VERSION; $("$PBDRR" --version 2>&1 | head -1) ($(git -C "$root" rev-parse --short HEAD 2>/dev/null || echo '?'));"\
     "$(nproc) cores; $(date -u +%Y-%m-%dT%H:%MZ); CT: $CT"
echo

# ------------------------------------------------------------------------------- 1. the convention check
log "1. convention check (synthetic volumes in $OUT)"
: >"$OUT/plastimatch.log"
PH_ISO=$("$PY" "$HELP" phantoms "$OUT")
pb phantom.mha -o pb_g30.mha --input-units mu --exact siddon --gantry 30 --size 80 60 --spacing 2 2
for unit in deg rad; do
  y=30; [ $unit = rad ] && y=$("$PY" -c 'import math; print(repr(math.radians(30)))')
  plm -P none -i exact -y "$y" -r "80 60" -z "160 120" -o "$PH_ISO" -O "pl_${unit}_colrow_" phantom.mha
  plm -P none -i exact -y "$y" -r "60 80" -z "120 160" -o "$PH_ISO" -O "pl_${unit}_rowcol_" phantom.mha
done
pb cube.mha -o pb_cube_g0.mha --input-units mu --exact siddon --gantry 0 --size 80 60 --spacing 2 2
pb slab0.mha -o pb_slab0.mha --input-units mu --exact siddon --gantry 0 --size 80 60 --spacing 2 2
plm -P none -i exact -y 0 -r "80 60" -z "160 120" -o "$PH_ISO" -O pl_cube_g0_ cube.mha
plm -P none -i exact -y 0 -r "80 60" -z "160 120" -o "$PH_ISO" -O pl_slab0_ slab0.mha
plm -P none -i exact -y 0 -r "11 11" -z "22 22" -o "0 0 0" -O pl_one_ one.mha
for hu in -1000 -801 -800 -799 -500 0 1000 2000; do
  plm -i exact -y 0 -r "11 11" -z "22 22" -o "0 0 0" -O "pl_hu_${hu}_" "hu_${hu}.mha"
done
echo "## 1. plastimatch's conventions, by experiment"
echo
"$PY" "$HELP" conventions "$OUT"
echo
# shellcheck disable=SC1091
. "$OUT/conventions.env"
[ "$PLM_OK" = 1 ] || { echo "error: plastimatch's conventions were not recognised (see above)" >&2; exit 1; }

Y=$GANTRY
[ "$PLM_Y_UNIT" = rad ] && Y=$("$PY" -c "import math; print(repr(math.radians($GANTRY)))")
cr() { if [ "$PLM_ORDER" = colrow ]; then echo "$1 $2"; else echo "$2 $1"; fi; }
Z=$(cr "$("$PY" -c "print(repr($COLS*$DU))")" "$("$PY" -c "print(repr($ROWS*$DV))")")
C=$(cr "$("$PY" -c "print(($COLS-1)/2)")" "$("$PY" -c "print(($ROWS-1)/2)")")
R=$(cr "$COLS" "$ROWS")

# ---------------------------------------------------------------------------------------- 2. the chest
log "2. chest: plastimatch convert, mu volume"
plastimatch convert --input "$CT" --output-img "$OUT/ct.mha" >"$OUT/convert.log" 2>&1 \
  || { echo "error: plastimatch convert failed, see $OUT/convert.log" >&2; exit 1; }
ISO=$("$PY" "$HELP" prepare "$OUT/ct.mha" "$OUT")
GEOM=(--gantry "$GANTRY" --size "$COLS" "$ROWS" --spacing "$DU" "$DV" --sad "$SAD" --sid "$SID")
PLGEOM=(-y "$Y" -r "$R" -z "$Z" -c "$C" -o "$ISO")
# pbdrr's own default isocenter must be the one passed to plastimatch
pbiso=$("$PBDRR" mu.mha -o "$OUT/iso_check.mha" --input-units mu --exact siddon "${GEOM[@]}" --size 4 4 -v 2>&1 \
        | sed -n 's/.*isocenter \[\([^]]*\)\].*/\1/p' | tr -d ,)
"$PY" -c "import sys; a=[float(x) for x in '$pbiso'.split()]; b=[float(x) for x in '$ISO'.split()];
sys.exit(0 if max(abs(x-y) for x,y in zip(a,b)) < 1e-3 else 1)" \
  || { echo "error: pbdrr's isocenter [$pbiso] is not the volume centre [$ISO]" >&2; exit 1; }

log "2. chest: renders"
pb mu.mha -o pb_siddon1.mha --input-units mu --exact siddon "${GEOM[@]}"
pb mu.mha -o pb_siddon8.mha --input-units mu --exact siddon --ss 8 "${GEOM[@]}"
pb mu.mha -o pb_points.mha --input-units mu --samples "$SAMPLES" "${GEOM[@]}"
plm -P none -i exact "${PLGEOM[@]}" -O pl_exact_ mu.mha
plm -P none -i uniform "${PLGEOM[@]}" -O pl_uniform_ mu.mha
plm -P none -i exact "${PLGEOM[@]}" -O pl_exact_pad_ mu_pad.mha
pb "$CT" -o pb_hu_default.mha --exact siddon "${GEOM[@]}"
pb ct.mha -o pb_hu_plmconv.mha --exact siddon --mu-water 0.022 --air-threshold -799.5 "${GEOM[@]}"
plm -i exact "${PLGEOM[@]}" -O pl_hu_default_ ct.mha

echo "## 2. The chest, AP"
echo
echo "Same geometry, same mu volume (\`mu.mha\`, 1/mm):"
echo
echo '```sh'
echo "pbdrr mu.mha -o pb.mha --input-units mu ${GEOM[*]} [--exact siddon | --samples N]"
echo "plastimatch drr -A cpu -P none -i exact -y $Y -r \"$R\" -z \"$Z\" -c \"$C\" -o \"$ISO\" --sad $SAD --sid $SID -t pfm -O pl_ mu.mha"
echo '```'
echo
echo "(plastimatch's value times $PLM_SCALE is pbdrr's line integral; its -y is in $PLM_Y_UNIT, its -r/-z/-c are $([ "$PLM_ORDER" = colrow ] && echo 'columns first' || echo 'rows first').)"
echo
"$PY" "$HELP" compare "$OUT" "$PNG"
echo
NMATCH=$(cat "$OUT/nmatch.txt")
NLABEL=$("$PY" -c "print('%.3g' % $NMATCH)")

# ---------------------------------------------------------------------------------------------- 3. time
log "3. timing: $RUNS interleaved runs"
: >"$OUT/times.tsv"
now() { date +%s.%N; }
timed() {  # label run image cmd...
  local label=$1 run=$2 image=$3; shift 3
  local tag=${label//[^A-Za-z0-9]/_} t0 t1 wall load="" pre="" rend=""
  t0=$(now); "$@" >"$OUT/time_$tag.log" 2>&1; t1=$(now)
  wall=$("$PY" -c "print($t1 - $t0)")
  if [ "$1" = plastimatch ]; then
    rend=$(sed -n 's/^Total time: *\([0-9.e+-]*\).*/\1/p' "$OUT/time_$tag.log" | tail -1)
    [ -n "$rend" ] && load=$("$PY" -c "print($wall - $rend)")
  else
    load=$(sed -n 's/.*time: load \([0-9.]*\) s.*/\1/p' "$OUT/time_$tag.log")
    pre=$(sed -n 's/.*; preprocess \([0-9.]*\) s.*/\1/p' "$OUT/time_$tag.log")
    rend=$(sed -n 's/.*; \(sample+project\|exact projection\) \([0-9.]*\) s.*/\2/p' "$OUT/time_$tag.log")
  fi
  local cmd="" a
  for a in "$@"; do case "$a" in *" "*) cmd+="\"$a\" " ;; *) cmd+="$a " ;; esac; done
  cmd=${cmd//"$OUT"\//}
  printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\n' "$label" "$run" "$wall" "$load" "$pre" "$rend" "$image" \
         "${cmd% }" >>"$OUT/times.tsv"
}
load0=$(cut -d' ' -f1-3 /proc/loadavg)
for i in $(seq 1 "$RUNS"); do
  log "   run $i/$RUNS"
  timed "plastimatch -i exact" "$i" t_plm_0000.pfm plastimatch drr -A cpu -P none -i exact "${PLGEOM[@]}" \
        --sad "$SAD" --sid "$SID" -t pfm -O "$OUT/t_plm_" "$OUT/mu.mha"
  timed "pbdrr --exact siddon" "$i" t_pb_siddon.mha "$PBDRR" "$OUT/mu.mha" -o "$OUT/t_pb_siddon.mha" --input-units mu \
        --exact siddon "${GEOM[@]}" -v
  timed "pbdrr, 1e7 points" "$i" t_pb_1e7.mha "$PBDRR" "$OUT/mu.mha" -o "$OUT/t_pb_1e7.mha" --input-units mu \
        --samples 1e7 "${GEOM[@]}" -v
  if [ "$MATCH" = 1 ]; then
    timed "pbdrr, $NLABEL points" "$i" t_pb_match.mha "$PBDRR" "$OUT/mu.mha" -o "$OUT/t_pb_match.mha" \
          --input-units mu --samples "$NMATCH" "${GEOM[@]}" -v
  fi
done
load1=$(cut -d' ' -f1-3 /proc/loadavg)
echo "## 3. Time, whole process, $COLS x $ROWS, median of $RUNS interleaved runs"
echo
echo "Load average (1, 5, 15 min) before: $load0; after: $load1 (on $(nproc) cores; other users' jobs included)."
echo "plastimatch prints only 'Total time' (render + write, after the volume is read): its load column is wall"
echo "minus that. pbdrr's columns are its -v stage times (its preprocess builds the attenuation-level table)."
echo
"$PY" "$HELP" timing "$OUT"
echo
echo "Outputs and logs: $OUT; picture: $PNG"
