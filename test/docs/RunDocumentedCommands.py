#!/usr/bin/python3
"""Runs every shell command that README.md and docs/*.md show, on small data (issue 40, item 7): a documented command
cannot crash unseen, and a command added to the docs later is run too (it is extracted, not copied here).

The rule of extraction:
- The files: README.md and docs/*.md. Not yet the result pages under docs/benchmark/ and docs/registration/: the
  commands there ran benchmarks on the real CTs (minutes to hours each) and their blocks hold the runs' output.
- The blocks: fenced code blocks (``` or ~~~, indented or not) whose language is sh, bash, shell or console, or that
  name none (the docs' command blocks without a language hold commands and the output they print). Blocks in
  other languages (cpp, cmake, python, diff) are programs, not commands: the examples' tests build and run them
  (examples/CMakeLists.txt: RenderDRR is the README's C++ lines, RenderDRR.py docs/wrapping.md's Python).
- The commands: inside a block (its fence's indentation removed), a command starts on a line that starts with neither
  a blank nor '#', and goes on over the lines its backslash-newlines join. Lines that start with a blank and do not
  continue a command are the output the doc shows or commentary; blank and '#' lines are comments.

Every command is then either run or skipped:
- Skipped: it matches an entry of SKIPS (a doc file, a regular expression, the reason: a cluster, the network, root,
  a build of hours, data the CI does not have, a synopsis rather than a command, ...). An entry that matches no command
  fails the test, so that the list cannot keep an entry for a line the docs no longer have.
- Run: every other command, as its text is (bash -o pipefail -e -c TEXT), with a timeout. The commands of one block
  run in order in one temporary folder (a block is a session as a reader types it: `mkdir -p out` before the command
  that writes into out/). Before every command, the placeholders for the reader's data that it names
  (docsdata.PLACEHOLDERS: ct.mha, ct_dir/, S1000/I10, poses.csv, ...) are put there afresh, made from the CLI tests'
  data (test/cli/MakeTestVolumes.cxx, fixture pbdrrData) or by docsdata.py. The few words that stand for data but are
  not file names (plastimatch's isocenter "X Y Z") are replaced by REWRITES. `build` and `build-bench` are links to the
  build folder, so build/benchmark/PROGRAM runs the built program, and ../shared/data/ct/lidc-idri-0314-chest (the
  chest CT the benchmarks' docs use) is a link to a small DICOM series. `pbdrr` on PATH is a wrapper that runs the
  built pbdrr and then checks that the files its -o, --stderr, --label-channels and --write-rtk-geometry (or a
  manifest's output column) name are there (a printf counter as any number; `pbdrr register -o X.png` writes X.1.png,
  ...); `plastimatch` on PATH likewise checks the files of its -O prefix (it exits 0 on an input it cannot read).
  A command fails the test when it exits other than 0, is killed (a crash: the signal is named) or runs over its
  time, with the command, its folder and its output shown. A placeholder that no command run names, like an entry of
  SKIPS, CAPS or REWRITES that matches no command, fails the test too: none of the lists can rot.
- Long commands: a few documented commands render 360 views of 512 x 512 pixels from 10^7 points; on the CLI phantom
  one of them takes 30 s on 2 cores and writes 363 MB (measured), and there are four. CAPS lists them with the flags
  appended to their text (a later flag overrides an earlier one in pbdrr; before GNU parallel's ::: if there is one):
  every documented flag is still given and parsed, the views are smaller. An entry that matches no command fails.

Usage: RunDocumentedCommands.py --source SOURCE_DIR --build BUILD_DIR --pbdrr PBDRR --data CLI_DATA_DIR --work DIR
       RunDocumentedCommands.py --source SOURCE_DIR --list     (prints what would run and what is skipped)
Exit 0: every command ran as documented; 1: a failure (listed at the end); 2: bad usage.
"""
import argparse
import fnmatch
import glob
import os
import re
import shutil
import subprocess
import sys
import time

import docsdata  # the placeholders' files (docsdata.py, beside this script)

