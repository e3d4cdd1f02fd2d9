#!/usr/bin/python3
"""Does `--control-variate auto` land within 20% of the fastest setting at equal error? (issue 27, item 5)

    /usr/bin/python3 benchmark/auto_choice.py CASE OUT       (run by benchmark/auto_choice.sh; see its header)

CASE is one of chest, head, x2, batch; the inputs, the binary and the counts come from the environment that
auto_choice.sh sets (PBDRR, CHEST, HEAD, X2, RUNS, SEEDS, BATCH_SEEDS, BATCH_VIEWS, BATCH_SCORED, BATCH_N).

For the case's view (or batch of views):
  1. the reference: pbdrr --exact siddon --ss 4 (for a batch: of every (BATCH_VIEWS / BATCH_SCORED)-th view);
  2. the target: NRMSE of `--control-variate auto` at N0 (10M for a single view, BATCH_N for a batch), the mean of
     NRMSE^2 over SEEDS seeds (and over the scored views of a batch);
  3. for each setting off, 2, 4, 8, 16: NRMSE^2 at two or three N (N0, the N that a / N alone predicts from N0, and
     a third point when those two are close), fitted by least squares with NRMSE^2 = a / N + b (b >= 0), solved for the
     N at which the setting reaches the target;
  4. RUNS interleaved rounds of every setting at its N (auto at N0), whole processes under
     /usr/bin/time -f '%e s %M KB %U %S'; medians.
Results: OUT/CASE/result.json, and the case's markdown section on stdout (and OUT/CASE/section.md).
NRMSE = RMSE / (max - min of the reference), as benchmark/scale.sh computes it.
"""
import json
import math
import os
import re
import statistics
import subprocess
import sys
import time

import numpy as np

SETTINGS = ["auto", "off", "2", "4", "8", "16"]
CHEST_VIEW = ["--gantry", "90", "--size", "256", "256", "--spacing", "2.4", "2.4", "--sad", "1000", "--sid", "1500"]


def env(name, default):
    return os.environ.get(name, default)


def read_mha(path):
    data = open(path, "rb").read()
    header, _, body = data.partition(b"ElementDataFile = LOCAL\n")
    fields = dict(line.split(" = ", 1) for line in header.decode().splitlines() if " = " in line)
    size = [int(v) for v in fields["DimSize"].split()]
    assert fields.get("ElementType", "MET_FLOAT").strip() == "MET_FLOAT", path
    return np.frombuffer(body, dtype="<f4", count=int(np.prod(size))).astype(np.float64)


def nrmse2(image, reference):
    span = reference.max() - reference.min()
    return float(np.mean((image - reference) ** 2)) / span ** 2


def load1():
    return open("/proc/loadavg").read().split()[0]


def log(*args):
    print("auto_choice:", *args, file=sys.stderr, flush=True)


