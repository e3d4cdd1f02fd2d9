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
