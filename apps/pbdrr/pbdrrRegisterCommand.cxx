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
#include "pbdrrRegisterCommand.h"
#include "pbdrrMessages.h"
#include "pbdrrOptions.h"

#include "itkDRRImageSimilarity.h"
#include "itkImageFileWriter.h"
#include "itkPointBasedDRRRegistrationMethod.h"
#include "itkMultiThreaderBase.h"

#include <algorithm>
#include <cstdio>
#include <iomanip>
#include <iostream>
#include <sstream>

namespace pbdrr
{
namespace
{
using GrayType = itk::Image<unsigned char, 2>;

std::array<double, 6>
ParsePose(const std::vector<std::string> & words)
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
    levels.push_back(level);
  }
  if (levels.empty())
  {
    throw UsageError(usage);
  }
  return levels;
}

const std::vector<std::string> &
OptimizerNames()
{
  return itk::PointBasedDRRRegistrationMethod<VolumeType>::GetOptimizerNames();
}

std::string
JoinedOptimizerNames(const std::string & separator)
{
  std::string joined;
  for (const std::string & name : OptimizerNames())
  {
    joined += (joined.empty() ? "" : separator) + name;
  }
  return joined;
}

/** values -> 0..255 by their 1st and 99th percentiles over the mask (as many pixels as values). */
std::vector<unsigned char>
Windowed(const float * values, const itk::Image<unsigned char, 2> * maskImage)
{
  const std::vector<uint8_t> mask(maskImage->GetBufferPointer(),
                                  maskImage->GetBufferPointer() +
                                    maskImage->GetLargestPossibleRegion().GetNumberOfPixels());
  std::vector<float>         inside;
  for (size_t p = 0; p < mask.size(); ++p)
  {
    if (mask[p])
    {
      inside.push_back(values[p]);
    }
  }
  if (inside.empty())
  {
    inside.assign(values, values + mask.size());
  }
  std::sort(inside.begin(), inside.end());
  const double               low = inside[inside.size() / 100], high = inside[inside.size() - 1 - inside.size() / 100];
  const double               width = std::max(high - low, 1e-12);
  std::vector<unsigned char> gray(mask.size());
  for (size_t p = 0; p < mask.size(); ++p)
  {
    gray[p] = static_cast<unsigned char>(std::clamp((values[p] - low) / width, 0.0, 1.0) * 255.0 + 0.5);
  }
  return gray;
}

void
WriteGray(const std::vector<unsigned char> & pixels, const itk::Image<float, 2> * like, const std::string & path)
{
  auto image = GrayType::New();
  image->SetRegions(like->GetLargestPossibleRegion());
  image->Allocate();
  std::copy(pixels.begin(), pixels.end(), image->GetBufferPointer());
  itk::WriteImage(image, path);
}

/** OUT.png for one X-ray, OUT.N.png for the N-th of several; suffix before the extension. */
std::string
OutputPath(const std::string & output, size_t index, size_t count, const std::string & suffix)
{
  const std::string stem = output.substr(0, output.size() - 4);
  return stem + (count > 1 ? "." + std::to_string(index + 1) : std::string()) + suffix + ".png";
}
} // namespace

