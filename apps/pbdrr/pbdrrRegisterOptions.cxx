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
// The options of pbdrr register (RegisterOptionDeclarations()), declared as pbdrr's are (OptionBuilder), and parsed
// and helped by the same code (pbdrrOptionTable.h); the values' parsers of register's own options.
#include "pbdrrRegisterCommand.h"
#include "pbdrrMessages.h"
#include "pbdrrOptions.h"

#include "itkDRRImageSimilarity.h"
#include "itkPointBasedDRRRegistrationMethod.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace pbdrr
{
namespace
{
using Values = std::vector<std::string>;
using MethodType = itk::PointBasedDRRRegistrationMethod<VolumeType>;

std::array<double, 6>
ParsePose(const Values & words)
{
  std::array<double, 6> pose{};
  for (size_t k = 0; k < 6; ++k)
  {
    pose[k] = ParseNumber(words[k], "--start");
  }
  if (std::abs(pose[3]) > 180.0 || std::abs(pose[4]) > 180.0 || std::abs(pose[5]) > 180.0)
  {
    throw UsageError("--start angles are in degrees, within +-180");
  }
  return pose;
}

/** One level of --levels: SHRINK[:POINTS[:SIGMA]] (0 points, sigma -1: not given). */
struct Level
{
  unsigned Shrink{ 1 };
  uint64_t Samples{ 0 };
  double   Sigma{ -1.0 };
};

/** One level, SHRINK[:POINTS[:SIGMA_MM]], split at its colons; throws usage. */
Level
ParseLevel(const std::string & word, const std::string & flag, const std::string & usage)
{
  std::vector<std::string> parts;
  std::istringstream       fields(word);
  for (std::string field; std::getline(fields, field, ':');)
  {
    parts.push_back(field);
  }
  if (parts.empty() || parts.size() > 3 || parts[0].empty())
  {
    throw UsageError(usage);
  }
  Level        level;
  const double shrink = ParseNumber(parts[0], flag);
  if (shrink < 1 || shrink > 64 || shrink != std::floor(shrink))
  {
    throw UsageError(usage);
  }
  level.Shrink = static_cast<unsigned>(shrink);
  if (parts.size() > 1)
  {
    level.Samples = ParseSampleCount(parts[1]);
  }
  if (parts.size() > 2)
  {
    level.Sigma = ParseNumber(parts[2], flag);
    if (!(level.Sigma >= 0.0) || level.Sigma > 1000.0)
    {
      throw UsageError(usage);
    }
  }
  return level;
}

/** A comma-separated list of levels, coarse to fine, each SHRINK[:POINTS[:SIGMA_MM]]. */
std::vector<Level>
ParseLevels(std::string text, const std::string & flag)
{
  const std::string usage = flag + " expects levels SHRINK[:POINTS[:SIGMA]], coarse to fine, comma separated (shrink " +
                            "a whole factor from 1 to 64, points as --samples, sigma in mm), e.g. 4:5e5:2,2:1e6";
  std::replace(text.begin(), text.end(), ',', ' ');
  std::istringstream stream(text);
  std::vector<Level> levels;
  for (std::string word; stream >> word;)
  {
    levels.push_back(ParseLevel(word, flag, usage));
  }
  if (levels.empty())
  {
    throw UsageError(usage);
  }
  return levels;
}

/** --levels: the schedule, with the points of every level or of none, and the sigmas of those that give one. */
void
SetLevels(RegisterOptions & options, const Values & values)
{
  const std::vector<Level> levels = ParseLevels(values[0], "--levels");
  RegistrationSettings &   settings = options.settings;
  settings.Shrink.clear();
  settings.LevelSamples.clear();
  settings.LevelSigmas.clear();
  const bool samples = std::any_of(levels.begin(), levels.end(), [](const Level & l) { return l.Samples > 0; });
  const bool sigmas = std::any_of(levels.begin(), levels.end(), [](const Level & l) { return l.Sigma >= 0.0; });
  for (const Level & level : levels)
  {
    if (samples && level.Samples == 0)
    {
      throw UsageError("--levels: give the points of every level, or of none (e.g. 4:5e5,2:1e6)");
    }
    settings.Shrink.push_back(level.Shrink);
    if (samples)
    {
      settings.LevelSamples.push_back(level.Samples);
    }
    if (sigmas)
    {
      settings.LevelSigmas.push_back(std::max(0.0, level.Sigma));
    }
  }
}

/** --shrink: the schedule's binnings alone. */
void
SetShrink(RegisterOptions & options, const Values & values)
{
  options.settings.Shrink.clear();
  for (const Level & level : ParseLevels(values[0], "--shrink"))
  {
    if (level.Samples > 0 || level.Sigma >= 0.0)
    {
      throw UsageError("--shrink expects whole factors from 1 to 64, e.g. 4,2 (--levels takes points and sigmas)");
    }
    options.settings.Shrink.push_back(level.Shrink);
  }
}

/** A whole number from lowest to highest (range says them), or the UsageError "FLAG expects a whole number RANGE". */
double
WholeIn(const std::string & value, const std::string & flag, double lowest, double highest, const std::string & range)
{
  const double number = ParseNumber(value, flag);
  if (number < lowest || number > highest || number != std::floor(number))
  {
    throw UsageError(flag + " expects a whole number " + range);
  }
  return number;
}

double
MaxSeconds(const std::string & value)
{
  const double seconds = ParseNumber(value, "--max-seconds");
  if (!(seconds > 0.0))
  {
    throw UsageError("--max-seconds must be positive");
  }
  return seconds;
}

double
StartRadius(const std::string & value)
{
  const double radius = ParseNumber(value, "--start-radius");
  if (!(radius >= 0.0) || radius > 180.0)
  {
    throw UsageError("--start-radius expects mm and degrees from 0 to 180");
  }
  return radius;
}

/** --exact: register renders exactly with Siddon's projector alone (its derivative-free search fits no other). */
bool
Siddon(const std::string & name)
{
  if (name != "siddon")
  {
    throw UsageError("register --exact expects siddon, got '" + name + "'");
  }
  return true;
}

std::string
Metric(const std::string & name)
{
  if (!itk::DRRImageSimilarity::IsMetricName(name))
  {
    throw UsageError("--metric expects " + itk::DRRImageSimilarity::JoinMetricNames(" or ") + ", got '" + name + "'");
  }
  return name;
}

std::string
JoinedOptimizerNames(const std::string & separator)
{
  std::string joined;
  for (const std::string & name : MethodType::GetOptimizerNames())
  {
    joined += (joined.empty() ? "" : separator) + name;
  }
  return joined;
}

std::string
Optimizer(const std::string & name)
{
  const auto & names = MethodType::GetOptimizerNames();
  if (std::find(names.begin(), names.end(), name) == names.end())
  {
    throw UsageError("--optimizer expects " + JoinedOptimizerNames(" or ") + ", got '" + name + "'");
  }
  return name;
}

/** The X-ray a --geometry or a --projection-matrix gives the view of: the last --xray before it. */
XRayArgument &
LastXRay(RegisterOptions & options, const std::string & flag)
{
  if (options.xrays.empty())
  {
    throw UsageError(flag + " gives the view of the --xray before it: give --xray first");
  }
  return options.xrays.back();
}

/** The defaults register's help states that the registration method holds: its schedule (SHRINK:POINTS:SIGMA per
 * level) and its metric's points. Made for the help alone, so that reading a command line builds no ITK object. */
struct MethodDefaults
{
  std::string Schedule;
  std::string Samples;
};

MethodDefaults
TheMethodsDefaults()
{
  const auto     method = MethodType::New();
  MethodDefaults defaults;
  for (size_t level = 0; level < method->GetShrinkFactorsPerLevel().size(); ++level)
  {
    std::ostringstream one;
    one << method->GetShrinkFactorsPerLevel()[level] << ":" << method->GetNumberOfSamplesPerLevel()[level] << ":"
        << method->GetSmoothingSigmasPerLevel()[level];
    defaults.Schedule += (defaults.Schedule.empty() ? "" : ",") + one.str();
  }
  defaults.Samples = std::to_string(MethodType::MetricType::New()->GetNumberOfSamples());
  return defaults;
}

/** The groups of register's options: the X-rays and the output (the usage's), the registration's, and --help, which
 * the help does not list. */
enum class RegisterGroup
{
  XRays,
  Registration,
  Unlisted
};

using RegisterOptionDeclaration = OptionDeclarationOf<RegisterOptions, RegisterGroup>;

/** The options of pbdrr register; the defaults of the method are stated where given (the help's). */
std::vector<RegisterOptionDeclaration>
RegisterOptionDeclarations(const MethodDefaults & method = {})
{
  using Option = OptionBuilder<RegisterOptions, RegisterGroup>;
  using O = RegisterOptions;
  constexpr RegisterGroup XRays = RegisterGroup::XRays, Registration = RegisterGroup::Registration;
  const std::string       under(24, ' '); // the column of an X-ray's help
  // Laid out by hand, an option in a line or a few: clang-format would put each call of a chain on a line of its own.
  // clang-format off
  return {
    Option("--xray").In(XRays).Takes("FILE").Does([](O & o, const Values & v) { o.xrays.push_back({ v[0], "", "" }); })
      .Help("an X-ray: a CT localizer (DICOM; its view from its header), or a 2D image followed by"),
    Option("--geometry").In(XRays).Nested().Takes("FILE")
      .Does([](O & o, const Values & v) { LastXRay(o, "--geometry").GeometryFile = v[0]; })
      .Help("its view as a geometry file (as pbdrr --geometry reads it: where the file is silent,\n"
            "512 x 512 pixels of 1.2 mm about the CT's centre), or"),
    Option("--projection-matrix").In(XRays).Nested().Takes("FILE")
      .Does([](O & o, const Values & v) { LastXRay(o, "--projection-matrix").MatrixFile = v[0]; })
      .Help("its view as a 3 x 4 projection matrix")
      .Choices(under + "Two or more X-rays are registered jointly (biplane: a second view fixes the depth one\n" +
               under + "view sees only as magnification).\n"),
    Option("--output").Short("-o").In(XRays).Takes("OUT.png").Sets(&O::output)
      .Help("the DRR at the pose (OUT.N.png for the N-th of several X-rays) and OUT.checkerboard.png,\n"
            "the DRR and the X-ray in alternate 32-pixel squares"),
    Option("--start").In(Registration).Takes("TX TY TZ RX RY RZ")
      .Does([](O & o, const Values & v) { o.settings.StartPose = ParsePose(v); })
      .Help("the starting pose: mm and degrees (default 0 0 0 0 0 0)"),
    Option("--metric").In(Registration).Takes(itk::DRRImageSimilarity::JoinMetricNames("|"))
      .Does([](O & o, const Values & v) { o.settings.Metric = Metric(v[0]); })
      .Help("the similarity: gc, the gradient correlation (default: edges only, blind to a\n"
            "table or holder outside the CT's field, scatter, a heel effect), or ncc, the\n"
            "normalized cross-correlation of the images"),
    Option("--optimizer").In(Registration).Takes(JoinedOptimizerNames("|")).Default(MethodType::DefaultOptimizerName)
      .Does([](O & o, const Values & v) { o.settings.Optimizer = Optimizer(v[0]); })
      .Help("the ITK v4 optimizer (default {default}): rsgd regular-step gradient descent,\n"
            "lbfgsb L-BFGS-B, cg conjugate gradient with a line search; powell and amoeba\n"
            "(Nelder-Mead) use no derivative (powell is the default with --exact)"),
    Option("--levels").In(Registration).Takes("S[:N[:SIGMA]],...").Default(method.Schedule).Does(SetLevels)
      .Help("the schedule, coarse to fine: per level the detector binning S, the kept points N\n"
            "and a Gaussian smoothing of DRR and X-ray, SIGMA mm at the detector (default {default};\n"
            "levels without N take --samples points, without SIGMA no smoothing)"),
    Option("--shrink").In(Registration).Takes("S[,S...]").Does(SetShrink)
      .Help("the schedule's binnings alone (as --levels S,S)"),
    Option("--samples").In(Registration).Takes("N").Default(method.Samples)
      .Does([](O & o, const Values & v) { o.settings.Samples = ParseSampleCount(v[0]); })
      .Help("points per DRR, kept and re-projected at every pose: on every level (default: per level,\n"
            "as above; {default} on levels given without points)"),
    Option("--starts").In(Registration).Takes("K")
      .Does([](O & o, const Values & v) { o.settings.Starts = WholeIn(v[0], "--starts", 1, 1000, "from 1 to 1000"); })
      .Help("the global stage: the first level run from K starts, the best goes on (default 1)"),
    Option("--start-radius").In(Registration).Takes("R")
      .Does([](O & o, const Values & v) { o.settings.StartRadius = StartRadius(v[0]); })
      .Help("the spread of those starts about --start: up to R mm and R degrees per axis (default 10)"),
    Option("--exact").In(Registration).Takes("siddon")
      .Does([](O & o, const Values & v) { o.settings.Exact = Siddon(v[0]); })
      .Help("the exact Siddon projector instead of points (no noise, no derivative: powell)"),
    Option("--seed").In(Registration).Takes("S")
      .Does([](O & o, const Values & v) { o.settings.Seed = WholeIn(v[0], "--seed", 0, 0x1p53, "from 0 to 2^53"); })
      .Help("the points' seed (default 0): the same seed, the same pose on any thread count"),
    Option("--max-seconds").In(Registration).Takes("T")
      .Does([](O & o, const Values & v) { o.settings.MaxSeconds = MaxSeconds(v[0]); })
      .Help("stop after T seconds with the best pose so far (says so)"),
    Option("--series").In(Registration).Takes("UID").Sets(&O::seriesUID).Help("the DICOM series of the CT"),
    Option("--threads").In(Registration).Takes("T")
      .Does([](O & o, const Values & v) { o.settings.Threads = WholeIn(v[0], "--threads", 1, 1024, "from 1 to 1024"); })
      .Help("worker threads (default: all cores)"),
    Option("--verbose").Short("-v").In(Registration).Does([](O & o, const Values &) { o.settings.Verbose = true; })
      .Help("each level's similarity, pose and stop"),
    Option("--quiet").Short("-q").In(Registration).Sets(&O::quiet).Help("only the result lines"),
    Option("--help").Short("-h").In(RegisterGroup::Unlisted).Sets(&O::help).Help("this text"),
  };
  // clang-format on
}
} // namespace

RegisterOptions
ParseRegisterCommandLine(const std::vector<std::string> & arguments)
{
  RegisterOptions          options;
  std::vector<std::string> given;
  ParseOptionTable(arguments,
                   RegisterOptionDeclarations(),
                   " of pbdrr register (see pbdrr register --help)",
                   options,
                   given,
                   [&](const std::string & word) {
                     if (!options.input.empty())
                     {
                       throw UsageError("pbdrr register takes one CT, got a second input '" + word + "'");
                     }
                     options.input = word;
                   });
  if (options.help)
  {
    return options;
  }
  if (options.input.empty())
  {
    throw UsageError("pbdrr register needs a CT (see pbdrr register --help)");
  }
  if (options.xrays.empty())
  {
    throw UsageError("pbdrr register needs an X-ray: --xray FILE (a CT localizer, or an image with --geometry or "
                     "--projection-matrix)");
  }
  if (options.output.empty())
  {
    throw UsageError("pbdrr register needs -o OUT.png (the DRR at the pose; OUT.checkerboard.png beside it)");
  }
  if (!EndsWith(Lowercase(options.output), ".png"))
  {
    throw UsageError("pbdrr register writes PNG images: -o OUT.png, got '" + options.output + "'");
  }
  return options;
}

std::string
RegisterHelpText()
{
  const auto options = RegisterOptionDeclarations(TheMethodsDefaults());
  // The X-rays' options in the usage's columns (an X-ray's view nested under it), the others in a list of their own.
  const HelpLayout usage{ 0, 24, true }, list{ 2, 26, true };
  return R"(pbdrr register - the rigid pose of a CT that matches its DRRs to real X-rays

Usage: pbdrr register CT --xray X [--xray Y ...] -o OUT.png [options]

CT      a DICOM series directory, an export root or a volume ITK reads (HU), as for pbdrr
)" + GroupHelp(options, RegisterGroup::XRays, usage) +
         R"(
The pose is the CT moved in the room, x -> R (x - c) + c + t (c: the centre of the CT's grid; R: rotations rx, ry, rz
about z, then x, then y, as itk::Euler3DTransform); identity is where the scanner's frame of reference puts it.
The similarity is the gradient correlation (GC: the NCC of the images' row and column differences) of DRR and
X-ray, or their normalized cross-correlation (NCC), over the field both cover (the pixels whose
rays cross the CT), mean over the X-rays: blind to the X-ray's gain, offset and units. The DRRs are kept points
re-projected at every pose, and the similarity's derivative comes from one backward pass over them
(itk::PointBasedDRRMetricv4): an ITK v4 optimizer follows it on a multi-resolution schedule.

Options:
)" + GroupHelp(options, RegisterGroup::Registration, list) +
         R"(
Prints:
  pose: tx ty tz rx ry rz      (mm, degrees)
  similarity: S                (the metric at full resolution; and the start's on the first level)
  time: T s, N DRRs            (N poses rendered, M of them with the derivative)
)";
}
} // namespace pbdrr
