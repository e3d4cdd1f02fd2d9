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
// Label channels and label selection (docs/design.md section 13): one render, one line-integral image per label,
// whose fixed-point sums are the single-channel render's; each channel unbiased against the exact projector's channel,
// with its spread and the channels' covariance as reported; kept and dropped labels equal a volume without the others.
#include "itkPointBasedDRRImageFilter.h"
#include "itkExactDRRImageFilter.h"
#include "itkDRRSamplerFactory.h"
#include "PointBasedDRRTestHelpers.h"

#include "gtest/gtest.h"

#include <cstring>

namespace
{
using namespace PointBasedDRRTest;
using VolumeType = itk::Image<short, 3>;
using LabelImageType = itk::Image<unsigned short, 3>;
using ProjectionType = itk::Image<float, 2>;
using PointFilterType = itk::PointBasedDRRImageFilter<VolumeType, ProjectionType>;
using ExactFilterType = itk::ExactDRRImageFilter<VolumeType, ProjectionType>;
using LabelList = std::vector<unsigned short>;

constexpr double zBound = 5.0;

/** A 10 x 9 x 8 phantom of HU levels in four labels: 0 background (soft tissue and some air), 2 a bone block, 5 a
 * second block, 9 scattered voxels. */
struct Phantom
{
  VolumeType::Pointer     Volume;
  LabelImageType::Pointer Labels;
};

Phantom
MakeLabelledPhantom()
{
  VolumeType::SizeType    size = { { 10, 9, 8 } };
  VolumeType::SpacingType spacing;
  spacing[0] = 2.0;
  spacing[1] = 2.5;
  spacing[2] = 3.0;
  VolumeType::PointType origin;
  origin[0] = -9.0;
  origin[1] = -10.0;
  origin[2] = -10.5;
  VolumeType::DirectionType direction = RotationMatrix(Vec(1.0, 2.0, 3.0) / std::sqrt(14.0), 20.0);
  Phantom                   phantom;
  phantom.Volume = MakeVolume<VolumeType>(size, spacing, origin, direction);
  phantom.Labels = MakeVolume<LabelImageType>(size, spacing, origin, direction);
  const short      levels[4] = { -1000, -100, 40, 300 };
  unsigned int     state = 777u;
  short *          hu = phantom.Volume->GetBufferPointer();
  unsigned short * label = phantom.Labels->GetBufferPointer();
  for (size_t v = 0; v < phantom.Volume->GetBufferedRegion().GetNumberOfPixels(); ++v)
  {
    state = state * 1664525u + 1013904223u;
    hu[v] = levels[(state >> 8) % 4];
    label[v] = (state >> 20) % 7 == 0 ? 9 : 0;
  }
  FillBlock(phantom.Volume.GetPointer(), { { 2, 2, 1 } }, { { 5, 6, 4 } }, short(1200));
  FillBlock(phantom.Labels.GetPointer(), { { 2, 2, 1 } }, { { 5, 6, 4 } }, (unsigned short)(2));
  FillBlock(phantom.Volume.GetPointer(), { { 6, 1, 4 } }, { { 8, 4, 7 } }, short(60));
  FillBlock(phantom.Labels.GetPointer(), { { 6, 1, 4 } }, { { 8, 4, 7 } }, (unsigned short)(5));
  return phantom;
}

/** The view of every test; wide: one 2 x 1 detector of 60 mm pixels that catch the whole phantom, so that a pixel's
 * channels share most of the points (a strong covariance between channels). */
itk::DRRProjectionGeometry::Pointer
MakeView(bool wide = false)
{
  auto geometry = itk::DRRProjectionGeometry::New();
  geometry->SetSourceToIsocenterDistance(60.0);
  geometry->SetSourceToDetectorDistance(100.0);
  geometry->SetGantryAngleInDegrees(35.0);
  geometry->SetIsocenter(Pt(0.5, -0.5, 1.0));
  geometry->SetDetectorSize({ { wide ? 2u : 9u, wide ? 1u : 7u } });
  itk::Vector<double, 2> spacing;
  spacing[0] = wide ? 60.0 : 5.0;
  spacing[1] = wide ? 90.0 : 6.0;
  geometry->SetDetectorSpacing(spacing);
  return geometry;
}

PointFilterType::Pointer
MakePointFilter(const Phantom & phantom, const std::string & sampler, bool channels)
{
  auto drr = PointFilterType::New();
  drr->SetInput(phantom.Volume);
  drr->SetGeometry(MakeView());
  drr->SetSampler(itk::DRRSamplerFactory::Create(sampler));
  drr->SetNumberOfSamples(40000);
  if (channels)
  {
    drr->SetLabelImage(phantom.Labels);
    drr->SetLabelChannels(true);
  }
  return drr;
}

std::vector<float>
Components(const PointFilterType::ChannelImageType * image)
{
  const size_t n = image->GetBufferedRegion().GetNumberOfPixels() * image->GetNumberOfComponentsPerPixel();
  return std::vector<float>(image->GetBufferPointer(), image->GetBufferPointer() + n);
}

/** The exact channels (64 x 64 rays per pixel, Richardson-extrapolated with 32 x 32) and their error estimate. */
void
ExactChannels(const Phantom & phantom, bool wide, std::vector<double> & reference, std::vector<double> & error)
{
  std::vector<float> images[2];
  for (unsigned int i = 0; i < 2; ++i)
  {
    auto exact = ExactFilterType::New();
    exact->SetInput(phantom.Volume);
    exact->SetGeometry(MakeView(wide));
    exact->SetLabelImage(phantom.Labels);
    exact->SetLabelChannels(true);
    exact->SetRaysPerPixelSide(i == 0 ? 64 : 32);
    exact->Update();
    images[i] = Components(exact->GetChannelOutput());
  }
  reference.resize(images[0].size());
  error.resize(images[0].size());
  for (size_t i = 0; i < reference.size(); ++i)
  {
    reference[i] = images[0][i] + (images[0][i] - images[1][i]) / 3.0;
    error[i] = std::abs(images[0][i] - images[1][i]) / 3.0;
  }
}

class DRRLabelChannels : public testing::TestWithParam<std::string>
{};

// The channels' sums are the single-channel render's: the image and its standard error are the same bits, for every
// sampler (independent points, strata, interleaved strata), both splats, and kept points; the float channels add up
// to the image within their rounding.
TEST_P(DRRLabelChannels, SumToTheSingleChannelImageBitForBit)
{
  const Phantom phantom = MakeLabelledPhantom();
  for (auto splat : { itk::PointBasedDRREnums::Splat::Nearest, itk::PointBasedDRREnums::Splat::Bilinear })
  {
    for (bool reuse : { false, true })
    {
      auto single = MakePointFilter(phantom, GetParam(), false);
      auto split = MakePointFilter(phantom, GetParam(), true);
      for (auto * drr : { single.GetPointer(), split.GetPointer() })
      {
        drr->SetSplat(splat);
        drr->SetReusePoints(reuse);
        drr->SetSeed(31);
        drr->Update();
      }
      const auto image = ToVector(single->GetOutput());
      const auto splitImage = ToVector(split->GetOutput());
      ASSERT_EQ(image.size(), splitImage.size());
      EXPECT_EQ(0, std::memcmp(image.data(), splitImage.data(), image.size() * sizeof(float)))
        << GetParam() << ": the image of a render with channels differs from the render without";
      const auto se = ToVector(single->GetStandardErrorOutput());
      const auto splitSE = ToVector(split->GetStandardErrorOutput());
      EXPECT_EQ(0, std::memcmp(se.data(), splitSE.data(), se.size() * sizeof(float)));
      ASSERT_EQ(split->GetChannelLabels(), (LabelList{ 0, 2, 5, 9 }));
      const auto channels = Components(split->GetChannelOutput());
      ASSERT_EQ(channels.size(), 4 * image.size());
      for (size_t p = 0; p < image.size(); ++p)
      {
        double sum = 0.0, magnitude = 0.0;
        for (size_t k = 0; k < 4; ++k)
        {
          sum += channels[4 * p + k];
          magnitude += std::abs(channels[4 * p + k]);
        }
        // Each channel and the image are rounded once to float from the exact sums: 5 half-ulps at most.
        EXPECT_LE(std::abs(sum - image[p]), 5 * 0.5 * 1.2e-7 * magnitude + 1e-30) << GetParam() << " pixel " << p;
      }
    }
  }
}

/** Each channel's mean over 48 seeds against the exact channel (a z-test with the estimator's own spread), the
 * covariance output's diagonal against the channels' spread, and its off-diagonal against their covariance (pooled
 * over pixels). */
void
CheckChannelsUnbiased(const std::string & sampler, bool wide)
{
  const Phantom       phantom = MakeLabelledPhantom();
  std::vector<double> reference, referenceError;
  ExactChannels(phantom, wide, reference, referenceError);
  const size_t        K = 4, pairs = K * (K + 1) / 2;
  const size_t        values = reference.size(), pixels = values / K;
  const unsigned int  seeds = wide ? 1200 : 48; // 2 pixels: more seeds for the power of the pooled tests
  std::vector<double> sum(values, 0.0), products(pixels * pairs, 0.0), predicted(pixels * pairs, 0.0);
  auto                drr = MakePointFilter(phantom, sampler, true);
  drr->SetGeometry(MakeView(wide));
  for (unsigned int seed = 0; seed < seeds; ++seed)
  {
    drr->SetSeed(500 + seed);
    drr->Update();
    const auto channels = Components(drr->GetChannelOutput());
    const auto covariance = Components(drr->GetChannelCovarianceOutput());
    for (size_t p = 0; p < pixels; ++p)
    {
      size_t entry = p * pairs;
      for (size_t m = 0; m < K; ++m)
      {
        sum[p * K + m] += channels[p * K + m];
        for (size_t m2 = m; m2 < K; ++m2, ++entry)
        {
          products[entry] += double(channels[p * K + m]) * channels[p * K + m2];
          predicted[entry] += covariance[entry];
        }
      }
    }
  }
  const double peak = *std::max_element(reference.begin(), reference.end());
  double       worstZ = 0.0;
  size_t       tested = 0;
  double       observedVariance = 0.0, predictedVariance = 0.0, observedCovariance = 0.0, predictedCovariance = 0.0;
  double       covarianceScale = 0.0;
  for (size_t p = 0; p < pixels; ++p)
  {
    size_t entry = p * pairs;
    for (size_t m = 0; m < K; ++m)
    {
      for (size_t m2 = m; m2 < K; ++m2, ++entry)
      {
        const double meanM = sum[p * K + m] / seeds, meanM2 = sum[p * K + m2] / seeds;
        const double observed = (products[entry] - seeds * meanM * meanM2) / (seeds - 1.0);
        const double reported = predicted[entry] / seeds;
        if (m == m2)
        {
          if (observed == 0.0)
          {
            // A sliver of a channel's shadow that no point of 48 seeds reached: far below any bias of a wrong weight.
            EXPECT_LT(reference[p * K + m], 1e-3 * peak) << "channel " << m << " pixel " << p << " never reached";
            continue;
          }
          const double z = std::abs(meanM - reference[p * K + m]) /
                           std::sqrt(observed / seeds + referenceError[p * K + m] * referenceError[p * K + m]);
          worstZ = std::max(worstZ, z);
          observedVariance += observed;
          predictedVariance += reported;
          ++tested;
        }
        else
        {
          observedCovariance += observed;
          predictedCovariance += reported;
          covarianceScale += std::sqrt(predicted[p * pairs + m * K - m * (m - 1) / 2] *
                                       predicted[p * pairs + m2 * K - m2 * (m2 - 1) / 2]) /
                             seeds;
        }
      }
    }
  }
  EXPECT_GT(tested, pixels * 2);
  EXPECT_LT(worstZ, zBound) << sampler << ": a channel's mean is off its exact reference";
  // Pooled variance ratio: sqrt(2 / (seeds - 1)) per pixel, over pixels coupled by a systematic sample: a quarter.
  EXPECT_NEAR(observedVariance / predictedVariance, 1.0, zBound * std::sqrt(2.0 / ((seeds - 1.0) * tested / 4.0)))
    << sampler << ": the covariance output's diagonal does not predict the channels' spread";
  // The pooled covariance, in units of the pooled standard deviations: its sampling error is about
  // 1 / sqrt(seeds - 1) per pair, pooled over a quarter of the pairs.
  const double covariancePairs = pixels * (pairs - K) / 4.0;
  EXPECT_NEAR((observedCovariance - predictedCovariance) / covarianceScale,
              0.0,
              zBound * std::sqrt(1.0 / ((seeds - 1.0) * covariancePairs)))
    << sampler << ": the covariance output's off-diagonal does not predict the channels' covariance (observed "
    << observedCovariance << ", reported " << predictedCovariance << ")";
}

// Each channel is unbiased, and the covariance output predicts the channels' spread and covariance: on a detector of
// 63 pixels, and on one of 2 pixels that catch the whole phantom (where the channels of a pixel are strongly
// correlated).
TEST_P(DRRLabelChannels, EachChannelIsUnbiasedAndItsCovarianceIsPredicted)
{
  CheckChannelsUnbiased(GetParam(), false);
  CheckChannelsUnbiased(GetParam(), true);
}

INSTANTIATE_TEST_SUITE_P(Samplers,
                         DRRLabelChannels,
                         testing::Values("level-alias", "stratified", "metropolis", "paper-hybrid"),
                         [](const testing::TestParamInfo<std::string> & info) {
                           std::string name = info.param;
                           name.erase(std::remove(name.begin(), name.end(), '-'), name.end());
                           return name;
                         });

// The exact projector's channels: channel k equals the exact image of the volume with only label k kept, for the box
// and the tent models, and the channels add up to the image.
TEST(DRRLabelChannelsExact, EachChannelIsTheImageOfItsLabelAlone)
{
  const Phantom phantom = MakeLabelledPhantom();
  for (auto kernel :
       { itk::PointBasedDRREnums::ReconstructionKernel::Box, itk::PointBasedDRREnums::ReconstructionKernel::Tent })
  {
    auto exact = ExactFilterType::New();
    exact->SetInput(phantom.Volume);
    exact->SetGeometry(MakeView());
    exact->SetReconstructionKernel(kernel);
    exact->SetRaysPerPixelSide(2);
    exact->SetLabelImage(phantom.Labels);
    exact->SetLabelChannels(true);
    exact->Update();
    const auto      channels = Components(exact->GetChannelOutput());
    const auto      image = ToVector(exact->GetOutput());
    const LabelList labels = exact->GetChannelLabels();
    ASSERT_EQ(labels.size(), 4u);
    EXPECT_EQ(Components(exact->GetChannelCovarianceOutput()), std::vector<float>(image.size() * 10, 0.0f));
    std::vector<double> sum(image.size(), 0.0);
    for (size_t k = 0; k < labels.size(); ++k)
    {
      auto alone = ExactFilterType::New();
      alone->SetInput(phantom.Volume);
      alone->SetGeometry(MakeView());
      alone->SetReconstructionKernel(kernel);
      alone->SetRaysPerPixelSide(2);
      alone->SetLabelImage(phantom.Labels);
      alone->SetKeptLabels({ labels[k] });
      alone->Update();
      const auto own = ToVector(alone->GetOutput());
      for (size_t p = 0; p < own.size(); ++p)
      {
        EXPECT_NEAR(channels[4 * p + k], own[p], 1e-5 * (1.0 + own[p])) << "label " << labels[k] << " pixel " << p;
        sum[p] += channels[4 * p + k];
      }
    }
    for (size_t p = 0; p < image.size(); ++p)
    {
      EXPECT_NEAR(sum[p], image[p], 1e-5 * (1.0 + image[p]));
    }
  }
}

// Kept and dropped labels: the same bits as a volume whose other voxels are air (-1000 HU), for the point-based and
// the exact filters.
TEST(DRRLabelSelection, KeptAndDroppedLabelsEqualAVolumeWithoutTheOthers)
{
  const Phantom phantom = MakeLabelledPhantom();
  struct Case
  {
    LabelList Kept, Dropped;
  };
  for (const Case & c : { Case{ { 2, 5 }, {} }, Case{ {}, { 0 } }, Case{ { 0, 9, 2 }, { 9 } } })
  {
    auto masked = VolumeType::New();
    masked->Graft(phantom.Volume);
    auto copy = MakeVolume<VolumeType>(phantom.Volume->GetLargestPossibleRegion().GetSize(),
                                       phantom.Volume->GetSpacing(),
                                       phantom.Volume->GetOrigin(),
                                       phantom.Volume->GetDirection());
    for (size_t v = 0; v < copy->GetBufferedRegion().GetNumberOfPixels(); ++v)
    {
      const unsigned short label = phantom.Labels->GetBufferPointer()[v];
      const bool           kept = (c.Kept.empty() || std::count(c.Kept.begin(), c.Kept.end(), label)) &&
                        !std::count(c.Dropped.begin(), c.Dropped.end(), label);
      copy->GetBufferPointer()[v] = kept ? phantom.Volume->GetBufferPointer()[v] : short(-1000);
    }
    for (const std::string sampler : { "stratified", "level-alias" })
    {
      auto selected = MakePointFilter(phantom, sampler, false);
      selected->SetLabelImage(phantom.Labels);
      selected->SetKeptLabels(c.Kept);
      selected->SetDroppedLabels(c.Dropped);
      auto reference = MakePointFilter(phantom, sampler, false);
      reference->SetInput(copy);
      for (auto * drr : { selected.GetPointer(), reference.GetPointer() })
      {
        drr->SetSeed(8);
        drr->Update();
      }
      EXPECT_EQ(ToVector(selected->GetOutput()), ToVector(reference->GetOutput())) << sampler;
    }
    auto exactSelected = ExactFilterType::New();
    exactSelected->SetInput(phantom.Volume);
    exactSelected->SetLabelImage(phantom.Labels);
    exactSelected->SetKeptLabels(c.Kept);
    exactSelected->SetDroppedLabels(c.Dropped);
    auto exactReference = ExactFilterType::New();
    exactReference->SetInput(copy);
    for (auto * exact : { exactSelected.GetPointer(), exactReference.GetPointer() })
    {
      exact->SetGeometry(MakeView());
      exact->Update();
    }
    EXPECT_EQ(ToVector(exactSelected->GetOutput()), ToVector(exactReference->GetOutput()));
  }
}

// A label image on another grid is resampled by nearest neighbour, with a warning: a label image of twice the
// resolution gives the labels of the volume's own grid.
TEST(DRRLabelSelection, ALabelImageOnAnotherGridIsResampledByNearestNeighbour)
{
  const Phantom phantom = MakeLabelledPhantom();
  auto          fine = MakeVolume<LabelImageType>({ { 20, 18, 16 } },
                                         phantom.Labels->GetSpacing() / 2.0,
                                         phantom.Labels->GetOrigin(),
                                         phantom.Labels->GetDirection());
  // Fine voxel (i, j, k) centred at coarse continuous index ((i, j, k) - 0.5 (0, 0, 0)... shifted by a quarter
  // voxel: the origin moved back a quarter coarse voxel makes fine voxel 2c and 2c + 1 straddle coarse voxel c.
  VolumeType::PointType origin = phantom.Labels->GetOrigin();
  const auto            quarter = phantom.Labels->GetDirection() * (phantom.Labels->GetSpacing() * 0.25);
  origin -= quarter;
  fine->SetOrigin(origin);
  for (itk::IndexValueType k = 0; k < 16; ++k)
    for (itk::IndexValueType j = 0; j < 18; ++j)
      for (itk::IndexValueType i = 0; i < 20; ++i)
        fine->SetPixel({ { i, j, k } }, phantom.Labels->GetPixel({ { i / 2, j / 2, k / 2 } }));
  auto sameGrid = MakePointFilter(phantom, "level-alias", true);
  auto resampled = MakePointFilter(phantom, "level-alias", true);
  resampled->SetLabelImage(fine);
  for (auto * drr : { sameGrid.GetPointer(), resampled.GetPointer() })
  {
    drr->SetSeed(3);
    drr->Update();
  }
  EXPECT_EQ(Components(sameGrid->GetChannelOutput()), Components(resampled->GetChannelOutput()));
}

TEST(DRRLabelSelection, RefusesLabelsThatDoNotExistAndSettingsThatCannotHold)
{
  const Phantom phantom = MakeLabelledPhantom();
  {
    auto drr = MakePointFilter(phantom, "stratified", false);
    drr->SetLabelImage(phantom.Labels);
    drr->SetKeptLabels({ 2, 4 });
    const std::string message = ExceptionMessage([&] { drr->Update(); }, "a kept label not in the image");
    EXPECT_TRUE(Contains(message, "kept label 4 is in no voxel")) << message;
    EXPECT_TRUE(Contains(message, "0, 2, 5, 9")) << message;
  }
  {
    auto drr = MakePointFilter(phantom, "stratified", false);
    drr->SetLabelImage(phantom.Labels);
    drr->SetDroppedLabels({ 7 });
    EXPECT_TRUE(Contains(ExceptionMessage([&] { drr->Update(); }, "a dropped label"), "dropped label 7"));
  }
  {
    auto drr = MakePointFilter(phantom, "stratified", false);
    drr->SetLabelImage(phantom.Labels);
    drr->SetKeptLabels({ 2 });
    drr->SetDroppedLabels({ 2 });
    EXPECT_TRUE(Contains(ExceptionMessage([&] { drr->Update(); }, "nothing left"), "leave no label"));
  }
  {
    // A label image of another volume: resampled, it would label every voxel 0.
    auto elsewhere = MakeVolume<LabelImageType>({ { 4, 4, 4 } },
                                                phantom.Labels->GetSpacing(),
                                                phantom.Labels->GetOrigin() + Vec(500.0, 0.0, 0.0),
                                                phantom.Labels->GetDirection());
    auto drr = MakePointFilter(phantom, "stratified", false);
    drr->SetLabelImage(elsewhere);
    EXPECT_TRUE(
      Contains(ExceptionMessage([&] { drr->Update(); }, "a label image elsewhere"), "covers no voxel of the volume"));
  }
  {
    auto drr = MakePointFilter(phantom, "stratified", false);
    drr->SetLabelChannels(true);
    EXPECT_TRUE(Contains(ExceptionMessage([&] { drr->Update(); }, "channels without labels"), "need a label image"));
  }
  {
    auto drr = MakePointFilter(phantom, "stratified", true);
    drr->SetControlVariateFactor(4);
    EXPECT_TRUE(Contains(ExceptionMessage([&] { drr->Update(); }, "channels with a control variate"),
                         "without a control variate"));
    // The automatic factor renders channels without one.
    drr->SetControlVariateFactor(PointFilterType::AutomaticControlVariateFactor);
    EXPECT_NO_THROW(drr->Update());
    EXPECT_EQ(drr->GetControlVariate(), nullptr);
  }
}
} // namespace