SHELL_LANGUAGES = {"", "sh", "bash", "shell", "console"}

# (doc file or pattern, regular expression searched in the command's one-line text, why it is not run here).
SKIPS = [
    ("README.md", r"^bash scripts/demo\.sh$",
     "installs Debian packages as root (apt-get), then renders InVesalius' head CT (a package download)"),
    ("README.md", r"^bash scripts/test\.sh$", "runs this whole suite, this test among it"),
    ("README.md", r"^pbdrr register ct_dir/ --xray S1000/I10 -o pose\.png$",
     "the CLI data's localizers hold geometry, not an image (constant pixels), on a 32 x 24 mm field that the first "
     "level's smoothing (5 mm) erodes away; register's own tests (pbdrr.register_*) run it on X-rays"),
    ("README.md", r"^sbatch ", "needs a Slurm cluster; slurm.ArrayShardsEqualOneRun runs the script on one it starts"),
    ("README.md", r"^cmake --install build --prefix /opt/pbdrr",
     "writes to /opt; install.DownstreamProject and install.PbdrrAgainstTheInstalledModule install and use it"),
    ("docs/benchmark.md", r"^(BENCH_QUICK=1 )?bash scripts/benchmark\.sh$",
     "hours (the full run) or about 20 minutes (BENCH_QUICK); benchmark.Benchmark_series runs its program"),
    ("docs/benchmark.md", r"^build-bench/benchmark/PointBasedDRRBenchmark CT_DIR_OR_FILE OUTDIR \[",
     "a synopsis ([options]), not a command; benchmark.Benchmark_series runs the program on a tiny series"),
    ("docs/benchmark.md", r"^/usr/bin/python3 benchmark/plot_benchmark\.py .*OUTDIR/NAME\.csv \.\.\.$",
     "a synopsis (OUTDIR/NAME.csv ...): its CSV files are a benchmark run's"),
    ("docs/fuzzing.md", r"^(CC=clang CXX=clang\+\+ cmake|cmake --build build-fuzz|mkdir -p fuzz-corpus|build-fuzz/)",
     "a sanitized clang build and 10-minute fuzzing runs; the fuzz tests run the committed corpus"),
    ("docs/itk-remote-module.md", r"^cd build && ctest -R ITKModuleTestConfigure",
     "is the suite's test ITKModuleTestConfigure (running it inside the suite would race the suite's run)"),
    ("docs/itk-remote-module.md", r"^(cmake -S test/itkmodule|cmake --build build-itkmodule)",
     "builds the ITK test driver (minutes); ITKModuleTestConfigure configures it"),
    ("docs/itk-remote-module.md", r"^(cmake -S ITK -B ITK-build|cmake --build ITK-build)",
     "needs an ITK source tree and a build of hours"),
    ("docs/itk-remote-module.md", r"^(scripts/build-itk\.sh <|nohup nice -n 19 bash scripts/build-itk\.sh)",
     "a synopsis, and a build of ITK 6 of hours"),
    ("docs/itk-remote-module.md", r"^cmake -S \. -B build-itk6 .*ITK_DIR=/work/itk/build-6\.0",
     "needs an ITK 6 build"),
    ("docs/itk-remote-module.md", r"^grep .*build\.log",
     "reads the log of a whole build with ITK 6 (build.log), which a test does not have"),
    ("docs/performance.md", r"^(before|after): ", "the output of pbdrr -v the doc shows, not a command"),
    ("docs/performance.md", r"bash scripts/benchmark\.sh$", "benchmark runs of minutes to hours on the real chest CT"),
    ("docs/performance.md", r"^bash benchmark/scale\.sh", "renders the real chest and its 2x copy (gigabytes)"),
    ("docs/performance.md", r"^X2=chest_x2\.mha bash benchmark/accuracy_target\.sh ",
     "renders the real chest, the head, the 2x chest and a 360-view sweep against 16 x 16-ray references (an hour)"),
    ("docs/performance.md", r"^/usr/bin/python3 scripts/make_large_ct\.py ",
     "reads the real chest and writes its copy (144 MB at factor 1); the commands after it read the phantom instead"),
    ("docs/performance.md", r"^/usr/bin/python3 benchmark/plot_scale\.py .*\.\./scale_data/",
     "plots the CSV files of scale.sh's runs (../scale_data), which a test does not have"),
    ("docs/registration.md", r"^bash scripts/registration-benchmark\.sh$", "80 registrations on the real CTs (hours)"),
    ("docs/sanitizers.md", r"^bash scripts/sanitize\.sh (asan|tsan)", "a sanitized build of the whole suite (an hour)"),
    ("docs/slurm.md", r"^sbatch ",
     "needs a Slurm cluster; slurm.ArrayShardsEqualOneRun runs the script on one it starts"),
    ("docs/slurm.md", r"^bash test/slurm/pbdrrSlurmArrayTest\.sh /path/to/pbdrr",
     "is the test slurm.ArrayShardsEqualOneRun (it starts a Slurm cluster of its own)"),
    ("docs/wrapping.md", r"^(cmake -S ITK -B ITK-build|cmake --build ITK-build)",
     "needs an ITK source tree and a build of hours"),
    ("docs/wrapping.md", r"^(ITK 6\.0\.0 from |[1-5]\. |PASSED$)", "the output of PointBasedDRR.Python the doc shows"),
    ("docs/wrapping.md", r"^git clone https://", "the network"),
    ("docs/wrapping.md", r"^(bash scripts/build-wrapping-tools\.sh|off=|for m in ITK|bash scripts/build-itk\.sh)",
     "builds SWIG, CastXML and a wrapped ITK 6 from source trees (hours)"),
    ("docs/wrapping.md", r"^cmake (-S \. -B|--build) (/work/itk/pbdrr-py|build-6\.0)",
     "needs the wrapped ITK 6 build of the commands above"),
]

