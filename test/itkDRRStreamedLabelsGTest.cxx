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
// One route from voxels to the model (issue 40, item 4): the preprocessing stage models a slab of the volume (its
// requested region) with the slab's labels and materials, the DRR filters stream by asking it, and so kept and dropped
// labels (and the exact filter's material channels) stream: the streamed render is the unstreamed one's.
#include "itkPointBasedDRRImageFilter.h"
#include "itkDRRImageToAttenuationVolumeFilter.h"
#include "itkDRRMaterialTable.h"
#include "itkExactDRRImageFilter.h"
#include "itkImageRegionIterator.h"
#include "itkImageRegionIteratorWithIndex.h"
#include "itkImageSource.h"
#include "PointBasedDRRTestHelpers.h"

#include "gtest/gtest.h"

#include <array>
#include <limits>
#include <type_traits>

namespace
{
using namespace PointBasedDRRTest;
using ProjectionEnum = itk::PointBasedDRREnums::Projection;
using LabelImageType = itk::Image<uint16_t, 3>;
using StageType = itk::DRRImageToAttenuationVolumeFilter<HUVolumeType>;
using ExactType = itk::ExactDRRImageFilter<HUVolumeType, ProjectionType>;
using PointType = itk::PointBasedDRRImageFilter<HUVolumeType, ProjectionType>;

/** 19 x 17 x 45 voxels, rotated and anisotropic: an ellipsoid of random HU levels in air (several brick planes deep,
 * so that the point filter makes several slabs). */
HUVolumeType::Pointer
MakeVolumeOfLevels()
{
  HUVolumeType::SpacingType spacing;
  spacing[0] = 1.0;
  spacing[1] = 1.2;
  spacing[2] = 0.8;
  HUVolumeType::PointType origin;
  origin[0] = -9.0;
  origin[1] = -11.0;
  origin[2] = -17.0;
  auto volume =
    MakeVolume<HUVolumeType>({ { 19, 17, 45 } }, spacing, origin, RotationMatrix(Vec(2.0 / 3, 1.0 / 3, 2.0 / 3), 20.0));
  const short  levels[6] = { -900, -300, 0, 60, 700, 1800 };
  unsigned int state = 2024u;
  for (itk::ImageRegionIteratorWithIndex<HUVolumeType> it(volume, volume->GetLargestPossibleRegion()); !it.IsAtEnd();
       ++it)
  {
    const auto   index = it.GetIndex();
    const double x = (index[0] - 9.0) / 8.5, y = (index[1] - 8.0) / 7.5, z = (index[2] - 22.0) / 20.0;
    state = state * 1664525u + 1013904223u;
    it.Set(x * x + y * y + z * z <= 1.0 ? levels[(state >> 8) % 6] : static_cast<short>(-1000));
  }
  return volume;
}

/** Labels on the volume's grid: 0 outside the ellipsoid, 1 to 4 by octant-like zones, 7 in the top planes alone. */
LabelImageType::Pointer
MakeLabels(const HUVolumeType * volume)
{
  auto labels = LabelImageType::New();
  labels->CopyInformation(volume);
  labels->SetRegions(volume->GetLargestPossibleRegion());
  labels->Allocate();
  for (itk::ImageRegionIteratorWithIndex<LabelImageType> it(labels, labels->GetLargestPossibleRegion()); !it.IsAtEnd();
       ++it)
  {
    const auto index = it.GetIndex();
    const bool inside = volume->GetPixel(index) > -1000;
    it.Set(!inside ? 0 : index[2] >= 40 ? 7 : static_cast<uint16_t>(1 + (index[0] > 9) + 2 * (index[1] > 8)));
  }
  return labels;
}

/** The same labels on a coarser grid of its own (2 mm, shifted): resampled onto the volume by nearest neighbour. */
LabelImageType::Pointer
MakeOffGridLabels(const HUVolumeType * volume)
{
  auto labels = LabelImageType::New();
  labels->SetRegions(LabelImageType::SizeType{ { 14, 14, 24 } });
  LabelImageType::SpacingType spacing;
  spacing.Fill(2.0);
  labels->SetSpacing(spacing);
  labels->SetOrigin(Pt(-14.0, -15.0, -22.0));
  labels->Allocate();
  for (itk::ImageRegionIteratorWithIndex<LabelImageType> it(labels, labels->GetLargestPossibleRegion()); !it.IsAtEnd();
       ++it)
  {
    const auto index = it.GetIndex();
    it.Set(static_cast<uint16_t>(1 + (index[0] + index[1] + index[2]) % 4));
  }
  (void)volume;
  return labels;
}

itk::DRRProjectionGeometry::Pointer
MakeView(ProjectionEnum projection)
{
  auto geometry = itk::DRRProjectionGeometry::New();
  geometry->SetProjection(projection);
  geometry->SetSourceToIsocenterDistance(300.0);
  geometry->SetSourceToDetectorDistance(500.0);
  geometry->SetGantryAngleInDegrees(35.0);
  geometry->SetDetectorSize({ { 34, 30 } });
  itk::Vector<double, 2> spacing;
  spacing[0] = 1.3;
  spacing[1] = 1.1;
  geometry->SetDetectorSpacing(spacing);
  return geometry;
}

/** The rows of mu of a model, x fastest. */
std::vector<float>
MuOf(const itk::DRRAttenuationVolume & model)
{
  const auto         size = model.GetSize();
  std::vector<float> mu(model.GetNumberOfVoxels());
  for (uint64_t k = 0; k < size[2]; ++k)
  {
    for (uint64_t j = 0; j < size[1]; ++j)
    {
      model.FillMuRow(0, j, k, size[0], mu.data() + (k * size[1] + j) * size[0]);
    }
  }
  return mu;
}

struct Selection
{
  itk::DRRLabelSelection::LabelListType Kept;
  itk::DRRLabelSelection::LabelListType Dropped;
};

const std::vector<Selection> selections{ { {}, { 2 } }, { { 1, 4, 7 }, {} }, { { 1, 3 }, { 3 } } };

// The stage's model of a slab is the whole volume's model of those planes, bit for bit: its mu (labels applied, on the
// volume's grid or resampled), its materials, its grid; and it holds the slab alone.
TEST(DRRStreamedLabels, TheStagesSlabIsTheWholeModelsPlanesBitForBit)
{
  const auto volume = MakeVolumeOfLevels();
  for (const bool onGrid : { true, false })
  {
    const auto labels = onGrid ? MakeLabels(volume) : MakeOffGridLabels(volume);
    for (const auto & selection : selections)
    {
      if (!onGrid && selection.Kept.size() == 3)
      {
        continue; // label 7 is the on-grid labels' alone
      }
      auto stage = StageType::New();
      stage->SetInput(volume);
      stage->SetLabelImage(labels);
      stage->SetKeptLabels(selection.Kept);
      stage->SetDroppedLabels(selection.Dropped);
      stage->Update();
      const std::vector<float> whole = MuOf(*stage->GetOutput());
      const auto               wholeOrigin = stage->GetOutput()->GetOrigin();
      const size_t             plane = 19 * 17;
      for (const auto & slab : { std::make_pair(0, 8), std::make_pair(8, 13), std::make_pair(21, 24) })
      {
        auto region = volume->GetLargestPossibleRegion();
        region.SetIndex(2, slab.first);
        region.SetSize(2, slab.second);
        itk::DRRAttenuationVolume * model = stage->GetOutput();
        model->SetRequestedRegion(region);
        model->Update();
        EXPECT_EQ(model->GetBufferedRegion(), region);
        ASSERT_EQ(model->GetNumberOfVoxels(), plane * slab.second);
        const std::vector<float> mu = MuOf(*model);
        for (size_t v = 0; v < mu.size(); ++v)
        {
          ASSERT_EQ(mu[v], whole[plane * slab.first + v])
            << (onGrid ? "on grid" : "resampled") << ", slab at " << slab.first << ", voxel " << v;
        }
        HUVolumeType::PointType first;
        volume->TransformIndexToPhysicalPoint(region.GetIndex(), first);
        EXPECT_LT(first.EuclideanDistanceTo(model->GetOrigin()), 1e-9);
        EXPECT_EQ(model->GetIndexToPhysicalMatrix(), stage->GetOutput()->GetIndexToPhysicalMatrix());
      }
      stage->UpdateLargestPossibleRegion();
      EXPECT_EQ(stage->GetOutput()->GetOrigin(), wholeOrigin);
      EXPECT_EQ(MuOf(*stage->GetOutput()), whole);
    }
  }
}

/** Two materials (air below -500 HU, water above). */
itk::DRRMaterialTable::Pointer
AirAndWater()
{
  auto         table = itk::DRRMaterialTable::New();
  const double inf = std::numeric_limits<double>::infinity();
  table->AddMaterial(-inf, -500.0, "Air, Dry (near sea level)", 0.0, 0.0);
  table->AddMaterial(-500.0, inf, "Water, Liquid", 1.0, 1.0);
  return table;
}

// The exact filter streams kept and dropped labels (on the volume's grid, read slab by slab from a streaming source,
// or resampled) and material channels: the streamed image is the unstreamed one to rounding (the slabs' sums), and the
// labels change it.
TEST(DRRStreamedLabels, TheExactFilterStreamsLabelsAndMaterialChannels)
{
  const auto volume = MakeVolumeOfLevels();
  const auto geometry = MakeView(ProjectionEnum::Perspective);
  for (const bool onGrid : { true, false })
  {
    const auto labels = onGrid ? MakeLabels(volume) : MakeOffGridLabels(volume);
    for (const auto & selection : selections)
    {
      if (!onGrid && selection.Kept.size() == 3)
      {
        continue;
      }
      auto       labelSource = RecordingSource<LabelImageType>::New();
      const auto render = [&](unsigned int slabs, bool withLabels) {
        auto exact = ExactType::New();
        exact->SetInput(volume);
        exact->SetGeometry(geometry);
        if (withLabels)
        {
          labelSource->Image = labels;
          exact->SetLabelImage(slabs > 1 ? labelSource->GetOutput() : labels.GetPointer());
          exact->SetKeptLabels(selection.Kept);
          exact->SetDroppedLabels(selection.Dropped);
        }
        exact->SetNumberOfStreamDivisions(slabs);
        exact->Update();
        return ToVector(exact->GetOutput());
      };
      const auto   whole = render(1, true);
      const auto   unlabelled = render(1, false);
      const double largest = *std::max_element(unlabelled.begin(), unlabelled.end());
      ASSERT_GT(largest, 0.3);
      EXPECT_GT(std::inner_product(whole.begin(),
                                   whole.end(),
                                   unlabelled.begin(),
                                   0.0,
                                   std::plus<>(),
                                   [](double a, double b) { return std::abs(a - b); }),
                0.1 * largest);
      for (const unsigned int slabs : { 2u, 3u, 7u })
      {
        labelSource = RecordingSource<LabelImageType>::New();
        const auto streamed = render(slabs, true);
        ASSERT_EQ(streamed.size(), whole.size());
        for (size_t p = 0; p < whole.size(); ++p)
        {
          ASSERT_NEAR(streamed[p], whole[p], 1e-6 * largest) << slabs << " slabs, pixel " << p;
        }
        // Labels on the volume's grid are read slab by slab, as the volume; others whole, once.
        ASSERT_EQ(labelSource->Requests.size(), onGrid ? slabs : 1u);
        EXPECT_EQ(labelSource->Requests.front().GetSize()[2], onGrid ? 45u / slabs : 24u);
      }
    }
  }
  // Material channels: the slabs' channel images add up.
  const auto materials = [&](unsigned int slabs) {
    auto exact = ExactType::New();
    exact->SetInput(volume);
    exact->SetGeometry(geometry);
    exact->GetTransferFunction()->SetMaterialTable(AirAndWater());
    exact->SetMaterialChannels(true);
    exact->SetNumberOfStreamDivisions(slabs);
    exact->Update();
    const auto * channels = exact->GetChannelOutput();
    EXPECT_EQ(channels->GetNumberOfComponentsPerPixel(), 2u);
    const float * values = channels->GetBufferPointer();
    return std::vector<double>(values, values + 2 * channels->GetBufferedRegion().GetNumberOfPixels());
  };
  const auto whole = materials(1);
  const auto streamed = materials(3);
  ASSERT_EQ(streamed.size(), whole.size());
  const double largest = *std::max_element(whole.begin(), whole.end());
  ASSERT_GT(largest, 0.3);
  for (size_t c = 0; c < whole.size(); ++c)
  {
    ASSERT_NEAR(streamed[c], whole[c], 1e-6 * largest) << "channel value " << c;
  }
}

// The point filter streams kept and dropped labels with the stratified sampler: the same points as the unstreamed
// render, so the same image and standard error bit for bit.
TEST(DRRStreamedLabels, ThePointFilterStreamsLabelsBitForBit)
{
  const auto volume = MakeVolumeOfLevels();
  for (const bool onGrid : { true, false })
  {
    const auto labels = onGrid ? MakeLabels(volume) : MakeOffGridLabels(volume);
    for (const auto & selection : selections)
    {
      if (!onGrid && selection.Kept.size() == 3)
      {
        continue;
      }
      for (const unsigned int factor : { 0u, 4u })
      {
        const auto render = [&](unsigned int slabs) {
          auto drr = PointType::New();
          drr->SetInput(volume);
          drr->SetGeometry(MakeView(ProjectionEnum::Parallel));
          drr->SetLabelImage(labels);
          drr->SetKeptLabels(selection.Kept);
          drr->SetDroppedLabels(selection.Dropped);
          drr->SetNumberOfSamples(100000);
          drr->SetSeed(17);
          drr->SetControlVariateFactor(factor);
          drr->SetNumberOfStreamDivisions(slabs);
          drr->Update();
          EXPECT_EQ(drr->GetNumberOfSlabs(), std::min(slabs, 6u));
          return std::make_pair(ToVector(drr->GetOutput()), ToVector(drr->GetStandardErrorOutput()));
        };
        const auto whole = render(1);
        ASSERT_GT(*std::max_element(whole.first.begin(), whole.first.end()), 0.1);
        for (const unsigned int slabs : { 2u, 3u })
        {
          const auto streamed = render(slabs);
          ASSERT_EQ(streamed.first.size(), whole.first.size());
          for (size_t p = 0; p < whole.first.size(); ++p)
          {
            ASSERT_EQ(streamed.first[p], whole.first[p]) << "F " << factor << ", " << slabs << " slabs, pixel " << p;
            ASSERT_EQ(streamed.second[p], whole.second[p]) << "F " << factor << ", " << slabs << " slabs, pixel " << p;
          }
        }
      }
    }
  }
}

// Kept points drawn slab by slab are made of the labels too: a new selection, or a label image modified in place,
// draws them again, and the image is that of a fresh filter with the new labels (they were re-used, stale, before).
TEST(DRRStreamedLabels, StreamedKeptPointsAreDrawnAgainWhenTheLabelsChange)
{
  const auto volume = MakeVolumeOfLevels();
  const auto labels = MakeLabels(volume);
  const auto make = [&](const PointType::LabelListType & kept) {
    auto drr = PointType::New();
    drr->SetInput(volume);
    drr->SetGeometry(MakeView(ProjectionEnum::Parallel));
    drr->SetLabelImage(labels);
    drr->SetKeptLabels(kept);
    drr->SetNumberOfSamples(100000);
    drr->SetSeed(5);
    drr->SetReusePoints(true);
    drr->SetNumberOfStreamDivisions(3);
    return drr;
  };
  auto drr = make({ 1, 2 });
  drr->Update();
  ASSERT_EQ(drr->GetNumberOfSlabs(), 3u);
  drr->SetKeptLabels({ 3, 4 });
  drr->Update();
  EXPECT_EQ(drr->GetNumberOfPointCloudDraws(), 2u) << "a new selection draws the points again";
  auto fresh = make({ 3, 4 });
  fresh->Update();
  EXPECT_EQ(ToVector(drr->GetOutput()), ToVector(fresh->GetOutput()));
  // The label image modified in place: its own time, newer than the points.
  labels->GetBufferPointer()[0] = labels->GetBufferPointer()[0];
  labels->Modified();
  drr->Update();
  EXPECT_EQ(drr->GetNumberOfPointCloudDraws(), 3u) << "a modified label image draws the points again";
}

// The stage numbers a slab's label channels by the labels of the whole volume, not by the slab's own: the slab's model
// has the whole model's channel labels and its planes' voxel channels (label 7, in the top planes alone, keeps its
// channel in the slabs that lack it).
TEST(DRRStreamedLabels, TheStageNumbersASlabsChannelsAsTheWholeVolume)
{
  const auto volume = MakeVolumeOfLevels();
  for (const bool onGrid : { true, false })
  {
    const auto labels = onGrid ? MakeLabels(volume) : MakeOffGridLabels(volume);
    for (const auto & selection : { selections[0], selections[1] })
    {
      if (!onGrid && selection.Kept.size() == 3)
      {
        continue;
      }
      auto stage = StageType::New();
      stage->SetInput(volume);
      stage->SetLabelImage(labels);
      stage->SetKeptLabels(selection.Kept);
      stage->SetDroppedLabels(selection.Dropped);
      stage->SetLabelChannels(true);
      stage->Update();
      const itk::DRRAttenuationVolume &           whole = *stage->GetOutput();
      const itk::DRRLabelSelection::LabelListType wholeLabels = whole.GetChannelLabels();
      ASSERT_GT(wholeLabels.size(), 1u);
      const std::vector<uint8_t> wholeChannels(whole.GetVoxelChannels(),
                                               whole.GetVoxelChannels() + whole.GetNumberOfVoxels());
      const std::vector<float>   wholeMu = MuOf(whole);
      const size_t               plane = 19 * 17;
      for (const auto & slab : { std::make_pair(0, 8), std::make_pair(8, 13), std::make_pair(40, 5) })
      {
        auto region = volume->GetLargestPossibleRegion();
        region.SetIndex(2, slab.first);
        region.SetSize(2, slab.second);
        itk::DRRAttenuationVolume * model = stage->GetOutput();
        model->SetRequestedRegion(region);
        model->Update();
        ASSERT_EQ(model->GetNumberOfVoxels(), plane * slab.second);
        EXPECT_EQ(model->GetChannelLabels(), wholeLabels) << "slab at " << slab.first;
        ASSERT_EQ(model->GetNumberOfChannels(), wholeLabels.size());
        ASSERT_NE(model->GetVoxelChannels(), nullptr);
        const std::vector<float> mu = MuOf(*model);
        for (size_t v = 0; v < mu.size(); ++v)
        {
          ASSERT_EQ(mu[v], wholeMu[plane * slab.first + v]) << "slab at " << slab.first << ", voxel " << v;
          ASSERT_EQ(model->GetVoxelChannels()[v], wholeChannels[plane * slab.first + v])
            << (onGrid ? "on grid" : "resampled") << ", slab at " << slab.first << ", voxel " << v;
        }
      }
    }
  }
}

/** The four images of a point or exact render: line integral, standard error (the point filter's), channels and their
 * covariance, in buffer order. */
template <typename TFilter>
std::array<std::vector<double>, 4>
ImagesOf(TFilter & drr)
{
  const auto channelsOf = [](const auto * image) {
    const float * values = image->GetBufferPointer();
    return std::vector<double>(
      values, values + image->GetNumberOfComponentsPerPixel() * image->GetBufferedRegion().GetNumberOfPixels());
  };
  std::array<std::vector<double>, 4> images;
  images[0] = ToVector(drr.GetOutput());
  images[2] = channelsOf(drr.GetChannelOutput());
  images[3] = channelsOf(drr.GetChannelCovarianceOutput());
  if constexpr (std::is_same_v<TFilter, PointType>)
  {
    images[1] = ToVector(drr.GetStandardErrorOutput());
  }
  return images;
}

// The point filter streams label channels (on the volume's grid or resampled, kept or dropped labels) and material
// channels, drawn anew or kept: the same points as the unstreamed render in the same channels, so the image, its
// standard error, the channel images and their covariance are the same bit for bit. `auto` renders channels without a
// control variate, streamed or not.
TEST(DRRStreamedLabels, ThePointFilterStreamsLabelAndMaterialChannelsBitForBit)
{
  const auto volume = MakeVolumeOfLevels();
  enum class Kind
  {
    OnGrid,
    Resampled,
    Materials
  };
  for (const Kind kind : { Kind::OnGrid, Kind::Resampled, Kind::Materials })
  {
    const auto labels = kind == Kind::Resampled ? MakeOffGridLabels(volume) : MakeLabels(volume);
    for (const auto & selection : { selections[0], selections[1] })
    {
      if (kind != Kind::OnGrid && selection.Kept.size() == 3)
      {
        continue;
      }
      for (const bool reuse : { false, true })
      {
        for (const unsigned int factor : { 0u, PointType::AutomaticControlVariateFactor })
        {
          itk::DRRLabelSelection::LabelListType channelLabels;
          const auto                            render = [&](unsigned int slabs) {
            auto drr = PointType::New();
            drr->SetInput(volume);
            drr->SetGeometry(MakeView(ProjectionEnum::Perspective));
            if (kind == Kind::Materials)
            {
              drr->GetTransferFunction()->SetMaterialTable(AirAndWater());
              drr->SetMaterialChannels(true);
            }
            else
            {
              drr->SetLabelImage(labels);
              drr->SetKeptLabels(selection.Kept);
              drr->SetDroppedLabels(selection.Dropped);
              drr->SetLabelChannels(true);
            }
            drr->SetNumberOfSamples(100000);
            drr->SetSeed(23);
            drr->SetReusePoints(reuse);
            drr->SetControlVariateFactor(factor);
            drr->SetNumberOfStreamDivisions(slabs);
            drr->Update();
            EXPECT_EQ(drr->GetNumberOfSlabs() > 1, slabs > 1); // `auto`'s F aligns the slabs
            channelLabels = drr->GetChannelLabels();
            return ImagesOf(*drr);
          };
          const auto whole = render(1);
          const auto wholeLabels = channelLabels;
          ASSERT_GT(wholeLabels.size(), 1u);
          ASSERT_GT(*std::max_element(whole[2].begin(), whole[2].end()), 0.1);
          for (const unsigned int slabs : { 2u, 3u })
          {
            const auto streamed = render(slabs);
            EXPECT_EQ(channelLabels, wholeLabels);
            for (size_t i = 0; i < whole.size(); ++i)
            {
              ASSERT_EQ(streamed[i].size(), whole[i].size()) << "image " << i;
              for (size_t p = 0; p < whole[i].size(); ++p)
              {
                ASSERT_EQ(streamed[i][p], whole[i][p])
                  << "kind " << static_cast<int>(kind) << ", reuse " << reuse << ", F " << factor << ", " << slabs
                  << " slabs, image " << i << ", value " << p;
              }
            }
          }
        }
      }
    }
  }
}

// `auto` renders channels without a control variate, streamed as unstreamed, even where it would keep one: a volume of
// water alone, whose residual is nothing (with one, the points would draw no channel at all).
TEST(DRRStreamedLabels, AutoRendersStreamedChannelsWithoutAControlVariate)
{
  HUVolumeType::SpacingType spacing;
  spacing.Fill(1.0);
  const auto volume = MakeVolume<HUVolumeType>(
    { { 16, 16, 32 } }, spacing, Pt(-8.0, -8.0, -16.0), RotationMatrix(Vec(0.0, 0.0, 1.0), 0.0));
  volume->FillBuffer(0);
  auto labels = LabelImageType::New();
  labels->CopyInformation(volume);
  labels->SetRegions(volume->GetLargestPossibleRegion());
  labels->Allocate();
  for (itk::ImageRegionIteratorWithIndex<LabelImageType> it(labels, labels->GetLargestPossibleRegion()); !it.IsAtEnd();
       ++it)
  {
    it.Set(static_cast<uint16_t>(1 + (it.GetIndex()[0] >= 8) + 2 * (it.GetIndex()[2] >= 16)));
  }
  const auto render = [&](unsigned int slabs) {
    auto drr = PointType::New();
    drr->SetInput(volume);
    drr->SetGeometry(MakeView(ProjectionEnum::Parallel));
    drr->SetLabelImage(labels);
    drr->SetLabelChannels(true);
    drr->SetNumberOfSamples(50000);
    drr->SetControlVariateFactor(PointType::AutomaticControlVariateFactor);
    drr->SetNumberOfStreamDivisions(slabs);
    drr->Update();
    EXPECT_EQ(drr->GetNumberOfSlabs(), slabs);
    return ImagesOf(*drr);
  };
  const auto whole = render(1);
  ASSERT_GT(*std::max_element(whole[2].begin(), whole[2].end()), 0.1);
  const auto streamed = render(2);
  for (size_t i = 0; i < whole.size(); ++i)
  {
    EXPECT_EQ(streamed[i], whole[i]) << "image " << i;
  }
}

// The exact filter streams label channels: the slabs' channel images add up to the unstreamed ones (to rounding), in
// the whole volume's channels; the label image, which numbers them, is read whole once.
TEST(DRRStreamedLabels, TheExactFilterStreamsLabelChannels)
{
  const auto volume = MakeVolumeOfLevels();
  for (const bool onGrid : { true, false })
  {
    const auto labels = onGrid ? MakeLabels(volume) : MakeOffGridLabels(volume);
    for (const auto & selection : { selections[0], Selection{ { 1, 3, 4 }, {} } })
    {
      auto                                  labelSource = RecordingSource<LabelImageType>::New();
      itk::DRRLabelSelection::LabelListType channelLabels;
      const auto                            render = [&](unsigned int slabs) {
        labelSource = RecordingSource<LabelImageType>::New();
        labelSource->Image = labels;
        auto exact = ExactType::New();
        exact->SetInput(volume);
        exact->SetGeometry(MakeView(ProjectionEnum::Perspective));
        exact->SetLabelImage(labelSource->GetOutput());
        exact->SetKeptLabels(selection.Kept);
        exact->SetDroppedLabels(selection.Dropped);
        exact->SetLabelChannels(true);
        exact->SetNumberOfStreamDivisions(slabs);
        exact->Update();
        EXPECT_EQ(exact->GetNumberOfSlabs(), slabs);
        channelLabels = exact->GetChannelLabels();
        return ImagesOf(*exact);
      };
      const auto whole = render(1);
      const auto wholeLabels = channelLabels;
      ASSERT_GT(wholeLabels.size(), 1u);
      const double largest = *std::max_element(whole[0].begin(), whole[0].end());
      ASSERT_GT(*std::max_element(whole[2].begin(), whole[2].end()), 0.1);
      for (const unsigned int slabs : { 2u, 3u, 7u })
      {
        const auto streamed = render(slabs);
        EXPECT_EQ(channelLabels, wholeLabels);
        for (const size_t i : { 0, 2 })
        {
          ASSERT_EQ(streamed[i].size(), whole[i].size());
          for (size_t p = 0; p < whole[i].size(); ++p)
          {
            ASSERT_NEAR(streamed[i][p], whole[i][p], 1e-6 * largest)
              << (onGrid ? "on grid" : "resampled") << ", " << slabs << " slabs, image " << i << ", value " << p;
          }
        }
        EXPECT_EQ(streamed[3], whole[3]); // an exact projection's covariance: zeros
        ASSERT_EQ(labelSource->Requests.size(), 1u);
        EXPECT_EQ(labelSource->Requests.front(), labels->GetLargestPossibleRegion());
      }
    }
  }
}

// What does not stream is refused by name, and a kept label in no slab is refused as in no voxel of the whole volume.
TEST(DRRStreamedLabels, WhatCannotStreamIsRefusedByName)
{
  const auto volume = MakeVolumeOfLevels();
  const auto labels = MakeLabels(volume);
  auto       exact = ExactType::New();
  exact->SetInput(volume);
  exact->SetGeometry(MakeView(ProjectionEnum::Perspective));
  exact->SetLabelImage(labels);
  exact->SetNumberOfStreamDivisions(3);
  exact->SetKeptLabels({ 1, 9 });
  EXPECT_TRUE(Contains(ExceptionMessage([&] { exact->Update(); }, "kept 9"), "the kept label 9 is in no voxel"));
  exact->SetKeptLabels({ 7 });
  exact->SetDroppedLabels({ 7 });
  EXPECT_TRUE(Contains(ExceptionMessage([&] { exact->Update(); }, "none left"), "leave no label to render"));
  // With label channels, the whole volume's labels are checked before the first slab.
  exact->SetDroppedLabels({});
  exact->SetKeptLabels({ 1, 9 });
  exact->SetLabelChannels(true);
  EXPECT_TRUE(
    Contains(ExceptionMessage([&] { exact->Update(); }, "channels, kept 9"), "the kept label 9 is in no voxel"));
  exact->SetKeptLabels({});
  EXPECT_NO_THROW(exact->Update());
  EXPECT_EQ(exact->GetChannelLabels(), (itk::DRRLabelSelection::LabelListType{ 0, 1, 2, 3, 4, 7 }));
  // A new selection numbers the channels anew.
  exact->SetDroppedLabels({ 2 });
  EXPECT_NO_THROW(exact->Update());
  EXPECT_EQ(exact->GetChannelLabels(), (itk::DRRLabelSelection::LabelListType{ 0, 1, 3, 4, 7 }));
  exact->SetDroppedLabels({});

  // More channels than a render holds, and a label image of another volume, streamed as unstreamed.
  auto many = LabelImageType::New();
  many->CopyInformation(volume);
  many->SetRegions(volume->GetLargestPossibleRegion());
  many->Allocate();
  uint16_t next = 0;
  for (itk::ImageRegionIterator<LabelImageType> it(many, many->GetLargestPossibleRegion()); !it.IsAtEnd(); ++it)
  {
    it.Set(static_cast<uint16_t>(next++ % 300));
  }
  auto elsewhere = MakeVolume<LabelImageType>(
    { { 4, 4, 4 } }, volume->GetSpacing(), volume->GetOrigin() + Vec(500.0, 0.0, 0.0), volume->GetDirection());
  auto points = PointType::New();
  points->SetInput(volume);
  points->SetGeometry(MakeView(ProjectionEnum::Perspective));
  points->SetLabelChannels(true);
  const auto refuses = [&](auto & drr) {
    for (const unsigned int slabs : { 1u, 2u })
    {
      drr->SetNumberOfStreamDivisions(slabs);
      drr->SetLabelImage(many);
      EXPECT_TRUE(Contains(ExceptionMessage([&] { drr->Update(); }, "300 channels"), "keep fewer labels"));
      drr->SetLabelImage(elsewhere);
      EXPECT_TRUE(Contains(ExceptionMessage([&] { drr->Update(); }, "labels elsewhere"), "covers no voxel"));
    }
  };
  refuses(exact);
  refuses(points);
  // A chosen control variate with channels: refused streamed as unstreamed; `auto` renders without one.
  points->SetLabelImage(labels);
  points->SetControlVariateFactor(4);
  EXPECT_TRUE(Contains(ExceptionMessage([&] { points->Update(); }, "streamed channels, F 4"),
                       "label channels are rendered without a control variate"));
  points->SetControlVariateFactor(PointType::AutomaticControlVariateFactor);
  EXPECT_NO_THROW(points->Update());
  EXPECT_EQ(points->GetChannelOutput()->GetNumberOfComponentsPerPixel(), 6u);

  // The stage refuses a region of other than whole z planes.
  auto stage = StageType::New();
  stage->SetInput(volume);
  stage->SetLabelImage(labels);
  auto slab = volume->GetLargestPossibleRegion();
  slab.SetSize(2, 4);
  slab.SetSize(0, 5);
  stage->GetOutput()->SetRequestedRegion(slab);
  EXPECT_TRUE(Contains(ExceptionMessage([&] { stage->Update(); }, "part planes"), "is not whole z planes"));
}
} // namespace
