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
#include "pbdrrBenchmarkOptions.h"
#include "pbdrrBenchmarkSupport.h"

#include "itkDRRSamplerFactory.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <iostream>
#include <stdexcept>

namespace pbdrr
{
namespace bench
{
namespace
{
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

/** The arguments one after the other: the option at hand and its value. */
class ArgumentReader
{
public:
  ArgumentReader(int argc, char * argv[]) : m_Argc(argc), m_Argv(argv) {}

  bool
  Next()
  {
    if (++m_Index >= m_Argc)
      return false;
    Arg = m_Argv[m_Index];
    return true;
  }
  std::string
  Value()
  {
    if (m_Index + 1 >= m_Argc)
    {
      throw std::runtime_error("option " + Arg + " needs a value");
    }
    return m_Argv[++m_Index];
  }
  double
  Number()
  {
    return ParseNumber(Value(), Arg);
  }

  std::string Arg;

private:
  int     m_Argc;
  char ** m_Argv;
  int     m_Index{ 0 };
};

/** --kernels box,tent or --splats nearest,bilinear. */
void
ParseKernelsOrSplats(ArgumentReader & in, Options & options)
{
  const std::string & arg = in.Arg;
  const auto          names = SplitList(in.Value());
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

/** The mode, the names and the view; false if `in.Arg` is none of them. */
bool
ParseViewOption(ArgumentReader & in, Options & options)
{
  const std::string & arg = in.Arg;
  if (arg == "--mode")
    options.Mode = in.Value();
  else if (arg == "--name")
    options.Name = in.Value();
  else if (arg == "--description")
    options.Description = in.Value();
  else if (arg == "--cols")
    options.Columns = static_cast<unsigned>(in.Number());
  else if (arg == "--rows")
    options.Rows = static_cast<unsigned>(in.Number());
  else if (arg == "--spacing")
    options.Spacing = in.Number();
  else if (arg == "--gantry")
    options.Gantry = in.Number();
  else if (arg == "--sad")
    options.Sad = in.Number();
  else if (arg == "--sid")
    options.Sid = in.Number();
  else
    return false;
  return true;
}

/** What is measured and how often; false if `in.Arg` is none of these options. */
bool
ParseMethodOption(ArgumentReader & in, Options & options)
{
  const std::string & arg = in.Arg;
  if (arg == "--samplers")
    options.Samplers = SplitList(in.Value());
  else if (arg == "--kernels" || arg == "--splats")
    ParseKernelsOrSplats(in, options);
  else if (arg == "--min-samples")
    options.MinSamples = in.Number();
  else if (arg == "--max-samples")
    options.MaxSamples = in.Number();
  else if (arg == "--budget")
    options.Budget = in.Number();
  else if (arg == "--runs")
    options.Runs = std::max(1u, static_cast<unsigned>(in.Number()));
  else if (arg == "--repeat-limit")
    options.RepeatLimit = in.Number();
  else if (arg == "--reference-rays")
    options.ReferenceRays = std::max(1u, static_cast<unsigned>(in.Number()));
  else if (arg == "--exact-rays" || arg == "--detector-cols")
  {
    std::vector<unsigned> list;
    for (const auto & item : SplitList(in.Value()))
      list.push_back(static_cast<unsigned>(ParseNumber(item, arg)));
    (arg == "--exact-rays" ? options.ExactRays : options.DetectorColumns) = list;
  }
  else
    return false;
  return true;
}

/** The other programs, files, seed, threads and the scaling and collimated modes; false if `in.Arg` is none. */
bool
ParseRunOption(ArgumentReader & in, Options & options)
{
  const std::string & arg = in.Arg;
  if (arg == "--no-itk")
    options.Itk = false;
  else if (arg == "--no-plastimatch")
    options.Plastimatch = false;
  else if (arg == "--plastimatch")
    options.PlastimatchExe = in.Value();
  else if (arg == "--work")
    options.WorkDirectory = in.Value();
  else if (arg == "--seed")
    options.Seed = static_cast<uint64_t>(in.Number());
  else if (arg == "--threads")
    options.Threads = static_cast<unsigned>(in.Number());
  else if (arg == "--save-images")
    options.SaveImages = true;
  else if (arg == "--scaling-samples")
    options.ScalingSamples = in.Number();
  else if (arg == "--volume-fractions")
  {
    options.VolumeFractions.clear();
    for (const auto & item : SplitList(in.Value()))
      options.VolumeFractions.push_back(ParseNumber(item, arg));
  }
  else if (arg == "--collimated-cols")
    options.CollimatedColumns = static_cast<unsigned>(in.Number());
  else
    return false;
  return true;
}

/** The positional arguments and the defaults that depend on other options. */
void
Complete(Options & options, const std::vector<std::string> & positional)
{
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
}
} // namespace

Options
ParseOptions(int argc, char * argv[])
{
  Options                  options;
  std::vector<std::string> positional;
  for (ArgumentReader in(argc, argv); in.Next();)
  {
    const std::string & arg = in.Arg;
    if (arg == "-h" || arg == "--help")
    {
      std::cout << Usage;
      std::exit(0);
    }
    else if (ParseViewOption(in, options) || ParseMethodOption(in, options) || ParseRunOption(in, options))
      continue;
    else if (!arg.empty() && arg[0] == '-')
      throw std::runtime_error("unknown option " + arg + " (see --help)");
    else
      positional.push_back(arg);
  }
  Complete(options, positional);
  return options;
}

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
} // namespace bench
} // namespace pbdrr
