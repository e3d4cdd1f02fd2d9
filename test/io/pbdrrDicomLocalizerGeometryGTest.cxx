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
// The view of a CT localizer from its header (pbdrr --geometry-from): on the synthetic localizer MakeTestVolumes writes
// (a point of the header's image plane lands on the pixel the header puts it at), and on the real Philips surview of
// ../shared/data, whose DRRs from both tilted series must match it better than the same DRRs in wrong views.
#include "pbdrrDicomLocalizerGeometry.h"
#include "pbdrrVolumeLoader.h"

#include "itkExactDRRImageFilter.h"
#include "itkGDCMImageIO.h"
#include "itkImageFileReader.h"
#include "gtest/gtest.h"

#include <algorithm>
#include <cmath>
#include <iostream>
#include <filesystem>
#include <string>
#include <vector>

namespace
{
using ProjectionType = itk::Image<float, 2>;
using MuVolumeType = itk::Image<float, 3>;

std::vector<double>
RenderExact(const itk::ImageBase<3> * volume, itk::DRRProjectionGeometry * geometry, bool muInput)
{
  std::vector<double> values;
  const auto          collect = [&](auto filter) {
    filter->SetGeometry(geometry);
    filter->SetRaysPerPixelSide(2);
    if (muInput)
    {
      filter->GetTransferFunction()->SetMode(itk::PointBasedDRREnums::TransferFunction::Identity);
    }
    filter->Update();
    const ProjectionType * output = filter->GetOutput();
    values.assign(output->GetBufferPointer(),
                  output->GetBufferPointer() + output->GetLargestPossibleRegion().GetNumberOfPixels());
  };
  if (muInput)
  {
    auto filter = itk::ExactDRRImageFilter<MuVolumeType, ProjectionType>::New();
    filter->SetInput(static_cast<const MuVolumeType *>(volume));
    collect(filter);
  }
  else if (const auto * hu = dynamic_cast<const pbdrr::HUVolumeType *>(volume))
  {
    auto filter = itk::ExactDRRImageFilter<pbdrr::HUVolumeType, ProjectionType>::New();
    filter->SetInput(hu);
    collect(filter);
  }
  else
  {
    auto filter = itk::ExactDRRImageFilter<pbdrr::VolumeType, ProjectionType>::New();
    filter->SetInput(static_cast<const pbdrr::VolumeType *>(volume));
    collect(filter);
  }
  return values;
}

/** Normalized cross-correlation of a and b over the pixels where mask > 5% of its maximum. */
double
MaskedCorrelation(const std::vector<double> & a, const std::vector<double> & b, const std::vector<double> & mask)
{
  const double peak = *std::max_element(mask.begin(), mask.end());
  double       sa = 0, sb = 0, n = 0;
  for (size_t p = 0; p < a.size(); ++p)
  {
    if (mask[p] > 0.05 * peak)
    {
      sa += a[p];
      sb += b[p];
      ++n;
    }
  }
  const double ma = sa / n, mb = sb / n;
  double       ab = 0, aa = 0, bb = 0;
  for (size_t p = 0; p < a.size(); ++p)
  {
    if (mask[p] > 0.05 * peak)
    {
      ab += (a[p] - ma) * (b[p] - mb);
      aa += (a[p] - ma) * (a[p] - ma);
      bb += (b[p] - mb) * (b[p] - mb);
    }
  }
  return ab / std::sqrt(aa * bb);
}
} // namespace

// The header's image plane is the isocenter plane: a 1 mm cube centred on the plane point the header gives pixel
// (20, 10) casts its shadow on that pixel alone, one pixel wide (its 1 mm magnified SID / SAD, the column pitch).
TEST(PbdrrLocalizerView, APointOfTheHeadersPlaneLandsOnItsPixel)
{
  const std::string file = std::string(PBDRR_TEST_DATA_DIR) + "/localizer_lateral.dcm";
  const auto        view = pbdrr::ReadLocalizerView(file);
  const auto &      g = *view.Geometry;
  EXPECT_EQ(g.GetProjection(), itk::PointBasedDRREnums::Projection::Localizer);
  EXPECT_EQ(g.GetDetectorSize()[0], 32u);
  EXPECT_EQ(g.GetDetectorSize()[1], 24u);
  EXPECT_DOUBLE_EQ(g.GetSourceToIsocenterDistance(), 570.0);
  EXPECT_DOUBLE_EQ(g.GetSourceToDetectorDistance(), 1040.0);
  EXPECT_NEAR(g.GetDetectorSpacing()[0], 1040.0 / 570.0, 1e-12);
  EXPECT_NEAR(g.GetDetectorSpacing()[1], 1.0, 1e-12);
  for (unsigned int a = 0; a < 3; ++a)
  {
    EXPECT_NEAR(g.GetIsocenter()[a], 0.0, 1e-12);
  }
  EXPECT_NEAR(g.GetSourcePosition()[0], 570.0, 1e-9) << "source on +x: n = rows x columns of the header";
  EXPECT_NE(view.Description.find("32 x 24"), std::string::npos) << view.Description;

  // Pixel (20, 10) of the header: (0, -15.5 + 20, 11.5 - 10) = (0, 4.5, 1.5).
  auto volume = MuVolumeType::New();
  volume->SetRegions(MuVolumeType::SizeType{ { 1, 1, 1 } });
  double origin[3] = { 0.0, 4.5, 1.5 };
  volume->SetOrigin(origin);
  volume->Allocate();
  volume->FillBuffer(0.01f);
  const auto image = RenderExact(volume, view.Geometry, true);
  size_t     brightest = 0;
  for (size_t p = 0; p < image.size(); ++p)
  {
    brightest = image[p] > image[brightest] ? p : brightest;
  }
  EXPECT_EQ(brightest % 32, 20u);
  EXPECT_EQ(brightest / 32, 10u);
  // Across the fan the cube's near face (depth 569.5) is magnified 1040 / 569.5, its far face 1040 / 570.5: about one
  // column pitch; most of the pixel's rays cross 1 mm of it, and its neighbours get a sliver at most.
  EXPECT_GT(image[brightest], 0.4 * 0.01);
  EXPECT_LT(image[brightest - 1] + image[brightest + 1], 0.05 * image[brightest]);
  EXPECT_LT(image[brightest - 32] + image[brightest + 32], 1e-12);
}

