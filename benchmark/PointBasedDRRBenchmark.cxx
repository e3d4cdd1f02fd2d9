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
// The speed/accuracy trade of one DRR view of one volume (docs/design.md section 7): every registered sampler with
// every kernel and splat at a ladder of sample counts, the exact projectors, ITK's ray caster and plastimatch, each
// timed (wall, CPU, peak memory) and compared with the exact pixel-averaged reference. Writes OUTDIR/NAME.csv (one
// row per method and setting), OUTDIR/NAME.md (the same as Markdown tables) and OUTDIR/NAME_agreement.csv.
//
//   PointBasedDRRBenchmark INPUT OUTDIR [--mode trade|scaling|collimated] [options]   (--help lists them)
//
// Modes: trade (default) the table above; scaling: time against samples, volume size and detector size;
// collimated: a small detector centred on the view against the same crop of the full render.
// Geometry: plastimatch's drr convention (DRRProjectionGeometry), isocenter at the volume centre, square detector.
// docs/benchmark.md explains every column; scripts/benchmark.sh runs the configurations of the issue.
#include "itkPointBasedDRRImageFilter.h"
#include "itkExactDRRImageFilter.h"
#include "itkDRRSamplerFactory.h"
#include "pbdrrVolumeLoader.h"

#include "itkIdentityTransform.h"
#include "itkImageFileWriter.h"
#include "itkNearestNeighborInterpolateImageFunction.h"
#include "itkRayCastInterpolateImageFunction.h"
#include "itkResampleImageFilter.h"

#include <sys/resource.h>
#include <sys/wait.h>
#include <fcntl.h>
#include <spawn.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <functional>
#include <iomanip>
#include <iostream>
#include <limits>
#include <map>
#include <sstream>
#include <string>
#include <vector>

extern char ** environ;

namespace
{
using VolumeType = pbdrr::VolumeType; // float voxels (HU for CT)
using MuImageType = itk::Image<float, 3>;
using ProjectionType = itk::Image<float, 2>;
using KernelEnum = itk::PointBasedDRREnums::ReconstructionKernel;
using SplatEnum = itk::PointBasedDRREnums::Splat;
using ExactType = itk::ExactDRRImageFilter<VolumeType, ProjectionType>;
using PointFilterType = itk::PointBasedDRRImageFilter<VolumeType, ProjectionType>;
using Image = std::vector<double>; // a projection, columns fastest
constexpr double NaN = std::numeric_limits<double>::quiet_NaN();

// ------------------------------------------------------------------------------------------------------ options
struct Options
{
  std::string              Input, OutputDirectory, Mode{ "trade" }, Name, WorkDirectory, Description;
  unsigned int             Columns{ 256 }, Rows{ 0 };
  double                   Spacing{ 2.4 }, Gantry{ 90.0 }, Sad{ 1000.0 }, Sid{ 1500.0 };
  std::vector<std::string> Samplers;
  std::vector<KernelEnum>  Kernels{ KernelEnum::Box, KernelEnum::Tent };
  std::vector<SplatEnum>   Splats{ SplatEnum::Nearest, SplatEnum::Bilinear };
  double                   MinSamples{ 1e5 }, MaxSamples{ 1e9 }, Budget{ 60.0 }, RepeatLimit{ 10.0 };
  unsigned int             Runs{ 3 }, ReferenceRays{ 8 }, Threads{ 0 };
  std::vector<unsigned>    ExactRays{ 1, 2, 4 };
  bool                     Itk{ true }, Plastimatch{ true }, SaveImages{ false };
  std::string              PlastimatchExe{ "plastimatch" };
  uint64_t                 Seed{ 1 };
  double                   ScalingSamples{ 1e7 };
  std::vector<double>      VolumeFractions{ 0.125, 0.25, 0.5, 1.0 };
  std::vector<unsigned>    DetectorColumns{ 64, 128, 256, 512, 1024 };
  unsigned int             CollimatedColumns{ 64 };
};

const char * Usage = R"(usage: PointBasedDRRBenchmark INPUT OUTDIR [options]

INPUT: a DICOM series directory or a volume ITK reads (HU). OUTDIR: where NAME.csv, NAME.md and
NAME_agreement.csv go (created).

