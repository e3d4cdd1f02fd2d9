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
#include "pbdrrOptions.h"
#include "pbdrrMessages.h"
#include "itkDRRControlVariate.h"
#include "itkDRRNumberParser.h"
#include "itkDRRSamplerFactory.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <sstream>
#include <map>

namespace pbdrr
{
namespace
{
/** pbdrr's one line of help per policy, by the name the library registers it under (the kernels, splats and beams of
 * itkDRRPolicies.h, the samplers of DRRSamplerFactory). The library registers a policy once, with its name; what the
 * help says about it is the program's, here and nowhere else. PolicyRegistry.* checks that every registered name has
 * a line and every line a registered name. */
const std::map<std::string, std::string> &
PolicyHelpLines()
{
  static const std::map<std::string, std::string> lines = {
    // samplers (--sampler)
    { "level-alias", "exact importance sampling: a level by alias table, a voxel uniform in it" },
    { "paper-hybrid", "the paper's Algorithm 1 (uniform level, accept, roulette) with exact weights" },
    { "metropolis", "the paper's Markov chain over levels, started in its stationary law" },
    { "stratified", "systematic along a Morton curve of the mass, culled to the view: least noise" },
    { "mcvr", "Monte Carlo volume rendering baseline: uniform voxels weighted by mu" },
    // reconstruction kernels (--kernel)
    { "box", "uniform in the voxel: the piecewise-constant model" },
    { "tent", "voxel centre plus a triangular offset per axis: the trilinear model" },
    // splats (--splat)
    { "nearest", "the whole point to the pixel that contains it: unbiased" },
    { "bilinear", "shared among the 4 nearest pixel centres: less noise, a one-pixel blur" },
    // beams (--projection)
    { "perspective", "rays from the source to every pixel, perspective weights" },
    { "parallel", "lines along the detector normal through every pixel, weight 1" },
    { "localizer", "a CT scout: a fan across the table (columns), parallel along it (rows)" },
  };
  return lines;
}
} // namespace

std::string
PolicyHelpLine(const std::string & name)
{
  const auto found = PolicyHelpLines().find(name);
  return found == PolicyHelpLines().end() ? std::string() : found->second;
}

std::vector<std::string>
PolicyHelpNames()
{
  std::vector<std::string> names;
  for (const auto & line : PolicyHelpLines())
  {
    names.push_back(line.first);
  }
  return names;
}

std::string
ExactReferenceName(itk::PointBasedDRREnums::ReconstructionKernel kernel)
{
  return itk::PointBasedDRREnums::GetExactReferenceName(kernel);
}

double
ParseNumber(const std::string & text, const std::string & flag)
{
  double value = 0.0;
  if (!itk::DRRNumberParser::ParseFiniteNumber(text, value))
  {
    throw UsageError(flag + " expects a finite number, got '" + text + "'");
  }
  return value;
}

uint64_t
ParseSampleCount(const std::string & text)
{
  std::string number = text;
  double      multiplier = 1.0;
  if (!number.empty())
  {
    const char                   suffix = number.back();
    const std::map<char, double> suffixes = { { 'k', 1e3 }, { 'K', 1e3 }, { 'm', 1e6 },
                                              { 'M', 1e6 }, { 'g', 1e9 }, { 'G', 1e9 } };
    if (suffixes.count(suffix))
    {
      multiplier = suffixes.at(suffix);
      number.pop_back();
    }
  }
  const double value = ParseNumber(number, "--samples") * multiplier;
  if (!(value >= 1.0) || value > std::ldexp(1.0, 40) || value != std::floor(value))
  {
    throw UsageError("--samples expects a whole number from 1 to 2^40 (e.g. 1e7, 16M), got '" + text + "'");
  }
  return static_cast<uint64_t>(value);
}

bool
IsBatch(const Options & options)
{
  return options.angles || !options.viewsFile.empty() || !options.rtkGeometryFile.empty() || !options.manifest.empty();
}

bool
IsGiven(const Options & options, const std::string & name)
{
  return std::find(options.given.begin(), options.given.end(), name) != options.given.end();
}

void
CheckOptionsApply(const Options & options, unsigned mode)
{
  std::vector<std::string> refused;
  for (const OptionDeclaration & declaration : OptionDeclarations())
  {
    if (!(declaration.Modes & mode) && IsGiven(options, declaration.Name))
    {
      if (mode != OptionModes::SingleView)
      {
        throw UsageError(declaration.Refusal);
      }
      refused.push_back(declaration.Name);
    }
  }
  if (!refused.empty())
  {
    throw UsageError(JoinWords(refused, ", ") +
                     ": for a batch of views (--angles, --views, --rtk-geometry or --manifest)");
  }
}

Options
ParseCommandLine(const std::vector<std::string> & arguments)
{
  Options                  options;
  std::vector<std::string> positional;
  ParseOptionTable(
    arguments, OptionDeclarations(), " (see pbdrr --help)", options, options.given, [&](const std::string & word) {
      positional.push_back(word);
    });
  if (options.help || options.version || (!options.listSeries.empty() && positional.empty()))
  {
    return options;
  }
  if (!options.manifest.empty())
  {
    if (!positional.empty())
    {
      throw UsageError("--manifest names the volumes: give no INPUT (got '" + positional[0] + "')");
    }
    if (!options.output.empty())
    {
      throw UsageError("--manifest names the outputs (its output column): give no -o");
    }
  }
  else if (positional.size() != 1)
  {
    throw UsageError(positional.empty() ? "no input given (pbdrr INPUT -o OUTPUT; see pbdrr --help)"
                                        : "one input expected, got " + std::to_string(positional.size()) + ": '" +
                                            positional[0] + "', '" + positional[1] + "', ...");
  }
  else
  {
    options.input = positional[0];
  }
  if (options.output.empty() && options.manifest.empty())
  {
    throw UsageError("no output given: -o OUTPUT (.mha, .nrrd, .nii, .nii.gz, .tif: float; .png: 8-bit gray)");
  }
  if (options.gantryDegrees && std::abs(*options.gantryDegrees) <= 2.0 * 3.14159265358979323846 &&
      *options.gantryDegrees != std::floor(*options.gantryDegrees))
  {
    // plastimatch's -y takes radians: 1.57 for an AP view is a habit, and in degrees it is nearly the lateral view.
    std::ostringstream warning;
    warning << "--gantry " << *options.gantryDegrees << " is in degrees (a view " << *options.gantryDegrees
            << " degrees from --gantry 0); for " << *options.gantryDegrees << " radians give --gantry "
            << *options.gantryDegrees * 180.0 / 3.14159265358979323846;
    options.warnings.push_back(warning.str());
  }
  if (options.energyKeV && options.muWater)
  {
    throw UsageError("--energy and --mu-water both set mu_water: give one");
  }
  // The options that do not apply to the projector chosen: the command line's own rules. The render's rules (the
  // control variate's kernel and weighting, what streams) are the filter's, asked of it before the load
  // (VerifyRenderSettings()); there `auto` resolves to off where the control variate cannot apply.
  if (options.exact && options.accuracyPercent)
  {
    throw UsageError("--accuracy chooses its estimator, exact rays among them: give --accuracy or --exact, not "
                     "both");
  }
  if (options.exact && options.paperCount)
  {
    throw UsageError("--paper-count applies to point sampling, not to --exact");
  }
  if (options.exact && options.controlVariateGiven && options.controlVariate > 0)
  {
    throw UsageError("--control-variate applies to point sampling, not to --exact");
  }
  if (!options.accuracyPercent && DefaultAccuracyApplies(options))
  {
    options.accuracyPercent = DefaultAccuracyPercent;
    options.accuracyIsDefault = true;
  }
  return options;
}

bool
DefaultAccuracyApplies(const Options & options)
{
  if (!options.manifest.empty() || !options.standardErrorOutput.empty() || !options.labelChannelsOutput.empty() ||
      !options.spectrumFile.empty() || options.kvp)
  {
    return false;
  }
  for (const OptionDeclaration & declaration : OptionDeclarations())
  {
    if (declaration.Group == OptionGroup::Rendering && declaration.Name != "--seed" &&
        declaration.Name != "--threads" && IsGiven(options, declaration.Name))
    {
      return false;
    }
  }
  return true;
}

std::string
HelpText()
{
  // The groups of the options, in the order of the help, each with its heading.
  const std::vector<std::pair<OptionGroup, std::string>> groups = {
    { OptionGroup::Geometry,
      "Geometry (plastimatch drr convention; lengths in mm, angles in DEGREES; world = the CT's LPS frame):\n" },
    { OptionGroup::Rendering, "Rendering:\n" },
    { OptionGroup::Physics, "Physics:\n" },
    { OptionGroup::Batches,
      R"(Batches: many views in one run, the volume loaded once and the points drawn once for every view; view k's image
depends only on (--seed, k), whichever run, shard or thread count renders it, and view 0 is the single view of the
same options (--geometry, then the flags, then the view's own fields). The sampling options are a single view's;
for speed, --control-variate 16 --samples 2M renders a 256 x 256 chest view in 26 ms at NRMSE < 2%
(--control-variate 8: 33 ms, < 1.4%; docs/benchmark/batch_chest_360.md):
)" },
    { OptionGroup::Messages, "Input, other outputs and messages:\n" },
  };
  std::string text =
    R"(pbdrr - digitally reconstructed radiographs by unbiased Monte Carlo point sampling (PointBasedDRR)

Usage: pbdrr INPUT -o OUTPUT [options]
       pbdrr register CT --xray X -o OUT.png [options]   the CT's pose from X-rays (pbdrr register --help)

INPUT   a DICOM series directory (the largest series, or --series UID), or a volume ITK reads
        (.mha, .nrrd, .nii, .nii.gz, ...). Voxels are HU unless --input-units mu.
OUTPUT  the extension decides: .mha .nrrd .nii .nii.gz .tif hold float values (line integrals by default);
        .png holds 8-bit gray levels (window from the 0.5 and 99.5 percentiles unless --window), bone bright.
)";
  for (const auto & group : groups)
  {
    text += "\n" + group.second + GroupHelp(OptionDeclarations(), group.first);
  }
  return text + R"(Option forms: --size 256 256 or --size=256,256 or --size 256x256; --samples=1e7; -vq for -v -q.

Examples:
  pbdrr ct_dir/ -o ap.png --gantry 90                       AP radiograph of a DICOM series, 10M samples
  pbdrr ct.nii.gz -o lat.mha --gantry 0 --samples 1e8       lateral view, line integrals, 10^8 samples
  pbdrr ct.mha -o drr.mha --stderr drr_se.mha --seed 7      with its standard-error image
  pbdrr ct.mha -o ref.mha --exact siddon --ss 4             noise-free Siddon DRR, 16 rays per pixel
  pbdrr ct.mha -o drr.png --geometry view.txt --size 256 256 --spacing 2.4 2.4
  pbdrr mu.mha -o drr.tif --input-units mu --parallel --nrm 0 -1 0
  pbdrr ct_dir/ -o views/v_%04d.mha --angles 360 --angle-step 1 --size 256 256 --spacing 2.4 2.4
                                                            a 360-view sweep, one load and one draw
)";
}
} // namespace pbdrr
