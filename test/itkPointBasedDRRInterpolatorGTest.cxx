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
// The drop-in for ITK's ray caster: it answers as the filter renders, it runs where the ray caster runs (a
// multi-threaded ResampleImageFilter) and agrees with it, and it renders once per pose.
#include "itkPointBasedDRRInterpolateImageFunction.h"
#include "itkEuler3DTransform.h"
#include "itkRayCastInterpolateImageFunction.h"
#include "itkResampleImageFilter.h"
#include "PointBasedDRRTestHelpers.h"

#include "gtest/gtest.h"

namespace
{
using namespace PointBasedDRRTest;
using InterpolatorType = itk::PointBasedDRRInterpolateImageFunction<MuVolumeType, double>;
using RayCasterType = itk::RayCastInterpolateImageFunction<MuVolumeType, double>;
using TransformType = itk::Euler3DTransform<double>;

/** mu (1/mm): a water-like box holding a denser block, in a margin of air; 2 mm voxels. */
MuVolumeType::Pointer
MakeBoxPhantom()
{
  MuVolumeType::SizeType    size = { { 40, 36, 30 } };
  MuVolumeType::SpacingType spacing(2.0);
  MuVolumeType::PointType   origin;
  for (unsigned a = 0; a < 3; ++a)
  {
    origin[a] = -0.5 * (size[a] - 1) * spacing[a] + 3.0 * a;
  }
  MuVolumeType::DirectionType identity;
  identity.SetIdentity();
  auto volume = MakeVolume<MuVolumeType>(size, spacing, origin, identity);
  FillBlock<MuVolumeType>(volume.GetPointer(), { { 4, 4, 4 } }, { { 35, 31, 25 } }, 0.02f);
  FillBlock<MuVolumeType>(volume.GetPointer(), { { 10, 8, 12 } }, { { 20, 15, 19 } }, 0.05f);
  return volume;
}

itk::DRRProjectionGeometry::Pointer
MakeDetector(const itk::Point<double, 3> & centre)
{
  auto geometry = itk::DRRProjectionGeometry::New();
  geometry->SetGantryAngleInDegrees(70.0);
  geometry->SetSourceToIsocenterDistance(400.0);
  geometry->SetSourceToDetectorDistance(600.0);
  geometry->SetIsocenter(centre);
  geometry->SetDetectorSize({ { 24, 20 } });
  geometry->SetDetectorSpacing(itk::Vector<double, 2>(6.0));
  return geometry;
}

TransformType::Pointer
MakePose(const itk::Point<double, 3> & centre, double scale)
{
  auto transform = TransformType::New();
  transform->SetCenter(centre);
  TransformType::ParametersType parameters(6);
  parameters[0] = 0.05 * scale;
  parameters[1] = -0.03 * scale;
  parameters[2] = 0.04 * scale;
  parameters[3] = 4.0 * scale;
  parameters[4] = -3.0 * scale;
  parameters[5] = 2.0 * scale;
  transform->SetParameters(parameters);
  return transform;
}

itk::Point<double, 3>
Centre(const MuVolumeType * volume)
{
  itk::ContinuousIndex<double, 3> index;
  for (unsigned a = 0; a < 3; ++a)
  {
    index[a] = (volume->GetLargestPossibleRegion().GetSize()[a] - 1) / 2.0;
  }
  itk::Point<double, 3> centre;
  volume->TransformContinuousIndexToPhysicalPoint(index, centre);
  return centre;
}

/** At the pixel centres of its detector (mapped into the CT frame by the pose, as a metric asks), the interpolator
 * returns the filter's pixels, and it renders once per pose however many points are asked. */
TEST(PointBasedDRRInterpolator, AnswersWithTheFilterPixelsAndRendersOncePerPose)
{
  const auto volume = MakeBoxPhantom();
  const auto centre = Centre(volume);
  auto       geometry = MakeDetector(centre);
  auto       transform = MakePose(centre, 0.0);

  auto interpolator = InterpolatorType::New();
  interpolator->SetInputImage(volume);
  interpolator->SetTransform(transform);
  InterpolatorType::InputPointType focalPoint = geometry->GetSourcePosition();
  interpolator->SetFocalPoint(focalPoint);
  interpolator->SetDetectorGeometry(geometry);
  interpolator->GetDRRFilter()->SetNumberOfSamples(200000);
  interpolator->GetDRRFilter()->SetSeed(3);
  interpolator->Evaluate(centre); // renders the first pose
  transform->SetParameters(MakePose(centre, 1.0)->GetParameters());

  auto filter = itk::PointBasedDRRImageFilter<MuVolumeType, ProjectionType>::New();
  filter->SetInput(volume);
  filter->GetTransferFunction()->SetPiecewiseLinearPoints({ { 0.0, 0.0 }, { 1e9, 1e9 } });
  filter->SetGeometry(geometry);
  filter->SetTransform(transform);
  filter->SetSampler(itk::DRRStratifiedSampler::New());
  filter->SetSplat(itk::PointBasedDRREnums::Splat::Bilinear);
  filter->SetReconstructionKernel(itk::PointBasedDRREnums::ReconstructionKernel::Tent);
  filter->SetNumberOfSamples(200000);
  filter->SetSeed(3);
  filter->ReusePointsOn();
  filter->Update();
  const auto expected = ToVector(filter->GetOutput());

  double peak = 0.0;
  for (unsigned row = 0; row < 20; ++row)
  {
    for (unsigned column = 0; column < 24; ++column)
    {
      const auto pixel = geometry->GetPixelCenter(column, row);
      const auto value = interpolator->Evaluate(transform->TransformPoint(pixel));
      EXPECT_NEAR(value, expected[row * 24 + column], 1e-6 * (1.0 + expected[row * 24 + column]))
        << "pixel " << column << ", " << row;
      peak = std::max(peak, value);
    }
  }
  EXPECT_GT(peak, 0.5); // the phantom's shadow is on the detector
  EXPECT_EQ(interpolator->GetNumberOfRenders(), 2u);
  EXPECT_EQ(interpolator->GetDRRFilter()->GetNumberOfPointCloudDraws(), 1u) << "poses re-project the kept points";

  // A second view sharing the filter: its own detector, the same points; the first view's answers are unchanged.
  auto lateral = InterpolatorType::New();
  lateral->SetInputImage(volume);
  lateral->SetTransform(transform);
  auto lateralGeometry = MakeDetector(centre);
  lateralGeometry->SetGantryAngleInDegrees(160.0);
  InterpolatorType::InputPointType lateralFocalPoint = lateralGeometry->GetSourcePosition();
  lateral->SetFocalPoint(lateralFocalPoint);
  lateral->SetDetectorGeometry(lateralGeometry);
  lateral->SetDRRFilter(interpolator->GetDRRFilter());
  EXPECT_GT(lateral->Evaluate(transform->TransformPoint(lateralGeometry->GetPixelCenter(12, 10))), 0.5);
  const auto pixel = geometry->GetPixelCenter(12, 10);
  EXPECT_NEAR(interpolator->Evaluate(transform->TransformPoint(pixel)),
              expected[10 * 24 + 12],
              1e-6 * (1.0 + expected[10 * 24 + 12]));
  EXPECT_EQ(interpolator->GetDRRFilter()->GetNumberOfPointCloudDraws(), 1u) << "the views share their points";
}

/** ITK's DRR pipeline (a multi-threaded ResampleImageFilter writing a one-slice image on the detector plane) runs with
 * either interpolator, the same code but for the type; the images agree within the Monte Carlo error (z-score of
 * the standard-error output) plus the pixel averaging, away from the shadow's edges. */
TEST(PointBasedDRRInterpolator, RunsInTheRayCastersPipelineAndAgreesWithIt)
{
  const auto volume = MakeBoxPhantom();
  const auto centre = Centre(volume);
  auto       geometry = MakeDetector(centre);
  const auto render = [&](auto interpolator, bool fromImage) {
    using ResampleType = itk::ResampleImageFilter<MuVolumeType, MuVolumeType>;
    auto transform = MakePose(centre, 1.0);
    interpolator->SetTransform(transform);
    typename std::remove_reference_t<decltype(*interpolator)>::InputPointType focalPoint =
      geometry->GetSourcePosition();
    interpolator->SetFocalPoint(focalPoint);
    interpolator->SetThreshold(0.0);
    auto resample = ResampleType::New();
    resample->SetInput(volume);
    resample->SetTransform(transform);
    resample->SetInterpolator(interpolator);
    resample->SetSize({ { 24, 20, 1 } });
    MuVolumeType::SpacingType spacing(6.0);
    resample->SetOutputSpacing(spacing);
    MuVolumeType::PointType     origin;
    MuVolumeType::DirectionType direction;
    for (unsigned r = 0; r < 3; ++r)
    {
      origin[r] = geometry->GetPixelCenter(0.0, 0.0)[r];
      direction[r][0] = geometry->GetColumnDirection()[r];
      direction[r][1] = geometry->GetRowDirection()[r];
      direction[r][2] = -geometry->GetNormal()[r];
    }
    resample->SetOutputOrigin(origin);
    resample->SetOutputDirection(direction);
    resample->SetNumberOfWorkUnits(4);
    if (fromImage)
    {
      resample->UpdateOutputInformation();
      auto detector = MuVolumeType::New();
      detector->CopyInformation(resample->GetOutput());
      detector->SetRegions(resample->GetOutput()->GetLargestPossibleRegion());
      if constexpr (std::is_same<decltype(interpolator), InterpolatorType::Pointer>::value)
      {
        interpolator->SetDetectorFromImage(detector);
      }
    }
    resample->Update();
    const float * b = resample->GetOutput()->GetBufferPointer();
    return std::vector<double>(b, b + 24 * 20);
  };
  const auto rayCast = render(RayCasterType::New(), false);

  auto pointBased = InterpolatorType::New();
  pointBased->GetDRRFilter()->SetNumberOfSamples(2000000);
  const auto onDetector = render(pointBased, true);
  const auto standardError = ToVector(pointBased->GetDRRFilter()->GetStandardErrorOutput());
  // Away from edges, the ray caster's one ray and the pixel average of the tent model agree where the image is
  // locally flat (the four neighbours within 2%).
  const auto flat = [&](size_t p) {
    for (const size_t q : { p - 1, p + 1, p - 24, p + 24 })
    {
      if (!(std::abs(rayCast[q] - rayCast[p]) < 0.02 * rayCast[p]))
      {
        return false;
      }
    }
    return rayCast[p] > 0.1;
  };
  unsigned compared = 0;
  for (unsigned row = 1; row + 1 < 20; ++row)
  {
    for (unsigned column = 1; column + 1 < 24; ++column)
    {
      const size_t p = row * 24 + column;
      if (flat(p))
      {
        EXPECT_LT(std::abs(onDetector[p] - rayCast[p]), 5.0 * standardError[p] + 0.01 * rayCast[p])
          << "pixel " << column << ", " << row;
        ++compared;
      }
    }
  }
  EXPECT_GE(compared, 30u);

  // The one-line swap alone (an automatic virtual detector of 64 x 64 pixels, about 2.5 mm at the volume): the
  // ray caster's image again, to the Monte Carlo error of the virtual pixels (about 1000 points each: 3%, 5 sigma).
  auto automatic = InterpolatorType::New();
  automatic->GetDRRFilter()->SetNumberOfSamples(4000000);
  automatic->SetDetectorSize(64);
  const auto virtualDetector = render(automatic, false);
  for (size_t p = 25; p + 25 < rayCast.size(); ++p)
  {
    if (flat(p))
    {
      EXPECT_LT(std::abs(virtualDetector[p] - rayCast[p]), 0.15 * rayCast[p]) << "pixel " << p;
    }
  }
  ASSERT_NE(automatic->GetDetectorGeometry(), nullptr);
  EXPECT_EQ(automatic->GetDetectorGeometry()->GetDetectorSize()[0], 64u);
}

TEST(PointBasedDRRInterpolator, ExplainsWhatIsMissing)
{
  auto interpolator = InterpolatorType::New();
  interpolator->SetInputImage(MakeBoxPhantom());
  itk::Point<double, 3> origin;
  origin.Fill(0.0);
  EXPECT_THROW(interpolator->Evaluate(origin), itk::ExceptionObject); // no transform
  interpolator->SetTransform(TransformType::New());
  interpolator->SetFocalPoint(origin); // inside the volume
  EXPECT_THROW(interpolator->Evaluate(origin), itk::ExceptionObject);
}
} // namespace