# (doc file, regular expression, flags appended to the command, why).
CAPS = [
    ("README.md", r"--angles 360( |$)(?!.*--view-index)", "--size 64 64 --samples 1e5",
     "360 views of 512 x 512 pixels from 10^7 points: 30 s and 363 MB of files on the phantom, for each of them"),
    ("docs/slurm.md", r"--angles 360 .*--size 512 512 .*--samples 1e7", "--size 64 64 --samples 1e5",
     "as above, four processes at once"),
]

# (doc file, text, what it becomes, why): the few words of a command that stand for the reader's data but are not
# file names (docsdata.PLACEHOLDERS puts files there); an entry whose text is in no command fails the test too.
REWRITES = [
    ("README.md", '-o "X Y Z"', '-o "0 0 0"', "plastimatch's isocenter (-o), X Y Z in mm: the phantom's centre"),
]

TIMEOUT_SECONDS = 120

# Programs outside this project that some commands run (the first word, or parallel's): where one is not installed,
# its commands are reported as not run rather than failed (Debian's plastimatch, parallel and dpkg are in the image
# scripts/install-dependencies.sh makes, so they run in the CI).
OPTIONAL_PROGRAMS = ("plastimatch", "parallel", "dpkg")


class Command:
    def __init__(self, doc, line, block, text):
        self.doc, self.line, self.block, self.text = doc, line, block, text
        # One line, as SKIPS and CAPS search it: the comments at the lines' ends (a '#' after a blank) removed, the
        # backslash-newlines joined, blanks collapsed.
        uncommented = "\n".join(re.sub(r"\s#.*$", "", line) for line in text.split("\n"))
        self.flat = re.sub(r"\s+", " ", uncommented.replace("\\\n", " ")).strip()

    def where(self):
        return f"{self.doc}:{self.line}"


