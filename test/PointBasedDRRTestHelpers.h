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
#ifndef PointBasedDRRTestHelpers_h
#define PointBasedDRRTestHelpers_h

#include "itkImage.h"
#include "itkImageRegionConstIterator.h"
#include "itkImageRegionIterator.h"
#include "itkImageSource.h"
#include "itkMath.h"
#include "itkProcessObject.h"

#include "gtest/gtest.h"

#include <cmath>
#include <string>
#include <vector>

/** Small builders shared by the PointBasedDRR tests. */
namespace PointBasedDRRTest
{
using HUVolumeType = itk::Image<short, 3>;
using MuVolumeType = itk::Image<float, 3>;
using ProjectionType = itk::Image<float, 2>;
using Projection3DType = itk::Image<float, 3>;

/** A zero-filled volume with the given grid. */
template <typename TVolume>
typename TVolume::Pointer
MakeVolume(const typename TVolume::SizeType &      size,
           const typename TVolume::SpacingType &   spacing,
           const typename TVolume::PointType &     origin,
           const typename TVolume::DirectionType & direction)
{
  auto volume = TVolume::New();
  volume->SetRegions(size);
  volume->SetSpacing(spacing);
  volume->SetOrigin(origin);
  volume->SetDirection(direction);
  volume->Allocate();
  volume->FillBuffer(0);
  return volume;
}

/** 32 x 28 x 24 voxels of 3 mm about the room origin, HU: a soft-tissue ellipsoid in air with two bone blocks placed
 * asymmetrically, so that every rotation and translation changes its projections (the registration tests' CT). */
inline MuVolumeType::Pointer
MakeAsymmetricPhantom()
{
  auto volume = MuVolumeType::New();
  volume->SetRegions(MuVolumeType::SizeType{ { 32, 28, 24 } });
  MuVolumeType::SpacingType spacing;
  spacing.Fill(3.0);
  volume->SetSpacing(spacing);
  const double origin[3] = { -46.5, -40.5, -34.5 };
  volume->SetOrigin(origin);
  volume->Allocate();
  for (unsigned int k = 0; k < 24; ++k)
  {
    for (unsigned int j = 0; j < 28; ++j)
    {
      for (unsigned int i = 0; i < 32; ++i)
      {
        const double x = -46.5 + 3.0 * i, y = -40.5 + 3.0 * j, z = -34.5 + 3.0 * k;
        float        hu = (x * x / 1600.0 + y * y / 1156.0 + z * z / 900.0) < 1.0 ? 40.0f : -1000.0f;
        if ((x > -25 && x < -8 && y > -18 && y < 4 && z > -10 && z < 18) ||
            (x > 6 && x < 24 && y > 8 && y < 20 && z > -22 && z < -6))
        {
          hu = 1200.0f;
        }
        volume->SetPixel({ { i, j, k } }, hu);
      }
    }
  }
  return volume;
}

/** Sets voxels low[a] <= index[a] <= high[a] to value. */
template <typename TVolume>
void
FillBlock(TVolume * volume, const itk::Index<3> & low, const itk::Index<3> & high, typename TVolume::PixelType value)
{
  for (auto k = low[2]; k <= high[2]; ++k)
  {
    for (auto j = low[1]; j <= high[1]; ++j)
    {
      for (auto i = low[0]; i <= high[0]; ++i)
      {
        volume->SetPixel({ { i, j, k } }, value);
      }
    }
  }
}

/** Rotation matrix about a unit axis by an angle in degrees. */
inline itk::Matrix<double, 3, 3>
RotationMatrix(const itk::Vector<double, 3> & axis, double angleInDegrees)
{
  const double              a = angleInDegrees * itk::Math::pi / 180.0;
  const double              c = std::cos(a);
  const double              s = std::sin(a);
  const double              x = axis[0], y = axis[1], z = axis[2];
  itk::Matrix<double, 3, 3> r;
  r[0][0] = c + x * x * (1 - c);
  r[0][1] = x * y * (1 - c) - z * s;
  r[0][2] = x * z * (1 - c) + y * s;
  r[1][0] = y * x * (1 - c) + z * s;
  r[1][1] = c + y * y * (1 - c);
  r[1][2] = y * z * (1 - c) - x * s;
  r[2][0] = z * x * (1 - c) - y * s;
  r[2][1] = z * y * (1 - c) + x * s;
  r[2][2] = c + z * z * (1 - c);
  return r;
}

/** Pixel values of an image as doubles, in buffer order. */
template <typename TImage>
std::vector<double>
ToVector(const TImage * image)
{
  const auto *        buffer = image->GetBufferPointer();
  std::vector<double> values(image->GetBufferedRegion().GetNumberOfPixels());
  for (size_t p = 0; p < values.size(); ++p)
  {
    values[p] = static_cast<double>(buffer[p]);
  }
  return values;
}

/** Directory of the shared real CT data, or empty if absent. */
inline std::string
SharedDataDirectory()
{
#ifdef POINTBASEDDRR_SHARED_DATA_DIR
  return POINTBASEDDRR_SHARED_DATA_DIR;
#else
  return "";
#endif
}

/** The vector (x, y, z), mm or unitless. */
inline itk::Vector<double, 3>
Vec(double x, double y, double z)
{
  itk::Vector<double, 3> v;
  v[0] = x;
  v[1] = y;
  v[2] = z;
  return v;
}

/** The point (x, y, z), mm. */
inline itk::Point<double, 3>
Pt(double x, double y, double z)
{
  itk::Point<double, 3> p;
  p[0] = x;
  p[1] = y;
  p[2] = z;
  return p;
}

/** Runs f; returns the description of the itk::ExceptionObject it throws, or records a failure (GoogleTest). */
template <typename TFunction>
std::string
ExceptionMessage(TFunction f, const std::string & what)
{
  try
  {
    f();
  }
  catch (const itk::ExceptionObject & e)
  {
    return e.GetDescription();
  }
  catch (...)
  {
    ADD_FAILURE() << what << ": threw something other than itk::ExceptionObject";
    return "";
  }
  ADD_FAILURE() << what << ": did not throw";
  return "";
}

/** Updates a filter; returns the description of the itk::ExceptionObject it throws, or "" if it does not throw. */
inline std::string
UpdateError(itk::ProcessObject * filter)
{
  try
  {
    filter->Update();
  }
  catch (const itk::ExceptionObject & e)
  {
    return e.GetDescription();
  }
  return "";
}

/** True if text contains part. */
inline bool
Contains(const std::string & text, const std::string & part)
{
  return text.find(part) != std::string::npos;
}

/** An image source that generates only the region requested of it, from an image in memory, and records each
 * request: a stand-in for a streaming reader. */
template <typename TImage>
class RecordingSource : public itk::ImageSource<TImage>
{
public:
  ITK_DISALLOW_COPY_AND_MOVE(RecordingSource);
  using Self = RecordingSource;
  using Superclass = itk::ImageSource<TImage>;
  using Pointer = itk::SmartPointer<Self>;
  itkNewMacro(Self);

  typename TImage::ConstPointer            Image;
  std::vector<typename TImage::RegionType> Requests;

protected:
  RecordingSource() = default;
  void
  GenerateOutputInformation() override
  {
    this->GetOutput()->CopyInformation(Image);
  }
  void
  GenerateData() override
  {
    TImage *   output = this->GetOutput();
    const auto region = output->GetRequestedRegion();
    Requests.push_back(region);
    output->SetBufferedRegion(region);
    output->Allocate();
    itk::ImageRegionConstIterator<TImage> in(Image, region);
    itk::ImageRegionIterator<TImage>      out(output, region);
    for (; !in.IsAtEnd(); ++in, ++out)
    {
      out.Set(in.Get());
    }
  }
};
} // namespace PointBasedDRRTest

#endif
