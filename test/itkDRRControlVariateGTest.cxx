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
// The control variate (DESIGN 10) at its extremes: a residual of zero renders the coarse image alone, exactly where
// the coarse image is flat over every pixel; all air, one voxel, a factor larger than the volume, int16 extremes, the
// source inside the volume; the same bits on any number of threads; the split itself (masses, signs, block means).
#include "itkPointBasedDRRImageFilter.h"
#include "itkExactDRRImageFilter.h"
#include "itkDRRControlVariate.h"
#include "itkDRRRefinementTrend.h"
#include "itkDRRSamplerFactory.h"
#include "itkDRRTransferFunction.h"
#include "itkEuler3DTransform.h"
#include "PointBasedDRRTestHelpers.h"

#include "gtest/gtest.h"

#include <algorithm>
#include <cstring>
#include <limits>

namespace
{
using namespace PointBasedDRRTest;
using FilterType = itk::PointBasedDRRImageFilter<MuVolumeType, ProjectionType>;
using ProjectionEnum = itk::PointBasedDRREnums::Projection;

MuVolumeType::Pointer
MakeMuVolume(const MuVolumeType::SizeType & size, float value)
{
  MuVolumeType::SpacingType spacing;
  spacing.Fill(1.0);
  MuVolumeType::PointType origin;
  origin.Fill(0.0);
  MuVolumeType::DirectionType direction;
  direction.SetIdentity();
  auto volume = MakeVolume<MuVolumeType>(size, spacing, origin, direction);
  volume->FillBuffer(value);
  return volume;
}

/** A parallel beam along -y whose 1 mm pixels line up with the voxels of a volume at the origin: every ray through a
 * pixel crosses the same boxes over the same lengths. */
itk::DRRProjectionGeometry::Pointer
AlignedParallelGeometry(unsigned int columns, unsigned int rows, const itk::Point<double, 3> & isocenter)
{
  auto geometry = itk::DRRProjectionGeometry::New();
  geometry->SetProjection(ProjectionEnum::Parallel);
  geometry->SetGantryAngleInDegrees(90.0);
  geometry->SetIsocenter(isocenter);
  geometry->SetDetectorSize({ { columns, rows } });
  itk::Vector<double, 2> spacing;
  spacing.Fill(1.0);
  geometry->SetDetectorSpacing(spacing);
  return geometry;
}

FilterType::Pointer
MakeFilter(const MuVolumeType * volume, itk::DRRProjectionGeometry * geometry, unsigned int factor)
{
  auto filter = FilterType::New();
  filter->SetInput(volume);
  filter->GetTransferFunction()->SetMode(itk::PointBasedDRREnums::TransferFunction::Identity);
  filter->SetGeometry(geometry);
  filter->SetControlVariateFactor(factor);
  filter->SetNumberOfSamples(100000);
  filter->SetSampler(itk::DRRSamplerFactory::Create("stratified"));
  return filter;
}

TEST(DRRControlVariate, ConstantVolumeRendersTheCoarseImageAloneExactlyWithZeroError)
{
  // 8 x 8 x 8 voxels of mu 0.02 /mm, F = 4 divides it: r = 0 everywhere, no point is drawn; the aligned parallel beam
  // sees 8 mm of tissue over every pixel of the shadow, whatever ray the coarse image draws.
  const auto volume = MakeMuVolume({ { 8, 8, 8 } }, 0.02f);
  auto       filter = MakeFilter(volume, AlignedParallelGeometry(12, 12, Pt(3.5, 3.5, 3.5)), 4);
  filter->Update();
  ASSERT_NE(filter->GetControlVariate(), nullptr);
  EXPECT_EQ(filter->GetControlVariate()->GetResidualMass(), 0.0);
  EXPECT_EQ(filter->GetPointsOnDetector(), 0u);
  const auto values = ToVector(filter->GetOutput());
  const auto errors = ToVector(filter->GetStandardErrorOutput());
  for (unsigned int row = 0; row < 12; ++row)
  {
    for (unsigned int column = 0; column < 12; ++column)
    {
      const size_t p = row * 12 + column;
      const bool   shadow = row >= 2 && row < 10 && column >= 2 && column < 10;
      EXPECT_NEAR(values[p], shadow ? 8 * 0.02 : 0.0, 1e-6) << "pixel " << column << ", " << row;
      EXPECT_NEAR(errors[p], 0.0, 1e-7) << "pixel " << column << ", " << row;
    }
  }
}

TEST(DRRControlVariate, AllAirAndNothingInViewGiveZeroImagesWithZeroError)
{
  const auto air = MakeMuVolume({ { 5, 6, 7 } }, 0.0f);
  auto       filter = MakeFilter(air, AlignedParallelGeometry(8, 8, Pt(2, 2.5, 3)), 2);
  filter->Update();
  for (float v : ToVector(filter->GetOutput()))
  {
    EXPECT_EQ(v, 0.0f);
  }
  for (float v : ToVector(filter->GetStandardErrorOutput()))
  {
    EXPECT_EQ(v, 0.0f);
  }
}

/** Mean of many seeds of a filter against the exact pixel-averaged Siddon image, within 5 standard errors of the mean
 * (from the spread of the seeds) plus the reference's own midpoint error. */
template <typename TFilter>
void
ExpectUnbiasedAgainstSiddon(TFilter * filter, const std::string & what, unsigned int seeds = 48)
{
  using VolumeType = typename TFilter::InputImageType;
  auto exact = itk::ExactDRRImageFilter<VolumeType, ProjectionType>::New();
  exact->SetInput(filter->GetInput());
  exact->SetTransferFunction(filter->GetTransferFunction());
  exact->SetGeometry(filter->GetGeometry());
  exact->SetRaysPerPixelSide(32);
  exact->Update();
  const auto          reference = ToVector(exact->GetOutput());
  std::vector<double> sum(reference.size(), 0.0), sumOfSquares(reference.size(), 0.0);
  for (unsigned int seed = 0; seed < seeds; ++seed)
  {
    filter->SetSeed(seed + 1);
    filter->Update();
    const auto values = ToVector(filter->GetOutput());
    for (size_t p = 0; p < values.size(); ++p)
    {
      sum[p] += values[p];
      sumOfSquares[p] += values[p] * values[p];
    }
  }
  const double peak = *std::max_element(reference.begin(), reference.end());
  for (size_t p = 0; p < reference.size(); ++p)
  {
    const double mean = sum[p] / seeds;
    const double standardErrorOfMean = std::sqrt(std::max(0.0, sumOfSquares[p] / seeds - mean * mean) / (seeds - 1.0));
    EXPECT_LE(std::abs(mean - reference[p]), 5.0 * standardErrorOfMean + 2e-3 * peak) << what << " pixel " << p;
  }
}

TEST(DRRControlVariate, WithoutStandardErrorTheCoarseImageTracesOneReplicateAndStaysUnbiased)
{
  // A volume with structure at every scale: mu varies voxel by voxel, so the coarse image is not exact.
  auto    volume = MakeMuVolume({ { 9, 7, 6 } }, 0.0f);
  float * mu = volume->GetBufferPointer();
  for (size_t v = 0; v < 9 * 7 * 6; ++v)
  {
    mu[v] = 0.01f + 0.002f * static_cast<float>((v * 37) % 11);
  }
  auto filter = MakeFilter(volume, AlignedParallelGeometry(7, 5, Pt(4, 3, 2.5)), 2);
  filter->GetGeometry()->SetGantryAngleInDegrees(70.0); // oblique: rays cross the blocks at every fraction
  filter->SetSeed(3);
  filter->Update();
  const auto withError = ToVector(filter->GetOutput());
  filter->ComputeStandardErrorOff();
  filter->Update();
  const auto without = ToVector(filter->GetOutput());
  for (float se : ToVector(filter->GetStandardErrorOutput()))
  {
    EXPECT_EQ(se, 0.0f);
  }
  EXPECT_NE(withError, without) << "half the rays must give another coarse image";
  filter->Refine(20000);
  for (float se : ToVector(filter->GetStandardErrorOutput()))
  {
    EXPECT_EQ(se, 0.0f) << "after Refine()";
  }
  ExpectUnbiasedAgainstSiddon(filter.GetPointer(), "one replicate of coarse rays");

  // Without a control variate the option changes no bit of the image: the points are the same.
  filter->SetControlVariateFactor(0);
  filter->SetSeed(5);
  filter->ComputeStandardErrorOn();
  filter->Update();
  const auto pointsWithError = ToVector(filter->GetOutput());
  filter->ComputeStandardErrorOff();
  filter->Update();
  EXPECT_EQ(pointsWithError, ToVector(filter->GetOutput()));
}

TEST(DRRControlVariate, OneVoxelAndAFactorLargerThanTheVolumeStayUnbiased)
{
  auto one = MakeMuVolume({ { 1, 1, 1 } }, 0.05f);
  auto filter = MakeFilter(one, AlignedParallelGeometry(3, 3, Pt(0, 0, 0)), 8);
  filter->Update();
  // One voxel in a coarse box of 8^3: M_r = (1 - 1/512) mu + 511 mu / 512 = 2 (511 / 512) mu V.
  EXPECT_NEAR(filter->GetControlVariate()->GetResidualMass(), 2.0 * 511.0 / 512.0 * double(0.05f), 1e-8);
  EXPECT_EQ(filter->GetControlVariate()->GetCoarseVolume().GetNumberOfVoxels(), 1u);
  ExpectUnbiasedAgainstSiddon(filter.GetPointer(), "one voxel, F = 8");
}

TEST(DRRControlVariate, Int16ExtremesStayUnbiased)
{
  using HUFilterType = itk::PointBasedDRRImageFilter<HUVolumeType, ProjectionType>;
  HUVolumeType::SpacingType spacing;
  spacing.Fill(1.0);
  HUVolumeType::PointType origin;
  origin.Fill(0.0);
  HUVolumeType::DirectionType direction;
  direction.SetIdentity();
  auto volume = MakeVolume<HUVolumeType>({ { 5, 6, 3 } }, spacing, origin, direction);
  auto buffer = volume->GetBufferPointer();
  for (size_t v = 0; v < 90; ++v)
  {
    buffer[v] = v % 3 == 0 ? std::numeric_limits<short>::max() : v % 3 == 1 ? std::numeric_limits<short>::min() : 0;
  }
  auto filter = HUFilterType::New();
  filter->SetInput(volume);
  filter->SetGeometry(AlignedParallelGeometry(8, 8, Pt(2, 2.5, 1)));
  filter->SetControlVariateFactor(2);
  filter->SetNumberOfSamples(100000);
  filter->Update();
  const double mass = filter->GetControlVariate()->GetTotalMass();
  EXPECT_GT(mass, 0.0);
  EXPECT_GT(filter->GetControlVariate()->GetResidualMass(), 0.0);
  for (float v : ToVector(filter->GetOutput()))
  {
    EXPECT_TRUE(std::isfinite(v));
  }
  ExpectUnbiasedAgainstSiddon(filter.GetPointer(), "int16 extremes");
}

TEST(DRRControlVariate, SourceInsideTheVolumeGivesAFiniteImageAndAWarning)
{
  const auto volume = MakeMuVolume({ { 10, 10, 10 } }, 0.02f);
  auto       geometry = itk::DRRProjectionGeometry::New();
  geometry->SetSourceToIsocenterDistance(2.0); // the source 2 mm from the centre: inside
  geometry->SetSourceToDetectorDistance(30.0);
  geometry->SetIsocenter(Pt(4.5, 4.5, 4.5));
  geometry->SetDetectorSize({ { 16, 16 } });
  itk::Vector<double, 2> spacing;
  spacing.Fill(4.0);
  geometry->SetDetectorSpacing(spacing);
  auto       filter = MakeFilter(volume, geometry, 4);
  const bool warnings = itk::Object::GetGlobalWarningDisplay(); // a process-wide switch: restored below, for the
  filter->GlobalWarningDisplayOff();                            // tests after this one that expect warnings
  filter->Update();
  itk::Object::SetGlobalWarningDisplay(warnings);
  for (float v : ToVector(filter->GetOutput()))
  {
    EXPECT_TRUE(std::isfinite(v));
  }
  for (float v : ToVector(filter->GetStandardErrorOutput()))
  {
    EXPECT_TRUE(std::isfinite(v));
  }
}

std::vector<double>
RenderOnThreads(unsigned int threads, itk::PointBasedDRREnums::Splat splat, bool standardError, bool reuse)
{
  MuVolumeType::SpacingType spacing;
  spacing[0] = 1.0;
  spacing[1] = 1.5;
  spacing[2] = 2.0;
  MuVolumeType::PointType origin;
  origin.Fill(-5.0);
  MuVolumeType::DirectionType direction;
  direction.SetIdentity();
  auto         volume = MakeVolume<MuVolumeType>({ { 13, 11, 9 } }, spacing, origin, direction);
  unsigned int state = 7u;
  for (size_t v = 0; v < volume->GetBufferedRegion().GetNumberOfPixels(); ++v)
  {
    state = state * 1664525u + 1013904223u;
    volume->GetBufferPointer()[v] = 0.001f * static_cast<float>((state >> 8) % 40);
  }
  auto geometry = itk::DRRProjectionGeometry::New();
  geometry->SetSourceToIsocenterDistance(60.0);
  geometry->SetSourceToDetectorDistance(100.0);
  geometry->SetGantryAngleInDegrees(30.0);
  geometry->SetIsocenter(Pt(1, 2, 3));
  geometry->SetDetectorSize({ { 24, 20 } });
  itk::Vector<double, 2> pixel;
  pixel.Fill(1.5);
  geometry->SetDetectorSpacing(pixel);
  auto filter = MakeFilter(volume, geometry, 4);
  filter->SetSampler(itk::DRRSamplerFactory::Create("level-alias"));
  filter->SetSplat(splat);
  filter->SetReusePoints(reuse);
  filter->SetSeed(11);
  filter->SetNumberOfWorkUnits(threads);
  filter->GetMultiThreader()->SetMaximumNumberOfThreads(threads);
  filter->Update();
  return ToVector(standardError ? filter->GetStandardErrorOutput() : filter->GetOutput());
}

TEST(DRRControlVariate, SameSeedSameBitsOnOneTwoAndSevenThreads)
{
  for (auto splat : { itk::PointBasedDRREnums::Splat::Nearest, itk::PointBasedDRREnums::Splat::Bilinear })
  {
    for (bool standardError : { false, true })
    {
      for (bool reuse : { false, true })
      {
        const auto one = RenderOnThreads(1, splat, standardError, reuse);
        const auto two = RenderOnThreads(2, splat, standardError, reuse);
        const auto seven = RenderOnThreads(7, splat, standardError, reuse);
        ASSERT_EQ(one.size(), two.size());
        EXPECT_EQ(0, std::memcmp(one.data(), two.data(), one.size() * sizeof(double))) << splat << " reuse " << reuse;
        EXPECT_EQ(0, std::memcmp(one.data(), seven.data(), one.size() * sizeof(double))) << splat << " reuse " << reuse;
      }
    }
  }
}

TEST(DRRControlVariate, SplitsIntoBlockMeansAndASignedResidual)
{
  // 3 x 2 x 1 voxels, F = 2: two coarse voxels; the second holds one column of the volume and a column of padding.
  auto        volume = itk::DRRAttenuationVolume::New();
  const float mu[6] = { 0.1f, 0.3f, 0.5f, 0.2f, 0.4f, 0.8f };
  auto        transfer = itk::DRRTransferFunction::New();
  transfer->SetMode(itk::PointBasedDRREnums::TransferFunction::Identity);
  volume->Build(mu, { { 3, 2, 1 } }, *transfer, nullptr);
  auto split = itk::DRRControlVariate::New();
  split->Build(*volume, 2, nullptr);
  const auto & coarse = split->GetCoarseVolume();
  ASSERT_EQ(coarse.GetNumberOfVoxels(), 2u);
  EXPECT_FLOAT_EQ(coarse.GetMuBuffer()[0], (0.1f + 0.3f + 0.2f + 0.4f) / 8.0f);
  EXPECT_FLOAT_EQ(coarse.GetMuBuffer()[1], (0.5f + 0.8f) / 8.0f); // padding is air, the mean over all F^3
  const auto & residual = split->GetResidualVolume();
  ASSERT_EQ(residual.GetSize()[0], 4u);
  ASSERT_EQ(residual.GetSize()[2], 2u);
  double sumOfMagnitudes = 0.0;
  for (uint64_t v = 0; v < residual.GetNumberOfVoxels(); ++v)
  {
    const uint64_t i = v % 4, j = (v / 4) % 2, k = v / 8;
    const double   fine = (i < 3 && k == 0) ? mu[i + 3 * j] : 0.0;
    const double   r = fine - coarse.GetMuBuffer()[i / 2];
    const bool     negative = residual.IsNegativeResidual(i, j, k);
    EXPECT_NEAR(negative ? -residual.GetMuBuffer()[v] : residual.GetMuBuffer()[v], r, 1e-7) << "voxel " << v;
    sumOfMagnitudes += std::abs(r);
  }
  EXPECT_NEAR(split->GetResidualMass(), sumOfMagnitudes, 1e-6);
  EXPECT_NEAR(split->GetTotalMass(), 2.3, 1e-6);
  EXPECT_NE(ExceptionMessage([&] { split->Build(*volume, 1, nullptr); }, "factor 1"), "");
}

TEST(DRRControlVariate, RefusesTheTentKernelThePaperCountAndFactorOne)
{
  const auto volume = MakeMuVolume({ { 4, 4, 4 } }, 0.02f);
  auto       filter = MakeFilter(volume, AlignedParallelGeometry(6, 6, Pt(1.5, 1.5, 1.5)), 2);
  filter->SetReconstructionKernel(itk::PointBasedDRREnums::ReconstructionKernel::Tent);
  EXPECT_TRUE(Contains(ExceptionMessage([&] { filter->Update(); }, "tent"), "needs the box kernel"));
  filter->SetReconstructionKernel(itk::PointBasedDRREnums::ReconstructionKernel::Box);
  filter->SetPointWeighting(itk::PointBasedDRREnums::PointWeighting::PaperCount);
  EXPECT_TRUE(Contains(ExceptionMessage([&] { filter->Update(); }, "paper count"), "unbiased point weighting"));
  filter->SetPointWeighting(itk::PointBasedDRREnums::PointWeighting::Unbiased);
  filter->SetControlVariateFactor(1);
  EXPECT_TRUE(Contains(ExceptionMessage([&] { filter->Update(); }, "factor 1"), "ControlVariateFactor 1"));
  filter->SetControlVariateFactor(FilterType::AutomaticControlVariateFactor);
  EXPECT_NO_THROW(filter->Update());
  EXPECT_GE(filter->GetControlVariate()->GetFactor(), 2u);
}

// `auto` resolves to off, in the filter, where a control variate cannot apply (the tent kernel, the paper's count): the
// image is the render without one, bit for bit, whole and streamed; a chosen F there is refused (the test above).
TEST(DRRControlVariate, AutomaticFactorResolvesToOffWhereTheControlVariateCannotApply)
{
  auto volume = MakeMuVolume({ { 16, 16, 16 } }, 0.0f);
  for (itk::SizeValueType v = 0; v < 16 * 16 * 16; ++v)
  {
    volume->GetBufferPointer()[v] = 0.02f + 0.001f * static_cast<float>((v * 2654435761u) % 7);
  }
  const auto geometry = AlignedParallelGeometry(16, 16, Pt(7.5, 7.5, 7.5));
  using KernelEnum = itk::PointBasedDRREnums::ReconstructionKernel;
  using WeightingEnum = itk::PointBasedDRREnums::PointWeighting;
  for (const bool tent : { true, false })
  {
    for (const unsigned int slabs : { 1u, 2u })
    {
      const auto render = [&](unsigned int factor) {
        auto filter = MakeFilter(volume, geometry, factor);
        filter->SetReconstructionKernel(tent ? KernelEnum::Tent : KernelEnum::Box);
        filter->SetPointWeighting(tent ? WeightingEnum::Unbiased : WeightingEnum::PaperCount);
        filter->SetNumberOfStreamDivisions(slabs);
        filter->Update();
        EXPECT_EQ(filter->GetControlVariate(), nullptr);
        EXPECT_EQ(filter->ResolveStreamedControlVariateFactor(), 0u);
        return std::vector<float>(filter->GetOutput()->GetBufferPointer(),
                                  filter->GetOutput()->GetBufferPointer() + 16 * 16);
      };
      const std::vector<float> automatic = render(FilterType::AutomaticControlVariateFactor);
      EXPECT_EQ(automatic, render(0)) << (tent ? "tent" : "paper count") << ", " << slabs << " slab(s)";
      EXPECT_GT(*std::max_element(automatic.begin(), automatic.end()), 0.0f);
    }
  }
}

// `auto` never keeps a split whose residual holds more than MaximumAutomaticResidualFraction of the mass: a one-slice
// volume's F = 2 blocks average the slice with the air that pads it, so |r| is as large as mu itself.
TEST(DRRControlVariate, AutomaticFactorIsDeclinedWhereTheResidualExceedsItsStatedFraction)
{
  const auto slice = MakeMuVolume({ { 16, 16, 1 } }, 0.0f);
  for (itk::SizeValueType v = 0; v < 256; ++v)
  {
    slice->GetBufferPointer()[v] = 0.01f + 0.0001f * static_cast<float>(v % 17);
  }
  const auto geometry = AlignedParallelGeometry(16, 1, Pt(7.5, 7.5, 0.0));
  auto       explicitTwo = MakeFilter(slice, geometry, 2);
  explicitTwo->Update();
  ASSERT_NE(explicitTwo->GetControlVariate(), nullptr);
  const double fraction =
    explicitTwo->GetControlVariate()->GetResidualMass() / explicitTwo->GetControlVariate()->GetTotalMass();
  EXPECT_GT(fraction, FilterType::MaximumAutomaticResidualFraction); // asked for, it is built all the same
  auto automatic = MakeFilter(slice, geometry, FilterType::AutomaticControlVariateFactor);
  automatic->Update();
  EXPECT_EQ(automatic->GetControlVariate(), nullptr) << "M_r / M = " << fraction;
  // A smooth volume keeps its split under `auto`.
  const auto smooth = MakeMuVolume({ { 16, 16, 16 } }, 0.02f);
  auto       kept =
    MakeFilter(smooth, AlignedParallelGeometry(16, 16, Pt(7.5, 7.5, 7.5)), FilterType::AutomaticControlVariateFactor);
  kept->Update();
  ASSERT_NE(kept->GetControlVariate(), nullptr);
  EXPECT_LE(kept->GetControlVariate()->GetResidualMass(),
            FilterType::MaximumAutomaticResidualFraction * kept->GetControlVariate()->GetTotalMass());
}

// `auto` with kept points (a batch): one pose keeps the geometric factor; many poses of few points take a larger one
// (the coarse image is paid per pose, the points once: docs/benchmark/auto_choice.md); very many points keep it; more
// poses never give a smaller factor.
TEST(DRRControlVariate, AutomaticFactorGrowsWithThePosesTheKeptPointsServe)
{
  auto volume = MakeMuVolume({ { 64, 64, 64 } }, 0.0f);
  for (itk::SizeValueType v = 0; v < 64 * 64 * 64; ++v)
  {
    volume->GetBufferPointer()[v] = 0.02f + 0.001f * static_cast<float>((v * 2654435761u) % 7);
  }
  const auto geometry = AlignedParallelGeometry(64, 64, Pt(31.5, 31.5, 31.5));
  const auto factorFor = [&](uint64_t poses, uint64_t samples) {
    auto filter = MakeFilter(volume, geometry, FilterType::AutomaticControlVariateFactor);
    filter->SetReusePoints(true);
    filter->SetExpectedNumberOfPoses(poses);
    filter->SetNumberOfSamples(samples);
    filter->Update();
    return filter->GetControlVariate() ? filter->GetControlVariate()->GetFactor() : 0u;
  };
  const unsigned int geometric = factorFor(1, 10000);
  EXPECT_EQ(geometric, 2u) << "1 mm pixels over 1 mm voxels";
  EXPECT_EQ(factorFor(1, 100), geometric) << "one pose: the geometric factor, whatever the points";
  EXPECT_GT(factorFor(360, 10000), geometric) << "360 poses of 10^4 points: the coarse image dominates";
  EXPECT_EQ(factorFor(360, 100000000), geometric) << "10^8 points: the points dominate";
  unsigned int last = geometric;
  for (const uint64_t poses : { 2, 10, 100, 1000, 10000 })
  {
    const unsigned int factor = factorFor(poses, 10000);
    EXPECT_GE(factor, last) << poses << " poses";
    last = factor;
  }
  // Without kept points the expected poses are ignored.
  auto separate = MakeFilter(volume, geometry, FilterType::AutomaticControlVariateFactor);
  separate->SetExpectedNumberOfPoses(360);
  separate->SetNumberOfSamples(10000);
  separate->Update();
  ASSERT_NE(separate->GetControlVariate(), nullptr);
  EXPECT_EQ(separate->GetControlVariate()->GetFactor(), geometric);
}
} // namespace