RegisterOptions
ParseRegisterCommandLine(const std::vector<std::string> & arguments)
{
  RegisterOptions options;
  const auto      value = [&](size_t & i, size_t count) {
    if (i + count >= arguments.size())
    {
      throw UsageError(arguments[i] + " expects " + std::to_string(count) + " value(s)");
    }
    std::vector<std::string> values(arguments.begin() + i + 1, arguments.begin() + i + 1 + count);
    i += count;
    return values;
  };
  const auto lastXRay = [&](const std::string & flag) -> XRayArgument & {
    if (options.xrays.empty())
    {
      throw UsageError(flag + " gives the view of the --xray before it: give --xray first");
    }
    return options.xrays.back();
  };
  for (size_t i = 0; i < arguments.size(); ++i)
  {
    const std::string & word = arguments[i];
    if (word == "--help" || word == "-h")
    {
      options.help = true;
    }
    else if (word == "--xray")
    {
      options.xrays.push_back({ value(i, 1)[0], "", "" });
    }
    else if (word == "--geometry")
    {
      lastXRay(word).GeometryFile = value(i, 1)[0];
    }
    else if (word == "--projection-matrix")
    {
      lastXRay(word).MatrixFile = value(i, 1)[0];
    }
    else if (word == "-o" || word == "--output")
    {
      options.output = value(i, 1)[0];
    }
    else if (word == "--series")
    {
      options.seriesUID = value(i, 1)[0];
    }
    else if (word == "--start")
    {
      options.settings.StartPose = ParsePose(value(i, 6));
    }
    else if (word == "--seed")
    {
      const double seed = ParseNumber(value(i, 1)[0], "--seed");
      if (seed < 0 || seed != std::floor(seed) || seed > 9007199254740992.0)
      {
        throw UsageError("--seed expects a whole number from 0 to 2^53");
      }
      options.settings.Seed = static_cast<uint64_t>(seed);
    }
    else if (word == "--max-seconds")
    {
      options.settings.MaxSeconds = ParseNumber(value(i, 1)[0], "--max-seconds");
      if (!(options.settings.MaxSeconds > 0.0))
      {
        throw UsageError("--max-seconds must be positive");
      }
    }
    else if (word == "--samples")
    {
      options.settings.Samples = ParseSampleCount(value(i, 1)[0]);
    }
    else if (word == "--exact")
    {
      const std::string name = value(i, 1)[0];
      if (name != "siddon")
      {
        throw UsageError("register --exact expects siddon, got '" + name + "'");
      }
      options.settings.Exact = true;
    }
    else if (word == "--metric")
    {
      const std::string name = value(i, 1)[0];
      if (!itk::DRRImageSimilarity::IsMetricName(name))
      {
        throw UsageError("--metric expects " + itk::DRRImageSimilarity::JoinMetricNames(" or ") + ", got '" + name +
                         "'");
      }
      options.settings.Metric = name;
    }
    else if (word == "--shrink")
    {
      const std::vector<Level> levels = ParseLevels(value(i, 1)[0], word);
      options.settings.Shrink.clear();
      for (const Level & level : levels)
      {
        if (level.Samples > 0 || level.Sigma >= 0.0)
        {
          throw UsageError("--shrink expects whole factors from 1 to 64, e.g. 4,2 (--levels takes points and sigmas)");
        }
        options.settings.Shrink.push_back(level.Shrink);
      }
    }
    else if (word == "--levels")
    {
      const std::vector<Level> levels = ParseLevels(value(i, 1)[0], word);
      options.settings.Shrink.clear();
      options.settings.LevelSamples.clear();
      options.settings.LevelSigmas.clear();
      const bool samples = std::any_of(levels.begin(), levels.end(), [](const Level & l) { return l.Samples > 0; });
      const bool sigmas = std::any_of(levels.begin(), levels.end(), [](const Level & l) { return l.Sigma >= 0.0; });
      for (const Level & level : levels)
      {
        if (samples && level.Samples == 0)
        {
          throw UsageError("--levels: give the points of every level, or of none (e.g. 4:5e5,2:1e6)");
        }
        options.settings.Shrink.push_back(level.Shrink);
        if (samples)
        {
          options.settings.LevelSamples.push_back(level.Samples);
        }
        if (sigmas)
        {
          options.settings.LevelSigmas.push_back(std::max(0.0, level.Sigma));
        }
      }
    }
    else if (word == "--optimizer")
    {
      const std::string name = value(i, 1)[0];
      const auto &      names = OptimizerNames();
      if (std::find(names.begin(), names.end(), name) == names.end())
      {
        throw UsageError("--optimizer expects " + JoinedOptimizerNames(" or ") + ", got '" + name + "'");
      }
      options.settings.Optimizer = name;
    }
    else if (word == "--starts")
    {
      const double starts = ParseNumber(value(i, 1)[0], "--starts");
      if (starts < 1 || starts > 1000 || starts != std::floor(starts))
      {
        throw UsageError("--starts expects a whole number from 1 to 1000");
      }
      options.settings.Starts = static_cast<unsigned>(starts);
    }
    else if (word == "--start-radius")
    {
      options.settings.StartRadius = ParseNumber(value(i, 1)[0], "--start-radius");
      if (!(options.settings.StartRadius >= 0.0) || options.settings.StartRadius > 180.0)
      {
        throw UsageError("--start-radius expects mm and degrees from 0 to 180");
      }
    }
    else if (word == "--threads")
    {
      const double threads = ParseNumber(value(i, 1)[0], "--threads");
      if (threads < 1 || threads > 1024 || threads != std::floor(threads))
      {
        throw UsageError("--threads expects a whole number from 1 to 1024");
      }
      options.settings.Threads = static_cast<unsigned>(threads);
    }
    else if (word == "--verbose" || word == "-v")
    {
      options.settings.Verbose = true;
    }
    else if (word == "--quiet" || word == "-q")
    {
      options.quiet = true;
    }
    else if (!word.empty() && word[0] == '-')
    {
      throw UsageError("unknown option '" + word + "' of pbdrr register (see pbdrr register --help)");
    }
    else if (options.input.empty())
    {
      options.input = word;
    }
    else
    {
      throw UsageError("pbdrr register takes one CT, got a second input '" + word + "'");
    }
  }
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
  const auto pad = [](std::string text) {
    text.resize(std::max<size_t>(text.size() + 1, 26), ' ');
    return text;
  };
  using MethodType = itk::PointBasedDRRRegistrationMethod<VolumeType>;
  const auto  defaults = MethodType::New();
  std::string schedule;
  for (size_t level = 0; level < defaults->GetShrinkFactorsPerLevel().size(); ++level)
  {
    std::ostringstream one;
    one << defaults->GetShrinkFactorsPerLevel()[level] << ":" << defaults->GetNumberOfSamplesPerLevel()[level] << ":"
        << defaults->GetSmoothingSigmasPerLevel()[level];
    schedule += (schedule.empty() ? "" : ",") + one.str();
  }
  const auto metric = MethodType::MetricType::New();
  return R"(pbdrr register - the rigid pose of a CT that matches its DRRs to real X-rays

Usage: pbdrr register CT --xray X [--xray Y ...] -o OUT.png [options]

CT      a DICOM series directory, an export root or a volume ITK reads (HU), as for pbdrr
--xray FILE             an X-ray: a CT localizer (DICOM; its view from its header), or a 2D image followed by
  --geometry FILE         its view as a geometry file (as pbdrr --geometry reads it: where the file is silent,
                          512 x 512 pixels of 1.2 mm about the CT's centre), or
  --projection-matrix FILE  its view as a 3 x 4 projection matrix
                        Two or more X-rays are registered jointly (biplane: a second view fixes the depth one
                        view sees only as magnification).
-o OUT.png              the DRR at the pose (OUT.N.png for the N-th of several X-rays) and OUT.checkerboard.png,
                        the DRR and the X-ray in alternate 32-pixel squares

The pose is the CT moved in the room, x -> R (x - c) + c + t (c: the centre of the CT's grid; R: rotations rx, ry, rz
about z, then x, then y, as itk::Euler3DTransform); identity is where the scanner's frame of reference puts it.
The similarity is the gradient correlation (GC: the NCC of the images' row and column differences) of DRR and
X-ray, or their normalized cross-correlation (NCC), over the field both cover (the pixels whose
rays cross the CT), mean over the X-rays: blind to the X-ray's gain, offset and units. The DRRs are kept points
re-projected at every pose, and the similarity's derivative comes from one backward pass over them
(itk::PointBasedDRRMetricv4): an ITK v4 optimizer follows it on a multi-resolution schedule.

Options:
  --start TX TY TZ RX RY RZ   the starting pose: mm and degrees (default 0 0 0 0 0 0)
)" + pad("  --metric " + itk::DRRImageSimilarity::JoinMetricNames("|")) +
         R"(the similarity: gc, the gradient correlation (default: edges only, blind to a
                          table or holder outside the CT's field, scatter, a heel effect), or ncc, the
                          normalized cross-correlation of the images
)" + pad("  --optimizer " + JoinedOptimizerNames("|")) +
         "the ITK v4 optimizer (default " + MethodType::DefaultOptimizerName +
         R"(): rsgd regular-step gradient descent,
                          lbfgsb L-BFGS-B, cg conjugate gradient with a line search; powell and amoeba
                          (Nelder-Mead) use no derivative (powell is the default with --exact)
  --levels S[:N[:SIGMA]],...  the schedule, coarse to fine: per level the detector binning S, the kept points N
                          and a Gaussian smoothing of DRR and X-ray, SIGMA mm at the detector (default )" +
         schedule + R"(;
                          levels without N take --samples points, without SIGMA no smoothing)
  --shrink S[,S...]       the schedule's binnings alone (as --levels S,S)
  --samples N             points per DRR, kept and re-projected at every pose: on every level (default: per level,
                          as above; )" +
         std::to_string(metric->GetNumberOfSamples()) + R"( on levels given without points))
  --starts K              the global stage: the first level run from K starts, the best goes on (default 1)
  --start-radius R        the spread of those starts about --start: up to R mm and R degrees per axis (default 10)
  --exact siddon          the exact Siddon projector instead of points (no noise, no derivative: powell)
  --seed S                the points' seed (default 0): the same seed, the same pose on any thread count
  --max-seconds T         stop after T seconds with the best pose so far (says so)
  --series UID            the DICOM series of the CT
  --threads T             worker threads (default: all cores)
  --verbose, -v           each level's similarity, pose and stop     --quiet, -q   only the result lines