class Case:
    def __init__(self, name, out):
        self.name = name
        self.pbdrr = env("PBDRR", "/work/auto_bench/pbdrr")
        self.dir = os.path.join(out, name)
        os.makedirs(self.dir, exist_ok=True)
        self.seeds = [int(s) for s in env("SEEDS", "1 2").split()]
        self.batch = name == "batch"
        if name == "chest":
            self.input, self.view, self.n0 = env("CHEST", ""), CHEST_VIEW, 10_000_000
        elif name == "head":
            self.input, self.view, self.n0 = env("HEAD", ""), ["--gantry", "0", "--spacing", "0.8", "0.8"], 10_000_000
        elif name == "x2":
            self.input, self.view, self.n0 = env("X2", ""), CHEST_VIEW, 10_000_000
        elif name == "batch":
            self.input, self.n0 = env("CHEST", ""), int(float(env("BATCH_N", "2e6")))
            self.views = int(env("BATCH_VIEWS", "360"))
            self.scored = int(env("BATCH_SCORED", "36"))
            self.stride = self.views // self.scored
            step = 360.0 / self.views
            self.view = CHEST_VIEW + ["--angles", str(self.views), "--angle-step", repr(step)]
            # the scored views alone, for the references: view j of this sweep is view j * stride of the batch
            self.ref_view = CHEST_VIEW + ["--angles", str(self.scored), "--angle-step", repr(step * self.stride)]
            self.seeds = [int(s) for s in env("BATCH_SEEDS", "1").split()]
        else:
            raise SystemExit("unknown case " + name)
        # the error runs go up to min(NMAX, 100 N0) points; a setting that needs more than NMAX is timed at NMAX (its
        # time a lower bound)
        self.nmax = int(float(env("NMAX", "") or (self.n0 * (10 if self.batch else 200))))
        if not self.input or not os.path.exists(self.input):
            raise SystemExit("auto_choice.py: %s: no input (%r)" % (name, self.input))

    # --- running pbdrr -------------------------------------------------------------------------------------------
    def run(self, args, tag, timed=False):
        """pbdrr INPUT args -v -q; returns (stderr text, time line or None)."""
        cmd = [self.pbdrr, self.input] + args + ["-v", "-q"]
        err = os.path.join(self.dir, tag + ".err")
        tfile = os.path.join(self.dir, tag + ".time")
        if timed:
            cmd = ["/usr/bin/time", "-f", "%e s %M KB %U %S", "-o", tfile] + cmd
        with open(err, "w") as e:
            rc = subprocess.call(cmd, stdout=subprocess.DEVNULL, stderr=e)
        text = open(err).read()
        if rc != 0:
            raise SystemExit("auto_choice.py: %s failed (%d): %s\n%s" % (tag, rc, " ".join(cmd), text[-2000:]))
        return text, (open(tfile).read().strip().splitlines()[-1] if timed else None)

    def output(self, tag):
        if self.batch:
            d = os.path.join(self.dir, tag)
            os.makedirs(d, exist_ok=True)
            return d + "/v_%04d.mha"
        return os.path.join(self.dir, tag + ".mha")

    def reference(self):
        path = self.output("ref")
        first = path % 0 if self.batch else path
        if not os.path.exists(first):
            log(self.name, "reference (--exact siddon --ss 4)")
            view = self.ref_view if self.batch else self.view
            self.run(view + ["--exact", "siddon", "--ss", "4", "-o", path], "ref")
        if self.batch:
            self.ref = [read_mha(path % j) for j in range(self.scored)]
        else:
            self.ref = [read_mha(path)]

    def error2(self, path):
        """mean NRMSE^2 over the (scored) views of an output, and the per-view NRMSE."""
        if self.batch:
            e = [nrmse2(read_mha(path % (j * self.stride)), self.ref[j]) for j in range(self.scored)]
        else:
            e = [nrmse2(read_mha(path), self.ref[0])]
        return float(np.mean(e)), [math.sqrt(x) for x in e]

    @staticmethod
    def parse(text):
        info = {}
        m = re.search(r"control variate F (\d+)[:,].*?M_r / M ([0-9.eE+-]+)", text)
        if m:
            info["F"], info["MrM"] = int(m.group(1)), float(m.group(2))
        m = re.search(r"attenuation mass M ([0-9.eE+-]+)", text)
        if m:
            info["M"] = float(m.group(1))
        m = re.search(r"pbdrr: time: (.*)", text)
        if m:
            info["stages"] = m.group(1).strip()
            for k, v in re.findall(r"([a-z+' ()]+?) ([0-9.]+) s", m.group(1)):
                info.setdefault("stage", {})[k.strip(" ;")] = float(v)
        return info

    def measure(self, setting, n):
        """mean NRMSE^2 over the seeds at N (cached)."""
        key = "%s_%d" % (setting, n)
        cache = os.path.join(self.dir, "err_" + key + ".json")
        if os.path.exists(cache):
            return json.load(open(cache))
        e2, per_view, info = [], [], {}
        for seed in self.seeds:
            tag = "e_%s_s%d" % (key, seed)
            path = self.output("img")
            text, _ = self.run(self.view + ["--control-variate", setting, "--samples", str(n), "--seed", str(seed),
                                            "-o", path], tag)
            info = self.parse(text)
            m, v = self.error2(path)
            e2.append(m)
            per_view += v
        r = {"setting": setting, "N": n, "nrmse2": float(np.mean(e2)), "nrmse2_seeds": e2, "F": info.get("F"),
             "MrM": info.get("MrM"), "per_view_median": float(np.median(per_view)), "per_view_max": max(per_view)}
        json.dump(r, open(cache, "w"))
        log(self.name, setting, "N", n, "NRMSE %.5f" % math.sqrt(r["nrmse2"]), "F", r["F"], "M_r/M", r["MrM"])
        return r

    # --- the fit -------------------------------------------------------------------------------------------------
    @staticmethod
    def fit(points):
        """least squares of e2 = a / N + b, relative residuals; b >= 0."""
        n = np.array([p["N"] for p in points], float)
        e = np.array([p["nrmse2"] for p in points], float)
        A = np.stack([1.0 / n, np.ones_like(n)], 1) / e[:, None]
        a, b = np.linalg.lstsq(A, np.ones_like(e), rcond=None)[0]
        if b < 0 or a <= 0:
            a, b = float(np.sum(e / n) / np.sum(1 / n ** 2)), 0.0  # a / N alone
        return float(a), float(b)

    @staticmethod
    def solve(points, target2):
        """N at which NRMSE^2 reaches target2: the fit a / N + b over all points if it holds (b >= 0, every point
        within 5% in NRMSE), else a local power law NRMSE^2 = c N^-p through the two points nearest the target."""
        a, b = Case.fit(points)
        ok = all(abs(math.sqrt((a / p["N"] + b) / p["nrmse2"]) - 1) < 0.05 for p in points)
        if ok or len(points) < 2:
            return (a / (target2 - b) if target2 > b else float("inf")), "a/N+b"
        near = sorted(points, key=lambda p: abs(math.log(p["nrmse2"] / target2)))[:2]
        (n1, e1), (n2, e2) = [(p["N"], p["nrmse2"]) for p in near]
        if n1 == n2 or e1 == e2:
            return n1 * e1 / target2, "a/N"
        slope = math.log(e2 / e1) / math.log(n2 / n1)  # -p
        return n1 * math.exp(math.log(target2 / e1) / slope), "local N^%.2f" % slope

    def equal_error(self, setting, target2):
        """NRMSE^2 at N0, then at the N the measurements so far predict (until one is within 20% of it; at most
        four N), and the N at equal error."""
        lo, hi = self.n0 / 30, min(self.nmax, self.n0 * 100)
        clamp = lambda n: int(round(min(max(n, lo), hi), -4))
        pts = [self.measure(setting, self.n0)]
        nstar = clamp(self.n0 * pts[0]["nrmse2"] / target2)
        if abs(math.log(nstar / self.n0)) < math.log(1.2):  # close already: bracket it for the fit
            pts.append(self.measure(setting, clamp(self.n0 / 2)))
            pts.append(self.measure(setting, clamp(self.n0 * 2)))
        else:
            for _ in range(3):
                pts.append(self.measure(setting, nstar))
                n, _ = self.solve(pts, target2)
                if not math.isfinite(n):
                    break
                nstar = clamp(n)
                if min(abs(math.log(nstar / p["N"])) for p in pts) < math.log(1.2):
                    break
        a, b = self.fit(pts)
        n, how = self.solve(pts, target2)
        return {"points": pts, "a": a, "b": b, "N": n, "how": how}

    # --- the whole case ------------------------------------------------------------------------------------------
    def go(self, runs):
        t0 = time.time()
        load_before = open("/proc/loadavg").read().split()[:3]
        self.reference()
        target = self.measure("auto", self.n0)
        target2 = target["nrmse2"]
        res = {"case": self.name, "N0": self.n0, "target_nrmse": math.sqrt(target2), "auto": target, "settings": {}}
        for s in SETTINGS[1:]:
            res["settings"][s] = self.equal_error(s, target2)
            log(self.name, s, "N at equal error %.4g" % res["settings"][s]["N"])
        res["settings"]["auto"] = {"points": [target], "a": None, "b": None, "N": float(self.n0)}
        # timed rounds
        nrun = {s: (self.n0 if s == "auto" else int(round(min(res["settings"][s]["N"], self.nmax), -4)))
                for s in SETTINGS}
        res["nmax"] = self.nmax
        times = {s: [] for s in nrun}
        for r in range(runs):
            for s in nrun:
                tag = "t_%s_r%d" % (s, r)
                text, line = self.run(self.view + ["--control-variate", s, "--samples", str(nrun[s]), "--seed", "1",
                                                   "-o", self.output("timed")], tag, timed=True)
                w = line.split()
                info = self.parse(text)
                times[s].append({"wall": float(w[0]), "rss_kb": int(w[2]), "user": float(w[4]), "sys": float(w[5]),
                                 "load": load1(), "F": info.get("F"), "MrM": info.get("MrM"),
                                 "stages": info.get("stages"), "stage": info.get("stage", {})})
                if r == runs - 1:  # the timed image's error (seed 1, last round): a check of the fit
                    res["settings"][s]["timed_nrmse"] = math.sqrt(self.error2(self.output("timed"))[0])
                log(self.name, "round", r + 1, s, "N", nrun[s], line)
        res["N_run"] = nrun
        res["times"] = times
        res["load_before"] = load_before
        res["load_after"] = open("/proc/loadavg").read().split()[:3]
        res["seconds"] = time.time() - t0
        res["ref_time"] = self.parse(open(os.path.join(self.dir, "ref.err")).read()).get("stages")
        json.dump(res, open(os.path.join(self.dir, "result.json"), "w"), indent=1)
        return res


