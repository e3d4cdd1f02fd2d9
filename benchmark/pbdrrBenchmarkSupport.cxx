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
#include "pbdrrBenchmarkSupport.h"

#include "itkRayCastInterpolateImageFunction.h"

#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>

namespace pbdrr
{
namespace bench
{
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

double
Median(std::vector<double> values)
{
  if (values.empty())
    return NaN;
  std::sort(values.begin(), values.end());
  const size_t n = values.size();
  return n % 2 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

std::vector<std::string>
SplitList(const std::string & text, bool keepEmpty)
{
  std::vector<std::string> items;
  std::stringstream        list(text);
  for (std::string item; std::getline(list, item, ',');)
  {
    if (keepEmpty || !item.empty())
    {
      items.push_back(item);
    }
  }
  return items;
}

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
  const double rmse = std::sqrt(squared / n);
  e.Nrmse = rmse / span;
  e.RelativeRmse = rmse / (referenceSum / n);
  e.MaxError = worst / span;
  e.SumRatio = sum / referenceSum;
  e.Pearson = sxy / std::sqrt(sxx * syy);
  return e;
}

MuImageType::Pointer
MuImage(const itk::ImageBase<3> * grid, const itk::DRRAttenuationVolume * attenuation)
{
  auto mu = MuImageType::New();
  mu->CopyInformation(grid);
  mu->SetRegions(grid->GetLargestPossibleRegion());
  mu->Allocate();
  std::copy(
    attenuation->GetMuBuffer(), attenuation->GetMuBuffer() + attenuation->GetNumberOfVoxels(), mu->GetBufferPointer());
  return mu;
}

RayCastResampleType::Pointer
MakeRayCaster(const MuImageType *                mu,
              const itk::DRRProjectionGeometry * geometry,
              itk::Transform<double, 3, 3> *     transform)
{
  using InterpolatorType = itk::RayCastInterpolateImageFunction<MuImageType, double>;
  auto interpolator = InterpolatorType::New();
  interpolator->SetTransform(transform);
  interpolator->SetThreshold(0.0);
  InterpolatorType::InputPointType focalPoint;
  const auto                       source = geometry->GetSourcePosition();
  for (unsigned r = 0; r < 3; ++r)
    focalPoint[r] = source[r];
  interpolator->SetFocalPoint(focalPoint);

  auto resample = RayCastResampleType::New();
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
  return resample;
}
} // namespace bench
} // namespace pbdrr