Prints:
  pose: tx ty tz rx ry rz      (mm, degrees)
  similarity: S                (the metric at full resolution; and the start's on the first level)
  time: T s, N DRRs            (N poses rendered, M of them with the derivative)
)";
}

void
RunRegister(const RegisterOptions & options)
{
  if (options.settings.Threads > 0)
  {
    itk::MultiThreaderBase::SetGlobalDefaultNumberOfThreads(options.settings.Threads);
  }
  std::vector<XRay> xrays;
  for (const auto & argument : options.xrays)
  {
    xrays.push_back(ReadXRay(argument.Image, argument.GeometryFile, argument.MatrixFile));
    if (!options.quiet)
    {
      std::cerr << "pbdrr: register: X-ray " << xrays.back().Description << std::endl;
    }
  }
  const LoadedVolume loaded = LoadVolume(options.input, options.seriesUID);
  if (!options.quiet)
  {
    for (const auto & note : loaded.Notes)
    {
      std::cerr << "pbdrr: " << note << std::endl;
    }
    std::cerr << "pbdrr: register: CT " << loaded.Description << std::endl;
  }
  // A geometry file's view as a single view of it is built, its default isocenter the CT's centre: built again now
  // that the CT is loaded (above, before the load, to check the X-rays first).
  const itk::ImageBase<3> * volume = loaded.Grid();
  for (size_t x = 0; x < xrays.size(); ++x)
  {
    if (!options.xrays[x].GeometryFile.empty())
    {
      xrays[x].Geometry = XRayViewOfFile(options.xrays[x].GeometryFile, volume);
    }
  }
  const RegistrationResult result =
    loaded.Visit([&](auto * ct) { return RegisterToXRays(ct, xrays, options.settings); });
  std::cout << std::fixed << std::setprecision(3) << "pose: " << result.Pose[0] << " " << result.Pose[1] << " "
            << result.Pose[2] << " " << result.Pose[3] << " " << result.Pose[4] << " " << result.Pose[5] << "\n"
            << std::setprecision(4) << "similarity: " << result.Similarity << " (" << options.settings.Metric
            << "; at the start " << result.StartSimilarity << " on the first level)\n"
            << std::setprecision(2) << "time: " << result.Seconds << " s, " << result.Evaluations << " DRRs ("
            << result.DerivativeEvaluations << " with the derivative)"
            << (result.StoppedByTime ? ", stopped at --max-seconds: the best pose so far" : "") << std::endl;
  for (size_t x = 0; x < xrays.size(); ++x)
  {
    const auto *               drr = result.FinalDRRs[x].GetPointer();
    const auto                 drrGray = Windowed(drr->GetBufferPointer(), result.Masks[x]);
    const auto                 xrayGray = Windowed(xrays[x].Image->GetBufferPointer(), result.Masks[x]);
    const auto                 size = drr->GetLargestPossibleRegion().GetSize();
    std::vector<unsigned char> checkerboard(drrGray.size());
    for (size_t p = 0; p < checkerboard.size(); ++p)
    {
      const size_t column = p % size[0], row = p / size[0];
      checkerboard[p] = ((column / 32 + row / 32) % 2) ? drrGray[p] : xrayGray[p];
    }
    const std::string drrPath = OutputPath(options.output, x, xrays.size(), "");
    const std::string boardPath = OutputPath(options.output, x, xrays.size(), ".checkerboard");
    WriteGray(drrGray, drr, drrPath);
    WriteGray(checkerboard, drr, boardPath);
    if (!options.quiet)
    {
      std::cerr << "pbdrr: wrote " << drrPath << " and " << boardPath << std::endl;
    }
  }
}
} // namespace pbdrr
