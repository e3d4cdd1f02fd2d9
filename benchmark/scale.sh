#!/usr/bin/env bash
# How pbdrr and plastimatch scale with the CT (issue 27): the same chest at 1x, 2x and 4x per axis, one view.
#
#   bash benchmark/scale.sh [PBDRR_BINARY] [CT_DIR]
#
# defaults: build/apps/pbdrr/pbdrr and ../shared/data/ct/lidc-idri-0314-chest (relative to the repository root).
# Give another binary to compare builds (a copy of a binary that links a libPointBasedDRR of its own build tree needs
# that .so beside it: the binary's folder is put on LD_LIBRARY_PATH).
# Environment: DATA (the large volumes, default ../scale_data; never committed), OUT (results, default
# DATA/scale_<binary name>), RUNS (timed runs, default 3), SCALE_X4=1 adds the 4x chest (9.2 GB of HU, 18 GB of mu
# on disk), CAP_GB (address-space cap of every process on the 4x chest, default 20), VOLUMES (default "chest x2").
#
# Volumes: the chest as pbdrr reads it (the DICOM series), and scripts/make_large_ct.py's 2x (1024 x 1024 x 550,
# int16 HU .mha) and 4x (2048 x 2048 x 1100) chests: trilinear upsampling + 20 HU of Gaussian noise, same box.
# View: AP (pbdrr --gantry 90), 256 x 256 pixels of 2.4 mm, SAD 1000, SID 1500, isocenter at the volume centre.
# Per volume, RUNS interleaved rounds of three whole processes, each under /usr/bin/time -f '%e s %M KB %U %S'
# (elapsed, peak RSS, user and system CPU seconds: the CPU time is what other jobs on the machine disturb least):
#   (a) pbdrr with its defaults on the HU volume (-v: its stage times and table sizes go to OUT/VOLUME/default.*.err)
#   (b) pbdrr --exact siddon on the HU volume
#   (c) plastimatch drr -A cpu -P none -i exact on the mu volume mu = 0.02059 max(0, 1 + HU/1000) (1/mm): pbdrr's
#       default conversion, which plastimatch cannot be given (its own is 0.022 (1 + HU/1000), air at <= -800 HU),
#       so make_large_ct.py --mu writes it (untimed), as compare_plastimatch.sh does. plastimatch thus reads float
#       (twice pbdrr's bytes) and does no conversion. Its flags are compare_plastimatch.sh's: -y in radians,
#       -r/-z/-c columns first, values L / 10.
# NRMSE (RMSE / range of the reference) of each image against pbdrr --exact siddon --ss 4 (16 rays per pixel, the
# pixel average that a pbdrr pixel estimates), from the last round's images. Markdown on stdout (and OUT/scale.md),
# OUT/scale.csv for benchmark/plot_scale.py.
set -euo pipefail

root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
abspath() { realpath -m "$1"; }
PBDRR=$(abspath "${1:-$root/build/apps/pbdrr/pbdrr}")
CT=$(abspath "${2:-$root/../shared/data/ct/lidc-idri-0314-chest}")
DATA=$(abspath "${DATA:-$root/../scale_data}")
OUT=$(abspath "${OUT:-$DATA/scale_$(basename "$PBDRR")}")
RUNS=${RUNS:-3}
SCALE_X4=${SCALE_X4:-0}
CAP_GB=${CAP_GB:-20}
PY=/usr/bin/python3                      # Debian's python3 (numpy)
LD_LIBRARY_PATH="$(dirname "$PBDRR")${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
export LD_LIBRARY_PATH

command -v plastimatch >/dev/null || { echo "error: plastimatch is not installed (apt-get install plastimatch)" >&2; exit 1; }
[ -x "$PBDRR" ] || { echo "error: no pbdrr binary at $PBDRR" >&2; exit 1; }
[ -e "$CT" ] || { echo "error: no CT at $CT" >&2; exit 1; }
"$PY" -c "import numpy" 2>/dev/null || { echo "error: $PY needs numpy (apt-get install python3-numpy)" >&2; exit 1; }
mkdir -p "$DATA" "$OUT"
log() { echo "$*" >&2; }

GEOM=(--gantry 90 --size 256 256 --spacing 2.4 2.4 --sad 1000 --sid 1500)
PLGEOM=(-y 1.5707963267948966 -r "256 256" -z "614.4 614.4" -c "127.5 127.5" --sad 1000 --sid 1500)