def extract(source):
    """The commands of README.md and docs/*.md, by the rule of the header comment."""
    docs = ["README.md"] + sorted(os.path.relpath(p, source) for p in glob.glob(os.path.join(source, "docs", "*.md")))
    commands = []
    fence = re.compile(r"^( *)(```+|~~~+)\s*([\w+-]*)")
    for doc in docs:
        with open(os.path.join(source, doc), encoding="utf-8") as f:
            lines = f.read().split("\n")
        inside, shell, indent, marker, block = False, False, 0, "", 0
        current = None  # [first line number, text] of a command still continued by a backslash
        for number, line in enumerate(lines, 1):
            match = fence.match(line)
            if not inside and match:
                inside, indent, marker, block = True, len(match.group(1)), match.group(2), number
                shell = match.group(3).lower() in SHELL_LANGUAGES
                continue
            if inside and line.strip().startswith(marker[:3]) and line.strip().strip(marker[0]) == "":
                inside, current = False, None
                continue
            if not inside or not shell:
                continue
            text = line[indent:] if line[:indent].strip() == "" else line.lstrip()
            if current is not None:
                current[1] += "\n" + text
            elif text and not text[0].isspace() and not text.startswith("#"):
                current = [number, text]
            else:
                continue
            if not current[1].endswith("\\"):
                commands.append(Command(doc, current[0], block, current[1]))
                current = None
    return commands


def classify(commands):
    """Sets command.skip (a reason or None) and command.cap (flags or None); returns the entries that match nothing."""
    unused = []
    for table, attribute in ((SKIPS, "skip"), (CAPS, "cap")):
        for entry in table:
            doc, pattern = entry[0], entry[1]
            matched = [c for c in commands if fnmatch.fnmatch(c.doc, doc) and re.search(pattern, c.flat)]
            for c in matched:
                setattr(c, attribute, entry[2:])
            if not matched:
                unused.append(f"{attribute} entry ({doc}, {pattern!r}) matches no command of {doc}")
    for doc, text, _, _ in REWRITES:
        if not any(c.doc == doc and text in c.text for c in commands):
            unused.append(f"rewrite entry ({doc}, {text!r}) matches no command of {doc}")
    for c in commands:
        c.skip = getattr(c, "skip", None)
        c.cap = getattr(c, "cap", None)
    return unused