namespace
{
/** A z-score bound: about 6e-7 two-sided for a normal statistic. */
constexpr double zBound = 5.0;

/** NRMSE of image against reference: the root mean square difference over the reference's range. */
double
RelativeRmsError(const ProjectionType * image, const ProjectionType * reference)
{
  const size_t  pixels = reference->GetBufferedRegion().GetNumberOfPixels();
  const float * a = image->GetBufferPointer();
  const float * b = reference->GetBufferPointer();
  double        sum = 0.0;
  for (size_t p = 0; p < pixels; ++p)
  {
    sum += (double(a[p]) - double(b[p])) * (double(a[p]) - double(b[p]));
  }
  const auto range = std::minmax_element(b, b + pixels);
  return std::sqrt(sum / static_cast<double>(pixels)) / (double(*range.second) - double(*range.first));
}

// TargetError (issue 41): the filter adds passes until its estimated relative error is at most the target, and the
// image's error against the exact one (a parallel beam whose pixels line up with the voxels: one exact ray is the
// pixel's average) is then at most the target, at every seed, within the z-bound of the error's own spread; over the
// seeds the true error is at most the estimated one, within its spread (the estimate is not optimistic). P pixels: the
// true RMS error fluctuates by sqrt(1 / (2 P)) relative, the estimate (4 strata, 3 degrees of freedom per pixel) by
// sqrt(1 / (6 P)).
TEST(PointBasedDRRTargetError, ReachesTheTargetAgainstTheExactImageAtEverySeed)
{
  constexpr unsigned int side = 32;
  auto                   volume = MakeMuVolume({ { side, 8, side } }, 0.0f);
  for (itk::SizeValueType v = 0; v < side * 8 * side; ++v)
  {
    volume->GetBufferPointer()[v] = 0.01f + 0.002f * static_cast<float>((v * 2654435761u) % 11);
  }
  const auto geometry = AlignedParallelGeometry(side, side, Pt(15.5, 3.5, 15.5));
  using ExactType = itk::ExactDRRImageFilter<MuVolumeType, ProjectionType>;
  auto exact = ExactType::New();
  exact->SetInput(volume);
  exact->GetTransferFunction()->SetMode(itk::PointBasedDRREnums::TransferFunction::Identity);
  exact->SetGeometry(geometry);
  exact->Update();
  constexpr double target = 0.01;
  const double     pixels = side * side;
  const double     spread = std::sqrt(1.0 / (2.0 * pixels) + 1.0 / (6.0 * pixels)); // of true / estimated error
  double           sumOfRatios = 0.0;
  constexpr int    seeds = 6;
  for (int seed = 0; seed < seeds; ++seed)
  {
    auto filter = MakeFilter(volume, geometry, 0);
    filter->SetSeed(static_cast<uint64_t>(seed));
    filter->SetNumberOfSamples(2000); // far too few: the passes must add the rest
    filter->SetTargetError(target);
    filter->Update();
    const double estimated = filter->GetEstimatedError();
    const double error = RelativeRmsError(filter->GetOutput(), exact->GetOutput());
    EXPECT_LE(estimated, target) << "seed " << seed;
    EXPECT_GT(filter->GetTotalNumberOfSamples(), 2000u) << "seed " << seed << ": passes were added";
    EXPECT_LE(error, target * (1.0 + zBound * spread)) << "seed " << seed << ", estimated " << estimated;
    sumOfRatios += error / estimated;
  }
  // Not optimistic: over the seeds the true error is at most the estimated one, within its spread (the stratified
  // sampler's strata overstate its error by about a tenth here: the target is met with points to spare).
  EXPECT_LE(sumOfRatios / seeds, 1.0 + zBound * spread / std::sqrt(double(seeds))) << "the estimate is not optimistic";
  EXPECT_GT(sumOfRatios / seeds, 0.5) << "the estimate is not wildly pessimistic either";
}

// A target that cannot be met within MaximumNumberOfSamples is refused with a message, after a bounded number of
// passes; a target without the standard error it is estimated from is refused before any render.
TEST(PointBasedDRRTargetError, RefusesATargetBeyondItsBudgetAndOneWithoutStandardError)
{
  const auto volume = MakeMuVolume({ { 8, 8, 8 } }, 0.0f);
  for (itk::SizeValueType v = 0; v < 512; ++v)
  {
    volume->GetBufferPointer()[v] = 0.01f + 0.003f * static_cast<float>((v * 2654435761u) % 7);
  }
  auto filter = MakeFilter(volume, AlignedParallelGeometry(8, 8, Pt(3.5, 3.5, 3.5)), 0);
  filter->SetNumberOfSamples(1000);
  filter->SetTargetError(1e-6);
  filter->SetMaximumNumberOfSamples(1000000);
  EXPECT_TRUE(
    Contains(ExceptionMessage([&] { filter->Update(); }, "budget"), "is not reached within MaximumNumberOfSamples"));
  EXPECT_LE(filter->GetTotalNumberOfSamples(), 1000000u);
  filter->SetTargetError(0.05);
  filter->ComputeStandardErrorOff();
  EXPECT_TRUE(Contains(ExceptionMessage([&] { filter->Update(); }, "no SE"), "TargetError needs the standard error"));
  filter->ComputeStandardErrorOn();
  EXPECT_NO_THROW(filter->Update());
  EXPECT_LE(filter->GetEstimatedError(), 0.05);
}

// The choice of estimator for a target (DRREstimatorChoice, PointBasedDRRImageFilter::ChooseEstimator) on the
// asymmetric phantom seen obliquely in perspective: its edges cross the pixels, so one ray per pixel has an error.
itk::DRRProjectionGeometry::Pointer
ObliquePhantomGeometry()
{
  auto geometry = itk::DRRProjectionGeometry::New();
  geometry->SetGantryAngleInDegrees(30.0);
  geometry->SetDetectorSize({ { 40, 40 } });
  itk::Vector<double, 2> spacing;
  spacing.Fill(4.0);
  geometry->SetDetectorSpacing(spacing);
  return geometry;
}

ProjectionType::Pointer
ExactImage(const MuVolumeType * volume, itk::DRRProjectionGeometry * geometry, unsigned int raysPerSide)
{
  auto exact = itk::ExactDRRImageFilter<MuVolumeType, ProjectionType>::New();
  exact->SetInput(volume);
  exact->SetGeometry(geometry);
  exact->SetRaysPerPixelSide(raysPerSide);
  exact->Update();
  return exact->GetOutput();
}

FilterType::Pointer
MakeChoosingFilter(const MuVolumeType * volume, itk::DRRProjectionGeometry * geometry, double target)
{
  auto filter = FilterType::New();
  filter->SetInput(volume);
  filter->SetGeometry(geometry);
  filter->SetTargetError(target);
  filter->ChooseEstimatorOn();
  return filter;
}

// The pilot's exact errors are upper estimates of the true ones (against 16 x 16 rays per pixel), and not wildly
// pessimistic: the rule e_k = RMS(v_k - v_8) / (1 - k / 8) holds for an error that falls as 1 / k or faster.
TEST(DRREstimatorChoice, ExactErrorsBoundTheTrueOnes)
{
  const auto volume = MakeAsymmetricPhantom();
  const auto geometry = ObliquePhantomGeometry();
  const auto reference = ExactImage(volume, geometry, 16);
  auto       filter = MakeChoosingFilter(volume, geometry, 0.5);
  filter->Update();
  const itk::DRREstimatorChoice * choice = filter->GetEstimatorChoice();
  ASSERT_NE(choice, nullptr);
  for (const unsigned int k : { 1u, 2u, 4u })
  {
    const double truth = RelativeRmsError(ExactImage(volume, geometry, k), reference);
    const double predicted = choice->GetExactError(k);
    EXPECT_GT(truth, 0.0) << k << " rays per side: the edges cross the pixels";
    // The pilot's 256 of 1600 pixels: its RMS has a spread of about 1 / sqrt(2 * 256) relative, 5 sigma of it.
    EXPECT_LE(truth, predicted * (1.0 + zBound / std::sqrt(2.0 * 256.0))) << k << " rays per side";
    EXPECT_GE(truth, predicted / 4.0) << k << " rays per side";
  }
}

// Choose() never picks an estimator whose predicted error is above the target, and picks the least work of those
// that reach it, whatever the costs: for targets from 5% to below what any estimator reaches, 1 and 10^6 poses, the
// default cost model and one where points are nearly free.
TEST(DRREstimatorChoice, NeverPicksAnEstimatorWhoseEstimateIsAboveTheTarget)
{
  const auto volume = MakeAsymmetricPhantom();
  auto       filter = MakeChoosingFilter(volume, ObliquePhantomGeometry(), 0.5);
  filter->Update();
  itk::DRREstimatorChoice choice = *filter->GetEstimatorChoice();
  auto                    cheapPoints = choice.GetCostModel();
  cheapPoints.PointNanoseconds = 1e-3;
  cheapPoints.KeptPointNanoseconds = 1e-4;
  cheapPoints.TableNanosecondsPerVoxel = 1e-3;
  bool pointsChosen = false;
  bool exactChosen = false;
  for (const auto & model : { itk::DRREstimatorChoice::CostModel{}, cheapPoints })
  {
    choice.SetCostModel(model);
    for (const double target : { 0.05, 0.01, 0.003, 0.001, 0.0003 })
    {
      for (const uint64_t poses : { uint64_t{ 1 }, uint64_t{ 1000000 } })
      {
        const auto candidates = choice.ListCandidates(target, poses, true);
        const auto chosen = choice.Choose(target, poses, true, uint64_t{ 1 } << 40);
        EXPECT_LE(chosen.Error, target) << chosen.Describe() << " for " << target;
        for (const auto & candidate : candidates)
        {
          if (candidate.Error <= target)
          {
            EXPECT_LE(chosen.Seconds, candidate.Seconds) << chosen.Describe() << " over " << candidate.Describe();
          }
        }
        pointsChosen |= chosen.Kind == itk::DRREstimatorChoice::Estimator::Points;
        exactChosen |= chosen.Kind == itk::DRREstimatorChoice::Estimator::ExactRays;
      }
    }
  }
  EXPECT_TRUE(pointsChosen && exactChosen) << "the sweep chose both kinds";
  // Below what 16 x 16 rays reach, with points beyond the budget: refused, with the reason.
  EXPECT_TRUE(Contains(ExceptionMessage([&] { choice.Choose(1e-9, 1, true, 1000); }, "unreachable"),
                       "no estimator is predicted to reach the target error"));
}

// 64 x 64 x 32 voxels of 1 mm, HU: a soft-tissue cylinder along z with a bone block off its axis. Its rows along x
// (the fastest axis) are 4 cache lines of mu: long enough for a lateral ray to read its own.
MuVolumeType::Pointer
MakeCylinderPhantom()
{
  MuVolumeType::SpacingType spacing;
  spacing.Fill(1.0);
  MuVolumeType::DirectionType direction;
  direction.SetIdentity();
  auto volume = MakeVolume<MuVolumeType>({ { 64, 64, 32 } }, spacing, MuVolumeType::PointType(), direction);
  for (itk::IndexValueType k = 0; k < 32; ++k)
  {
    for (itk::IndexValueType j = 0; j < 64; ++j)
    {
      for (itk::IndexValueType i = 0; i < 64; ++i)
      {
        const double x = i - 31.5, y = j - 31.5;
        volume->SetPixel({ { i, j, k } }, x * x + y * y < 900.0 ? 40.0f : -1000.0f);
      }
    }
  }
  FillBlock(volume.GetPointer(), { { 10, 30, 8 } }, { { 20, 50, 20 } }, 1200.0f);
  return volume;
}

// A wide cone (SAD 200 mm, SID 300 mm) at a gantry angle: 32 x 32 pixels of 4 mm, 2.7 mm apart at the isocentre.
itk::DRRProjectionGeometry::Pointer
WideConeGeometry(const MuVolumeType * volume, double gantryDegrees, unsigned int side = 32)
{
  auto geometry = itk::DRRProjectionGeometry::New();
  geometry->SetSourceToIsocenterDistance(200.0);
  geometry->SetSourceToDetectorDistance(300.0);
  geometry->SetIsocenterToImageCenter(volume);
  geometry->SetGantryAngleInDegrees(gantryDegrees);
  geometry->SetDetectorSize({ { side, side } });
  itk::Vector<double, 2> spacing;
  spacing.Fill(4.0);
  geometry->SetDetectorSpacing(spacing);
  return geometry;
}

// The pilot counts each view's reads that miss the cache: a lateral ray reads the CT's rows along x, and the ray of
// the pixel before it reads other rows, so that its reads miss; an AP ray's neighbours read its lines. Their cost is
// in the exact rays' work. A choice over several views (a batch's) takes the largest error of any of them and the mean
// work, and the renders after it keep it.
TEST(DRREstimatorChoice, CountsEachViewsCacheMissesAndChoosesOverAllViews)
{
  const auto volume = MakeCylinderPhantom();
  auto       filter = MakeChoosingFilter(volume, WideConeGeometry(volume, 90.0), 0.01);
  filter->ReusePointsOn();
  filter->SetExpectedNumberOfPoses(100);
  itk::DRREstimatorChoice choice = filter->MeasureEstimatorChoice();
  filter->SetGeometry(WideConeGeometry(volume, 0.0));
  const itk::DRREstimatorChoice lateral = filter->MeasureEstimatorChoice();
  const itk::DRREstimatorChoice ap = choice;
  ASSERT_EQ(ap.GetNumberOfViews(), 1u);
  EXPECT_NEAR(lateral.GetMeanCellsPerRay(), ap.GetMeanCellsPerRay(), 1e-6 * ap.GetMeanCellsPerRay())
    << "a square section: the same cells at 0 and 90 degrees";
  EXPECT_GT(lateral.GetMeanUnforeseenMissesPerRay(), 4.0 * ap.GetMeanUnforeseenMissesPerRay());
  const auto exactSeconds = [](const itk::DRREstimatorChoice & pilots) {
    return pilots.ListCandidates(0.01, 100, true).front().Seconds; // exact, 1 x 1 rays per pixel
  };
  EXPECT_GT(exactSeconds(lateral), 1.2 * exactSeconds(ap)) << "the lateral rays' misses cost";

  choice.AddViews(lateral);
  ASSERT_EQ(choice.GetNumberOfViews(), 2u);
  EXPECT_NEAR(exactSeconds(choice), 0.5 * (exactSeconds(ap) + exactSeconds(lateral)), 1e-9 * exactSeconds(choice));
  for (const unsigned int k : { 1u, 2u, 4u, 16u })
  {
    EXPECT_EQ(choice.GetExactError(k), std::max(ap.GetExactError(k), lateral.GetExactError(k))) << k;
  }
  EXPECT_NE(ap.GetExactError(1), lateral.GetExactError(1)) << "the views differ";
  for (const unsigned int factor : { 0u, 8u })
  {
    EXPECT_EQ(choice.GetPointsError(100000, factor),
              std::max(ap.GetPointsError(100000, factor), lateral.GetPointsError(100000, factor)));
  }
  itk::DRREstimatorChoice other = lateral;
  other.AddViews(lateral);
  EXPECT_EQ(other.GetNumberOfViews(), 2u);
  auto smaller = MakeChoosingFilter(volume, WideConeGeometry(volume, 0.0, 16), 0.01);
  EXPECT_TRUE(Contains(ExceptionMessage([&] { other.AddViews(smaller->MeasureEstimatorChoice()); }, "other detector"),
                       "the same detector"));

  // The renders keep the choice over both views: at each view, the exact rays' estimate is the larger one's.
  const auto chosen = filter->MakeEstimatorChoice(choice);
  EXPECT_EQ(chosen.Error, choice.Choose(0.01, 100, true, uint64_t{ 1 } << 40).Error);
  for (const double gantry : { 90.0, 0.0 })
  {
    filter->SetGeometry(WideConeGeometry(volume, gantry));
    filter->Update();
    ASSERT_NE(filter->GetEstimatorChoice(), nullptr);
    EXPECT_EQ(filter->GetEstimatorChoice()->GetNumberOfViews(), 2u) << "kept at gantry " << gantry;
    EXPECT_EQ(filter->GetChosenEstimator().Describe(), chosen.Describe());
  }
}

// The refinement's rules: an estimate that falls as 1 / sqrt(N) has not stalled, one that stays has (judged over 1.5
// times the points at least); the points grow for the part of the estimate that is theirs, the coarse image's stays.
TEST(DRRRefinementTrend, JudgesTheFallWithThePointsAndGrowsThemForTheirOwnPart)
{
  itk::DRRRefinementTrend falling;
  EXPECT_FALSE(falling.AddEstimate(1e6, 0.02));
  EXPECT_FALSE(falling.AddEstimate(4e6, 0.0101)) << "1 / sqrt(N), a little noise";
  EXPECT_FALSE(falling.AddEstimate(16e6, 0.0052));
  itk::DRRRefinementTrend flat;
  EXPECT_FALSE(flat.AddEstimate(1e6, 0.02));
  EXPECT_FALSE(flat.AddEstimate(1.2e6, 0.02)) << "not judged: too few points more";
  EXPECT_TRUE(flat.AddEstimate(4e6, 0.017)) << "fell by 0.003 where 1 / sqrt(N) says 0.01";
  itk::DRRRefinementTrend half;
  EXPECT_FALSE(half.AddEstimate(1e6, 0.02));
  EXPECT_FALSE(half.AddEstimate(4e6, 0.0140)) << "fell by 0.006: more than half of 0.01";

  using Trend = itk::DRRRefinementTrend;
  EXPECT_DOUBLE_EQ(Trend::GetGrowthToTarget(0.02, 0.0, 0.01), 1.1 * 4.0);
  // A coarse image of 0.005 (it stays): the points' part must fall from sqrt(4 - 0.25) to sqrt(1 - 0.25) (x 0.01).
  EXPECT_DOUBLE_EQ(Trend::GetGrowthToTarget(0.02, 0.005, 0.01), 1.1 * 3.75 / 0.75);
  EXPECT_TRUE(std::isinf(Trend::GetGrowthToTarget(0.02, 0.0081, 0.01))) << "the coarse image near the target alone";
}

// ChooseEstimator reaches the target against the exact image at every seed: the exact rays of a single view, and
// the kept points of many poses (where points are chosen), whose estimate and true error are at most the target.
TEST(PointBasedDRRChooseEstimator, ReachesTheTargetAgainstTheExactImageAtEverySeed)
{
  const auto volume = MakeAsymmetricPhantom();
  const auto geometry = ObliquePhantomGeometry();
  const auto reference = ExactImage(volume, geometry, 16);
  for (const double target : { 0.02, 0.01 })
  {
    auto single = MakeChoosingFilter(volume, geometry, target);
    single->Update();
    EXPECT_EQ(single->GetChosenEstimator().Kind, itk::DRREstimatorChoice::Estimator::ExactRays);
    EXPECT_LE(RelativeRmsError(single->GetOutput(), reference), target) << single->GetChosenEstimator().Describe();
    EXPECT_LE(single->GetEstimatedError(), target);
  }
  constexpr double target = 0.05;
  const double     spread = std::sqrt(1.0 / (2.0 * 1600.0) + 1.0 / (6.0 * 1600.0)); // of true / estimated error
  for (uint64_t seed = 0; seed < 4; ++seed)
  {
    auto kept = MakeChoosingFilter(volume, geometry, target);
    kept->SetSeed(seed);
    kept->ReusePointsOn();
    kept->SetExpectedNumberOfPoses(1000000);
    kept->Update();
    EXPECT_EQ(kept->GetChosenEstimator().Kind, itk::DRREstimatorChoice::Estimator::Points)
      << kept->GetChosenEstimator().Describe();
    EXPECT_LE(kept->GetEstimatedError(), target) << "seed " << seed;
    EXPECT_LE(RelativeRmsError(kept->GetOutput(), reference), target * (1.0 + zBound * spread)) << "seed " << seed;
    EXPECT_EQ(kept->GetTotalNumberOfSamples(), kept->GetChosenEstimator().NumberOfSamples)
      << "one pass of kept points: the next poses re-project all of them";
  }
  // A sampler whose error the choice underestimates (uniform in the volume, not in proportion to mu): the first
  // pose's kept points miss the target, are drawn again, more of them, and the next pose re-projects those.
  auto kept = MakeChoosingFilter(volume, geometry, target);
  kept->SetSampler(itk::DRRSamplerFactory::Create("mcvr"));
  kept->SetReconstructionKernel(itk::PointBasedDRREnums::ReconstructionKernel::Tent); // plain points: no split
  kept->ReusePointsOn();
  kept->SetExpectedNumberOfPoses(1000000);
  kept->Update();
  ASSERT_EQ(kept->GetChosenEstimator().Kind, itk::DRREstimatorChoice::Estimator::Points);
  EXPECT_GE(kept->GetNumberOfPointCloudDraws(), 2u) << "drawn again";
  EXPECT_LE(kept->GetEstimatedError(), target);
  EXPECT_EQ(kept->GetTotalNumberOfSamples(), kept->GetChosenEstimator().NumberOfSamples);
  auto transform = itk::Euler3DTransform<double>::New();
  transform->SetTranslation(Vec(2.0, 0.0, 1.0));
  kept->SetTransform(transform);
  const unsigned int draws = kept->GetNumberOfPointCloudDraws();
  kept->Update();
  EXPECT_EQ(kept->GetNumberOfPointCloudDraws(), draws) << "the next pose re-projects the points drawn again";
  EXPECT_LE(kept->GetEstimatedError(), target * (1.0 + zBound * spread)) << "the next pose";
}

// A control variate chosen for kept points whose coarse image alone is near the target (the phantom's 3 mm voxels
// under 2.7 mm pixels: its few jittered rays per pixel have an error of their own, about 0.45% here, which no number
// of points lowers): the filter renders the exact rays that reach the target instead, and keeps them for the next
// poses.
TEST(PointBasedDRRChooseEstimator, FallsBackToExactRaysWhenThePointsStall)
{
  const auto       volume = MakeAsymmetricPhantom();
  const auto       geometry = ObliquePhantomGeometry();
  const auto       reference = ExactImage(volume, geometry, 16);
  constexpr double target = 0.005;
  auto             kept = MakeChoosingFilter(volume, geometry, target);
  kept->ReusePointsOn();
  kept->SetExpectedNumberOfPoses(1000000);
  kept->Update();
  const auto first = kept->GetEstimatorChoice()->Choose(target, 1000000, true, kept->GetMaximumNumberOfSamples());
  ASSERT_GT(first.ControlVariateFactor, 0u) << first.Describe() << ": the case needs a control variate chosen";
  EXPECT_EQ(kept->GetChosenEstimator().Kind, itk::DRREstimatorChoice::Estimator::ExactRays)
    << kept->GetChosenEstimator().Describe();
  EXPECT_LE(kept->GetEstimatedError(), target);
  EXPECT_LE(RelativeRmsError(kept->GetOutput(), reference), target);
  auto transform = itk::Euler3DTransform<double>::New();
  transform->SetTranslation(Vec(2.0, 0.0, 1.0));
  kept->SetTransform(transform);
  kept->Update();
  EXPECT_EQ(kept->GetChosenEstimator().Kind, itk::DRREstimatorChoice::Estimator::ExactRays) << "kept for the next pose";
}

// The choice is made of counts, not of a clock: the same estimator and the same image on 1 and 2 threads. Bad
// settings are refused before any render.
TEST(PointBasedDRRChooseEstimator, SameImageOnAnyThreadsAndRefusesBadSettings)
{
  const auto          volume = MakeAsymmetricPhantom();
  const auto          geometry = ObliquePhantomGeometry();
  std::vector<double> images[2];
  for (const unsigned int threads : { 1u, 2u })
  {
    auto filter = MakeChoosingFilter(volume, geometry, 0.01);
    filter->SetNumberOfWorkUnits(threads);
    filter->Update();
    images[threads - 1] = ToVector(filter->GetOutput());
  }
  EXPECT_EQ(images[0], images[1]);
  auto filter = MakeChoosingFilter(volume, geometry, 0.0);
  EXPECT_TRUE(Contains(UpdateError(filter), "ChooseEstimator chooses the fastest estimator to a TargetError"));
  filter->SetTargetError(1e-9);
  EXPECT_TRUE(Contains(UpdateError(filter), "no estimator is predicted to reach the target error"));
  filter->SetTargetError(0.01);
  filter->SetPointWeighting(itk::PointBasedDRREnums::PointWeighting::PaperCount);
  EXPECT_TRUE(Contains(UpdateError(filter), "ChooseEstimator needs the unbiased point weighting"));
}
} // namespace
