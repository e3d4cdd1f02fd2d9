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

// Regression tests of what the fuzz targets of test/fuzz found (docs/fuzzing.md), one test per finding, and of the
// stream form of the geometry-file reader the geometry fuzzer drives.

#include "itkDRRAttenuationVolume.h"
#include "itkDRRProjectionGeometry.h"
#include "itkExactDRRImageFilter.h"
#include "itkPointBasedDRRImageFilter.h"
#include "PointBasedDRRTestHelpers.h"
#include "gtest/gtest.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

namespace
{
using namespace PointBasedDRRTest;
using GeometryType = itk::DRRProjectionGeometry;
using OutputModeEnum = itk::PointBasedDRREnums::OutputMode;
using TransferEnum = itk::PointBasedDRREnums::TransferFunction;

template <typename TVolume>
typename TVolume::Pointer
MakeFilledVolume(const typename TVolume::SizeType & size, double spacing, typename TVolume::PixelType value)
{
  typename TVolume::SpacingType   s;
  typename TVolume::PointType     origin;
  typename TVolume::DirectionType direction;
  s.Fill(spacing);
  origin.Fill(0.0);
  direction.SetIdentity();
  auto volume = MakeVolume<TVolume>(size, s, origin, direction);
  volume->FillBuffer(value);
  return volume;
}

GeometryType::Pointer
GeometryLookingAt(const GeometryType::PointType & isocenter, double pixelSpacing)
{
  auto geometry = GeometryType::New();
  geometry->SetIsocenter(isocenter);
  geometry->SetDetectorSize({ { 4, 4 } });
  geometry->SetDetectorSpacing(GeometryType::DetectorVectorType(pixelSpacing));
  return geometry;
}
} // namespace

// Fuzzing found: a volume whose voxels are all one huge integral value (3e38 in float) converted its level offset to
// int64 (undefined behaviour, UBSan: "3e+38 is outside the range of representable values of type 'long'").
TEST(PointBasedDRRFuzzRegression, HugeIntegralVoxelsBuildLevelsWithoutOverflow)
{
  const itk::DRRAttenuationVolume::SizeType size = { { 1, 3, 1 } };
  auto                                      identity = itk::DRRTransferFunction::New();
  identity->SetMode(TransferEnum::Identity);

  const std::vector<float> floats(3, 3e38f);
  auto                     volume = itk::DRRAttenuationVolume::New();
  ASSERT_NO_THROW(volume->Build(floats.data(), size, *identity, nullptr));
  ASSERT_TRUE(volume->HasLevels());
  ASSERT_EQ(volume->GetNumberOfLevels(), 1u);
  EXPECT_EQ(volume->GetLevelMu(0), static_cast<double>(3e38f));

  const std::vector<double> doubles(3, 1e20); // HU: mu 2e15 /mm, within float
  auto                      natural = itk::DRRTransferFunction::New();
  ASSERT_NO_THROW(volume->Build(doubles.data(), size, *natural, nullptr));
  ASSERT_EQ(volume->GetNumberOfLevels(), 1u);
  EXPECT_EQ(volume->GetLevelMu(0), static_cast<float>(natural->Evaluate(1e20)));
}