  --mode trade|scaling|collimated   what to measure (default trade)
  --name NAME                 file names in OUTDIR (default: the mode)
  --description TEXT          a line for the Markdown header (e.g. the git commit)
  --cols N --rows N           detector size (default 256 x cols)
  --spacing MM                detector pixel size (default 2.4)
  --gantry DEG --sad MM --sid MM   geometry (default 90, 1000, 1500); isocenter: the volume centre
  --samplers a,b,...          default: every sampler of itk::DRRSamplerFactory::GetEntries()
  --kernels box,tent          --splats nearest,bilinear    (default: both of each)
  --min-samples N --max-samples N   sample ladder 1, 3, 10, 30, ... x 10^k (default 1e5 .. 1e9)
  --budget S                  skip a setting whose run is predicted (previous rung x N / N_prev) to take longer
                              than S seconds (default 60)
  --runs R                    timing runs per setting, the median is reported (default 3)
  --repeat-limit S            a setting whose first run took longer than S seconds is not repeated (default 10)
  --reference-rays K          K x K rays per pixel for the exact references (default 8)
  --exact-rays 1,2,4          rays per pixel side of the exact projector rows
  --no-itk --no-plastimatch   leave out ITK's ray caster / plastimatch drr
  --plastimatch EXE           plastimatch executable (default: plastimatch on PATH)
  --work DIR                  scratch directory for plastimatch (default OUTDIR/NAME_work)
  --seed S                    seed of every point render (default 1)
  --threads T                 ITK threads and OMP_NUM_THREADS of plastimatch (default: ITK's default)
  --save-images               write the references and the ITK/plastimatch images as .mha into the work directory
 scaling mode:
  --scaling-samples N         samples of the volume- and detector-size sweeps (default 1e7)
  --volume-fractions f,...    fractions of the number of voxels (default 0.125,0.25,0.5,1)
  --detector-cols c,...       detector sizes at the same field of view (default 64,128,256,512,1024)
 collimated mode:
  --collimated-cols C         the small detector (C x C at the same pixel size, default 64)
)";

std::vector<std::string>
SplitList(const std::string & text)
{
  std::vector<std::string> items;
  std::stringstream        list(text);
  for (std::string item; std::getline(list, item, ',');)
  {
    if (!item.empty())
    {
      items.push_back(item);
    }
  }
  return items;
}

double
ParseNumber(const std::string & text, const std::string & option)
{
  size_t used = 0;
  double value = NaN;
  try
  {
    value = std::stod(text, &used);
  }
  catch (const std::exception &)
  {
    used = 0;
  }
  if (used != text.size() || !std::isfinite(value))
  {
    throw std::runtime_error("option " + option + ": not a number: '" + text + "'");
  }
  return value;
}

Options
ParseOptions(int argc, char * argv[])
{
  Options                  options;
  std::vector<std::string> positional;
  for (int i = 1; i < argc; ++i)
  {
    const std::string arg = argv[i];
    auto              value = [&]() -> std::string {
      if (i + 1 >= argc)
      {
        throw std::runtime_error("option " + arg + " needs a value");
      }
      return argv[++i];
    };
    auto number = [&]() { return ParseNumber(value(), arg); };
    if (arg == "-h" || arg == "--help")
    {
      std::cout << Usage;
      std::exit(0);
    }
    else if (arg == "--mode")
      options.Mode = value();
    else if (arg == "--name")
      options.Name = value();
    else if (arg == "--description")
      options.Description = value();
    else if (arg == "--cols")
      options.Columns = static_cast<unsigned>(number());
    else if (arg == "--rows")
      options.Rows = static_cast<unsigned>(number());
    else if (arg == "--spacing")
      options.Spacing = number();
    else if (arg == "--gantry")
      options.Gantry = number();
    else if (arg == "--sad")
      options.Sad = number();
    else if (arg == "--sid")
      options.Sid = number();
    else if (arg == "--samplers")
      options.Samplers = SplitList(value());
    else if (arg == "--kernels" || arg == "--splats")
    {
      const auto names = SplitList(value());
      if (arg == "--kernels")
        options.Kernels.clear();
      else
        options.Splats.clear();
      for (const auto & name : names)
      {
        if (arg == "--kernels" && (name == "box" || name == "tent"))
          options.Kernels.push_back(name == "box" ? KernelEnum::Box : KernelEnum::Tent);
        else if (arg == "--splats" && (name == "nearest" || name == "bilinear"))
          options.Splats.push_back(name == "nearest" ? SplatEnum::Nearest : SplatEnum::Bilinear);
        else
          throw std::runtime_error("option " + arg + ": unknown '" + name + "'");
      }
    }
    else if (arg == "--min-samples")
      options.MinSamples = number();
    else if (arg == "--max-samples")
      options.MaxSamples = number();
    else if (arg == "--budget")
      options.Budget = number();
    else if (arg == "--runs")
      options.Runs = std::max(1u, static_cast<unsigned>(number()));
    else if (arg == "--repeat-limit")
      options.RepeatLimit = number();
    else if (arg == "--reference-rays")
      options.ReferenceRays = std::max(1u, static_cast<unsigned>(number()));
    else if (arg == "--exact-rays" || arg == "--detector-cols")
    {
      std::vector<unsigned> list;
      for (const auto & item : SplitList(value()))
        list.push_back(static_cast<unsigned>(ParseNumber(item, arg)));
      (arg == "--exact-rays" ? options.ExactRays : options.DetectorColumns) = list;
    }
    else if (arg == "--no-itk")
      options.Itk = false;
    else if (arg == "--no-plastimatch")
      options.Plastimatch = false;
    else if (arg == "--plastimatch")
      options.PlastimatchExe = value();
    else if (arg == "--work")
      options.WorkDirectory = value();
    else if (arg == "--seed")
      options.Seed = static_cast<uint64_t>(number());
    else if (arg == "--threads")
      options.Threads = static_cast<unsigned>(number());
    else if (arg == "--save-images")
      options.SaveImages = true;
    else if (arg == "--scaling-samples")
      options.ScalingSamples = number();
    else if (arg == "--volume-fractions")
    {
      options.VolumeFractions.clear();
      for (const auto & item : SplitList(value()))
        options.VolumeFractions.push_back(ParseNumber(item, arg));
    }
    else if (arg == "--collimated-cols")
      options.CollimatedColumns = static_cast<unsigned>(number());
    else if (!arg.empty() && arg[0] == '-')
      throw std::runtime_error("unknown option " + arg + " (see --help)");
    else
      positional.push_back(arg);
  }
  if (positional.size() != 2)
  {
    throw std::runtime_error("expected INPUT and OUTDIR (see --help)");
  }
  options.Input = positional[0];
  options.OutputDirectory = positional[1];
  if (options.Mode != "trade" && options.Mode != "scaling" && options.Mode != "collimated")
  {
    throw std::runtime_error("unknown mode " + options.Mode);
  }
  if (options.Name.empty())
    options.Name = options.Mode;
  if (options.Rows == 0)
    options.Rows = options.Columns;
  if (options.WorkDirectory.empty())
    options.WorkDirectory = options.OutputDirectory + "/" + options.Name + "_work";
  if (options.Samplers.empty())
  {
    for (const auto & entry : itk::DRRSamplerFactory::GetEntries())
      options.Samplers.push_back(entry.Name);
  }
  return options;
}

/** 1, 3, 10, 30, ... x 10^k between min and max (inclusive). */
std::vector<uint64_t>
SampleLadder(double minimum, double maximum)
{
  std::vector<uint64_t> ladder;
  for (int decade = 0; decade <= 19; ++decade)
  {
    for (double mantissa : { 1.0, 3.0 })
    {
      const double n = mantissa * std::pow(10.0, decade);
      if (n >= minimum * (1 - 1e-9) && n <= maximum * (1 + 1e-9))
        ladder.push_back(static_cast<uint64_t>(std::llround(n)));
    }
  }
  return ladder;
}

const char *
KernelName(KernelEnum kernel)
{
  return kernel == KernelEnum::Box ? "box" : "tent";
}
const char *
SplatName(SplatEnum splat)
{
  return splat == SplatEnum::Nearest ? "nearest" : "bilinear";
}

// -------------------------------------------------------------------------------------- time, CPU and memory
double
Now()
{
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

double
CpuSeconds()
{
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_utime.tv_sec + usage.ru_stime.tv_sec + 1e-6 * (usage.ru_utime.tv_usec + usage.ru_stime.tv_usec);
}

/** A field of /proc/self/status in MiB (VmHWM, VmRSS); NaN if absent. */
double
StatusMiB(const std::string & key)
{
  std::ifstream status("/proc/self/status");
  for (std::string line; std::getline(status, line);)
  {
    if (line.compare(0, key.size() + 1, key + ":") == 0)
      return std::stod(line.substr(key.size() + 1)) / 1024.0;
  }
  return NaN;
}

/** Resets the peak resident set size (VmHWM) to the current one (Linux >= 4.0). */
void
ResetPeakMemory()
{
  std::ofstream clear("/proc/self/clear_refs");
  clear << "5";
}

double
Median(std::vector<double> values)
{
  if (values.empty())
    return NaN;
  std::sort(values.begin(), values.end());
  const size_t n = values.size();
  return n % 2 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

struct Timing
{
  unsigned int Runs{ 0 };
  double       Wall{ NaN }, WallMin{ NaN }, WallMax{ NaN }, Cpu{ NaN }, PeakMiB{ NaN }, ExtraMiB{ NaN };
  double       Render{ NaN }, Load{ NaN }; // subprocesses: what the program reports of its own time
};

/** Runs `render` up to `runs` times (once if the first run takes longer than repeatLimit): median wall and CPU time,
 * peak resident memory of the process during the runs, and its growth over the resident memory at the start. */
Timing
Measure(const std::function<void()> & render, unsigned int runs, double repeatLimit)
{
  ResetPeakMemory();
  const double        base = StatusMiB("VmRSS");
  std::vector<double> walls, cpus;
  for (unsigned int r = 0; r < runs; ++r)
  {
    const double cpu0 = CpuSeconds();
    const double wall0 = Now();
    render();
    walls.push_back(Now() - wall0);
    cpus.push_back(CpuSeconds() - cpu0);
    if (walls.front() > repeatLimit)
      break;
  }
  Timing timing;
  timing.Runs = static_cast<unsigned>(walls.size());
  timing.Wall = Median(walls);
  timing.WallMin = *std::min_element(walls.begin(), walls.end());
  timing.WallMax = *std::max_element(walls.begin(), walls.end());
  timing.Cpu = Median(cpus);
  timing.PeakMiB = StatusMiB("VmHWM");
  timing.ExtraMiB = timing.PeakMiB - base;
  return timing;
}

/** One untimed render, so that one-time work a filter may do in its first Update (beyond the preprocessing that is
 * measured on its own) stays out of the timings; returns its wall time, reported as first_render_s. */
template <typename TFilter>
double
WarmUp(TFilter * filter)
{
  const double start = Now();
  filter->Modified();
  filter->Update();
  return Now() - start;
}

// ------------------------------------------------------------------------------------------------- errors
struct Errors
{
  double Nrmse{ NaN };    // RMSE / (max - min of the reference)
  double MaxError{ NaN }; // max |error| / (max - min of the reference)
  double SumRatio{ NaN }; // sum(image) / sum(reference): the bias
  double Pearson{ NaN };
};

Errors
Compare(const Image & image, const Image & reference)
{
  Errors e;
  if (image.size() != reference.size() || reference.empty())
    return e;
  double       squared = 0, worst = 0, sum = 0, referenceSum = 0, sxx = 0, syy = 0, sxy = 0;
  const auto   range = std::minmax_element(reference.begin(), reference.end());
  const double n = static_cast<double>(reference.size());
  double       meanA = 0, meanR = 0;
  for (size_t p = 0; p < reference.size(); ++p)
  {
    meanA += image[p];
    meanR += reference[p];
  }
  meanA /= n;
  meanR /= n;
  for (size_t p = 0; p < reference.size(); ++p)
  {
    const double d = image[p] - reference[p];
    squared += d * d;
    worst = std::max(worst, std::abs(d));
    sum += image[p];
    referenceSum += reference[p];
    sxx += (image[p] - meanA) * (image[p] - meanA);
    syy += (reference[p] - meanR) * (reference[p] - meanR);
    sxy += (image[p] - meanA) * (reference[p] - meanR);
  }
  const double span = *range.second - *range.first;
  e.Nrmse = std::sqrt(squared / n) / span;
  e.MaxError = worst / span;
  e.SumRatio = sum / referenceSum;
  e.Pearson = sxy / std::sqrt(sxx * syy);
  return e;
}

template <typename TImage>
Image
ToVector(const TImage * image)
{
  const size_t n = image->GetBufferedRegion().GetNumberOfPixels();
  return Image(image->GetBufferPointer(), image->GetBufferPointer() + n);
}

/** The columns [c0, c0 + cols) and rows [r0, r0 + rows) of an image `width` columns wide. */
Image
Crop(const Image & image, unsigned width, unsigned c0, unsigned r0, unsigned cols, unsigned rows)
{
  Image crop;
  crop.reserve(size_t(cols) * rows);
  for (unsigned r = 0; r < rows; ++r)
    for (unsigned c = 0; c < cols; ++c)
      crop.push_back(image[size_t(r0 + r) * width + c0 + c]);
  return crop;
}

// ------------------------------------------------------------------------------------------------------ rows
struct Row
{
  std::string Config, Sweep, Method, Sampler, Kernel, Splat, Model, Status{ "ok" }, Note;
  double      X{ NaN };
  uint64_t    Voxels{ 0 }, Samples{ 0 };
  unsigned    Columns{ 0 }, DetectorRows{ 0 }, Rays{ 0 };
  Timing      Time;
  double      HuToMu{ NaN }, Tables{ NaN }, TableBytes{ NaN }, TableBytesPerVoxel{ NaN };
  double      FirstRender{ NaN }; // the untimed first render of the filter at this row's setting
  Errors      Own, Box;
};

std::string
Format(double value, const char * format = "%.4g")
{
  if (!std::isfinite(value))
    return "";
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, format, value);
  return buffer;
}

std::string
CsvField(const std::string & text)
{
  if (text.find_first_of(",\"\n") == std::string::npos)
    return text;
  std::string quoted = "\"";
  for (char c : text)
    quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
  return quoted + "\"";
}

const char * CsvHeader =
  "config,sweep,x,voxels,cols,rows,method,sampler,kernel,splat,samples,rays_per_pixel,model,status,runs,wall_s,"
  "wall_min_s,wall_max_s,cpu_s,peak_rss_mib,peak_extra_mib,hu_to_mu_s,tables_s,table_bytes,"
  "table_bytes_per_nonair_voxel,load_s,render_s,first_render_s,nrmse,max_error,sum_ratio,nrmse_box,max_error_box,sum_"
  "ratio_box,"
  "wall_x_nrmse2,note";

void
WriteCsv(const std::string & path, const std::vector<Row> & rows)
{
  std::ofstream out(path);
  out << CsvHeader << "\n";
  for (const Row & r : rows)
  {
    const auto g = [](double v) { return Format(v, "%.6g"); };
    out << CsvField(r.Config) << "," << r.Sweep << "," << g(r.X) << "," << (r.Voxels ? std::to_string(r.Voxels) : "")
        << "," << r.Columns << "," << r.DetectorRows << "," << r.Method << "," << CsvField(r.Sampler) << "," << r.Kernel
        << "," << r.Splat << "," << (r.Samples ? std::to_string(r.Samples) : "") << ","
        << (r.Rays ? std::to_string(r.Rays * r.Rays) : "") << "," << r.Model << "," << CsvField(r.Status) << ","
        << (r.Time.Runs ? std::to_string(r.Time.Runs) : "") << "," << g(r.Time.Wall) << "," << g(r.Time.WallMin) << ","
        << g(r.Time.WallMax) << "," << g(r.Time.Cpu) << "," << Format(r.Time.PeakMiB, "%.1f") << ","
        << Format(r.Time.ExtraMiB, "%.1f") << "," << g(r.HuToMu) << "," << g(r.Tables) << "," << g(r.TableBytes) << ","
        << g(r.TableBytesPerVoxel) << "," << g(r.Time.Load) << "," << g(r.Time.Render) << "," << g(r.FirstRender) << ","
        << g(r.Own.Nrmse) << "," << g(r.Own.MaxError) << "," << Format(r.Own.SumRatio, "%.7f") << "," << g(r.Box.Nrmse)
        << "," << g(r.Box.MaxError) << "," << Format(r.Box.SumRatio, "%.7f") << ","
        << g(r.Time.Wall * r.Own.Nrmse * r.Own.Nrmse) << "," << CsvField(r.Note) << "\n";
  }
}

std::string
SamplesText(uint64_t n)
{
  if (n == 0)
    return "";
  const int    e = static_cast<int>(std::floor(std::log10(static_cast<double>(n)) + 1e-9));
  const double m = n / std::pow(10.0, e);
  return Format(m, "%.3g") + "e" + std::to_string(e);
}

// --------------------------------------------------------------------------------------------- subprocesses
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

// --------------------------------------------------------------------------------------------------- volumes
itk::Point<double, 3>
VolumeCentre(const itk::ImageBase<3> * volume)
{
  const auto                      region = volume->GetLargestPossibleRegion();
  itk::ContinuousIndex<double, 3> centreIndex;
  for (unsigned int a = 0; a < 3; ++a)
    centreIndex[a] = region.GetIndex()[a] + (region.GetSize()[a] - 1) / 2.0;
  itk::Point<double, 3> centre;
  volume->TransformContinuousIndexToPhysicalPoint(centreIndex, centre);
  return centre;
}

/** mu (1/mm) exactly as the DRR filters compute it (their attenuation volume), on the input's grid. */
MuImageType::Pointer
MuImage(const VolumeType * input, const itk::DRRAttenuationVolume * attenuation)
{
  auto mu = MuImageType::New();
  mu->CopyInformation(input);
  mu->SetRegions(input->GetLargestPossibleRegion());
  mu->Allocate();
  std::copy(
    attenuation->GetMuBuffer(), attenuation->GetMuBuffer() + attenuation->GetNumberOfVoxels(), mu->GetBufferPointer());
  return mu;
}

/** The same voxels at the same physical places with an identity direction matrix, for programs that ignore the
 * direction (ITK's ray caster; plastimatch is given the same). Only for axis-aligned directions (a signed
 * permutation): returns null otherwise. */
MuImageType::Pointer
WithIdentityDirection(const MuImageType * image)
{
  const auto & direction = image->GetDirection();
  bool         identity = true;
  int          axisOf[3]; // physical axis of index axis a
  double       signOf[3];
  for (unsigned a = 0; a < 3; ++a)
  {
    axisOf[a] = -1;
    for (unsigned p = 0; p < 3; ++p)
    {
      const double d = direction[p][a];
      if (std::abs(std::abs(d) - 1.0) < 1e-6)
      {
        axisOf[a] = static_cast<int>(p);
        signOf[a] = d > 0 ? 1.0 : -1.0;
      }
      else if (std::abs(d) > 1e-6)
        return nullptr;
      if (std::abs(d - (p == a ? 1.0 : 0.0)) > 1e-12)
        identity = false;
    }
    if (axisOf[a] < 0)
      return nullptr;
  }
  if (identity)
    return const_cast<MuImageType *>(image);
  const auto               size = image->GetLargestPossibleRegion().GetSize();
  MuImageType::SizeType    newSize;
  MuImageType::SpacingType newSpacing;
  MuImageType::PointType   newOrigin;
  for (unsigned a = 0; a < 3; ++a)
  {
    const int p = axisOf[a];
    newSize[p] = size[a];
    newSpacing[p] = image->GetSpacing()[a];
    newOrigin[p] = image->GetOrigin()[p] + (signOf[a] < 0 ? -(size[a] - 1.0) * image->GetSpacing()[a] : 0.0);
  }
  auto out = MuImageType::New();
  out->SetRegions(newSize);
  out->SetSpacing(newSpacing);
  out->SetOrigin(newOrigin);
  out->Allocate();
  const float *          in = image->GetBufferPointer();
  float *                o = out->GetBufferPointer();
  MuImageType::IndexType i;
  for (i[2] = 0; i[2] < static_cast<long>(size[2]); ++i[2])
    for (i[1] = 0; i[1] < static_cast<long>(size[1]); ++i[1])
      for (i[0] = 0; i[0] < static_cast<long>(size[0]); ++i[0])
      {
        MuImageType::IndexType j;
        for (unsigned a = 0; a < 3; ++a)
          j[axisOf[a]] = signOf[a] > 0 ? i[a] : static_cast<long>(size[a]) - 1 - i[a];
        o[j[0] + newSize[0] * (j[1] + newSize[1] * j[2])] = in[i[0] + size[0] * (i[1] + size[1] * i[2])];
      }
  return out;
}

/** Voxels with mu > 0 under the filter's transfer function, counted on the input (the attenuation volume may not hold
 * mu at all: level samplers never ask for it). */
uint64_t
CountNonAir(const VolumeType * volume, const itk::DRRTransferFunction * transfer)
{
  const float * values = volume->GetBufferPointer();
  const size_t  n = volume->GetBufferedRegion().GetNumberOfPixels();
  return static_cast<uint64_t>(
    std::count_if(values, values + n, [transfer](float v) { return transfer->Evaluate(v) > 0.0; }));
}

/** The volume with one layer of zero voxels all around (same physical voxel positions). */
MuImageType::Pointer
PadWithZeros(const MuImageType * image)
{
  const auto            size = image->GetLargestPossibleRegion().GetSize();
  MuImageType::SizeType padded;
  for (unsigned a = 0; a < 3; ++a)
    padded[a] = size[a] + 2;
  auto out = MuImageType::New();
  out->SetRegions(padded);
  out->SetSpacing(image->GetSpacing());
  out->SetDirection(image->GetDirection());
  MuImageType::IndexType minusOne;
  minusOne.Fill(-1);
  MuImageType::PointType origin;
  image->TransformIndexToPhysicalPoint(minusOne, origin);
  out->SetOrigin(origin);
  out->Allocate();
  out->FillBuffer(0.0f);
  const float * in = image->GetBufferPointer();
  float *       o = out->GetBufferPointer();
  for (size_t k = 0; k < size[2]; ++k)
    for (size_t j = 0; j < size[1]; ++j)
      std::copy(in + size[0] * (j + size[1] * k),
                in + size[0] * (j + 1 + size[1] * k),
                o + 1 + padded[0] * (j + 1 + padded[1] * (k + 1)));
  return out;
}

/** The volume resampled (nearest neighbour, so HU stay integers) to about `fraction` of its voxels over the same
 * box: size per axis scaled by fraction^(1/3). */
VolumeType::Pointer
ResampleToFraction(const VolumeType * volume, double fraction)
{
  if (std::abs(fraction - 1.0) < 1e-9)
    return const_cast<VolumeType *>(volume);
  const double            scale = std::cbrt(fraction);
  const auto              size = volume->GetLargestPossibleRegion().GetSize();
  VolumeType::SizeType    newSize;
  VolumeType::SpacingType newSpacing;
  for (unsigned a = 0; a < 3; ++a)
  {
    newSize[a] = std::max<itk::SizeValueType>(1, std::lround(size[a] * scale));
    newSpacing[a] = volume->GetSpacing()[a] * size[a] / newSize[a];
  }
  // same box: corner = origin - D (spacing / 2)
  itk::ContinuousIndex<double, 3> corner;
  corner.Fill(-0.5);
  VolumeType::PointType cornerPoint;
  volume->TransformContinuousIndexToPhysicalPoint(corner, cornerPoint);
  VolumeType::PointType origin;
  for (unsigned r = 0; r < 3; ++r)
  {
    origin[r] = cornerPoint[r];
    for (unsigned c = 0; c < 3; ++c)
      origin[r] += volume->GetDirection()[r][c] * 0.5 * newSpacing[c];
  }
  using ResampleType = itk::ResampleImageFilter<VolumeType, VolumeType>;
  auto resample = ResampleType::New();
  resample->SetInput(volume);
  resample->SetInterpolator(itk::NearestNeighborInterpolateImageFunction<VolumeType, double>::New());
  resample->SetSize(newSize);
  resample->SetOutputSpacing(newSpacing);
  resample->SetOutputOrigin(origin);
  resample->SetOutputDirection(volume->GetDirection());
  resample->SetDefaultPixelValue(-1000);
  resample->Update();
  VolumeType::Pointer out = resample->GetOutput();
  out->DisconnectPipeline();
  return out;
}

template <typename TImage>
void
Write(const TImage * image, const std::string & path)
{
  auto writer = itk::ImageFileWriter<TImage>::New();
  writer->SetInput(image);
  writer->SetFileName(path);
  writer->Update();
}

void
WriteProjection(const Image & values, unsigned cols, unsigned rows, double spacing, const std::string & path)
{
  auto image = ProjectionType::New();
  image->SetRegions(ProjectionType::SizeType{ { cols, rows } });
  image->SetSpacing(spacing);
  image->Allocate();
  std::copy(values.begin(), values.end(), image->GetBufferPointer());
  Write(image.GetPointer(), path);
}

// ------------------------------------------------------------------------------------------------ the bench
struct Geometry
{
  unsigned Columns, Rows;
  double   Spacing;
};

class Benchmark
{
public:
  explicit Benchmark(Options options) : m_Options(std::move(options)) {}

  int
  Run();

private:
  // set up
  void
  Load();
  itk::DRRProjectionGeometry::Pointer
  MakeGeometry(const VolumeType * volume, unsigned cols, unsigned rows, double spacing) const;
  std::string
  GeometryText(const Geometry & g) const;

  // methods
  Image
  ExactImage(ExactType * filter) const
  {
    return ToVector(filter->GetOutput());
  }
  void
  Reference(const VolumeType *           volume,
            itk::DRRProjectionGeometry * geometry,
            KernelEnum                   kernel,
            Image &                      reference,
            Image *                      oneRay,
            MuImageType::Pointer *       mu,
            Row                          base);
  void
  ExactRows(const VolumeType *                          volume,
            itk::DRRProjectionGeometry *                geometry,
            KernelEnum                                  kernel,
            Row                                         base,
            const std::function<Image(const Image &)> & view = nullptr);
  Image
  ItkRayCast(const MuImageType * mu, const itk::DRRProjectionGeometry * geometry, Timing * timing) const;
  void
  PlastimatchRows(const Row & base);
  void
  SamplerRows(const std::string & samplerName, const VolumeType * volume, Row base);

  // modes
  void
  Trade();
  void
  Scaling();
  void
  Collimated();

  void
  Add(Row row, const Image * image = nullptr, const Image * ownReference = nullptr)
  {
    if (image && ownReference)
      row.Own = Compare(*image, *ownReference);
    if (image && !m_BoxReference.empty() && image->size() == m_BoxReference.size())
      row.Box = Compare(*image, m_BoxReference);
    std::cerr << "  " << std::left << std::setw(11) << row.Sweep << std::setw(20) << row.Method << std::setw(14)
              << row.Sampler << std::setw(5) << row.Kernel << " " << std::setw(9) << row.Splat << std::setw(7)
              << SamplesText(row.Samples)
              << (row.Rays ? std::to_string(row.Rays) + "x" + std::to_string(row.Rays) + " rays " : "") << row.Status
              << "  " << Format(row.Time.Wall, "%.3g") << " s  NRMSE " << Format(row.Own.Nrmse, "%.3g") << std::right
              << std::endl;
    m_Rows.push_back(row);
  }
  void
  Agreement(const std::string & what, const std::string & against, const Image & a, const Image & b)
  {
    const Errors e = Compare(a, b);
    m_Agreement.push_back({ what, against, e });
    std::cerr << "  agreement: " << what << " vs " << against << ": NRMSE " << Format(e.Nrmse, "%.3g") << ", sum ratio "
              << Format(e.SumRatio, "%.6f") << std::endl;
  }
  void
  WriteOutputs() const;
  std::string
  MachineText() const;

  struct AgreementRow
  {
    std::string What, Against;
    Errors      E;
  };

  Options                   m_Options;
  VolumeType::Pointer       m_Volume;
  double                    m_LoadSeconds{ NaN };
  std::string               m_VolumeText;
  uint64_t                  m_NonAirVoxels{ 0 };
  MuImageType::Pointer      m_Mu; // identity direction, for ITK and plastimatch
  Image                     m_BoxReference, m_TentReference, m_Siddon1, m_Trilinear1;
  Geometry                  m_Geometry{};
  std::vector<Row>          m_Rows;
  std::vector<AgreementRow> m_Agreement;
  std::string               m_LoadBefore, m_LoadAfter;
  double                    m_Started{ Now() };
};

std::string
LoadAverage()
{
  std::ifstream in("/proc/loadavg");
  std::string   a, b, c;
  in >> a >> b >> c;
  return a + " " + b + " " + c;
}

std::string
Benchmark::MachineText() const
{
  std::string   model = "?";
  std::ifstream cpuinfo("/proc/cpuinfo");
  for (std::string line; std::getline(cpuinfo, line);)
  {
    if (line.compare(0, 10, "model name") == 0)
    {
      model = line.substr(line.find(':') + 2);
      break;
    }
  }
  double        memory = NaN;
  std::ifstream meminfo("/proc/meminfo");
  for (std::string line; std::getline(meminfo, line);)
  {
    if (line.compare(0, 9, "MemTotal:") == 0)
      memory = std::stod(line.substr(9)) / 1048576.0;
  }
  std::ostringstream text;
  text << model << ", " << sysconf(_SC_NPROCESSORS_ONLN) << " cores, " << Format(memory, "%.1f") << " GiB; ITK threads "
       << itk::MultiThreaderBase::GetGlobalDefaultNumberOfThreads();
  return text.str();
}

void
Benchmark::Load()
{
  const double start = Now();
  m_Volume = pbdrr::LoadVolume(m_Options.Input, "").Image;
  m_LoadSeconds = Now() - start;
  const auto         size = m_Volume->GetLargestPossibleRegion().GetSize();
  std::ostringstream text;
  text << size[0] << " x " << size[1] << " x " << size[2] << " voxels of " << Format(m_Volume->GetSpacing()[0], "%.4g")
       << " x " << Format(m_Volume->GetSpacing()[1], "%.4g") << " x " << Format(m_Volume->GetSpacing()[2], "%.4g")
       << " mm";
  const auto & d = m_Volume->GetDirection();
  bool         identity = true;
  for (unsigned r = 0; r < 3; ++r)
    for (unsigned c = 0; c < 3; ++c)
      identity = identity && std::abs(d[r][c] - (r == c ? 1.0 : 0.0)) < 1e-12;
  text << (identity ? ", identity direction" : ", direction not identity");
  m_VolumeText = text.str();
  std::cerr << "volume " << m_Options.Input << ": " << m_VolumeText << ", loaded in " << Format(m_LoadSeconds, "%.3g")
            << " s" << std::endl;
}

itk::DRRProjectionGeometry::Pointer
Benchmark::MakeGeometry(const VolumeType * volume, unsigned cols, unsigned rows, double spacing) const
{
  auto geometry = itk::DRRProjectionGeometry::New();
  geometry->SetGantryAngleInDegrees(m_Options.Gantry);
  geometry->SetSourceToIsocenterDistance(m_Options.Sad);
  geometry->SetSourceToDetectorDistance(m_Options.Sid);
  geometry->SetIsocenter(VolumeCentre(volume));
  geometry->SetDetectorSize({ { cols, rows } });
  geometry->SetDetectorSpacing(itk::Vector<double, 2>(spacing));
  geometry->VerifyGeometry();
  return geometry;
}

std::string
Benchmark::GeometryText(const Geometry & g) const
{
  std::ostringstream text;
  text << g.Columns << " x " << g.Rows << " pixels of " << g.Spacing << " mm, gantry " << m_Options.Gantry
       << " deg, SAD " << m_Options.Sad << " mm, SID " << m_Options.Sid << " mm, isocenter at the volume centre";
  return text.str();
}

/** The exact pixel-averaged reference of one model, timed (one run); optionally its one-ray image and the mu volume
 * the filter integrates. */
void
Benchmark::Reference(const VolumeType *           volume,
                     itk::DRRProjectionGeometry * geometry,
                     KernelEnum                   kernel,
                     Image &                      reference,
                     Image *                      oneRay,
                     MuImageType::Pointer *       mu,
                     Row                          base)
{
  auto filter = ExactType::New();
  filter->SetInput(volume);
  filter->SetGeometry(geometry);
  filter->SetReconstructionKernel(kernel);
  const double start = Now();
  filter->GetAttenuationVolume();
  const double huToMu = Now() - start;
  if (mu)
    *mu = MuImage(volume, filter->GetAttenuationVolume());
  if (volume == m_Volume.GetPointer())
    if (m_NonAirVoxels == 0)
      m_NonAirVoxels = CountNonAir(volume, filter->GetTransferFunction());
  if (oneRay)
  {
    filter->SetRaysPerPixelSide(1);
    filter->Update();
    *oneRay = ExactImage(filter);
  }
  filter->SetRaysPerPixelSide(m_Options.ReferenceRays);
  base.Method = "reference";
  base.Kernel = KernelName(kernel);
  base.Model = KernelName(kernel);
  base.Rays = m_Options.ReferenceRays;
  base.HuToMu = huToMu;
  base.Time = Measure([&] { filter->Update(); }, 1, 0.0);
  reference = ExactImage(filter);
  base.Note = "exact pixel average (" + std::to_string(base.Rays * base.Rays) + " rays per pixel)";
  Add(base);
}

/** Exact projector rows at the --exact-rays counts; `view` maps the rendered image to the compared pixels. */
void
Benchmark::ExactRows(const VolumeType *                          volume,
                     itk::DRRProjectionGeometry *                geometry,
                     KernelEnum                                  kernel,
                     Row                                         base,
                     const std::function<Image(const Image &)> & view)
{
  auto filter = ExactType::New();
  filter->SetInput(volume);
  filter->SetGeometry(geometry);
  filter->SetReconstructionKernel(kernel);
  const double start = Now();
  filter->GetAttenuationVolume();
  base.HuToMu = Now() - start;
  filter->SetRaysPerPixelSide(1);
  const double  first = WarmUp(filter.GetPointer());
  const Image & own = kernel == KernelEnum::Box ? m_BoxReference : m_TentReference;
  for (unsigned rays : m_Options.ExactRays)
  {
    Row row = base;
    row.Method = kernel == KernelEnum::Box ? "exact-siddon" : "exact-trilinear";
    row.Kernel = KernelName(kernel);
    row.Model = KernelName(kernel);
    row.Rays = rays;
    row.FirstRender = rays == 1 ? first : NaN;
    filter->SetRaysPerPixelSide(rays);
    row.Time = Measure(
      [&] {
        filter->Modified();
        filter->Update();
      },
      m_Options.Runs,
      m_Options.RepeatLimit);
    Image image = ExactImage(filter);
    if (view)
      image = view(image);
    Add(row, &image, own.empty() ? nullptr : &own);
  }
}

/** ITK's ray caster as in ITK's Examples/Filtering/DigitallyReconstructedRadiograph1.cxx: a ResampleImageFilter whose
 * interpolator is an itk::RayCastInterpolateImageFunction (threshold 0) with the focal point at the source, writing a
 * 3D image of one slice placed on the detector plane. The example rotates the volume with a CenteredEuler3DTransform
 * and keeps the camera on the z axis; here the volume stays put (identity transform) and the camera goes where the
 * geometry puts it: focal point = source S, output origin = centre of pixel (0, 0), direction (u, v, -n), spacing
 * (du, dv): the rays run from S through every pixel centre, as the exact projector's one-ray image. */
Image
Benchmark::ItkRayCast(const MuImageType * mu, const itk::DRRProjectionGeometry * geometry, Timing * timing) const
{
  using InterpolatorType = itk::RayCastInterpolateImageFunction<MuImageType, double>;
  using ResampleType = itk::ResampleImageFilter<MuImageType, MuImageType>;
  auto transform = itk::IdentityTransform<double, 3>::New();
  auto interpolator = InterpolatorType::New();
  interpolator->SetTransform(transform);
  interpolator->SetThreshold(0.0);
  InterpolatorType::InputPointType focalPoint;
  const auto                       source = geometry->GetSourcePosition();
  for (unsigned r = 0; r < 3; ++r)
    focalPoint[r] = source[r];
  interpolator->SetFocalPoint(focalPoint);

  auto resample = ResampleType::New();
  resample->SetInput(mu);
  resample->SetTransform(transform);
  resample->SetInterpolator(interpolator);
  resample->SetDefaultPixelValue(0.0f);
  const auto            size = geometry->GetDetectorSize();
  MuImageType::SizeType outputSize{ { size[0], size[1], 1 } };
  resample->SetSize(outputSize);
  MuImageType::SpacingType spacing;
  spacing[0] = geometry->GetDetectorSpacing()[0];
  spacing[1] = geometry->GetDetectorSpacing()[1];
  spacing[2] = 1.0;
  resample->SetOutputSpacing(spacing);
  const auto                 pixel00 = geometry->GetPixelCenter(0.0, 0.0);
  const auto                 u = geometry->GetColumnDirection();
  const auto                 v = geometry->GetRowDirection();
  const auto                 n = geometry->GetNormal();
  MuImageType::PointType     origin;
  MuImageType::DirectionType direction;
  for (unsigned r = 0; r < 3; ++r)
  {
    origin[r] = pixel00[r];
    direction[r][0] = u[r];
    direction[r][1] = v[r];
    direction[r][2] = -n[r];
  }
  resample->SetOutputOrigin(origin);
  resample->SetOutputDirection(direction);
  const auto render = [&] {
    resample->Modified();
    resample->Update();
  };
  if (timing)
    *timing = Measure(render, m_Options.Runs, m_Options.RepeatLimit);
  else
    render();
  return ToVector(resample->GetOutput());
}

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
  const std::string work = m_Options.WorkDirectory;
  const std::string muPath = work + "/mu.mha";
  std::cerr << "plastimatch: writing " << muPath << std::endl;
  Write(m_Mu.GetPointer(), muPath);
  if (m_Options.Threads)
    setenv("OMP_NUM_THREADS", std::to_string(m_Options.Threads).c_str(), 1);
  // plastimatch 1.9.4 conventions (re-derived by benchmark/compare_plastimatch.sh): -y in radians, -r/-z/-c columns
  // first, values = line integral / 10 with -P none and mu in 1/mm, PFM rows top (+vup) first; the isocenter is the
  // volume centre, given with -o (plastimatch does not default to it).
  const auto & g = m_Geometry;
  const auto   iso = VolumeCentre(m_Mu);
  const double pi = 3.14159265358979323846;
  for (const std::string algorithm : { "exact", "uniform" })
  {
    const std::string        prefix = work + "/plm_" + algorithm + "_";
    std::vector<std::string> command{ m_Options.PlastimatchExe,
                                      "drr",
                                      "-A",
                                      "cpu",
                                      "-P",
                                      "none",
                                      "-i",
                                      algorithm,
                                      "-y",
                                      Repr(m_Options.Gantry * pi / 180.0),
                                      "-r",
                                      std::to_string(g.Columns) + " " + std::to_string(g.Rows),
                                      "-z",
                                      Repr(g.Columns * g.Spacing) + " " + Repr(g.Rows * g.Spacing),
                                      "-c",
                                      Repr((g.Columns - 1) / 2.0) + " " + Repr((g.Rows - 1) / 2.0),
                                      "-o",
                                      Repr(iso[0]) + " " + Repr(iso[1]) + " " + Repr(iso[2]),
                                      "--sad",
                                      Repr(m_Options.Sad),
                                      "--sid",
                                      Repr(m_Options.Sid),
                                      "-t",
                                      "pfm",
                                      "-O",
                                      prefix,
                                      muPath };
    Row                      row = base;
    row.Method = "plastimatch-" + algorithm;
    row.Model = algorithm == std::string("exact") ? "box" : "tent";
    std::ostringstream commandText;
    for (const auto & a : command)
      commandText << (a.find(' ') != std::string::npos ? "\"" + a + "\"" : a) << " ";
    std::vector<double> walls, cpus, renders;
    double              maxRss = 0;
    bool                failed = false;
    for (unsigned r = 0; r < m_Options.Runs; ++r)
    {
      const ChildRun run = RunChild(command, prefix + "log.txt");
      if (run.Status != 0)
      {
        failed = true;
        row.Status = "failed";
        row.Note = "exit status " + std::to_string(run.Status) + ", see " + prefix + "log.txt";
        break;
      }
      walls.push_back(run.Wall);
      cpus.push_back(run.Cpu);
      maxRss = std::max(maxRss, run.MaxRssMiB);
      // "Total time: X secs": plastimatch's own time after the volume is read (render + write)
      const std::string log = ReadFile(prefix + "log.txt");
      const auto        at = log.rfind("Total time:");
      if (at != std::string::npos)
        renders.push_back(std::stod(log.substr(at + 11)));
      if (walls.front() > m_Options.RepeatLimit)
        break;
    }
    if (!failed)
    {
      row.Time.Runs = static_cast<unsigned>(walls.size());
      row.Time.Wall = Median(walls);
      row.Time.WallMin = *std::min_element(walls.begin(), walls.end());
      row.Time.WallMax = *std::max_element(walls.begin(), walls.end());
      row.Time.Cpu = Median(cpus);
      row.Time.PeakMiB = maxRss;
      row.Time.Render = Median(renders);
      row.Time.Load = row.Time.Wall - row.Time.Render;
      unsigned w = 0, h = 0;
      Image    image = ReadPfm(prefix + "0000.pfm", w, h);
      if (w != g.Columns || h != g.Rows)
      {
        row.Status = "failed";
        row.Note = "plastimatch wrote " + std::to_string(w) + " x " + std::to_string(h);
        Add(row);
        continue;
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
    else
      Add(row);
  }
}

/** Preprocessing and the sample ladder of one sampler with every kernel and splat. */
void
Benchmark::SamplerRows(const std::string & samplerName, const VolumeType * volume, Row base)
{
  auto filter = PointFilterType::New();
  filter->SetInput(volume);
  filter->SetGeometry(MakeGeometry(volume, m_Geometry.Columns, m_Geometry.Rows, m_Geometry.Spacing));
  filter->SetSampler(itk::DRRSamplerFactory::Create(samplerName));
  filter->SetSeed(m_Options.Seed);
  base.Sampler = samplerName;
  {
    Row    row = base;
    double huToMu = NaN, tables = NaN;
    row.Method = "preprocess";
    row.Time = Measure(
      [&] {
        double start = Now();
        filter->GetAttenuationVolume();
        huToMu = Now() - start;
        start = Now();
        filter->PrepareSampling();
        tables = Now() - start;
      },
      1,
      0.0);
    row.HuToMu = huToMu;
    row.Tables = tables;
    row.TableBytes = static_cast<double>(filter->GetSampler()->GetTableSizeInBytes());
    if (m_NonAirVoxels == 0)
      m_NonAirVoxels = CountNonAir(volume, filter->GetTransferFunction());
    row.TableBytesPerVoxel = row.TableBytes / std::max<uint64_t>(1, m_NonAirVoxels);
    row.Note = "HU->mu + sampling tables, once per volume";
    Add(row);
  }
  const auto ladder = SampleLadder(m_Options.MinSamples, m_Options.MaxSamples);
  for (KernelEnum kernel : m_Options.Kernels)
  {
    const Image & own = kernel == KernelEnum::Box ? m_BoxReference : m_TentReference;
    for (SplatEnum splat : m_Options.Splats)
    {
      filter->SetReconstructionKernel(kernel);
      filter->SetSplat(splat);
      filter->SetNumberOfSamples(ladder.empty() ? 1 : ladder.front());
      const double first = WarmUp(filter.GetPointer());
      double       previousTime = NaN;
      uint64_t     previousSamples = 0;
      for (uint64_t samples : ladder)
      {
        Row row = base;
        row.Method = "points";
        row.Kernel = KernelName(kernel);
        row.Splat = SplatName(splat);
        row.Model = KernelName(kernel);
        row.Samples = samples;
        row.FirstRender = samples == ladder.front() ? first : NaN;
        const double predicted = previousTime * samples / std::max<uint64_t>(1, previousSamples);
        if (std::isfinite(predicted) && predicted > m_Options.Budget)
        {
          row.Status = "skipped";
          row.Note = "predicted " + Format(predicted, "%.3g") + " s > budget " + Format(m_Options.Budget, "%g") + " s";
          previousTime = predicted; // the next rungs are predicted from this one
          previousSamples = samples;
          Add(row);
          continue;
        }
        filter->SetNumberOfSamples(samples);
        try
        {
          row.Time = Measure(
            [&] {
              filter->Modified();
              filter->Update();
            },
            m_Options.Runs,
            m_Options.RepeatLimit);
          const Image image = ToVector(filter->GetOutput());
          previousTime = row.Time.Wall;
          previousSamples = samples;
          Add(row, &image, own.empty() ? nullptr : &own);
        }
        catch (const std::exception & e)
        {
          row.Status = "failed";
          row.Note = e.what();
          Add(row);
        }
      }
    }
  }
}

void
Benchmark::Trade()
{
  const Geometry g{ m_Options.Columns, m_Options.Rows, m_Options.Spacing };
  m_Geometry = g;
  auto geometry = MakeGeometry(m_Volume, g.Columns, g.Rows, g.Spacing);
  Row  base;
  base.Config = m_Options.Name;
  base.Sweep = "trade";
  base.Voxels = m_Volume->GetLargestPossibleRegion().GetNumberOfPixels();
  base.Columns = g.Columns;
  base.DetectorRows = g.Rows;

  std::cerr << "references (" << m_Options.ReferenceRays << " x " << m_Options.ReferenceRays << " rays per pixel)"
            << std::endl;
  MuImageType::Pointer mu;
  Reference(m_Volume, geometry, KernelEnum::Box, m_BoxReference, &m_Siddon1, &mu, base);
  Reference(m_Volume, geometry, KernelEnum::Tent, m_TentReference, &m_Trilinear1, nullptr, base);
  m_Mu = WithIdentityDirection(mu);
  mu = nullptr;
  Agreement("exact Siddon, 1 ray per pixel", "exact trilinear, 1 ray per pixel", m_Siddon1, m_Trilinear1);
  Agreement("reference box", "reference tent", m_BoxReference, m_TentReference);
  if (m_Options.SaveImages)
  {
    WriteProjection(m_BoxReference, g.Columns, g.Rows, g.Spacing, m_Options.WorkDirectory + "/reference_box.mha");
    WriteProjection(m_TentReference, g.Columns, g.Rows, g.Spacing, m_Options.WorkDirectory + "/reference_tent.mha");
    WriteProjection(m_Siddon1, g.Columns, g.Rows, g.Spacing, m_Options.WorkDirectory + "/siddon1.mha");
  }

  std::cerr << "exact projectors" << std::endl;
  for (KernelEnum kernel : { KernelEnum::Box, KernelEnum::Tent })
    ExactRows(m_Volume, geometry, kernel, base);

  if (m_Options.Itk)
  {
    std::cerr << "ITK ray caster" << std::endl;
    Row row = base;
    row.Method = "itk-raycast";
    row.Model = "tent";
    if (!m_Mu)
    {
      row.Status = "failed";
      row.Note = "the volume's direction is not axis-aligned: ITK's ray caster ignores it";
      Add(row);
    }
    else
    {
      const Image image = ItkRayCast(m_Mu, geometry, &row.Time);
      row.Note = "ResampleImageFilter + RayCastInterpolateImageFunction, threshold 0, float mu volume";
      Add(row, &image, &m_TentReference);
      Agreement("ITK ray caster", "exact Siddon, 1 ray per pixel", image, m_Siddon1);
      Agreement("ITK ray caster", "exact trilinear, 1 ray per pixel", image, m_Trilinear1);
      // the outer half-voxel shell: ITK's ray caster on the volume padded with one layer of zeros
      const Image padded = ItkRayCast(PadWithZeros(m_Mu), geometry, nullptr);
      Agreement("ITK ray caster, volume padded with zeros", "exact Siddon, 1 ray per pixel", padded, m_Siddon1);
      Agreement("ITK ray caster, volume padded with zeros", "exact trilinear, 1 ray per pixel", padded, m_Trilinear1);
      if (m_Options.SaveImages)
      {
        WriteProjection(image, g.Columns, g.Rows, g.Spacing, m_Options.WorkDirectory + "/itk_raycast.mha");
        WriteProjection(padded, g.Columns, g.Rows, g.Spacing, m_Options.WorkDirectory + "/itk_raycast_padded.mha");
      }
    }
  }
  if (m_Mu)
    PlastimatchRows(base);
  m_Mu = nullptr;

  std::cerr << "point samplers" << std::endl;
  for (const auto & sampler : m_Options.Samplers)
  {
    try
    {
      SamplerRows(sampler, m_Volume, base);
    }
    catch (const std::exception & e)
    {
      Row row = base;
      row.Method = "points";
      row.Sampler = sampler;
      row.Status = "failed";
      row.Note = e.what();
      Add(row);
    }
  }
}

void
Benchmark::Scaling()
{
  const Geometry g{ m_Options.Columns, m_Options.Rows, m_Options.Spacing };
  m_Geometry = g;
  const uint64_t samples = static_cast<uint64_t>(std::llround(m_Options.ScalingSamples));
  Row            base;
  base.Config = m_Options.Name;
  base.Columns = g.Columns;
  base.DetectorRows = g.Rows;

  // 1. time against the number of samples (box kernel, nearest splat; no error computed)
  std::cerr << "scaling: samples" << std::endl;
  {
    base.Sweep = "samples";
    base.Voxels = m_Volume->GetLargestPossibleRegion().GetNumberOfPixels();
    Options saved = m_Options;
    m_Options.Kernels = { m_Options.Kernels.front() };
    m_Options.Splats = { m_Options.Splats.front() };
    for (const auto & sampler : m_Options.Samplers)
      SamplerRows(sampler, m_Volume, base);
    m_Options = saved;
    for (Row & r : m_Rows)
      r.X = static_cast<double>(r.Samples);
  }

  // 2. time against the volume size: the volume resampled to a fraction of its voxels over the same box
  std::cerr << "scaling: volume size" << std::endl;
  for (double fraction : m_Options.VolumeFractions)
  {
    VolumeType::Pointer volume = ResampleToFraction(m_Volume, fraction);
    Row                 row = base;
    row.Sweep = "volume";
    row.Voxels = volume->GetLargestPossibleRegion().GetNumberOfPixels();
    row.X = static_cast<double>(row.Voxels);
    const auto size = volume->GetLargestPossibleRegion().GetSize();
    row.Note = std::to_string(size[0]) + "x" + std::to_string(size[1]) + "x" + std::to_string(size[2]);
    std::cerr << " volume " << row.Note << " (fraction " << fraction << ")" << std::endl;
    auto geometry = MakeGeometry(volume, g.Columns, g.Rows, g.Spacing);
    for (const auto & samplerName : m_Options.Samplers)
    {
      auto filter = PointFilterType::New();
      filter->SetInput(volume);
      filter->SetGeometry(geometry);
      filter->SetSampler(itk::DRRSamplerFactory::Create(samplerName));
      filter->SetSeed(m_Options.Seed);
      filter->SetReconstructionKernel(m_Options.Kernels.front());
      filter->SetSplat(m_Options.Splats.front());
      Row    pre = row;
      double huToMu = NaN, tables = NaN;
      pre.Method = "preprocess";
      pre.Sampler = samplerName;
      pre.Time = Measure(
        [&] {
          double start = Now();
          filter->GetAttenuationVolume();
          huToMu = Now() - start;
          start = Now();
          filter->PrepareSampling();
          tables = Now() - start;
        },
        1,
        0.0);
      pre.HuToMu = huToMu;
      pre.Tables = tables;
      pre.TableBytes = static_cast<double>(filter->GetSampler()->GetTableSizeInBytes());
      pre.TableBytesPerVoxel =
        pre.TableBytes / std::max<uint64_t>(1, CountNonAir(volume, filter->GetTransferFunction()));
      Add(pre);
      Row render = row;
      render.Method = "points";
      render.Sampler = samplerName;
      render.Kernel = KernelName(m_Options.Kernels.front());
      render.Splat = SplatName(m_Options.Splats.front());
      render.Samples = samples;
      filter->SetNumberOfSamples(samples);
      render.FirstRender = WarmUp(filter.GetPointer());
      render.Time = Measure(
        [&] {
          filter->Modified();
          filter->Update();
        },
        m_Options.Runs,
        m_Options.RepeatLimit);
      Add(render);
    }
    auto exact = ExactType::New();
    exact->SetInput(volume);
    exact->SetGeometry(geometry);
    exact->GetAttenuationVolume();
    for (KernelEnum kernel : { KernelEnum::Box, KernelEnum::Tent })
    {
      Row r = row;
      r.Method = kernel == KernelEnum::Box ? "exact-siddon" : "exact-trilinear";
      r.Kernel = KernelName(kernel);
      r.Rays = 1;
      exact->SetReconstructionKernel(kernel);
      r.FirstRender = WarmUp(exact.GetPointer());
      r.Time = Measure(
        [&] {
          exact->Modified();
          exact->Update();
        },
        m_Options.Runs,
        m_Options.RepeatLimit);
      Add(r);
    }
    if (m_Options.Itk)
    {
      auto                 mu = MuImage(volume, exact->GetAttenuationVolume());
      MuImageType::Pointer oriented = WithIdentityDirection(mu);
      if (oriented)
      {
        Row r = row;
        r.Method = "itk-raycast";
        ItkRayCast(oriented, geometry, &r.Time);
        Add(r);
      }
    }
  }

  // 3. time against the detector size, same field of view (one sampler's filter alive at a time, so that the peak
  // memory is that sampler's)
  std::cerr << "scaling: detector size" << std::endl;
  const double fieldOfView = g.Columns * g.Spacing;
  Row          detectorBase = base;
  detectorBase.Sweep = "detector";
  detectorBase.Voxels = m_Volume->GetLargestPossibleRegion().GetNumberOfPixels();
  const auto detectorRow = [&](unsigned cols) {
    Row row = detectorBase;
    row.Columns = cols;
    row.DetectorRows = cols;
    row.X = cols;
    row.Note = "pixel " + Format(fieldOfView / cols, "%.4g") + " mm";
    return row;
  };
  for (const auto & samplerName : m_Options.Samplers)
  {
    auto filter = PointFilterType::New();
    filter->SetInput(m_Volume);
    filter->SetSampler(itk::DRRSamplerFactory::Create(samplerName));
    filter->SetSeed(m_Options.Seed);
    filter->SetReconstructionKernel(m_Options.Kernels.front());
    filter->SetSplat(m_Options.Splats.front());
    filter->PrepareSampling();
    filter->SetNumberOfSamples(samples);
    double first = NaN;
    for (unsigned cols : m_Options.DetectorColumns)
    {
      filter->SetGeometry(MakeGeometry(m_Volume, cols, cols, fieldOfView / cols));
      if (!std::isfinite(first))
        first = WarmUp(filter.GetPointer());
      Row r = detectorRow(cols);
      r.Method = "points";
      r.Sampler = samplerName;
      r.Kernel = KernelName(m_Options.Kernels.front());
      r.Splat = SplatName(m_Options.Splats.front());
      r.Samples = samples;
      r.FirstRender = cols == m_Options.DetectorColumns.front() ? first : NaN;
      r.Time = Measure(
        [&] {
          filter->Modified();
          filter->Update();
        },
        m_Options.Runs,
        m_Options.RepeatLimit);
      Add(r);
    }
  }
  auto exact = ExactType::New();
  exact->SetInput(m_Volume);
  for (unsigned cols : m_Options.DetectorColumns)
  {
    Row r = detectorRow(cols);
    r.Method = "exact-siddon";
    r.Kernel = "box";
    r.Rays = 1;
    exact->SetGeometry(MakeGeometry(m_Volume, cols, cols, fieldOfView / cols));
    if (cols == m_Options.DetectorColumns.front())
      r.FirstRender = WarmUp(exact.GetPointer()); // HU -> mu and any first-render work, outside the timings
    r.Time = Measure(
      [&] {
        exact->Modified();
        exact->Update();
      },
      m_Options.Runs,
      m_Options.RepeatLimit);
    Add(r);
  }
  if (m_Options.Itk)
  {
    MuImageType::Pointer oriented = WithIdentityDirection(MuImage(m_Volume, exact->GetAttenuationVolume()));
    exact = nullptr;
    for (unsigned cols : m_Options.DetectorColumns)
    {
      if (!oriented)
        break;
      Row r = detectorRow(cols);
      r.Method = "itk-raycast";
      ItkRayCast(oriented, MakeGeometry(m_Volume, cols, cols, fieldOfView / cols), &r.Time);
      Add(r);
    }
  }
}

void
Benchmark::Collimated()
{
  const Geometry full{ m_Options.Columns, m_Options.Rows, m_Options.Spacing };
  const unsigned c = m_Options.CollimatedColumns;
  if (c > full.Columns || c > full.Rows || (full.Columns - c) % 2 || (full.Rows - c) % 2)
    throw std::runtime_error("the collimated detector must be smaller than the full one by an even number of pixels");
  const Geometry small{ c, c, m_Options.Spacing };
  const unsigned c0 = (full.Columns - c) / 2, r0 = (full.Rows - c) / 2;
  m_Geometry = small;
  auto       fullGeometry = MakeGeometry(m_Volume, full.Columns, full.Rows, full.Spacing);
  auto       smallGeometry = MakeGeometry(m_Volume, c, c, small.Spacing);
  const auto crop = [&](const Image & image) { return Crop(image, full.Columns, c0, r0, c, c); };
  Row        base;
  base.Config = m_Options.Name;
  base.Voxels = m_Volume->GetLargestPossibleRegion().GetNumberOfPixels();

  // references of the collimated view (the same pixels as the crop of the full view)
  Row refBase = base;
  refBase.Sweep = "collimated";
  refBase.Columns = refBase.DetectorRows = c;
  Reference(m_Volume, smallGeometry, KernelEnum::Box, m_BoxReference, &m_Siddon1, nullptr, refBase);
  Reference(m_Volume, smallGeometry, KernelEnum::Tent, m_TentReference, nullptr, nullptr, refBase);
  {
    // check: the crop of the full view's one-ray image is the collimated view's one-ray image
    auto exact = ExactType::New();
    exact->SetInput(m_Volume);
    exact->SetGeometry(fullGeometry);
    exact->Update();
    Agreement("crop of the full view, Siddon 1 ray",
              "collimated view, Siddon 1 ray",
              crop(ToVector(exact->GetOutput())),
              m_Siddon1);
  }
  for (const std::string view : { "collimated", "crop" })
  {
    Row viewBase = base;
    viewBase.Sweep = view;
    viewBase.Columns = view == std::string("collimated") ? c : full.Columns;
    viewBase.DetectorRows = view == std::string("collimated") ? c : full.Rows;
    itk::DRRProjectionGeometry * geometry = view == std::string("collimated") ? smallGeometry : fullGeometry;
    const std::function<Image(const Image &)> map =
      view == std::string("collimated") ? std::function<Image(const Image &)>() : crop;
    for (KernelEnum kernel : m_Options.Kernels)
      ExactRows(m_Volume, geometry, kernel, viewBase, map);
  }
  const auto ladder = SampleLadder(m_Options.MinSamples, m_Options.MaxSamples);
  for (const auto & samplerName : m_Options.Samplers)
  {
    auto filter = PointFilterType::New();
    filter->SetInput(m_Volume);
    filter->SetSampler(itk::DRRSamplerFactory::Create(samplerName));
    filter->SetSeed(m_Options.Seed);
    filter->PrepareSampling();
    for (KernelEnum kernel : m_Options.Kernels)
    {
      const Image & own = kernel == KernelEnum::Box ? m_BoxReference : m_TentReference;
      for (SplatEnum splat : m_Options.Splats)
      {
        filter->SetReconstructionKernel(kernel);
        filter->SetSplat(splat);
        for (const std::string view : { "collimated", "crop" })
        {
          const bool collimated = view == std::string("collimated");
          filter->SetGeometry(collimated ? smallGeometry : fullGeometry);
          filter->SetNumberOfSamples(ladder.empty() ? 1 : ladder.front());
          const double first = WarmUp(filter.GetPointer());
          double       previousTime = NaN;
          uint64_t     previousSamples = 0;
          for (uint64_t samples : ladder)
          {
            Row row = base;
            row.Sweep = view;
            row.Columns = collimated ? c : full.Columns;
            row.DetectorRows = collimated ? c : full.Rows;
            row.Method = "points";
            row.Sampler = samplerName;
            row.Kernel = KernelName(kernel);
            row.Splat = SplatName(splat);
            row.Model = KernelName(kernel);
            row.Samples = samples;
            row.FirstRender = samples == ladder.front() ? first : NaN;
            const double predicted = previousTime * samples / std::max<uint64_t>(1, previousSamples);
            if (std::isfinite(predicted) && predicted > m_Options.Budget)
            {
              row.Status = "skipped";
              row.Note = "predicted " + Format(predicted, "%.3g") + " s > budget";
              previousTime = predicted;
              previousSamples = samples;
              Add(row);
              continue;
            }
            filter->SetNumberOfSamples(samples);
            row.Time = Measure(
              [&] {
                filter->Modified();
                filter->Update();
              },
              m_Options.Runs,
              m_Options.RepeatLimit);
            previousTime = row.Time.Wall;
            previousSamples = samples;
            Image image = ToVector(filter->GetOutput());
            if (!collimated)
              image = crop(image);
            Add(row, &image, &own);
          }
        }
      }
    }
  }
}

void
Benchmark::WriteOutputs() const
{
  const std::string prefix = m_Options.OutputDirectory + "/" + m_Options.Name;
  WriteCsv(prefix + ".csv", m_Rows);
  {
    std::ofstream out(prefix + "_agreement.csv");
    out << "image,against,nrmse,max_error,sum_ratio,pearson_r\n";
    for (const auto & a : m_Agreement)
      out << CsvField(a.What) << "," << CsvField(a.Against) << "," << Format(a.E.Nrmse, "%.6g") << ","
          << Format(a.E.MaxError, "%.6g") << "," << Format(a.E.SumRatio, "%.8f") << "," << Format(a.E.Pearson, "%.9f")
          << "\n";
  }
  std::ofstream md(prefix + ".md");
  md << "# Benchmark `" << m_Options.Name << "` (" << m_Options.Mode << ")\n\n";
  if (!m_Options.Description.empty())
    md << m_Options.Description << "\n\n";
  md << "- volume: `" << m_Options.Input << "`, " << m_VolumeText << ", " << m_NonAirVoxels
     << " non-air voxels; loaded in " << Format(m_LoadSeconds, "%.3g") << " s\n";
  md << "- view: " << GeometryText({ m_Options.Columns, m_Options.Rows, m_Options.Spacing }) << "\n";
  md << "- machine: " << MachineText() << "; load average (1, 5, 15 min) before " << m_LoadBefore << ", after "
     << m_LoadAfter << "\n";
  md << "- timing: median of " << m_Options.Runs << " runs (one if the first takes over "
     << Format(m_Options.RepeatLimit, "%g") << " s); a setting predicted over " << Format(m_Options.Budget, "%g")
     << " s is skipped; references: " << m_Options.ReferenceRays << " x " << m_Options.ReferenceRays
     << " rays per pixel; seed " << m_Options.Seed << "; total " << Format(Now() - m_Started, "%.0f") << " s\n\n";
  md << "NRMSE and max error are relative to the range (max - min) of the reference of the method's own model (box: "
        "Siddon, tent: trilinear); `vs box` against the box reference. Peak: resident memory of the process (of the "
        "child for plastimatch) during the method; +: over the resident memory before it. See docs/benchmark.md.\n\n";
  md << "| method | sampler | kernel | splat | samples / rays | status | runs | wall s | CPU s | peak MiB (+) | "
        "NRMSE | max err | sum ratio | NRMSE vs box | sweep | note |\n"
        "|---|---|---|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---|---|\n";
  for (const Row & r : m_Rows)
  {
    std::string count = r.Samples ? SamplesText(r.Samples)
                                  : (r.Rays ? std::to_string(r.Rays) + "x" + std::to_string(r.Rays) + " rays" : "");
    if (r.Method == "preprocess")
    {
      count = "";
    }
    std::string note = r.Note;
    if (std::isfinite(r.FirstRender))
      note = "first render " + Format(r.FirstRender, "%.3g") + " s" + (note.empty() ? "" : "; " + note);
    if (r.Method == "preprocess")
      note = "attenuation volume (HU->mu) " + Format(r.HuToMu, "%.3g") + " s + tables " + Format(r.Tables, "%.3g") +
             " s; tables " + Format(r.TableBytes / 1048576.0, "%.4g") +
             " MiB = " + Format(r.TableBytesPerVoxel, "%.3g") + " bytes per non-air voxel";
    else if (r.Method.compare(0, 11, "plastimatch") == 0 && r.Status == "ok")
      note = "load " + Format(r.Time.Load, "%.3g") + " s + render/write " + Format(r.Time.Render, "%.3g") +
             " s (whole process)";
    md << "| " << r.Method << " | " << r.Sampler << " | " << r.Kernel << " | " << r.Splat << " | " << count << " | "
       << r.Status << " | " << (r.Time.Runs ? std::to_string(r.Time.Runs) : "") << " | " << Format(r.Time.Wall, "%.3g")
       << " | " << Format(r.Time.Cpu, "%.3g") << " | " << Format(r.Time.PeakMiB, "%.0f")
       << (std::isfinite(r.Time.ExtraMiB) ? " (+" + Format(r.Time.ExtraMiB, "%.0f") + ")" : "") << " | "
       << Format(r.Own.Nrmse, "%.3g") << " | " << Format(r.Own.MaxError, "%.3g") << " | "
       << Format(r.Own.SumRatio, "%.5f") << " | " << Format(r.Box.Nrmse, "%.3g") << " | " << r.Sweep
       << (std::isfinite(r.X) && r.Sweep != "samples" ? " " + Format(r.X, "%.6g") : "") << " | " << note << " |\n";
  }
  if (!m_Agreement.empty())
  {
    md << "\n## Agreement\n\n| image | against | NRMSE | max err | sum ratio | Pearson r "
          "|\n|---|---|---:|---:|---:|---:|\n";
    for (const auto & a : m_Agreement)
      md << "| " << a.What << " | " << a.Against << " | " << Format(a.E.Nrmse, "%.3g") << " | "
         << Format(a.E.MaxError, "%.3g") << " | " << Format(a.E.SumRatio, "%.6f") << " | "
         << Format(a.E.Pearson, "%.7f") << " |\n";
  }
}

int
Benchmark::Run()
{
  if (m_Options.Threads)
    itk::MultiThreaderBase::SetGlobalDefaultNumberOfThreads(m_Options.Threads);
  std::string mkdir = "mkdir -p '" + m_Options.OutputDirectory + "' '" + m_Options.WorkDirectory + "'";
  if (std::system(mkdir.c_str()) != 0)
    throw std::runtime_error("cannot create " + m_Options.OutputDirectory);
  m_LoadBefore = LoadAverage();
  Load();
  std::cerr << m_Options.Mode << ": " << GeometryText({ m_Options.Columns, m_Options.Rows, m_Options.Spacing })
            << std::endl;
  try
  {
    if (m_Options.Mode == "trade")
      Trade();
    else if (m_Options.Mode == "scaling")
      Scaling();
    else
      Collimated();
  }
  catch (...)
  {
    m_LoadAfter = LoadAverage();
    WriteOutputs(); // what was measured so far
    throw;
  }
  m_LoadAfter = LoadAverage();
  WriteOutputs();
  std::cerr << "wrote " << m_Options.OutputDirectory << "/" << m_Options.Name << ".{csv,md} in "
            << Format(Now() - m_Started, "%.0f") << " s" << std::endl;
  return 0;
}
} // namespace

int
main(int argc, char * argv[])
{
  try
  {
    Benchmark benchmark(ParseOptions(argc, argv));
    return benchmark.Run();
  }
  catch (const std::exception & e)
  {
    std::cerr << "error: " << e.what() << "\n";
    return 1;
  }
}
