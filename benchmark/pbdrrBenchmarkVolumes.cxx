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
#include "pbdrrBenchmarkVolumes.h"

#include "itkNearestNeighborInterpolateImageFunction.h"
#include "itkResampleImageFilter.h"

#include <algorithm>
#include <cmath>

namespace pbdrr
{
namespace bench
{
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

uint64_t
CountNonAir(const VolumeType * volume, const itk::DRRTransferFunction * transfer)
{
  const float * values = volume->GetBufferPointer();
  const size_t  n = volume->GetBufferedRegion().GetNumberOfPixels();
  return static_cast<uint64_t>(
    std::count_if(values, values + n, [transfer](float v) { return transfer->Evaluate(v) > 0.0; }));
}

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

void
WriteProjection(const Image & values, unsigned cols, unsigned rows, double spacing, const std::string & path)
{
  auto image = ProjectionType::New();
  image->SetRegions(ProjectionType::SizeType{ { cols, rows } });
  ProjectionType::SpacingType pixelSpacing;
  pixelSpacing.Fill(spacing); // ITK 6 has no SetSpacing(double)
  image->SetSpacing(pixelSpacing);
  image->Allocate();
  std::copy(values.begin(), values.end(), image->GetBufferPointer());
  Write(image.GetPointer(), path);
}
} // namespace bench
} // namespace pbdrr
