"""Summarizes scripts/registration-benchmark.sh's result lines (OUT/VOLUME_METHOD.txt) into a Markdown table."""
import glob
import os
import statistics
import sys


def parse(path):
    runs = []
    for line in open(path):
        if line.startswith("result "):
            runs.append(dict(item.split("=", 1) for item in line.split()[1:]))
    return runs


def main(directory):
    print("| volume | DRR | starts | success (mTRE < 2 mm) | start mTRE mean (mm) | final mTRE median / mean / max (mm) "
          "| wall s per registration (mean) | CPU s (mean) | DRRs per registration (mean) | DRRs per s |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for path in sorted(glob.glob(os.path.join(directory, "*_*.txt"))):
        runs = parse(path)
        if not runs:
            continue
        volume, method = os.path.basename(path)[:-4].split("_", 1)
        final = [float(r["final_tre_mm"]) for r in runs]
        start = [float(r["start_tre_mm"]) for r in runs]
        wall = [float(r["seconds"]) for r in runs]
        cpu = [float(r.get("cpu_seconds", "nan")) for r in runs]
        drrs = [float(r["drrs"]) for r in runs]
        success = sum(1 for f in final if f < 2.0)
        label = "PBDRR (%s points, %s px)" % (runs[0].get("samples", "?"), runs[0]["size"]) if method == "pbdrr" \
            else "ITK ray caster (%s px)" % runs[0]["size"]
        print("| %s | %s | %d | %d / %d | %.2f | %.3f / %.3f / %.3f | %.1f | %.1f | %.0f | %.1f |" % (
            volume, label, len(runs), success, len(runs), statistics.mean(start), statistics.median(final),
            statistics.mean(final), max(final), statistics.mean(wall), statistics.mean(cpu), statistics.mean(drrs),
            sum(drrs) / sum(wall)))


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "out/registration")