// The real surview: both tilted series rendered in its view correlate with it better than in wrong views (the source
// on the other side, or the isocenter 10 mm off), the number the closing note of issue 15 reports.
TEST(PbdrrLocalizerView, RealSurviewMatchesTheDRRsOfBothTiltedSeries)
{
  const std::filesystem::path root = std::string(PBDRR_SHARED_DATA_DIR) + "/ct/philips-s21610-head-phantom";
  if (!std::filesystem::exists(root / "S1000" / "I10"))
  {
    GTEST_SKIP() << "SKIPPED: " << root.string() << " is absent (real data from ../shared/data)";
  }
  const std::string localizer = (root / "S1000" / "I10").string();
  const auto        view = pbdrr::ReadLocalizerView(localizer);
  EXPECT_NEAR(view.Geometry->GetIsocenter()[1], 124.71171875, 1e-9);
  EXPECT_NEAR(view.Geometry->GetDetectorSpacing()[0], 0.9765625 * 1040.0 / 570.0, 1e-12);
  const auto          xray = itk::ReadImage<ProjectionType>(localizer);
  std::vector<double> real(xray->GetBufferPointer(),
                           xray->GetBufferPointer() + xray->GetLargestPossibleRegion().GetNumberOfPixels());
  ASSERT_EQ(real.size(), 512u * 256u);

  auto wrongSide = itk::DRRProjectionGeometry::New();
  wrongSide->SetProjection(itk::PointBasedDRREnums::Projection::Localizer);
  wrongSide->SetSourceToIsocenterDistance(570.0);
  wrongSide->SetSourceToDetectorDistance(1040.0);
  wrongSide->SetIsocenter(view.Geometry->GetIsocenter());
  wrongSide->SetNormal(-view.Geometry->GetNormal());
  wrongSide->SetViewUp(view.Geometry->GetViewUp());
  wrongSide->SetColumnsMirrored(true); // the same pixel grid in the isocenter plane, the fan from the other side
  wrongSide->SetDetectorSize(view.Geometry->GetDetectorSize());
  wrongSide->SetDetectorSpacing(view.Geometry->GetDetectorSpacing());
  auto shifted = itk::DRRProjectionGeometry::New();
  auto isocenter = view.Geometry->GetIsocenter();
  isocenter[1] += 10.0;
  shifted->SetProjection(itk::PointBasedDRREnums::Projection::Localizer);
  shifted->SetSourceToIsocenterDistance(570.0);
  shifted->SetSourceToDetectorDistance(1040.0);
  shifted->SetIsocenter(isocenter);
  shifted->SetNormal(view.Geometry->GetNormal());
  shifted->SetViewUp(view.Geometry->GetViewUp());
  shifted->SetDetectorSize(view.Geometry->GetDetectorSize());
  shifted->SetDetectorSpacing(view.Geometry->GetDetectorSpacing());

  for (const char * series : { "S2010", "S3010" })
  {
    const auto   volume = pbdrr::LoadVolume((root / series).string(), "");
    const auto   drr = RenderExact(volume.Grid(), view.Geometry, false);
    const auto   side = RenderExact(volume.Grid(), wrongSide, false);
    const auto   off = RenderExact(volume.Grid(), shifted, false);
    const double header = MaskedCorrelation(real, drr, drr);
    const double otherSide = MaskedCorrelation(real, side, side);
    const double offCentre = MaskedCorrelation(real, off, off);
    std::cout << "[ NCC ] " << series << ": header view " << header << ", source on the other side " << otherSide
              << ", isocenter 10 mm off " << offCentre << std::endl;
    testing::Test::RecordProperty(std::string(series) + "_ncc", std::to_string(header));
    EXPECT_GT(header, 0.78) << series;
    EXPECT_GT(header, otherSide + 0.01) << series;
    EXPECT_GT(header, offCentre + 0.2) << series;
  }
}
