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
#ifndef pbdrrBenchmarkSupport_h
#define pbdrrBenchmarkSupport_h
// What the three benchmark programs (PointBasedDRRBenchmark, PointBasedDRRAccuracy, PointBasedDRRPoseRate) share:
// wall and CPU clocks, medians, comma-separated lists, projections as vectors, their errors against a reference, the
// mu volume of a DRR filter and ITK's ray caster set up on a DRRProjectionGeometry.
#include "itkDRRAttenuationVolume.h"
#include "itkDRRProjectionGeometry.h"

#include "itkImage.h"
#include "itkResampleImageFilter.h"
#include "itkTransform.h"

#include <limits>
#include <string>
#include <vector>

namespace pbdrr
{
namespace bench
{
using MuImageType = itk::Image<float, 3>;
using ProjectionType = itk::Image<float, 2>;
using Image = std::vector<double>; // a projection, columns fastest
constexpr double NaN = std::numeric_limits<double>::quiet_NaN();

/** Seconds of a steady clock (differences only). */
double
Now();

/** CPU seconds (user + system, every thread) of this process. */
double
CpuSeconds();

/** The median (the mean of the middle two for an even count); NaN if empty. */
double
Median(std::vector<double> values);

/** The items of "a,b,c"; empty items are left out unless keepEmpty. */
std::vector<std::string>
SplitList(const std::string & text, bool keepEmpty = false);

/** The pixels of an image's buffered region as doubles. */
template <typename TImage>
Image
ToVector(const TImage * image)
{
  const size_t n = image->GetBufferedRegion().GetNumberOfPixels();
  return Image(image->GetBufferPointer(), image->GetBufferPointer() + n);
}

struct Errors
{
  double Nrmse{ NaN };        // RMSE / (max - min of the reference)
  double RelativeRmse{ NaN }; // RMSE / mean of the reference
  double MaxError{ NaN };     // max |error| / (max - min of the reference)
  double SumRatio{ NaN };     // sum(image) / sum(reference): the bias
  double Pearson{ NaN };
};

/** The errors of an image against a reference of the same size (all NaN if the sizes differ or it is empty). */
Errors
Compare(const Image & image, const Image & reference);

/** mu (1/mm) exactly as the DRR filters compute it (their attenuation volume), on the grid of `grid`. */
MuImageType::Pointer
MuImage(const itk::ImageBase<3> * grid, const itk::DRRAttenuationVolume * attenuation);

using RayCastResampleType = itk::ResampleImageFilter<MuImageType, MuImageType>;

/** ITK's ray caster as in ITK's Examples/Filtering/DigitallyReconstructedRadiograph1.cxx and its 2D-3D registration:
 * a ResampleImageFilter whose interpolator is an itk::RayCastInterpolateImageFunction (threshold 0), both given
 * `transform`, with the focal point at the source of `geometry`, writing a 3D image of one slice placed on the
 * detector plane: output origin = centre of pixel (0, 0), direction (u, v, -n), spacing (du, dv), so that the rays run
 * from the source through every pixel centre. */
RayCastResampleType::Pointer
MakeRayCaster(const MuImageType *                mu,
              const itk::DRRProjectionGeometry * geometry,
              itk::Transform<double, 3, 3> *     transform);
} // namespace bench
} // namespace pbdrr

#endif