// Fuzzing found: a finite line integral beyond the float range (mu 3e38 /mm over 1e6 mm) was written as an infinite
// output pixel. Both filters now refuse it, naming the output pixel type.
TEST(PointBasedDRRFuzzRegression, LineIntegralBeyondTheOutputPixelTypeIsRefused)
{
  auto volume = MakeFilledVolume<MuVolumeType>({ { 2, 2, 2 } }, 1e6, 3e38f);
  auto geometry = GeometryLookingAt(volume->GetOrigin() + itk::Vector<double, 3>(5e5), 1e6);
  geometry->SetSourceToIsocenterDistance(1e7);
  geometry->SetSourceToDetectorDistance(1e7);

  auto exact = itk::ExactDRRImageFilter<MuVolumeType, ProjectionType>::New();
  exact->SetInput(volume);
  exact->SetGeometry(geometry);
  exact->GetTransferFunction()->SetMode(TransferEnum::Identity);
  const std::string exactError = UpdateError(exact.GetPointer());
  EXPECT_NE(exactError.find("output pixel type"), std::string::npos) << exactError;

  auto drr = itk::PointBasedDRRImageFilter<MuVolumeType, ProjectionType>::New();
  drr->SetInput(volume);
  drr->SetGeometry(geometry);
  drr->GetTransferFunction()->SetMode(TransferEnum::Identity);
  drr->SetNumberOfSamples(1000);
  const std::string drrError = UpdateError(drr.GetPointer());
  EXPECT_NE(drrError.find("output pixel type"), std::string::npos) << drrError;

  // The same volume in double output fits.
  auto exactDouble = itk::ExactDRRImageFilter<MuVolumeType, itk::Image<double, 2>>::New();
  exactDouble->SetInput(volume);
  exactDouble->SetGeometry(geometry);
  exactDouble->GetTransferFunction()->SetMode(TransferEnum::Identity);
  ASSERT_EQ(UpdateError(exactDouble.GetPointer()), "");
  double largest = 0.0;
  for (const double value : ToVector(exactDouble->GetOutput()))
  {
    EXPECT_TRUE(std::isfinite(value) && value >= 0.0) << value;
    largest = std::max(largest, value);
  }
  EXPECT_GT(largest, static_cast<double>(std::numeric_limits<float>::max()));
}

// Found while extending the filter fuzzer to unsigned char output (its seed gray16_unsigned_char_refused): Gray16
// levels (up to 65535) were cast to unsigned char, undefined behaviour (UBSan: "264 is outside the range of
// representable values of type unsigned char"). Refused now, naming the output pixel type.
TEST(PointBasedDRRFuzzRegression, Gray16IntoUnsignedCharIsRefused)
{
  auto volume = MakeFilledVolume<HUVolumeType>({ { 4, 4, 4 } }, 1.0, 0);
  auto exact = itk::ExactDRRImageFilter<HUVolumeType, itk::Image<unsigned char, 2>>::New();
  exact->SetInput(volume);
  exact->SetGeometry(GeometryLookingAt(volume->GetOrigin() + itk::Vector<double, 3>(1.5), 2.0));
  exact->SetOutputMode(OutputModeEnum::Gray16);
  EXPECT_NE(UpdateError(exact.GetPointer()).find("output pixel type"), std::string::npos);
  exact->SetOutputMode(OutputModeEnum::Gray8);
  EXPECT_EQ(UpdateError(exact.GetPointer()), "");
}

