/*=========================================================================
 *
 *  Copyright NumFOCUS and the PointBasedDRR contributors
 *
 *  Licensed under the Apache License, Version 2.0 (the "License");
 *  you may not use this file except in compliance with the License.
 *  You may obtain a copy of the License at
 *
 *         http://www.apache.org/licenses/LICENSE-2.0.txt
 *
 *  Unless required by applicable law or agreed to in writing, software
 *  distributed under the License is distributed on an "AS IS" BASIS,
 *  WITHOUT WARRANTIES OR CONDITIONS OF ANY KIND, either express or implied.
 *  See the License for the specific language governing permissions and
 *  limitations under the License.
 *
 *=========================================================================*/
// PointBasedDRRBenchmark: plastimatch drr (exact and uniform) on the same mu volume and view, each run as a child
// process timed from outside (wall, CPU and peak memory of the child) and compared with the exact references.
#include "pbdrrBenchmark.h"

#include <sys/resource.h>
#include <sys/wait.h>
#include <fcntl.h>
#include <spawn.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <sstream>

extern char ** environ;

namespace pbdrr
{
namespace bench
{
namespace
{
bool
OnPath(const std::string & exe)
{
  if (exe.find('/') != std::string::npos)
    return access(exe.c_str(), X_OK) == 0;
  const char *      path = std::getenv("PATH");
  std::stringstream dirs(path ? path : "");
  for (std::string dir; std::getline(dirs, dir, ':');)
  {
    if (!dir.empty() && access((dir + "/" + exe).c_str(), X_OK) == 0)
      return true;
  }
  return false;
}

struct ChildRun
{
  int    Status{ -1 };
  double Wall{ NaN }, Cpu{ NaN }, MaxRssMiB{ NaN };
};

/** Runs a program with stdout and stderr into logPath; wall time, and CPU time and peak memory of that child alone
 * (wait4). */
ChildRun
RunChild(const std::vector<std::string> & arguments, const std::string & logPath)
{
  std::vector<char *> argv;
  for (const auto & a : arguments)
    argv.push_back(const_cast<char *>(a.c_str()));
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 1, logPath.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&actions, 1, 2);
  ChildRun     run;
  pid_t        pid = 0;
  const double start = Now();
  if (posix_spawnp(&pid, argv[0], &actions, nullptr, argv.data(), environ) != 0)
  {
    posix_spawn_file_actions_destroy(&actions);
    return run;
  }
  posix_spawn_file_actions_destroy(&actions);
  int    status = 0;
  rusage usage{};
  wait4(pid, &status, 0, &usage);
  run.Wall = Now() - start;
  run.Status = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  run.Cpu = usage.ru_utime.tv_sec + usage.ru_stime.tv_sec + 1e-6 * (usage.ru_utime.tv_usec + usage.ru_stime.tv_usec);
  run.MaxRssMiB = usage.ru_maxrss / 1024.0;
  return run;
}

/** plastimatch's PFM: "Pf", "width height", scale (< 0: little endian), rows top first (the +vup edge, as here). */
Image
ReadPfm(const std::string & path, unsigned & width, unsigned & height)
{
  std::ifstream in(path, std::ios::binary);
  std::string   magic;
  double        scale = 0;
  in >> magic >> width >> height >> scale;
  in.get();
  if (!in || magic != "Pf")
    throw std::runtime_error("not a grey PFM: " + path);
  std::vector<float> values(size_t(width) * height);
  in.read(reinterpret_cast<char *>(values.data()), values.size() * sizeof(float));
  if (!in)
    throw std::runtime_error("truncated PFM: " + path);
  if (scale > 0) // big endian
  {
    for (float & v : values)
    {
      auto * b = reinterpret_cast<unsigned char *>(&v);
      std::swap(b[0], b[3]);
      std::swap(b[1], b[2]);
    }
  }
  return Image(values.begin(), values.end());
}

std::string
ReadFile(const std::string & path)
{
  std::ifstream     in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

std::string
Repr(double value)
{
  std::ostringstream text;
  text << std::setprecision(17) << value;
  return text.str();
}

/** The command line of plastimatch drr with `algorithm` (exact or uniform) for the view `g`, isocenter `iso`.
 * plastimatch 1.9.4 conventions (re-derived by benchmark/compare_plastimatch.sh): -y in radians, -r/-z/-c columns
 * first, values = line integral / 10 with -P none and mu in 1/mm, PFM rows top (+vup) first; the isocenter is the
 * volume centre, given with -o (plastimatch does not default to it). */
std::vector<std::string>
PlastimatchCommand(const Options &               options,
                   const std::string &           algorithm,
                   const Geometry &              g,
                   const itk::Point<double, 3> & iso,
                   const std::string &           prefix,
                   const std::string &           muPath)
{
  const double pi = 3.14159265358979323846;
  return { options.PlastimatchExe,
           "drr",
           "-A",
           "cpu",
           "-P",
           "none",
           "-i",
           algorithm,
           "-y",
           Repr(options.Gantry * pi / 180.0),
           "-r",
           std::to_string(g.Columns) + " " + std::to_string(g.Rows),
           "-z",
           Repr(g.Columns * g.Spacing) + " " + Repr(g.Rows * g.Spacing),
           "-c",
           Repr((g.Columns - 1) / 2.0) + " " + Repr((g.Rows - 1) / 2.0),
           "-o",
           Repr(iso[0]) + " " + Repr(iso[1]) + " " + Repr(iso[2]),
           "--sad",
           Repr(options.Sad),
           "--sid",
           Repr(options.Sid),
           "-t",
           "pfm",
           "-O",
           prefix,
           muPath };
}

/** Runs the command up to --runs times (once if the first run is over --repeat-limit) into row.Time; false, the row
 * failed, if a run exits with an error. */
bool
TimePlastimatch(const std::vector<std::string> & command,
                const std::string &              prefix,
                const Options &                  options,
                Row &                            row)
{
  std::vector<double> walls, cpus, renders;
  double              maxRss = 0;
  for (unsigned r = 0; r < options.Runs; ++r)
  {
    const ChildRun run = RunChild(command, prefix + "log.txt");
    if (run.Status != 0)
    {
      row.Status = "failed";
      row.Note = "exit status " + std::to_string(run.Status) + ", see " + prefix + "log.txt";
      return false;
    }
    walls.push_back(run.Wall);
    cpus.push_back(run.Cpu);
    maxRss = std::max(maxRss, run.MaxRssMiB);
    // "Total time: X secs": plastimatch's own time after the volume is read (render + write)
    const std::string log = ReadFile(prefix + "log.txt");
    const auto        at = log.rfind("Total time:");
    if (at != std::string::npos)
      renders.push_back(std::stod(log.substr(at + 11)));
    if (walls.front() > options.RepeatLimit)
      break;
  }
  row.Time.Runs = static_cast<unsigned>(walls.size());
  row.Time.Wall = Median(walls);
  row.Time.WallMin = *std::min_element(walls.begin(), walls.end());
  row.Time.WallMax = *std::max_element(walls.begin(), walls.end());
  row.Time.Cpu = Median(cpus);
  row.Time.PeakMiB = maxRss;
  row.Time.Render = Median(renders);
  row.Time.Load = row.Time.Wall - row.Time.Render;
  return true;
}
} // namespace

void
Benchmark::PlastimatchRows(const Row & base)
{
  if (!m_Options.Plastimatch)
    return;
  if (!OnPath(m_Options.PlastimatchExe))
  {
    std::cerr << "plastimatch: '" << m_Options.PlastimatchExe << "' not found on PATH, skipped" << std::endl;
    return;
  }
  const std::string muPath = m_Options.WorkDirectory + "/mu.mha";
  std::cerr << "plastimatch: writing " << muPath << std::endl;
  Write(m_Mu.GetPointer(), muPath);
  if (m_Options.Threads)
    setenv("OMP_NUM_THREADS", std::to_string(m_Options.Threads).c_str(), 1);
  const auto iso = itk::DRRProjectionGeometry::ComputeImageCenter(m_Mu);
  for (const std::string algorithm : { "exact", "uniform" })
    PlastimatchRow(algorithm, iso, muPath, base);
}

/** One plastimatch drr algorithm: timed runs, its image (x 10: plastimatch writes line integrals / 10) against the
 * references and the exact projectors' one-ray images. */
void
Benchmark::PlastimatchRow(const std::string &           algorithm,
                          const itk::Point<double, 3> & iso,
                          const std::string &           muPath,
                          const Row &                   base)
{
  const auto &                   g = m_Geometry;
  const std::string              work = m_Options.WorkDirectory;
  const std::string              prefix = work + "/plm_" + algorithm + "_";
  const std::vector<std::string> command = PlastimatchCommand(m_Options, algorithm, g, iso, prefix, muPath);
  Row                            row = base;
  row.Method = "plastimatch-" + algorithm;
  row.Model = algorithm == std::string("exact") ? "box" : "tent";
  std::ostringstream commandText;
  for (const auto & a : command)
    commandText << (a.find(' ') != std::string::npos ? "\"" + a + "\"" : a) << " ";
  if (!TimePlastimatch(command, prefix, m_Options, row))
  {
    Add(row);
    return;
  }
  unsigned w = 0, h = 0;
  Image    image = ReadPfm(prefix + "0000.pfm", w, h);
  if (w != g.Columns || h != g.Rows)
  {
    row.Status = "failed";
    row.Note = "plastimatch wrote " + std::to_string(w) + " x " + std::to_string(h);
    Add(row);
    return;
  }
  for (double & v : image)
    v *= 10.0;
  row.Note = "whole process (load_s: wall minus its 'Total time'); " + commandText.str();
  Add(row, &image, row.Model == "box" ? &m_BoxReference : &m_TentReference);
  Agreement(row.Method, "exact Siddon, 1 ray per pixel", image, m_Siddon1);
  Agreement(row.Method, "exact trilinear, 1 ray per pixel", image, m_Trilinear1);
  if (m_Options.SaveImages)
    WriteProjection(image, g.Columns, g.Rows, g.Spacing, work + "/plastimatch_" + algorithm + ".mha");
}
} // namespace bench
} // namespace pbdrr
