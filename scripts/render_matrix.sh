#!/usr/bin/env bash
# Renders a matrix of pbdrr configurations and prints the md5 of every output file: run it with two builds of pbdrr
# and diff the lists to show that a change leaves the images the same, bit for bit (issue 40's closing note).
#   bash scripts/render_matrix.sh OLD/apps/pbdrr/pbdrr /tmp/old > old.md5
#   bash scripts/render_matrix.sh build/apps/pbdrr/pbdrr /tmp/new > new.md5 && diff old.md5 new.md5
# The CLI tests' data (build/test/cli/data, made by the tests' pbdrrData fixture) and, when ../shared/data is there,
# the LIDC chest (its DICOM series, and an .mha copy made by scripts/make_large_ct.py for the streamed runs).
set -u
ROOT=$(cd "$(dirname "$0")/.." && pwd)
P=$(realpath "$1"); OUT=$(realpath -m "$2"); D=$ROOT/build/test/cli/data
rm -rf "$OUT"; mkdir -p "$OUT"; cd "$OUT"
CT=$D/phantom.mha
common="--size 64 48 --spacing 4 4 --samples 2e5 -q"
run() { name=$1; shift; "$P" "$@" > "$name.log" 2>&1; echo "exit $?" >> "$name.log"; }
for t in 1 2; do
run plain_t$t $CT -o plain_t$t.mha --stderr plain_t$t.se.mha $common --threads $t
done
for cv in off auto 2 4; do
  for s in stratified metropolis paper-hybrid level-alias mcvr; do
    run cv${cv}_$s $CT -o cv${cv}_$s.mha --stderr cv${cv}_$s.se.mha $common --control-variate $cv --sampler $s
  done
done
for k in box tent; do for sp in nearest bilinear; do
  run k${k}_$sp $CT -o k${k}_$sp.mha --stderr k${k}_$sp.se.mha $common --kernel $k --splat $sp
done; done
run paper $CT -o paper.mha $common --paper-count
run strata4 $CT -o strata4.mha --stderr strata4.se.mha $common --strata 4 --seed 7
for cv in off auto 4; do
  run stream_cv$cv $CT -o stream_cv$cv.mha --stderr stream_cv$cv.se.mha $common --stream 3 --control-variate $cv
  run streambatch_cv$cv $CT -o "streambatch_cv${cv}_%d.mha" $common --stream 3 --angles 3 --control-variate $cv
  run batch_cv$cv $CT -o "batch_cv${cv}_%d.mha" $common --angles 4 --control-variate $cv
  run batchind_cv$cv $CT -o "batchind_cv${cv}_%d.mha" $common --angles 3 --independent-views --control-variate $cv
  run budget_cv$cv $CT -o budget_cv$cv.mha $common --memory-budget 20K --control-variate $cv
done
run batch_bil $CT -o "batch_bil_%d.mha" $common --angles 3 --splat bilinear --sampler level-alias
run batch_stack $CT -o batch_stack.mha $common --angles 3 --stack
run labels_keep $CT -o labels_keep.mha $common --labels $D/labels.mha --keep-labels 1
run labels_drop $CT -o labels_drop.mha $common --labels $D/labels.mha --drop-labels 1
run labels_ch $CT -o labels_ch.mha $common --labels $D/labels.mha --label-channels labels_ch_channels.mha
run labels_ch_batch $CT -o "labels_chb_%d.mha" $common --labels $D/labels.mha --angles 3
run exact_siddon $CT -o exact_siddon.mha $common --exact siddon
run exact_tri $CT -o exact_tri.mha $common --exact trilinear
run gray8 $CT -o gray8.png $common
run trans $CT -o trans.mha $common --output-mode transmission --stderr trans.se.mha
run kvp $CT -o kvp.mha $common --kvp 100
run photons $CT -o photons.mha $common --photons 1e5 --seed 3
run parallel $CT -o parallel.mha $common --parallel --control-variate auto
C=$ROOT/../shared/data/ct/lidc-idri-0314-chest; mkdir -p "$OUT.ct"; C1=$OUT.ct/chest1.mha
if [ -d $C ]; then
  /usr/bin/python3 "$ROOT/scripts/make_large_ct.py" $C $C1 --factor 1 > /dev/null
  cc="--size 96 64 --spacing 4 4 --samples 1e6 -q"
  run chest_auto $C -o chest_auto.mha --stderr chest_auto.se.mha $cc --control-variate auto
  run chest_stream $C1 -o chest_stream.mha --stderr chest_stream.se.mha $cc --stream 4 --control-variate auto
  run chest_batch $C -o "chest_batch_%d.mha" $cc --angles 3 --control-variate auto
  run chest_streambatch $C1 -o "chest_streambatch_%d.mha" $cc --angles 3 --stream 4
  run chest_budget $C1 -o chest_budget.mha $cc --memory-budget 30M
fi

md5sum *.mha *.png 2>/dev/null
grep -H 'exit' *.log | grep -v 'exit 0'