// Fuzzing found: a negative line integral (-7.9e7) from the exact tent (trilinear) projector. The ray of an explicit
// parallel geometry (a frame rotated 180 degrees about x, about -180 about y: v has a z component of 1.2e-16) runs
// through the voxel centres of row y = 1, a plane of the dual grid; a Gauss node's fraction came out -1.1e-16, a
// negative weight on the neighbour's mu of 1e25 /mm. The fractions are clamped to the cell now, so the integrand is a
// convex combination of the corners' mu. Before that, this case gave -3.9e7 (neighbours 1e25) and -1.2e21 (3e38).
// Seed: corpus/Filter/regression_trilinear_ray_on_centre_plane.
TEST(PointBasedDRRFuzzRegression, TrilinearRayOnAVoxelCentrePlaneIsNeverNegative)
{
  MuVolumeType::SpacingType spacing;
  spacing[0] = 1.0;
  spacing[1] = 0.5;
  spacing[2] = 0.07;
  MuVolumeType::PointType origin;
  origin.Fill(0.0);
  MuVolumeType::DirectionType direction;
  direction.SetIdentity();
  auto volume = MakeVolume<MuVolumeType>({ { 1, 3, 1 } }, spacing, origin, direction);

  itk::Vector<double, 3> u;
  u[0] = -0.999999995403967;
  u[1] = -1.1741333277025684e-20;
  u[2] = -9.5875262036372092e-05;
  itk::Vector<double, 3> v;
  v[0] = 0.0;
  v[1] = -1.0;
  v[2] = 1.2246467991473532e-16;
  const itk::Vector<double, 3> n = itk::CrossProduct(u, v);
  MuVolumeType::PointType      centre = volume->GetOrigin();
  centre[1] += 0.5; // voxel (0, 1, 0)
  auto geometry = GeometryType::New();
  geometry->SetExplicitParallelGeometry(centre - n * 3.0, u, v);
  geometry->SetDetectorSize({ { 1, 1 } });
  geometry->SetDetectorSpacing(GeometryType::DetectorVectorType(2.0));

  auto exact = itk::ExactDRRImageFilter<MuVolumeType, itk::Image<double, 2>>::New();
  exact->SetInput(volume);
  exact->SetGeometry(geometry);
  exact->GetTransferFunction()->SetMode(TransferEnum::Identity);
  exact->SetNumberOfWorkUnits(1);
  for (const auto kernel :
       { itk::PointBasedDRREnums::ReconstructionKernel::Tent, itk::PointBasedDRREnums::ReconstructionKernel::Box })
  {
    exact->SetReconstructionKernel(kernel);
    for (const float neighbour : { 1e25f, 1.0f, 3e38f })
    {
      volume->SetPixel({ { 0, 0, 0 } }, neighbour);
      volume->SetPixel({ { 0, 1, 0 } }, 0.02f);
      volume->SetPixel({ { 0, 2, 0 } }, neighbour);
      volume->Modified();
      ASSERT_EQ(UpdateError(exact.GetPointer()), "") << kernel << ", neighbours " << neighbour;
      const double value = ToVector(exact->GetOutput())[0];
      EXPECT_TRUE(std::isfinite(value) && value >= 0.0) << kernel << ", neighbours " << neighbour << ": " << value;
      if (neighbour == 1.0f) // ordinary values: the integral of the centre row's mu along z, 0.02 x 0.07 mm
      {
        EXPECT_NEAR(value, 0.02 * 0.07, 1e-8) << kernel; // the tilt takes 2e-6 of it
      }
    }
  }
}

// ReadGeometry() reads the geometry-file format from a stream, as ReadGeometryFile() does from a file.
TEST(PointBasedDRRFuzzRegression, ReadGeometryFromAStreamNamesTheLine)
{
  auto               geometry = GeometryType::New();
  std::istringstream good("# comment\nprojection parallel\ncols 7 # seven\nrows 9\r\nspacing 0.5 2");
  ASSERT_NO_THROW(geometry->ReadGeometry(good));
  EXPECT_EQ(geometry->GetProjection(), itk::PointBasedDRREnums::Projection::Parallel);
  EXPECT_EQ(geometry->GetDetectorSize()[0], 7u);
  EXPECT_EQ(geometry->GetDetectorSize()[1], 9u);
  EXPECT_EQ(geometry->GetDetectorSpacing()[1], 2.0);

  std::istringstream bad("sad 900\n\nsid twelve\nsad 5\n");
  try
  {
    geometry->ReadGeometry(bad, "view.txt");
    FAIL() << "no exception";
  }
  catch (const itk::ExceptionObject & e)
  {
    EXPECT_NE(std::string(e.GetDescription()).find("view.txt:3: "), std::string::npos) << e.GetDescription();
  }
  EXPECT_EQ(geometry->GetSourceToIsocenterDistance(), 900.0); // lines before the error are applied

  std::istringstream unnamed("cols 0\n");
  try
  {
    geometry->ReadGeometry(unnamed);
    FAIL() << "no exception";
  }
  catch (const itk::ExceptionObject & e)
  {
    EXPECT_NE(std::string(e.GetDescription()).find("line 1: "), std::string::npos) << e.GetDescription();
  }
}