# the volumes: name, pbdrr's input (HU), plastimatch's (mu)
need() {  # output args...: make_large_ct.py unless the output exists
  [ -e "$1" ] && return
  log "making $1"
  nice "$PY" "$root/scripts/make_large_ct.py" "$CT" "$@" >&2
}
read -r -a VOLS <<<"${VOLUMES:-chest x2}"
[ "$SCALE_X4" = 1 ] && [[ " ${VOLS[*]} " != *" x4 "* ]] && VOLS+=(x4)
declare -A HU MU
HU[chest]=$CT; MU[chest]=$DATA/chest_mu.mha
need "${MU[chest]}" --factor 1 --noise 0 --mu
for v in x2 x4; do
  k=${v#x}; HU[$v]=$DATA/chest_$v.mha; MU[$v]=$DATA/chest_${v}_mu.mha
  if [[ " ${VOLS[*]} " == *" $v "* ]]; then need "${HU[$v]}" --factor "$k"; need "${MU[$v]}" --factor "$k" --mu; fi
done

info() {  # mu volume -> "voxels cx cy cz" (the volume centre: pbdrr's default isocenter)
  "$PY" -c "
import sys, numpy as np; sys.path.insert(0, '$root/scripts'); from make_large_ct import open_mha
a, h = open_mha(sys.argv[1]); f = lambda k: np.array([float(x) for x in h[k].split()])
d = f('TransformMatrix').reshape(3, 3).T; c = f('Offset') + d @ (f('ElementSpacing') * (np.array(a.shape[::-1]) - 1) / 2)
print(a.size, *(repr(float(x)) for x in c))" "$1"
}

: >"$OUT/times.tsv"
: >"$OUT/volumes.tsv"
timed() {  # volume tool run cmd...: whole process under /usr/bin/time, one line of OUT/times.tsv
  local vol=$1 tool=$2 run=$3 rc=0 cap=() load; shift 3
  load=$(cut -d' ' -f1 /proc/loadavg)
  [ "$vol" = x4 ] && cap=(prlimit --as=$((CAP_GB * 1024 ** 3)))
  /usr/bin/time -f '%e s %M KB %U %S' -o "$OUT/$vol/$tool.$run.time" "${cap[@]}" "$@" \
    >"$OUT/$vol/$tool.$run.out" 2>"$OUT/$vol/$tool.$run.err" || rc=$?
  printf '%s\t%s\t%s\t%s\t%s\t%s\n' "$vol" "$tool" "$run" "$rc" "$(tail -1 "$OUT/$vol/$tool.$run.time")" "$load" \
    >>"$OUT/times.tsv"
}

load0=$(cut -d' ' -f1-3 /proc/loadavg)
for vol in "${VOLS[@]}"; do
  d=$OUT/$vol; mkdir -p "$d"
  read -r nvox cx cy cz < <(info "${MU[$vol]}")
  printf '%s\t%s\t%s\t%s\n' "$vol" "$nvox" "${HU[$vol]}" "${MU[$vol]}" >>"$OUT/volumes.tsv"
  log "$vol: $nvox voxels, isocenter $cx $cy $cz; reference (--exact siddon --ss 4)"
  cap=(); [ "$vol" = x4 ] && cap=(prlimit --as=$((CAP_GB * 1024 ** 3)))
  "${cap[@]}" "$PBDRR" "${HU[$vol]}" -o "$d/ref.mha" --exact siddon --ss 4 "${GEOM[@]}" -v 2>"$d/ref.err" \
    || { log "$vol: the reference failed (see $d/ref.err)"; rm -f "$d/ref.mha"; }
  iso=$(sed -n 's/.*isocenter \[\([^]]*\)\].*/\1/p' "$d/ref.err" | head -1 | tr -d ,)
  [ -z "$iso" ] || "$PY" -c "import sys; a=[float(x) for x in '$iso'.split()]; b=[$cx, $cy, $cz];
sys.exit(0 if len(a) == 3 and max(abs(x-y) for x,y in zip(a,b)) < 1e-2 else 1)" \
    || { echo "error: $vol: pbdrr's isocenter [$iso] is not the volume centre [$cx $cy $cz]" >&2; exit 1; }
  for i in $(seq 1 "$RUNS"); do
    log "$vol: round $i/$RUNS"
    timed "$vol" default "$i" "$PBDRR" "${HU[$vol]}" -o "$d/default.mha" "${GEOM[@]}" -v
    timed "$vol" siddon "$i" "$PBDRR" "${HU[$vol]}" -o "$d/siddon.mha" --exact siddon "${GEOM[@]}" -v
    timed "$vol" plastimatch "$i" plastimatch drr -A cpu -P none -i exact "${PLGEOM[@]}" -o "$cx $cy $cz" \
          -t pfm -O "$d/pl_" "${MU[$vol]}"
  done
done
load1=$(cut -d' ' -f1-3 /proc/loadavg)

{
  echo "# pbdrr and plastimatch on larger CTs (issue 27)"
  echo
  echo "$("$PBDRR" --version 2>&1 | head -1) ($PBDRR), plastimatch $(plastimatch --version 2>&1 | awk '{print $NF; exit}');"\
       "$(nproc) cores, $(awk '/MemTotal/ {printf "%.0f GB", $2 / 1048576}' /proc/meminfo); $(date -u +%Y-%m-%dT%H:%MZ);"\
       "repository at $(git -C "$root" rev-parse --short HEAD 2>/dev/null || echo '?'). Load average (1, 5, 15 min)"\
       "before: $load0; after: $load1."
  echo
  echo "AP view, 256 x 256 pixels of 2.4 mm, SAD 1000, SID 1500, isocenter at the volume centre. Whole process,"\
       "median of $RUNS interleaved rounds (/usr/bin/time: elapsed, user + system CPU, peak RSS). NRMSE = RMSE / range of"\
       "pbdrr \`--exact siddon --ss 4\` on the same volume (plastimatch's image x 10), last round's image."
  echo
  "$PY" - "$OUT" "$root" <<'PYEOF'
import csv, os, statistics, sys
import numpy as np
out, root = sys.argv[1:3]
sys.path.insert(0, os.path.join(root, "benchmark"))
from compare_plastimatch import read_mha, read_pfm  # noqa: E402

TOOLS = [("default", "pbdrr (defaults)", "default.mha"), ("siddon", "pbdrr --exact siddon", "siddon.mha"),
         ("plastimatch", "plastimatch drr -i exact", "pl_0000.pfm")]
vols = [l.rstrip("\n").split("\t") for l in open(os.path.join(out, "volumes.tsv"))]
times = [l.rstrip("\n").split("\t") for l in open(os.path.join(out, "times.tsv"))]
rows = []
print("| volume | voxels | tool | time (s) | CPU (s) | peak RSS (MiB) | bytes/voxel | NRMSE | rounds (s) | status |")
print("|---|---:|---|---:|---:|---:|---:|---:|---|---|")
for vol, nvox, _, _ in vols:
    d = os.path.join(out, vol)
    ref = read_mha(os.path.join(d, "ref.mha"))[0].astype(float) if os.path.exists(os.path.join(d, "ref.mha")) else None
    for tool, name, img in TOOLS:
        t = [r for r in times if r[0] == vol and r[1] == tool]
        ok = [r for r in t if r[3] == "0"]
        use = ok or t  # a tool that always failed: how long it ran and how much memory it took
        secs = [float(r[4].split()[0]) for r in use]
        kb = [int(r[4].split()[2]) for r in use]
        cpu = [float(r[4].split()[4]) + float(r[4].split()[5]) for r in use]
        nrmse = ""
        if ok and ref is not None:
            a = read_pfm(os.path.join(d, img)) * 10.0 if img.endswith(".pfm") else read_mha(os.path.join(d, img))[0]
            nrmse = "%.3e" % (np.sqrt(np.mean((a.astype(float) - ref) ** 2)) / (ref.max() - ref.min()))
        status = "ok"
        if len(ok) < len(t):
            bad = [r for r in t if r[3] != "0"][-1]
            err = open(os.path.join(d, "%s.%s.err" % (tool, bad[2])), errors="replace").read().strip().splitlines()
            status = "%d/%d failed (exit %s): %s" % (len(t) - len(ok), len(t), bad[3],
                                                     (err[-1] if err else "").replace("|", "/")[:160])
        row = dict(volume=vol, voxels=int(nvox), tool=name, median_s="%.3f" % statistics.median(secs),
                   median_cpu_s="%.3f" % statistics.median(cpu),
                   peak_mib="%.0f" % (statistics.median(kb) / 1024), nrmse=nrmse,
                   times_s=" ".join("%.2f" % s for s in secs), peak_kb=" ".join(map(str, kb)),
                   ok_runs=len(ok), runs=len(t), status=status)
        rows.append(row)
        print("| %s | %.3g | %s | %s | %s | %s | %.1f | %s | %s | %s |" % (vol, int(nvox), name, row["median_s"],
              row["median_cpu_s"],
              row["peak_mib"], statistics.median(kb) * 1024 / int(nvox), nrmse, row["times_s"], status))
loads = [float(r[5]) for r in times]
print("\n1-minute load average at the start of each timed process: %.2f .. %.2f (%d cores)."
      % (min(loads), max(loads), os.cpu_count()))
with open(os.path.join(out, "scale.csv"), "w", newline="") as f:
    w = csv.DictWriter(f, fieldnames=list(rows[0]))
    w.writeheader()
    w.writerows(rows)
PYEOF
  echo
  for vol in "${VOLS[@]}"; do
    echo "pbdrr -v (stderr) of the defaults' last round on $vol:"
    echo
    echo '```'
    cat "$OUT/$vol/default.$RUNS.err"
    echo '```'
    echo
  done
  read -r _ cx cy cz < <(info "${MU[${VOLS[-1]}]}")
  echo "Commands (${VOLS[-1]}; CSV: $OUT/scale.csv):"
  echo
  echo '```sh'
  echo "pbdrr ${HU[${VOLS[-1]}]} -o default.mha ${GEOM[*]} -v"
  echo "pbdrr ${HU[${VOLS[-1]}]} -o siddon.mha --exact siddon ${GEOM[*]} -v"
  echo "pbdrr ${HU[${VOLS[-1]}]} -o ref.mha --exact siddon --ss 4 ${GEOM[*]}"
  echo "plastimatch drr -A cpu -P none -i exact -y 1.5707963267948966 -r \"256 256\" -z \"614.4 614.4\""\
       "-c \"127.5 127.5\" --sad 1000 --sid 1500 -o \"$cx $cy $cz\" -t pfm -O pl_ ${MU[${VOLS[-1]}]}"
  echo '```'
} | tee "$OUT/scale.md"