def med(xs):
    return statistics.median(xs)


def section(res):
    """the case's markdown."""
    name = {"chest": "(a) LIDC chest, AP, 256 x 256 of 2.4 mm, single view",
            "head": "(b) InVesalius head, lateral (gantry 0), 512 x 512 of 0.8 mm, single view",
            "x2": "(c) 2x chest (1024 x 1024 x 550), AP, 256 x 256 of 2.4 mm, single view",
            "batch": "(d) chest, 360-view sweep (--angles 360 from gantry 90), 256 x 256 of 2.4 mm, one batch"}[res["case"]]
    out = ["### " + name, ""]
    auto = res["auto"]
    auto_f = auto["F"] if auto["F"] else "off (declined)"
    out.append("Target: auto at N = %s, NRMSE %.5f (mean of NRMSE^2 over seeds%s). auto took F = %s. Load average "
               "(1, 5, 15 min) before: %s; after: %s." % (
                   fmt_n(res["N0"]), res["target_nrmse"], " and scored views" if res["case"] == "batch" else "",
                   auto_f, " ".join(res["load_before"]), " ".join(res["load_after"])))
    out.append("")
    out.append("| setting | F | M_r / M | N at equal error | NRMSE target; timed image at N (seed 1) | NRMSE measured (N) | wall s median | "
               "CPU s median (user+sys) | peak RSS MiB | stage times (median round) | wall / auto |")
    out.append("|---|---:|---:|---:|---:|---|---:|---:|---:|---|---:|")
    walls = {s: med([t["wall"] for t in res["times"][s]]) for s in res["times"]}
    fastest = min((s for s in walls if s != "auto" and res["settings"][s]["N"] <= res.get("nmax", float("inf"))),
                  key=walls.get)  # the fastest fixed setting (of those timed at their N)
    for s in SETTINGS:
        st = res["settings"][s]
        pts = st["points"]
        f = pts[0]["F"]
        mrm = pts[0]["MrM"]
        if s not in res["times"]:
            out.append("| %s | %s | %s | unreachable (b = %.3g) | | %s | | | | | |" % (
                s, f or "-", "%.4f" % mrm if mrm else "-", st["b"], measured(pts)))
            continue
        t = res["times"][s]
        cpu = med([x["user"] + x["sys"] for x in t])
        rss = med([x["rss_kb"] for x in t]) / 1024
        mid = sorted(t, key=lambda x: x["wall"])[len(t) // 2]
        fitted = res["target_nrmse"]
        bold = "**" if s == fastest else ""
        capped = not st["N"] <= res.get("nmax", float("inf")) * 1.0001
        ge = ">= " if capped else ""
        out.append("| %s%s%s | %s | %s | %s | %.5f; %.5f | %s | %s%s%s | %.2f | %.0f | %s | %.2f |" % (
            bold, s, bold, f or "-", "%.4f" % mrm if mrm else "-",
            fmt_n(st["N"]) + (" (timed at %s)" % fmt_n(res["N_run"][s]) if capped else ""), fitted,
            st.get("timed_nrmse") or 0, measured(pts),
            bold, ge + "%.2f" % walls[s], bold, cpu, rss, mid["stages"], walls[s] / walls["auto"]))
    out.append("")
    ratio = walls["auto"] / walls[fastest]
    cpu_ratio = med([x["user"] + x["sys"] for x in res["times"]["auto"]]) / \
        med([x["user"] + x["sys"] for x in res["times"][fastest]])
    # per-round ratios (same round: same load)
    rr = [a["wall"] / b["wall"] for a, b in zip(res["times"]["auto"], res["times"][fastest])]
    out.append("Fastest fixed setting: %s (auto ran F = %s). auto / fastest: wall %.2f (per round, the same round's "
               "runs: %s), CPU %.2f: **%s**." % (fastest, auto_f, ratio, ", ".join("%.2f" % x for x in rr), cpu_ratio,
        "within 20%" if ratio <= 1.2 else "not within 20%"))
    out.append("")
    out.append("Fits (NRMSE^2 = a / N + b over the measured N; the N at equal error from it, or where it misses a point "
               "by more than 5%, from the local power law through the two nearest points): " + "; ".join(
        "%s a = %.4g, b = %.3g (N from %s)" % (s, res["settings"][s]["a"], res["settings"][s]["b"],
                                              res["settings"][s].get("how", "a/N+b"))
        for s in SETTINGS[1:]) + ".")
    out.append("")
    return "\n".join(out), ratio, fastest


def fmt_n(n):
    return "%.3gM" % (n / 1e6)


def measured(pts):
    return ", ".join("%.5f (%s)" % (math.sqrt(p["nrmse2"]), fmt_n(p["N"])) for p in sorted(pts, key=lambda p: p["N"]))


def stage_fit(out, case):
    """least squares over the error runs' -v stage times of a case: the points' stage (sample+project of a single
    view; the ms per view after the first of a batch) = R_F + t_pt * N, one t_pt for every setting, R_F per setting."""
    d = os.path.join(out, case)
    rows = []
    for f in sorted(os.listdir(d)):
        m = re.match(r"e_(\w+?)_(\d+)_s\d+\.err$", f)
        if not m or m.group(1) == "auto":
            continue
        text = open(os.path.join(d, f)).read()
        if case == "batch":
            t = re.search(r"more views [0-9.]+ s, ([0-9.]+) ms each", text)
            y = float(t.group(1)) / 1000 if t else None
        else:
            y = Case.parse(text).get("stage", {}).get("sample+project")
        if y is not None:
            rows.append((m.group(1), int(m.group(2)), y))
    names = [s for s in SETTINGS[1:] if any(r[0] == s for r in rows)]
    A = np.array([[r[1] / 1e6] + [1.0 if r[0] == s else 0.0 for s in names] for r in rows])
    y = np.array([r[2] for r in rows])
    x = np.linalg.lstsq(A, y, rcond=None)[0]
    return {"t_pt_ns": x[0] * 1e3, "R": dict(zip(names, x[1:])), "runs": len(rows)}


def calibrate(out, rounds):
    """the cost model's constants on the chest: per setting, the -v stage times and the CPU time of a single view and
    of a CAL_VIEWS-view batch at two N (interleaved rounds); per setting a line stage = R_F + t_F * N."""
    os.environ["BATCH_VIEWS"] = env("CAL_VIEWS", "36")
    os.environ["BATCH_SCORED"] = os.environ["BATCH_VIEWS"]
    single, batch = Case("chest", out), Case("batch", out)
    single.dir = batch.dir = os.path.join(out, "calibrate")
    os.makedirs(single.dir, exist_ok=True)
    ns = [int(float(x)) for x in env("CAL_N", "1e6 2e7").split()]
    rows = []
    for r in range(rounds):
        for c, kind in ((single, "view"), (batch, "batch")):
            for s in SETTINGS[1:]:
                for n in ns:
                    tag = "c_%s_%s_%d_r%d" % (kind, s, n, r)
                    text, line = c.run(c.view + ["--control-variate", s, "--samples", str(n), "--seed", "1", "-o",
                                                 c.output("img")], tag, timed=True)
                    w = line.split()
                    st = Case.parse(text).get("stage", {})
                    if kind == "batch":
                        m = re.search(r"more views [0-9.]+ s, ([0-9.]+) ms each", text)
                        per = float(m.group(1)) / 1000
                        first = st.get("the first view (with the points' draw)")
                    else:
                        per, first = st.get("sample+project"), st.get("preprocess")
                    rows.append({"kind": kind, "setting": s, "N": n, "round": r, "wall": float(w[0]),
                                 "cpu": float(w[4]) + float(w[5]), "per_view": per, "first": first, "load": load1()})
                    log("calibrate", kind, s, n, line, "per view %.4f" % per)
    json.dump(rows, open(os.path.join(single.dir, "calibrate.json"), "w"), indent=1)
    calreport(out)


def calreport(out):
    """the calibration's table: per kind and setting, medians at each N; lines CPU = C + t * N."""
    rows = json.load(open(os.path.join(out, "calibrate", "calibrate.json")))
    ns = sorted({x["N"] for x in rows})
    views = int(env("CAL_VIEWS", "36"))
    print("| run | setting | CPU s at %s | CPU s at %s | CPU: ns per point | wall s at %s | wall s at %s | "
          "pbdrr -v: points' stage at %s, %s (s; batch: per view) |" % tuple([fmt_n(n) for n in ns] * 3))
    print("|---|---|---:|---:|---:|---:|---:|---|")
    for kind in ("view", "batch"):
        for s in SETTINGS[1:]:
            sel = lambda n, k: med([x[k] for x in rows if x["kind"] == kind and x["setting"] == s and x["N"] == n])
            cpu = [sel(n, "cpu") for n in ns]
            print("| %s | %s | %.2f | %.2f | %.2f | %.2f | %.2f | %.4f, %.4f |" % (
                "single view" if kind == "view" else "%d-view batch" % views, s, cpu[0], cpu[1],
                (cpu[1] - cpu[0]) / (ns[1] - ns[0]) * 1e9, sel(ns[0], "wall"), sel(ns[1], "wall"),
                sel(ns[0], "per_view"), sel(ns[1], "per_view")))


def main():
    case, out = sys.argv[1], sys.argv[2]
    if case == "calibrate":
        calibrate(out, int(env("RUNS", "2")))
        return
    if case == "calreport":
        calreport(out)
        return
    if case == "model":  # the cost model's constants from the error runs' stage times
        for c in ["chest", "head", "x2", "batch"]:
            if os.path.exists(os.path.join(out, c, "result.json")) or c == "batch":
                try:
                    r = stage_fit(out, c)
                except (OSError, ValueError, np.linalg.LinAlgError):
                    continue
                print("%s: t_pt %.2f ns per point (wall), R_F (s): %s (%d runs)" % (
                    c, r["t_pt_ns"], ", ".join("%s %.3f" % kv for kv in r["R"].items()), r["runs"]))
        return
    if case == "report":  # re-print the sections of the finished cases
        for c in ["chest", "head", "x2", "batch"]:
            p = os.path.join(out, c, "result.json")
            if os.path.exists(p):
                print(section(json.load(open(p)))[0])
        return
    res = Case(case, out).go(int(env("RUNS", "3")))
    text = section(res)[0]
    open(os.path.join(out, case, "section.md"), "w").write(text + "\n")
    print(text)


if __name__ == "__main__":
    main()