def run(commands, args):
    """Runs the commands not skipped, block by block; returns the failures."""
    work = os.path.abspath(args.work)
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    stage = os.path.join(work, "stage")
    placeholders = docsdata.make_stage(stage, os.path.abspath(args.data), os.path.abspath(args.pbdrr))
    # ../shared/data/... of the docs' benchmark commands: relative to a block's folder, under the work folder.
    docsdata.link(os.path.join(os.path.abspath(args.data), "dicom_good"),
                  os.path.join(work, "shared", "data", "ct", "lidc-idri-0314-chest"))
    bin_dir = os.path.join(work, "bin")
    os.makedirs(bin_dir)
    wrapper = os.path.join(bin_dir, "pbdrr")
    with open(wrapper, "w") as f:
        f.write(f"#!/usr/bin/python3\nimport sys\nsys.path.insert(0, {os.path.dirname(__file__)!r})\n"
                f"import docsdata\nsys.exit(docsdata.run_pbdrr({os.path.abspath(args.pbdrr)!r}, sys.argv[1:]))\n")
    os.chmod(wrapper, 0o755)
    if shutil.which("plastimatch"):  # plastimatch exits 0 having written nothing: its wrapper checks its files
        with open(os.path.join(bin_dir, "plastimatch"), "w") as f:
            f.write(f"#!/usr/bin/python3\nimport sys\nsys.path.insert(0, {os.path.dirname(__file__)!r})\n"
                    f"import docsdata\nsys.exit(docsdata.run_plastimatch({shutil.which('plastimatch')!r}, "
                    "sys.argv[1:]))\n")
        os.chmod(os.path.join(bin_dir, "plastimatch"), 0o755)
    environment = dict(os.environ, PATH=bin_dir + os.pathsep + os.environ.get("PATH", ""))

    failures, used, folders = [], set(), {}
    for c in commands:
        if c.skip:
            continue
        key = (c.doc, c.block)
        if key not in folders:
            folders[key] = os.path.join(work, re.sub(r"\W", "_", f"{c.doc}_{c.block}"))
            os.makedirs(folders[key])
            for name in ("build", "build-bench"):
                os.symlink(os.path.abspath(args.build), os.path.join(folders[key], name))
        folder = folders[key]
        names = [n for n in placeholders if re.search(r"(?<![\w./-])" + re.escape(n) + r"(?![\w-]|\.\w)", c.flat)]
        for name in names:
            docsdata.put(stage, name, folder)
            used.add(name)
        absent = [p for p in OPTIONAL_PROGRAMS if c.flat.split()[0] == p and not shutil.which(p)]
        if absent:
            print(f"not run {c.where()}: {c.flat} ({absent[0]} is not installed)", flush=True)
            continue
        text = c.text
        for entry in REWRITES:
            if entry[0] == c.doc and entry[1] in text:
                text = text.replace(entry[1], entry[2])
        if c.cap:  # at the end of pbdrr's arguments: before GNU parallel's ::: if there is one
            head, separator, tail = text.partition(" ::: ")
            text = head + " " + c.cap[0] + separator + tail
        start = time.monotonic()
        try:
            result = subprocess.run(["bash", "-o", "pipefail", "-e", "-c", text], cwd=folder, env=environment,
                                    stdout=subprocess.PIPE, stderr=subprocess.STDOUT, timeout=TIMEOUT_SECONDS)
            code, output = result.returncode, result.stdout.decode(errors="replace")
        except subprocess.TimeoutExpired as e:
            code, output = "timeout", (e.stdout or b"").decode(errors="replace")
        seconds = time.monotonic() - start
        capped = f" (capped: {c.cap[0]})" if c.cap else ""
        if code == 0:
            print(f"ok      {seconds:6.1f} s  {c.where()}: {c.flat}{capped}", flush=True)
            continue
        if code == "timeout":
            why = f"ran over {TIMEOUT_SECONDS} s"
        elif code > 128 or code < 0:
            why = f"killed by signal {abs(code) - 128 if code > 128 else -code} (a crash)"
        else:
            why = f"exit {code}"
        print(f"FAILED  {seconds:6.1f} s  {c.where()}: {c.flat}{capped}\n  {why}, in {folder}\n"
              + "".join(f"  | {l}\n" for l in output.splitlines()[-30:]), flush=True)
        failures.append(f"{c.where()}: {c.flat}{capped}: {why}")
    for name in placeholders:
        if name not in used:
            failures.append(f"the placeholder {name!r} (docsdata.PLACEHOLDERS) is named by no command run: remove it")
    return failures


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--source", required=True)
    parser.add_argument("--build")
    parser.add_argument("--pbdrr")
    parser.add_argument("--data")
    parser.add_argument("--work")
    parser.add_argument("--list", action="store_true")
    args = parser.parse_args()
    if not args.list and not (args.build and args.pbdrr and args.data and args.work):
        parser.error("--build, --pbdrr, --data and --work are needed to run the commands")

    commands = extract(args.source)
    problems = classify(commands)
    per_doc = {}
    for c in commands:
        counts = per_doc.setdefault(c.doc, [0, 0])
        counts[1 if c.skip else 0] += 1
    print(f"{len(commands)} commands in {len(per_doc)} files:")
    for doc, (ran, skipped) in per_doc.items():
        print(f"  {doc}: {ran + skipped} ({ran} run, {skipped} skipped)")
    for c in commands:
        if c.skip:
            print(f"skipped {c.where()}: {c.flat}\n  because: {c.skip[0]}")
    if args.list:
        for c in commands:
            if not c.skip:
                print(f"run     {c.where()}: {c.flat}" + (f"  + {c.cap[0]}  ({c.cap[1]})" if c.cap else ""))
    else:
        problems += run(commands, args)
    if problems:
        print(f"\n{len(problems)} failures:\n" + "\n".join("  " + p for p in problems))
        return 1
    print("\nevery documented command ran" if not args.list else "")
    return 0


if __name__ == "__main__":
    sys.exit(main())
