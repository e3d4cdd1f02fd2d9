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
// Statistical proof that the point-based estimate is unbiased for the exact pixel-averaged line integral, that its
// standard-error output predicts its spread, that the paper's unweighted count is biased in perspective, and that a
// seed fixes the image bit for bit on any number of threads.
#include "itkPointBasedDRRImageFilter.h"
#include "itkDRRImageToAttenuationVolumeFilter.h"
#include "itkExactDRRImageFilter.h"
#include "itkAffineTransform.h"
#include "itkDRRPhiloxRandom.h"
#include "itkDRRPolicies.h"
#include "itkDRRSamplerFactory.h"
#include "itkDRRLevelAliasSampler.h"
#include "itkDRRPaperHybridSampler.h"
#include "itkDRRStratifiedSampler.h"
#include "itkDRRBoxKernel.h"
#include "itkDRRNearestSplat.h"
#include "itkDRRTentKernel.h"
#include "itkCommand.h"
#include "itkImageRegionIterator.h"
#include "itkImageRegionIteratorWithIndex.h"
#include "itkImageSource.h"
#include "PointBasedDRRTestHelpers.h"

#include "gtest/gtest.h"

#include <functional>
#include <cstring>
#include <numeric>

namespace
{
using namespace PointBasedDRRTest;
using KernelEnum = itk::PointBasedDRREnums::ReconstructionKernel;
using SplatEnum = itk::PointBasedDRREnums::Splat;
using ProjectionEnum = itk::PointBasedDRREnums::Projection;
using WeightingEnum = itk::PointBasedDRREnums::PointWeighting;

// Family-wise bound for |z| over all pixels of one scenario: Bonferroni over <= 64 pixels at alpha = 1e-4 gives a
// per-pixel two-sided 1.6e-6, i.e. |z| < 4.8 for a normal mean; 5 leaves room for the t-distribution of 64 seeds.
constexpr double zBound = 5.0;

/** A small CT-like phantom: 6 x 7 x 5 voxels of a few HU levels (air included), anisotropic spacing, rotated
 * direction, off-centre origin. */
template <typename TVolume>
typename TVolume::Pointer
MakePhantom(bool continuousValues, bool sheared = false)
{
  typename TVolume::SizeType    size = { { 6, 7, 5 } };
  typename TVolume::SpacingType spacing;
  spacing[0] = 2.0;
  spacing[1] = 2.5;
  spacing[2] = 3.0;
  typename TVolume::PointType origin;
  origin[0] = -4.0;
  origin[1] = -9.0;
  origin[2] = -3.0;
  itk::Vector<double, 3> axis;
  axis[0] = 1.0 / std::sqrt(14.0);
  axis[1] = 2.0 / std::sqrt(14.0);
  axis[2] = 3.0 / std::sqrt(14.0);
  typename TVolume::DirectionType direction;
  direction = RotationMatrix(axis, 25.0);
  if (sheared)
  {
    // A gantry-tilted series: the image plane tilted by 18.5 degrees, the slices stepping along the third axis, so
    // the direction matrix is not orthogonal (its columns are unit vectors 18.5 degrees from perpendicular).
    typename TVolume::DirectionType tilt;
    tilt.SetIdentity();
    tilt[1][1] = std::cos(18.5 * itk::Math::pi / 180.0);
    tilt[2][1] = -std::sin(18.5 * itk::Math::pi / 180.0);
    direction = direction * tilt;
  }
  auto         volume = MakeVolume<TVolume>(size, spacing, origin, direction);
  const short  levels[5] = { -1000, -200, 0, 400, 1500 };
  unsigned int state = 12345u;
  auto *       buffer = volume->GetBufferPointer();
  for (size_t v = 0; v < volume->GetBufferedRegion().GetNumberOfPixels(); ++v)
  {
    state = state * 1664525u + 1013904223u;
    const unsigned int r = state >> 8;
    buffer[v] = continuousValues ? static_cast<typename TVolume::PixelType>(0.001 + 0.04 * (r % 10007) / 10007.0)
                                 : static_cast<typename TVolume::PixelType>(levels[r % 5]);
  }
  return volume;
}

struct Scenario
{
  ProjectionEnum projection;
  KernelEnum     kernel;
  SplatEnum      splat;
  bool           muInput;   // float input, mu per voxel continuous: binned levels with correction weights
  bool           transform; // an anisotropic affine transform between room and volume
  std::string    sampler{ "level-alias" };
  uint64_t       refine{ 0 };         // points added by Refine() after Update()
  bool           reuse{ false };      // kept points, drawn at another pose, re-projected
  unsigned int   controlVariate{ 0 }; // F of the control variate (0: off)
  bool           sheared{ false };    // a non-orthogonal direction matrix (a gantry-tilted series)
  bool           fromMatrix{ false }; // the view set from its 3 x 4 projection matrix, with mirrored columns
};

std::ostream &
operator<<(std::ostream & os, const Scenario & s)
{
  return os << s.sampler << (s.refine ? "+refine" : "") << (s.reuse ? "+reuse" : "")
            << (s.controlVariate ? "+cv" + std::to_string(s.controlVariate) : "") << "/" << s.projection << "/"
            << s.kernel << "/" << s.splat << (s.muInput ? "/mu-input" : "") << (s.transform ? "/affine" : "")
            << (s.sheared ? "/sheared" : "") << (s.fromMatrix ? "/mirrored-matrix" : "");
}

itk::DRRProjectionGeometry::Pointer
MakeGeometry(ProjectionEnum projection,
             unsigned int   cols,
             unsigned int   rows,
             double         du,
             double         dv,
             bool           fromMirroredMatrix = false)
{
  if (fromMirroredMatrix)
  {
    // The mirrored view's projection matrix, given back to a new geometry (SetProjectionMatrix keeps du and derives
    // dv).
    const auto mirrored = MakeGeometry(projection, cols, rows, du, dv);
    mirrored->SetColumnsMirrored(true);
    auto                   geometry = itk::DRRProjectionGeometry::New();
    itk::Vector<double, 2> spacing;
    spacing[0] = du;
    spacing[1] = 1.0;
    geometry->SetDetectorSpacing(spacing);
    geometry->SetProjectionMatrix(mirrored->GetProjectionMatrix(), mirrored->GetDetectorSize());
    return geometry;
  }
  auto geometry = itk::DRRProjectionGeometry::New();
  geometry->SetProjection(projection);
  geometry->SetSourceToIsocenterDistance(50.0); // strong magnification change across the phantom
  geometry->SetSourceToDetectorDistance(90.0);
  geometry->SetGantryAngleInDegrees(30.0);
  itk::Point<double, 3> iso;
  iso[0] = 1.0;
  iso[1] = -1.0;
  iso[2] = 2.0;
  geometry->SetIsocenter(iso);
  geometry->SetDetectorSize({ { cols, rows } });
  itk::Vector<double, 2> spacing;
  spacing[0] = du;
  spacing[1] = dv;
  geometry->SetDetectorSpacing(spacing);
  itk::Vector<double, 2> offset;
  offset[0] = 1.5;
  offset[1] = -2.0;
  geometry->SetDetectorOffset(offset);
  return geometry;
}

using AffineType = itk::AffineTransform<double, 3>;

AffineType::Pointer
MakeAffine()
{
  auto                   affine = AffineType::New();
  itk::Vector<double, 3> axis;
  axis[0] = 0.0;
  axis[1] = 0.6;
  axis[2] = 0.8;
  affine->Rotate3D(axis, 0.3);
  itk::Vector<double, 3> scale;
  scale[0] = 1.1;
  scale[1] = 0.9;
  scale[2] = 1.05;
  affine->Scale(scale);
  itk::Vector<double, 3> translation;
  translation[0] = 2.0;
  translation[1] = -1.0;
  translation[2] = 0.5;
  affine->Translate(translation);
  return affine;
}

/** Everything a scenario is checked against: the exact mean image of its estimator. */
class ReferenceBuilder
{
public:
  ReferenceBuilder(const Scenario & scenario, unsigned int cols, unsigned int rows, double du, double dv)
    : m_Scenario(scenario), m_Cols(cols), m_Rows(rows), m_DU(du), m_DV(dv)
  {}

  /** Exact expectation of the estimator: the pixel-area average (nearest) or the one-pixel-tent weighted average
   * (bilinear) of the exact line integral, by a midpoint rule: one ray per pixel of a detector `fine` times finer. The
   * fine detector reaches one coarse pixel past each edge, where bilinear splats still deposit. */
  template <typename TVolume>
  std::vector<double>
  Compute(const TVolume * volume, unsigned int fine) const
  {
    using ExactType = itk::ExactDRRImageFilter<TVolume, ProjectionType>;
    auto exact = ExactType::New();
    exact->SetInput(volume);
    this->Configure(exact.GetPointer());
    exact->SetGeometry(MakeGeometry(m_Scenario.projection,
                                    (m_Cols + 2) * fine,
                                    (m_Rows + 2) * fine,
                                    m_DU / fine,
                                    m_DV / fine,
                                    m_Scenario.fromMatrix));
    exact->SetReconstructionKernel(m_Scenario.kernel);
    exact->SetRaysPerPixelSide(1);
    exact->Update();
    const std::vector<double> fineImage = ToVector(exact->GetOutput());
    const unsigned int        fineCols = (m_Cols + 2) * fine;
    std::vector<double>       reference(m_Cols * m_Rows, 0.0);
    for (unsigned int r = 0; r < m_Rows; ++r)
    {
      for (unsigned int c = 0; c < m_Cols; ++c)
      {
        double sum = 0.0;
        for (unsigned int fr = 0; fr < (m_Rows + 2) * fine; ++fr)
        {
          // Offset of the fine pixel centre from coarse pixel centre (c, r), in coarse pixels.
          const double dr = (fr + 0.5) / fine - 1.0 - (r + 0.5);
          for (unsigned int fc = 0; fc < fineCols; ++fc)
          {
            const double dc = (fc + 0.5) / fine - 1.0 - (c + 0.5);
            double       kernel = 0.0;
            if (m_Scenario.splat == SplatEnum::Nearest)
            {
              kernel = (std::abs(dc) < 0.5 && std::abs(dr) < 0.5) ? 1.0 : 0.0;
            }
            else
            {
              kernel = std::max(0.0, 1.0 - std::abs(dc)) * std::max(0.0, 1.0 - std::abs(dr));
            }
            sum += kernel * fineImage[fr * fineCols + fc];
          }
        }
        reference[r * m_Cols + c] = sum / (fine * fine);
      }
    }
    return reference;
  }

  template <typename TFilter>
  void
  Configure(TFilter * filter) const
  {
    if (m_Scenario.muInput)
    {
      filter->GetTransferFunction()->SetMode(itk::PointBasedDRREnums::TransferFunction::Identity);
    }
    if (m_Scenario.transform)
    {
      filter->SetTransform(MakeAffine());
    }
  }

private:
  Scenario     m_Scenario;
  unsigned int m_Cols;
  unsigned int m_Rows;
  double       m_DU;
  double       m_DV;
};

struct SeedStatistics
{
  std::vector<double> Mean;
  std::vector<double> Variance;          // observed across seeds
  std::vector<double> PredictedVariance; // mean of the squared standard-error outputs
};

template <typename TVolume>
SeedStatistics
RenderSeeds(const TVolume *              volume,
            const Scenario &             scenario,
            const ReferenceBuilder &     builder,
            itk::DRRProjectionGeometry * geometry,
            WeightingEnum                weighting,
            uint64_t                     samples,
            unsigned int                 seeds,
            itk::DRRPointSampler *       sampler = nullptr)
{
  auto drr = itk::PointBasedDRRImageFilter<TVolume, ProjectionType>::New();
  drr->SetInput(volume);
  builder.Configure(drr.GetPointer());
  drr->SetGeometry(geometry);
  drr->SetReconstructionKernel(scenario.kernel);
  drr->SetSplat(scenario.splat);
  drr->SetPointWeighting(weighting);
  drr->SetSampler(sampler ? sampler : itk::DRRSamplerFactory::Create(scenario.sampler).GetPointer());
  drr->SetNumberOfSamples(samples);
  drr->SetControlVariateFactor(scenario.controlVariate);
  const size_t   pixels = geometry->GetDetectorSize()[0] * geometry->GetDetectorSize()[1];
  SeedStatistics stats;
  stats.Mean.assign(pixels, 0.0);
  stats.Variance.assign(pixels, 0.0);
  stats.PredictedVariance.assign(pixels, 0.0);
  std::vector<double> sumOfSquares(pixels, 0.0);
  // With reuse, every seed's points are drawn at another pose (gantry 90 degrees away), then re-projected.
  auto otherPose = MakeGeometry(scenario.projection, 8, 6, 7.0, 8.0);
  otherPose->SetGantryAngleInDegrees(geometry->GetGantryAngleInDegrees() + 90.0);
  drr->SetReusePoints(scenario.reuse);
  for (unsigned int seed = 0; seed < seeds; ++seed)
  {
    drr->SetSeed(1000 + seed);
    if (scenario.reuse)
    {
      drr->SetGeometry(otherPose);
      drr->Update();
      drr->SetGeometry(geometry);
    }
    drr->Update();
    if (scenario.refine > 0)
    {
      drr->Refine(scenario.refine);
      drr->Refine(scenario.refine / 2);
    }
    const auto values = ToVector(drr->GetOutput());
    const auto errors = ToVector(drr->GetStandardErrorOutput());
    for (size_t p = 0; p < pixels; ++p)
    {
      stats.Mean[p] += values[p];
      sumOfSquares[p] += values[p] * values[p];
      stats.PredictedVariance[p] += errors[p] * errors[p];
    }
  }
  for (size_t p = 0; p < pixels; ++p)
  {
    stats.Mean[p] /= seeds;
    stats.Variance[p] = (sumOfSquares[p] - seeds * stats.Mean[p] * stats.Mean[p]) / (seeds - 1.0);
    stats.PredictedVariance[p] /= seeds;
  }
  return stats;
}

class PointBasedDRRUnbiased : public testing::TestWithParam<Scenario>
{};

template <typename TVolume>
void
CheckUnbiased(const Scenario & scenario)
{
  const unsigned int cols = 8, rows = 6;
  // Magnified axes get larger pixels (a localizer magnifies its columns only).
  const bool       magnifiedColumns = scenario.projection != ProjectionEnum::Parallel;
  const bool       magnifiedRows = scenario.projection == ProjectionEnum::Perspective;
  const double     du = magnifiedColumns ? 7.0 : 3.5, dv = magnifiedRows ? 8.0 : 4.0;
  const auto       volume = MakePhantom<TVolume>(scenario.muInput, scenario.sheared);
  ReferenceBuilder builder(scenario, cols, rows, du, dv);
  // The midpoint rule converges at second order here (the line integral is continuous with kinks), so Richardson
  // extrapolation of 64 x 64 and 32 x 32 rays per pixel gives the reference, and its correction bounds its error.
  // A sheared grid puts more kinks inside the pixels: twice the rays keep the reference's error below the noise.
  const unsigned int  fineRays = scenario.sheared ? 128 : 64;
  const auto          fine = builder.Compute(volume.GetPointer(), fineRays);
  const auto          coarse = builder.Compute(volume.GetPointer(), fineRays / 2);
  std::vector<double> reference(fine.size()), referenceError(fine.size());
  for (size_t p = 0; p < fine.size(); ++p)
  {
    reference[p] = fine[p] + (fine[p] - coarse[p]) / 3.0;
    referenceError[p] = std::abs(fine[p] - coarse[p]) / 3.0;
  }
  const double peak = *std::max_element(reference.begin(), reference.end());

  const unsigned int seeds = 64;
  auto               geometry = MakeGeometry(scenario.projection, cols, rows, du, dv, scenario.fromMatrix);
  const auto         stats =
    RenderSeeds(volume.GetPointer(), scenario, builder, geometry, WeightingEnum::Unbiased, 200000, seeds);

  // The reference's error estimate enters the z denominator. On 90% of the pixels it must stay below half the
  // standard error of the mean (inflating the denominator by at most 12%), or the test would have lost its power.
  double worstZ = 0.0, observed = 0.0, predicted = 0.0;
  size_t pixelsWithSignal = 0, pixelsWithConvergedReference = 0;
  for (size_t p = 0; p < reference.size(); ++p)
  {
    const double standardErrorOfMean = std::sqrt(stats.Variance[p] / seeds);
    // Outside the shadow a control variate's padded coarse boxes still cast one, which its residual cancels on
    // average only: those pixels take the z-test.
    if (reference[p] == 0.0 && (scenario.controlVariate == 0 || stats.Variance[p] == 0.0))
    {
      EXPECT_EQ(stats.Mean[p], 0.0) << "pixel " << p << " outside the shadow got signal";
      continue;
    }
    if (stats.Variance[p] == 0.0)
    {
      // No point reached this pixel in any seed: only acceptable for a vanishing sliver of the shadow.
      EXPECT_LT(reference[p], 1e-4 * peak) << scenario << " pixel " << p << " never reached";
      continue;
    }
    pixelsWithConvergedReference += referenceError[p] < 0.5 * standardErrorOfMean ? 1 : 0;
    // A control variate's coarse rays rarely graze a sliver of a padded coarse box at the edge of the shadow: there
    // its estimate is unbiased but so skewed that 64 seeds see no normal mean. 1e-4 of the peak absorbs that; a dropped
    // sign or unjittered coarse rays are off by percents of the peak (z of 50 to 460; a wrong block mean is no bias
    // as long as the residual is taken against it: DRRControlVariate.SplitsIntoBlockMeansAndASignedResidual).
    // Likewise a pixel the shadow only grazes (a sheared box's corner: 1e-9 of the peak) gets a point in one seed of
    // 64 at most, and its mean cannot be normal: 1e-6 of the peak, far below any bias of a wrong weight.
    const double skewFloor = scenario.controlVariate > 0 ? 1e-4 * peak : 1e-6 * peak;
    const double z =
      std::abs(stats.Mean[p] - reference[p]) / std::sqrt(standardErrorOfMean * standardErrorOfMean +
                                                         referenceError[p] * referenceError[p] + skewFloor * skewFloor);
    worstZ = std::max(worstZ, z);
    observed += stats.Variance[p];
    predicted += stats.PredictedVariance[p];
    // Per pixel, the observed variance of 64 seeds is predicted variance * chi2(63) / 63: within +-5 sigma.
    const double ratio = stats.Variance[p] / stats.PredictedVariance[p];
    // The same skew at the shadow's edge leaves a sliver's variance unseen by most seeds: pooled below only.
    const bool sliver = scenario.controlVariate > 0 && std::abs(reference[p]) < 1e-2 * peak;
    // A control variate's predicted variance is itself noisy: each seed's coarse image has a one-degree-of-freedom
    // variance estimate, so the mean of 64 of them adds a relative variance of up to 2 / 64 to the ratio's.
    const double ratioVariance = 2.0 / (seeds - 1.0) + (scenario.controlVariate > 0 ? 2.0 / seeds : 0.0);
    if (!sliver)
    {
      EXPECT_NEAR(ratio, 1.0, zBound * std::sqrt(ratioVariance)) << scenario << " pixel " << p;
    }
    ++pixelsWithSignal;
  }
  EXPECT_GE(pixelsWithConvergedReference, 0.9 * pixelsWithSignal) << scenario << ": reference not converged";
  EXPECT_LT(worstZ, zBound) << scenario << ": the mean over seeds is off the exact reference";
  // Pooled over pixels, the variance ratio is known to sqrt(2 / ((seeds - 1) pixels)) if the pixels are independent.
  // A bilinear splat shares every point among 4 pixels, and a systematic sample (stratified) trades a deficit in one
  // pixel for a surplus in its neighbour: count about a quarter of the pixels as independent then.
  const bool   coupledPixels = scenario.splat == SplatEnum::Bilinear || scenario.sampler == "stratified";
  const double independentPixels = pixelsWithSignal / (coupledPixels ? 4.0 : 1.0);
  EXPECT_NEAR(observed / predicted, 1.0, zBound * std::sqrt(2.0 / ((seeds - 1.0) * independentPixels)))
    << scenario << ": the standard-error output does not predict the spread";
  EXPECT_GT(pixelsWithSignal, reference.size() / 2);
  testing::Test::RecordProperty("worst_z", std::to_string(worstZ));
}

TEST_P(PointBasedDRRUnbiased, MeanMatchesExactReferenceAndSpreadMatchesStandardError)
{
  const Scenario scenario = GetParam();
  if (scenario.muInput)
  {
    CheckUnbiased<MuVolumeType>(scenario);
  }
  else
  {
    CheckUnbiased<HUVolumeType>(scenario);
  }
}

std::vector<Scenario>
AllScenarios()
{
  // Every registered beam x kernel x splat with the default sampler, then every other registered sampler.
  std::vector<Scenario> scenarios;
  for (const auto & beam : itk::DRRPolicies::Beams::GetEntries())
  {
    for (const auto & kernel : itk::DRRPolicies::Kernels::GetEntries())
    {
      for (const auto & splat : itk::DRRPolicies::Splats::GetEntries())
      {
        scenarios.push_back({ beam.Id, kernel.Id, splat.Id, false, false });
      }
    }
  }
  scenarios.push_back({ ProjectionEnum::Perspective, KernelEnum::Tent, SplatEnum::Nearest, true, false });
  scenarios.push_back({ ProjectionEnum::Perspective, KernelEnum::Box, SplatEnum::Bilinear, false, true });
  const auto & samplers = itk::DRRSamplerFactory::GetEntries();
  for (auto entry = std::next(samplers.begin()); entry != samplers.end(); ++entry)
  {
    const std::string & sampler = entry->Name;
    // Every kernel x splat, across both beams.
    scenarios.push_back({ ProjectionEnum::Perspective, KernelEnum::Tent, SplatEnum::Bilinear, false, false, sampler });
    scenarios.push_back({ ProjectionEnum::Parallel, KernelEnum::Box, SplatEnum::Nearest, false, false, sampler });
    scenarios.push_back({ ProjectionEnum::Perspective, KernelEnum::Box, SplatEnum::Bilinear, false, false, sampler });
    scenarios.push_back({ ProjectionEnum::Parallel, KernelEnum::Tent, SplatEnum::Nearest, false, false, sampler });
  }
  scenarios.push_back(
    { ProjectionEnum::Perspective, KernelEnum::Box, SplatEnum::Nearest, true, false, "paper-hybrid" });
  scenarios.push_back(
    { ProjectionEnum::Perspective, KernelEnum::Tent, SplatEnum::Bilinear, false, false, "level-alias", 100000 });
  scenarios.push_back(
    { ProjectionEnum::Parallel, KernelEnum::Box, SplatEnum::Nearest, false, false, "stratified", 100000 });
  // Kept points re-projected: independent points with weights (mu input), interleaved strata, contiguous strata.
  scenarios.push_back(
    { ProjectionEnum::Perspective, KernelEnum::Tent, SplatEnum::Bilinear, true, true, "level-alias", 0, true });
  scenarios.push_back(
    { ProjectionEnum::Perspective, KernelEnum::Box, SplatEnum::Nearest, false, true, "stratified", 0, true });
  scenarios.push_back(
    { ProjectionEnum::Parallel, KernelEnum::Tent, SplatEnum::Nearest, false, false, "metropolis", 0, true });
  // The control variate (box model): every factor x sampler x splat x beam, on a 6 x 7 x 5 phantom that no factor
  // divides (8: one coarse voxel larger than the volume); kept points at a pose 90 degrees away, and refinement.
  for (unsigned int factor : { 2u, 4u, 8u })
  {
    for (const auto & entry : itk::DRRSamplerFactory::GetEntries())
    {
      for (const auto & beam : itk::DRRPolicies::Beams::GetEntries())
      {
        for (const auto & splat : itk::DRRPolicies::Splats::GetEntries())
        {
          scenarios.push_back({ beam.Id, KernelEnum::Box, splat.Id, false, false, entry.Name, 0, false, factor });
        }
      }
    }
  }
  scenarios.push_back(
    { ProjectionEnum::Perspective, KernelEnum::Box, SplatEnum::Nearest, false, true, "stratified", 0, true, 4 });
  scenarios.push_back(
    { ProjectionEnum::Perspective, KernelEnum::Box, SplatEnum::Bilinear, true, true, "level-alias", 0, true, 2 });
  scenarios.push_back(
    { ProjectionEnum::Parallel, KernelEnum::Box, SplatEnum::Nearest, true, false, "level-alias", 100000, false, 2 });
  // A sheared grid (gantry tilt): every sampler with both kernels and beams; kept points; the control variate.
  for (const auto & entry : itk::DRRSamplerFactory::GetEntries())
  {
    scenarios.push_back({ ProjectionEnum::Perspective,
                          KernelEnum::Box,
                          SplatEnum::Nearest,
                          false,
                          false,
                          entry.Name,
                          0,
                          false,
                          0,
                          true });
    scenarios.push_back(
      { ProjectionEnum::Parallel, KernelEnum::Tent, SplatEnum::Bilinear, false, false, entry.Name, 0, false, 0, true });
  }
  scenarios.push_back(
    { ProjectionEnum::Perspective, KernelEnum::Box, SplatEnum::Nearest, false, true, "stratified", 0, true, 0, true });
  scenarios.push_back({ ProjectionEnum::Perspective,
                        KernelEnum::Box,
                        SplatEnum::Bilinear,
                        false,
                        false,
                        "stratified",
                        0,
                        false,
                        2,
                        true });
  scenarios.push_back(
    { ProjectionEnum::Parallel, KernelEnum::Box, SplatEnum::Nearest, true, false, "level-alias", 0, false, 4, true });
  // A view from a projection matrix with mirrored columns: points, kept points, the control variate; and an affine one.
  for (const auto & sampler : { "stratified", "level-alias" })
  {
    scenarios.push_back({ ProjectionEnum::Perspective,
                          KernelEnum::Box,
                          SplatEnum::Nearest,
                          false,
                          false,
                          sampler,
                          0,
                          false,
                          0,
                          false,
                          true });
  }
  scenarios.push_back({ ProjectionEnum::Perspective,
                        KernelEnum::Tent,
                        SplatEnum::Bilinear,
                        false,
                        true,
                        "stratified",
                        0,
                        true,
                        0,
                        false,
                        true });
  scenarios.push_back({ ProjectionEnum::Perspective,
                        KernelEnum::Box,
                        SplatEnum::Bilinear,
                        false,
                        false,
                        "stratified",
                        0,
                        false,
                        4,
                        false,
                        true });
  scenarios.push_back({ ProjectionEnum::Parallel,
                        KernelEnum::Box,
                        SplatEnum::Nearest,
                        false,
                        false,
                        "stratified",
                        0,
                        false,
                        0,
                        false,
                        true });
  return scenarios;
}

INSTANTIATE_TEST_SUITE_P(KernelsSplatsBeams, PointBasedDRRUnbiased, testing::ValuesIn(AllScenarios()));

struct BiasCheck
{
  double SumZ;      // z of the image sum
  double MaxPixelZ; // largest |z| over pixels with signal
  double SumRatio;  // image sum / exact image sum
};

/** A sampler's mean over 32 seeds against the exact reference (perspective, box, nearest), in z-scores. */
BiasCheck
CheckSamplerBias(const HUVolumeType * volume, itk::DRRPointSampler * sampler, uint64_t samples)
{
  const Scenario     scenario{ ProjectionEnum::Perspective, KernelEnum::Box, SplatEnum::Nearest, false, false };
  ReferenceBuilder   builder(scenario, 8, 6, 7.0, 8.0);
  const auto         reference = builder.Compute(volume, 32);
  auto               geometry = MakeGeometry(scenario.projection, 8, 6, 7.0, 8.0);
  const unsigned int seeds = 32;
  const auto stats = RenderSeeds(volume, scenario, builder, geometry, WeightingEnum::Unbiased, samples, seeds, sampler);
  double     referenceSum = 0.0, meanSum = 0.0, spread = 0.0, worst = 0.0;
  for (size_t p = 0; p < reference.size(); ++p)
  {
    referenceSum += reference[p];
    meanSum += stats.Mean[p];
    // The standard deviation of a sum is at most the sum of the standard deviations: a conservative bound.
    spread += std::sqrt(stats.Variance[p]);
    if (stats.Variance[p] > 0.0)
    {
      worst = std::max(worst, std::abs(stats.Mean[p] - reference[p]) / std::sqrt(stats.Variance[p] / seeds));
    }
  }
  return { (meanSum - referenceSum) / (spread / std::sqrt(static_cast<double>(seeds))), worst, meanSum / referenceSum };
}

/** Mostly soft tissue, a little bone: level sizes as unequal as in CT. */
HUVolumeType::Pointer
MakeLopsidedPhantom()
{
  auto phantom = MakePhantom<HUVolumeType>(false);
  for (size_t v = 0; v < phantom->GetBufferedRegion().GetNumberOfPixels(); ++v)
  {
    phantom->GetBufferPointer()[v] = v % 23 == 0 ? 1500 : (v % 7 == 0 ? -1000 : 40);
  }
  return phantom;
}

TEST(PointBasedDRRPaperHybrid, RouletteExtremesAndOddLevelsStayUnbiased)
{
  auto phantom = MakePhantom<HUVolumeType>(false);
  for (double q : { 0.0, 1.0 })
  {
    auto sampler = itk::DRRPaperHybridSampler::New();
    sampler->SetRouletteSurvival(q);
    const BiasCheck check = CheckSamplerBias(MakeLopsidedPhantom(), sampler, 100000);
    EXPECT_LT(std::abs(check.SumZ), zBound) << "q = " << q;
    EXPECT_LT(check.MaxPixelZ, zBound + 0.5) << "q = " << q; // 48 pixels, t distribution of 32 seeds
  }
  // One non-air level; then a level holding one voxel; then fewer points than levels.
  auto oneLevel = MakePhantom<HUVolumeType>(false);
  oneLevel->FillBuffer(0);
  auto sampler = itk::DRRPaperHybridSampler::New();
  EXPECT_LT(std::abs(CheckSamplerBias(oneLevel, sampler, 100000).SumZ), zBound) << "one level";
  auto oneVoxelLevel = MakePhantom<HUVolumeType>(false);
  oneVoxelLevel->SetPixel({ { 3, 3, 2 } }, 3000);
  EXPECT_LT(std::abs(CheckSamplerBias(oneVoxelLevel, sampler, 100000).SumZ), zBound) << "a one-voxel level";
  auto manyLevels = MakePhantom<HUVolumeType>(false);
  for (size_t v = 0; v < manyLevels->GetBufferedRegion().GetNumberOfPixels(); ++v)
  {
    manyLevels->GetBufferPointer()[v] = static_cast<short>(-900 + 7 * static_cast<int>(v)); // 210 levels
  }
  EXPECT_LT(std::abs(CheckSamplerBias(manyLevels, sampler, 50).SumZ), zBound) << "50 points, 210 levels";
  EXPECT_LT(std::abs(CheckSamplerBias(manyLevels, itk::DRRLevelAliasSampler::New(), 50).SumZ), zBound) << "level-alias";
}

TEST(PointBasedDRRSamplers, EverySamplerStaysUnbiasedAtTheInt16Extremes)
{
  // Scanner padding (-3024, -32768 HU) is air; 3071 HU and the int16 maximum are the densest levels.
  auto         phantom = MakePhantom<HUVolumeType>(false);
  const short  extremes[] = { -32768, -3024, -2048, -1024, 3071, 32767 };
  unsigned int e = 0;
  for (size_t v = 0; v < phantom->GetBufferedRegion().GetNumberOfPixels(); v += 5)
  {
    phantom->GetBufferPointer()[v] = extremes[e++ % 6];
  }
  for (const auto & entry : itk::DRRSamplerFactory::GetEntries())
  {
    const BiasCheck check = CheckSamplerBias(phantom, entry.Create(), 100000);
    EXPECT_LT(std::abs(check.SumZ), zBound) << entry.Name;
    EXPECT_LT(check.MaxPixelZ, zBound + 0.5) << entry.Name;
  }
}

TEST(PointBasedDRRPaperHybrid, UnweightedCountIsBiasedAndTheBiasIsMeasured)
{
  // Without weights the paper's hybrid draws a level with probability ~ p(l) = mu_l / mu_max whatever its size: small
  // dense levels (bone) are drawn far too often, large ones (soft tissue) too rarely. The image sum hardly shows it
  // (every point carries M / (N a)), the pixels do.
  auto unweighted = itk::DRRPaperHybridSampler::New();
  unweighted->SetUseExactWeights(false);
  const BiasCheck biased = CheckSamplerBias(MakeLopsidedPhantom(), unweighted, 100000);
  auto            weighted = itk::DRRPaperHybridSampler::New();
  const BiasCheck exact = CheckSamplerBias(MakeLopsidedPhantom(), weighted, 100000);
  std::cout << "paper-hybrid without weights: worst pixel |z| " << biased.MaxPixelZ << ", image sum ratio "
            << biased.SumRatio << "; with exact weights: worst pixel |z| " << exact.MaxPixelZ << std::endl;
  EXPECT_GT(biased.MaxPixelZ, 20.0);
  EXPECT_LT(exact.MaxPixelZ, zBound + 0.5);
}

TEST(PointBasedDRRStandardError, PredictsTheSpreadOfManySeedsToFivePercent)
{
  // 768 cheap renders: the pooled ratio of observed to predicted variance is known to 5 sigma = 5 sqrt(2 / (767 P)),
  // about 4% here (nearest splat: the pixels are independent but for the multinomial's slight negative correlation),
  // so a standard-error formula off by 5% in variance fails.
  const Scenario     scenario{ ProjectionEnum::Perspective, KernelEnum::Tent, SplatEnum::Nearest, false, false };
  const auto         volume = MakePhantom<HUVolumeType>(false);
  auto               geometry = MakeGeometry(scenario.projection, 8, 6, 7.0, 8.0);
  ReferenceBuilder   builder(scenario, 8, 6, 7.0, 8.0);
  const unsigned int seeds = 768;
  const auto         stats =
    RenderSeeds(volume.GetPointer(), scenario, builder, geometry, WeightingEnum::Unbiased, 20000, seeds);
  double observed = 0.0, predicted = 0.0;
  size_t pixels = 0;
  for (size_t p = 0; p < stats.Mean.size(); ++p)
  {
    if (stats.Mean[p] > 0.0)
    {
      observed += stats.Variance[p];
      predicted += stats.PredictedVariance[p];
      ++pixels;
    }
  }
  ASSERT_GT(pixels, 30u);
  EXPECT_NEAR(observed / predicted, 1.0, zBound * std::sqrt(2.0 / ((seeds - 1.0) * pixels)));
}

TEST(PointBasedDRRPaperCount, PerspectiveBiasIsMeasuredAndMatchesTheMagnification)
{
  // The paper counts every point with weight 1. In perspective a point at depth z, landing at (u, v), stands for
  // 1 / w = (z / SID)^2 SID / R of what it should: the count underestimates by that factor, which across this
  // phantom ranges over the values of 1 / w at its corners.
  const Scenario     scenario{ ProjectionEnum::Perspective, KernelEnum::Box, SplatEnum::Nearest, false, false };
  const unsigned int cols = 8, rows = 6;
  const auto         volume = MakePhantom<HUVolumeType>(false);
  ReferenceBuilder   builder(scenario, cols, rows, 7.0, 8.0);
  const auto         reference = builder.Compute(volume.GetPointer(), 8);
  auto               geometry = MakeGeometry(scenario.projection, cols, rows, 7.0, 8.0);
  const unsigned int seeds = 16;
  const auto         counted =
    RenderSeeds(volume.GetPointer(), scenario, builder, geometry, WeightingEnum::PaperCount, 200000, seeds);
  const auto weighted =
    RenderSeeds(volume.GetPointer(), scenario, builder, geometry, WeightingEnum::Unbiased, 200000, seeds);

  const double referenceSum = std::accumulate(reference.begin(), reference.end(), 0.0);
  const double countedSum = std::accumulate(counted.Mean.begin(), counted.Mean.end(), 0.0);
  const double weightedSum = std::accumulate(weighted.Mean.begin(), weighted.Mean.end(), 0.0);
  const double countedSpread =
    std::sqrt(std::accumulate(counted.Variance.begin(), counted.Variance.end(), 0.0) / seeds);
  const double weightedSpread =
    std::sqrt(std::accumulate(weighted.Variance.begin(), weighted.Variance.end(), 0.0) / seeds);

  // Bounds of 1 / w over the phantom's box corners: z from the source, the obliquity at the corner's shadow.
  const double sid = geometry->GetSourceToDetectorDistance();
  double       lowest = 1e300, highest = 0.0;
  const auto   source = geometry->GetSourcePosition();
  const auto   n = geometry->GetNormal();
  for (unsigned int corner = 0; corner < 8; ++corner)
  {
    itk::ContinuousIndex<double, 3> index;
    for (unsigned int a = 0; a < 3; ++a)
    {
      index[a] = (corner >> a) & 1u ? volume->GetLargestPossibleRegion().GetSize()[a] - 0.5 : -0.5;
    }
    itk::Point<double, 3> x;
    volume->TransformContinuousIndexToPhysicalPoint(index, x);
    const auto   d = x - source;
    const double z = -(d * n);
    const double r = d.GetNorm();
    const double inverseWeight = (z / sid) * (z / sid) * sid / (sid * r / z); // (z/SID)^2 SID / R, R = SID r / z
    lowest = std::min(lowest, inverseWeight);
    highest = std::max(highest, inverseWeight);
  }
  const double ratio = countedSum / referenceSum;
  std::cout << "paper count / exact, image sum: " << ratio << " (1/w over the phantom: " << lowest << " .. " << highest
            << "); unbiased / exact: " << weightedSum / referenceSum << std::endl;
  RecordProperty("paper_count_bias", std::to_string(ratio - 1.0));
  EXPECT_GT(ratio, lowest);
  EXPECT_LT(ratio, highest);
  EXPECT_GT(std::abs(countedSum - referenceSum) / countedSpread, 20.0) << "the count's bias should be unmistakable";
  EXPECT_LT(std::abs(weightedSum - referenceSum) / weightedSpread, zBound);
}

TEST(PointBasedDRRPaperCount, ParallelCountIsUnbiased)
{
  // In parallel beam every weight is 1: the paper's count is the unbiased estimator, bit for bit.
  const auto volume = MakePhantom<HUVolumeType>(false);
  auto       geometry = MakeGeometry(ProjectionEnum::Parallel, 8, 6, 4.5, 5.0);
  using FilterType = itk::PointBasedDRRImageFilter<HUVolumeType, ProjectionType>;
  std::vector<double> images[2];
  for (int w = 0; w < 2; ++w)
  {
    auto drr = FilterType::New();
    drr->SetInput(volume);
    drr->SetGeometry(geometry);
    drr->SetNumberOfSamples(100000);
    drr->SetPointWeighting(w == 0 ? WeightingEnum::Unbiased : WeightingEnum::PaperCount);
    drr->Update();
    images[w] = ToVector(drr->GetOutput());
  }
  EXPECT_EQ(images[0], images[1]);
}

template <typename TOutput>
std::vector<double>
RenderWithThreads(unsigned int threads, uint64_t seed, SplatEnum splat, KernelEnum kernel, bool standardError)
{
  const auto volume = MakePhantom<HUVolumeType>(false);
  auto       drr = itk::PointBasedDRRImageFilter<HUVolumeType, TOutput>::New();
  drr->SetInput(volume);
  drr->SetGeometry(MakeGeometry(ProjectionEnum::Perspective, 8, 6, 7.0, 8.0));
  drr->SetNumberOfSamples(1000003); // 16 chunks, the last one partial
  drr->SetSeed(seed);
  drr->SetSplat(splat);
  drr->SetReconstructionKernel(kernel);
  drr->GetMultiThreader()->SetMaximumNumberOfThreads(threads);
  drr->SetNumberOfWorkUnits(threads);
  drr->Update();
  return ToVector(standardError ? drr->GetStandardErrorOutput() : drr->GetOutput());
}

TEST(PointBasedDRRReproducibility, SameSeedSameBitsOnOneTwoAndSevenThreads)
{
  for (auto splat : { SplatEnum::Nearest, SplatEnum::Bilinear })
  {
    for (bool standardError : { false, true })
    {
      const auto one = RenderWithThreads<ProjectionType>(1, 7, splat, KernelEnum::Tent, standardError);
      const auto two = RenderWithThreads<ProjectionType>(2, 7, splat, KernelEnum::Tent, standardError);
      const auto seven = RenderWithThreads<ProjectionType>(7, 7, splat, KernelEnum::Tent, standardError);
      ASSERT_EQ(one.size(), two.size());
      EXPECT_EQ(0, std::memcmp(one.data(), two.data(), one.size() * sizeof(double))) << splat;
      EXPECT_EQ(0, std::memcmp(one.data(), seven.data(), one.size() * sizeof(double))) << splat;
    }
  }
  const auto other = RenderWithThreads<ProjectionType>(2, 8, SplatEnum::Nearest, KernelEnum::Tent, false);
  EXPECT_NE(other, RenderWithThreads<ProjectionType>(2, 7, SplatEnum::Nearest, KernelEnum::Tent, false))
    << "a different seed must give a different image";
}

TEST(PointBasedDRRReproducibility, OneSlice3DOutputEquals2DOutput)
{
  const auto flat = RenderWithThreads<ProjectionType>(2, 3, SplatEnum::Nearest, KernelEnum::Box, false);
  const auto slice = RenderWithThreads<Projection3DType>(2, 3, SplatEnum::Nearest, KernelEnum::Box, false);
  EXPECT_EQ(flat, slice);
}

TEST(PointBasedDRRAccumulation, SeventeenMillionPointsInOnePixelSumExactly)
{
  // Parallel beam onto one pixel larger than the volume's shadow: every point lands, each with weight 1, so the
  // estimate is exactly M / a whatever the randomness: any loss in accumulating 2^24 + 1 points shows.
  auto volume = MakePhantom<HUVolumeType>(false);
  auto geometry = MakeGeometry(ProjectionEnum::Parallel, 1, 1, 80.0, 80.0);
  geometry->SetDetectorOffset(itk::Vector<double, 2>(0.0));
  auto drr = itk::PointBasedDRRImageFilter<HUVolumeType, ProjectionType>::New();
  drr->SetInput(volume);
  drr->SetGeometry(geometry);
  drr->SetNumberOfSamples((uint64_t{ 1 } << 24) + 1);
  drr->SetSampler(itk::DRRLevelAliasSampler::New()); // draws exactly N points (stratified rounds per stratum)
  drr->Update();
  // M from the phantom by hand: sum of mu_water (1 + HU / 1000) over voxels times the voxel volume.
  double muSum = 0.0;
  for (size_t v = 0; v < volume->GetBufferedRegion().GetNumberOfPixels(); ++v)
  {
    muSum += std::max(0.0, 0.02059 * (1.0 + volume->GetBufferPointer()[v] / 1000.0));
  }
  const double expected = muSum * 2.0 * 2.5 * 3.0 / (80.0 * 80.0);
  EXPECT_EQ(drr->GetPointsOnDetector(), (uint64_t{ 1 } << 24) + 1);
  EXPECT_NEAR(drr->GetOutput()->GetBufferPointer()[0], expected, 2e-7 * expected);
  // Every point contributed the same weight: the standard error of a constant sum is zero.
  EXPECT_NEAR(drr->GetStandardErrorOutput()->GetBufferPointer()[0], 0.0, 1e-6 * expected);
}

TEST(PointBasedDRRProgress, EventsFireDuringTheRenderOnThePipelineThread)
{
  // ITK invokes ProgressEvent observers only from the pipeline's thread: a filter whose workers alone report progress
  // shows none until it ends. Both filters must report intermediate progress.
  const auto volume = MakePhantom<HUVolumeType>(false);
  auto       geometry = MakeGeometry(ProjectionEnum::Perspective, 64, 48, 0.9, 1.0);
  auto       pointBased = itk::PointBasedDRRImageFilter<HUVolumeType, ProjectionType>::New();
  pointBased->SetNumberOfSamples(20000000);
  auto exact = itk::ExactDRRImageFilter<HUVolumeType, ProjectionType>::New();
  exact->SetRaysPerPixelSide(4);
  for (itk::DRRImageFilterBase<HUVolumeType, ProjectionType> * filter :
       { static_cast<itk::DRRImageFilterBase<HUVolumeType, ProjectionType> *>(pointBased.GetPointer()),
         static_cast<itk::DRRImageFilterBase<HUVolumeType, ProjectionType> *>(exact.GetPointer()) })
  {
    filter->SetInput(volume);
    filter->SetGeometry(geometry);
    std::vector<float> seen;
    auto               command = itk::CStyleCommand::New();
    command->SetClientData(&seen);
    command->SetCallback([](itk::Object * caller, const itk::EventObject &, void * data) {
      static_cast<std::vector<float> *>(data)->push_back(static_cast<itk::ProcessObject *>(caller)->GetProgress());
    });
    filter->AddObserver(itk::ProgressEvent(), command);
    filter->Update();
    const auto intermediate = std::count_if(seen.begin(), seen.end(), [](float p) { return p > 0.0f && p < 1.0f; });
    EXPECT_GE(intermediate, 10) << filter->GetNameOfClass() << ": " << ::testing::PrintToString(seen);
    EXPECT_TRUE(std::is_sorted(seen.begin(), seen.end())) << filter->GetNameOfClass();
    ASSERT_FALSE(seen.empty());
    EXPECT_EQ(seen.back(), 1.0f);
  }
}

// The settings' rules are checked once, in VerifyPreconditions(), which ITK's pipeline calls before any output
// information or data: UpdateOutputInformation() alone refuses them, before a voxel is read. Refine() applies the same
// rules to its own number of samples.
TEST(PointBasedDRRImageFilter, SettingsAreRefusedByVerifyPreconditionsBeforeTheRender)
{
  using FilterType = itk::PointBasedDRRImageFilter<HUVolumeType, ProjectionType>;
  const auto volume = MakePhantom<HUVolumeType>(false);
  const std::vector<std::pair<std::string, std::function<void(FilterType *)>>> wrong{
    { "zero samples", [](FilterType * f) { f->SetNumberOfSamples(0); } },
    { "one stratum", [](FilterType * f) { f->SetNumberOfStrata(1); } },
    { "factor 1", [](FilterType * f) { f->SetControlVariateFactor(1); } },
    { "control variate with the tent kernel",
      [](FilterType * f) {
        f->SetControlVariateFactor(2);
        f->SetReconstructionKernel(itk::PointBasedDRREnums::ReconstructionKernel::Tent);
      } },
  };
  for (const auto & setting : wrong)
  {
    auto drr = FilterType::New();
    drr->SetInput(volume);
    drr->SetGeometry(MakeGeometry(ProjectionEnum::Perspective, 8, 6, 7.0, 8.0));
    setting.second(drr);
    EXPECT_THROW(drr->UpdateOutputInformation(), itk::ExceptionObject) << setting.first;
  }
  auto drr = FilterType::New();
  drr->SetInput(volume);
  drr->SetGeometry(MakeGeometry(ProjectionEnum::Perspective, 8, 6, 7.0, 8.0));
  drr->SetNumberOfSamples(10000);
  drr->Update();
  EXPECT_THROW(drr->Refine(0), itk::ExceptionObject) << "Refine() with no samples";
  EXPECT_EQ(drr->GetTotalNumberOfSamples(), 10000u) << "a refused Refine() adds nothing";
}

TEST(PointBasedDRRRefine, IsReproducibleCountsItsPointsAndRefusesStaleSettings)
{
  const auto volume = MakePhantom<HUVolumeType>(false);
  auto       render = [&](unsigned int threads) {
    auto drr = itk::PointBasedDRRImageFilter<HUVolumeType, ProjectionType>::New();
    drr->SetInput(volume);
    drr->SetGeometry(MakeGeometry(ProjectionEnum::Perspective, 8, 6, 7.0, 8.0));
    drr->SetNumberOfSamples(100000);
    drr->SetNumberOfWorkUnits(threads);
    drr->Update();
    drr->Refine(70000);
    EXPECT_EQ(drr->GetTotalNumberOfSamples(), 170000u);
    return std::make_pair(ToVector(drr->GetOutput()), ToVector(drr->GetStandardErrorOutput()));
  };
  EXPECT_EQ(render(1), render(3));

  auto drr = itk::PointBasedDRRImageFilter<HUVolumeType, ProjectionType>::New();
  drr->SetInput(volume);
  drr->SetGeometry(MakeGeometry(ProjectionEnum::Perspective, 8, 6, 7.0, 8.0));
  EXPECT_THROW(drr->Refine(1000), itk::ExceptionObject) << "nothing rendered yet";
  drr->Update();
  const auto before = ToVector(drr->GetStandardErrorOutput());
  drr->Refine(3 * drr->GetNumberOfSamples());
  const auto after = ToVector(drr->GetStandardErrorOutput());
  // Four times the points: half the standard error (within the noise of the estimates themselves).
  const double ratio =
    std::accumulate(after.begin(), after.end(), 0.0) / std::accumulate(before.begin(), before.end(), 0.0);
  EXPECT_NEAR(ratio, 0.5, 0.05);
  drr->GetGeometry()->SetGantryAngleInDegrees(31.0);
  EXPECT_THROW(drr->Refine(1000), itk::ExceptionObject) << "the geometry changed since Update()";
}

TEST(PointBasedDRRRandom, PhiloxMatchesRandom123KnownAnswers)
{
  // Known-answer vectors of Philox4x32-10 from the Random123 distribution (kat_vectors).
  using R = itk::detail::DRRPhiloxRandom;
  EXPECT_EQ(R::Philox({ { 0, 0, 0, 0 } }, { { 0, 0 } }),
            (R::BlockType{ { 0x6627e8d5u, 0xe169c58du, 0xbc57ac4cu, 0x9b00dbd8u } }));
  EXPECT_EQ(R::Philox({ { 0xffffffffu, 0xffffffffu, 0xffffffffu, 0xffffffffu } }, { { 0xffffffffu, 0xffffffffu } }),
            (R::BlockType{ { 0x408f276du, 0x41c83b0eu, 0xa20bc7c6u, 0x6d5451fdu } }));
  EXPECT_EQ(R::Philox({ { 0x243f6a88u, 0x85a308d3u, 0x13198a2eu, 0x03707344u } }, { { 0xa4093822u, 0x299f31d0u } }),
            (R::BlockType{ { 0xd16cfe09u, 0x94fdccebu, 0x5001e420u, 0x24126ea1u } }));
}
/** 40 x 24 x 24 voxels of 1 mm (5 x 3 x 3 bricks of 8^3), centred on the origin: HU blocks of 4^3 voxels, a fifth
 * of them air. */
HUVolumeType::Pointer
MakeBrickPhantom()
{
  HUVolumeType::SizeType    size = { { 40, 24, 24 } };
  HUVolumeType::SpacingType spacing(1.0);
  HUVolumeType::PointType   origin;
  for (unsigned int a = 0; a < 3; ++a)
  {
    origin[a] = -0.5 * (size[a] - 1.0);
  }
  HUVolumeType::DirectionType direction;
  direction.SetIdentity();
  auto         volume = MakeVolume<HUVolumeType>(size, spacing, origin, direction);
  const short  levels[5] = { -1000, -500, 0, 300, 1200 };
  unsigned int state = 777u;
  for (itk::IndexValueType z = 0; z < 24; z += 4)
  {
    for (itk::IndexValueType y = 0; y < 24; y += 4)
    {
      for (itk::IndexValueType x = 0; x < 40; x += 4)
      {
        state = state * 1664525u + 1013904223u;
        FillBlock(volume.GetPointer(), { { x, y, z } }, { { x + 3, y + 3, z + 3 } }, levels[(state >> 8) % 5]);
      }
    }
  }
  return volume;
}

/** A 5 x 4 detector of 2 mm pixels that sees about a quarter of the brick phantom's shadow (gantry 0: rays along y). */
itk::DRRProjectionGeometry::Pointer
MakeCollimatedGeometry(ProjectionEnum projection)
{
  auto geometry = itk::DRRProjectionGeometry::New();
  geometry->SetProjection(projection);
  geometry->SetSourceToIsocenterDistance(100.0);
  geometry->SetSourceToDetectorDistance(180.0);
  geometry->SetGantryAngleInDegrees(0.0);
  geometry->SetDetectorSize({ { 5, 4 } });
  geometry->SetDetectorSpacing(itk::Vector<double, 2>(2.0));
  itk::Vector<double, 2> offset;
  offset[0] = 12.0; // mm on the detector: well off the centre, towards one end of the long (x) axis
  offset[1] = 6.0;
  geometry->SetDetectorOffset(offset);
  return geometry;
}

/** The stratified sampler samples only the bricks that can reach a collimated detector (sparse and dense walks,
 * both kernels, both beams) and stays unbiased: the mean of 64 seeds matches the exact pixel-area average within the
 * z bound, and the standard-error output predicts the spread. */
TEST(PointBasedDRRStratified, CullsToACollimatedViewAndStaysUnbiased)
{
  const auto volume = MakeBrickPhantom();
  for (auto projection : { ProjectionEnum::Parallel, ProjectionEnum::Perspective })
  {
    const auto geometry = MakeCollimatedGeometry(projection);
    for (auto kernel : { KernelEnum::Box, KernelEnum::Tent })
    {
      // Exact pixel averages: Richardson from 32^2 and 16^2 rays per pixel, its correction as the reference's error.
      std::vector<double> images[2];
      for (unsigned int level = 0; level < 2; ++level)
      {
        auto exact = itk::ExactDRRImageFilter<HUVolumeType, ProjectionType>::New();
        exact->SetInput(volume);
        exact->SetGeometry(geometry);
        exact->SetReconstructionKernel(kernel);
        exact->SetRaysPerPixelSide(level == 0 ? 32 : 16);
        exact->Update();
        images[level] = ToVector(exact->GetOutput());
      }
      for (uint64_t samples : { 2000, 200000 }) // below and above half the voxels in view: sparse and dense walks
      {
        std::ostringstream context;
        context << projection << "/" << kernel << "/" << samples << " samples";
        auto sampler = itk::DRRStratifiedSampler::New();
        auto drr = itk::PointBasedDRRImageFilter<HUVolumeType, ProjectionType>::New();
        drr->SetInput(volume);
        drr->SetGeometry(geometry);
        drr->SetReconstructionKernel(kernel);
        drr->SetSampler(sampler);
        drr->SetNumberOfSamples(samples);
        const unsigned int  seeds = 64;
        const size_t        pixels = images[0].size();
        std::vector<double> sum(pixels, 0.0), sumOfSquares(pixels, 0.0), predicted(pixels, 0.0);
        for (unsigned int seed = 0; seed < seeds; ++seed)
        {
          drr->SetSeed(seed);
          drr->Update();
          const auto values = ToVector(drr->GetOutput());
          const auto errors = ToVector(drr->GetStandardErrorOutput());
          for (size_t p = 0; p < pixels; ++p)
          {
            sum[p] += values[p];
            sumOfSquares[p] += values[p] * values[p];
            predicted[p] += errors[p] * errors[p] / seeds;
          }
        }
        // The plan the renders drew from (the filter's view, its kernel, the default nearest splat).
        const itk::DRRPointProjection projection(*geometry,
                                                 *drr->GetAttenuationVolume(),
                                                 itk::DRRPointProjection::MatrixType::GetIdentity(),
                                                 itk::DRRPointProjection::VectorType(0.0));
        const auto                    plan =
          sampler->MakeViewPlan(*drr->GetAttenuationVolume(),
                                &projection,
                                kernel == KernelEnum::Box ? itk::DRRBoxKernel::Reach : itk::DRRTentKernel::Reach,
                                itk::DRRNearestSplat::Reach);
        EXPECT_GT(sampler->GetNumberOfBricksInView(*plan), 0u) << context.str();
        EXPECT_LT(sampler->GetNumberOfBricksInView(*plan), sampler->GetNumberOfBricks() / 2) << context.str();
        EXPECT_LT(plan->GetSampledMass(), 0.6 * sampler->GetTotalMass()) << context.str();
        double worstZ = 0.0, observedVariance = 0.0, predictedVariance = 0.0;
        for (size_t p = 0; p < pixels; ++p)
        {
          const double reference = images[0][p] + (images[0][p] - images[1][p]) / 3.0;
          const double referenceError = std::abs(images[0][p] - images[1][p]) / 3.0;
          const double mean = sum[p] / seeds;
          const double variance = (sumOfSquares[p] - seeds * mean * mean) / (seeds - 1.0);
          if (reference == 0.0)
          {
            EXPECT_EQ(mean, 0.0) << context.str() << " pixel " << p << " sees only air";
            continue;
          }
          ASSERT_GT(variance, 0.0) << context.str() << " pixel " << p;
          const double z = std::abs(mean - reference) / std::sqrt(variance / seeds + referenceError * referenceError);
          worstZ = std::max(worstZ, z);
          observedVariance += variance;
          predictedVariance += predicted[p];
        }
        EXPECT_LT(worstZ, zBound) << context.str() << ": the mean over seeds is off the exact reference";
        // Pooled over pixels, with a quarter of them counted as independent (a systematic sample couples neighbours).
        EXPECT_NEAR(observedVariance / predictedVariance, 1.0, zBound * std::sqrt(2.0 / ((seeds - 1.0) * pixels / 4.0)))
          << context.str() << ": the standard-error output does not predict the spread";
      }
    }
  }
}

/** The merged walk of interleaved strata and the culled view are the same bit for bit on 1, 2 and 7 threads. */
TEST(PointBasedDRRStratified, SameSeedSameBitsOnOneTwoAndSevenThreads)
{
  const auto volume = MakeBrickPhantom();
  for (uint64_t samples : { 3001, 1000003 }) // sparse and dense; several chunks, the last one partial
  {
    std::vector<double> images[3];
    const unsigned int  threads[3] = { 1, 2, 7 };
    for (unsigned int t = 0; t < 3; ++t)
    {
      auto drr = itk::PointBasedDRRImageFilter<HUVolumeType, ProjectionType>::New();
      drr->SetInput(volume);
      drr->SetGeometry(MakeCollimatedGeometry(ProjectionEnum::Perspective));
      drr->SetSampler(itk::DRRStratifiedSampler::New());
      drr->SetSplat(SplatEnum::Bilinear);
      drr->SetNumberOfSamples(samples);
      drr->SetSeed(5);
      drr->GetMultiThreader()->SetMaximumNumberOfThreads(threads[t]);
      drr->SetNumberOfWorkUnits(threads[t]);
      drr->Update();
      images[t] = ToVector(drr->GetOutput());
      const auto errors = ToVector(drr->GetStandardErrorOutput());
      images[t].insert(images[t].end(), errors.begin(), errors.end());
    }
    EXPECT_EQ(images[0], images[1]) << samples;
    EXPECT_EQ(images[0], images[2]) << samples;
  }
}

/** Re-projecting kept points equals, bit for bit, a fresh filter drawing the same points at that pose (both
 * outputs, any thread count), draws once across poses, and draws again when the seed changes. */
TEST(PointBasedDRRReuse, CachedReprojectionEqualsAFreshRenderWithTheSameSeed)
{
  const auto volume = MakePhantom<MuVolumeType>(true); // mu input: weights are kept too
  using FilterType = itk::PointBasedDRRImageFilter<MuVolumeType, ProjectionType>;
  const auto render = [&](FilterType * drr, itk::DRRProjectionGeometry * geometry, const AffineType * transform) {
    drr->SetGeometry(geometry);
    drr->SetTransform(transform);
    drr->Update();
    auto       image = ToVector(drr->GetOutput());
    const auto errors = ToVector(drr->GetStandardErrorOutput());
    image.insert(image.end(), errors.begin(), errors.end());
    return image;
  };
  for (const char * sampler : { "level-alias", "stratified", "metropolis" })
  {
    for (auto splat : { SplatEnum::Nearest, SplatEnum::Bilinear })
    {
      const auto make = [&](unsigned int threads) {
        auto drr = FilterType::New();
        drr->SetInput(volume);
        drr->GetTransferFunction()->SetMode(itk::PointBasedDRREnums::TransferFunction::Identity);
        drr->SetSampler(itk::DRRSamplerFactory::Create(sampler));
        drr->SetSplat(splat);
        drr->SetReconstructionKernel(KernelEnum::Tent);
        drr->SetNumberOfSamples(300007); // several chunks, the last one partial
        drr->SetSeed(11);
        drr->SetReusePoints(true);
        drr->GetMultiThreader()->SetMaximumNumberOfThreads(threads);
        drr->SetNumberOfWorkUnits(threads);
        return drr;
      };
      auto firstPose = MakeGeometry(ProjectionEnum::Perspective, 8, 6, 7.0, 8.0);
      auto secondPose = MakeGeometry(ProjectionEnum::Perspective, 9, 7, 6.0, 6.5);
      secondPose->SetGantryAngleInDegrees(75.0);
      const auto transform = MakeAffine();

      auto       kept = make(1);
      const auto atFirst = render(kept, firstPose, nullptr);
      const auto reprojected = render(kept, secondPose, transform);
      EXPECT_EQ(kept->GetNumberOfPointCloudDraws(), 1u) << sampler << ": a pose change must not draw again";
      ASSERT_NE(kept->GetPointCloud(), nullptr);
      EXPECT_GE(kept->GetPointCloud()->GetNumberOfPoints(), 300007u); // R ceil(N / R) for interleaved strata
      EXPECT_LE(kept->GetPointCloud()->GetBytesPerPoint(), 17.0);

      auto fresh = make(3);
      EXPECT_EQ(reprojected, render(fresh, secondPose, transform)) << sampler << "/" << splat;
      EXPECT_NE(atFirst, reprojected);

      kept->SetSeed(12);
      const auto otherSeed = render(kept, secondPose, transform);
      EXPECT_EQ(kept->GetNumberOfPointCloudDraws(), 2u) << sampler << ": a new seed must draw new points";
      EXPECT_NE(otherSeed, reprojected);
    }
  }
}

// The preprocessing stage is a process object of ITK's pipeline: shared by a point-based and an exact filter, it runs
// once; a change of the pose does not run it; its input's buffer modified in place and Modified() runs it again, and
// both filters render the new volume, as filters of their own would.
TEST(DRRImageToAttenuationVolumeFilter, RunsOnceForTheFiltersSharingItAndAgainWhenItsInputIsModified)
{
  const auto volume = MakePhantom<HUVolumeType>(false);
  using StageType = itk::DRRImageToAttenuationVolumeFilter<HUVolumeType>;
  using PointType = itk::PointBasedDRRImageFilter<HUVolumeType, ProjectionType>;
  using ExactType = itk::ExactDRRImageFilter<HUVolumeType, ProjectionType>;
  auto         stage = StageType::New();
  unsigned int runs = 0;
  auto         counter = itk::CStyleCommand::New();
  counter->SetClientData(&runs);
  counter->SetCallback(
    [](itk::Object *, const itk::EventObject &, void * count) { ++*static_cast<unsigned int *>(count); });
  stage->AddObserver(itk::StartEvent(), counter);
  stage->SetInput(volume);
  const auto geometry = MakeGeometry(ProjectionEnum::Perspective, 8, 6, 7.0, 8.0);
  const auto configure = [&](auto * filter, bool shared) {
    filter->SetGeometry(geometry);
    if (shared)
    {
      filter->SetAttenuationVolume(stage->GetOutput());
    }
    else
    {
      filter->SetInput(volume);
    }
  };
  const auto makePoint = [&](bool shared) {
    auto drr = PointType::New();
    configure(drr.GetPointer(), shared);
    drr->SetNumberOfSamples(20000);
    drr->SetSeed(5);
    return drr;
  };
  const auto makeExact = [&](bool shared) {
    auto exact = ExactType::New();
    configure(exact.GetPointer(), shared);
    return exact;
  };
  const auto imageOf = [](itk::ProcessObject * filter, ProjectionType * output) {
    filter->Update();
    return ToVector(output);
  };
  auto       points = makePoint(true);
  auto       exact = makeExact(true);
  const auto pointImage = imageOf(points, points->GetOutput());
  const auto exactImage = imageOf(exact, exact->GetOutput());
  EXPECT_EQ(runs, 1u) << "two filters sharing the stage";
  auto ownPoints = makePoint(false);
  auto ownExact = makeExact(false);
  EXPECT_EQ(pointImage, imageOf(ownPoints, ownPoints->GetOutput())) << "a shared model renders as a filter's own";
  EXPECT_EQ(exactImage, imageOf(ownExact, ownExact->GetOutput()));

  geometry->SetGantryAngleInDegrees(40.0);
  const auto turnedImage = imageOf(points, points->GetOutput());
  const auto turnedExact = imageOf(exact, exact->GetOutput());
  EXPECT_EQ(runs, 1u) << "a new pose is not a new model";
  EXPECT_NE(turnedImage, pointImage);

  // The CT edited in place: its pixel container is the same, only its modified time says it changed.
  FillBlock(volume.GetPointer(), { { 1, 1, 1 } }, { { 4, 5, 3 } }, 1500);
  volume->Modified();
  const auto editedPoints = imageOf(points, points->GetOutput());
  const auto editedExact = imageOf(exact, exact->GetOutput());
  EXPECT_EQ(runs, 2u) << "the modified input runs the stage once for both filters";
  auto freshPoints = makePoint(false);
  auto freshExact = makeExact(false);
  EXPECT_EQ(editedPoints, imageOf(freshPoints, freshPoints->GetOutput())) << "the shared filter saw the edit";
  EXPECT_EQ(editedExact, imageOf(freshExact, freshExact->GetOutput()));
  EXPECT_NE(editedPoints, turnedImage);
  EXPECT_NE(editedExact, turnedExact);
}

// A filter's own stage sees what the hand-made keys saw: its input's buffer modified in place (and Modified()), and
// its transfer function changed in place, each re-render; a filter given a shared model refuses a volume or labels
// of its own.
TEST(DRRImageToAttenuationVolumeFilter, AFiltersOwnStageRebuildsForAnEditedInputOrTransferFunction)
{
  const auto volume = MakePhantom<HUVolumeType>(false);
  using PointType = itk::PointBasedDRRImageFilter<HUVolumeType, ProjectionType>;
  const auto geometry = MakeGeometry(ProjectionEnum::Perspective, 8, 6, 7.0, 8.0);
  const auto make = [&](const HUVolumeType * input, double energyInKeV) {
    auto drr = PointType::New();
    drr->SetInput(input);
    drr->SetGeometry(geometry);
    drr->GetTransferFunction()->SetEffectiveEnergyInKeV(energyInKeV);
    drr->SetNumberOfSamples(20000);
    drr->SetSeed(9);
    drr->Update();
    return drr;
  };
  auto       drr = make(volume, 60.0);
  const auto before = ToVector(drr->GetOutput());

  drr->GetTransferFunction()->SetEffectiveEnergyInKeV(100.0);
  drr->Update();
  const auto at100 = ToVector(drr->GetOutput());
  EXPECT_NE(at100, before) << "the transfer function changed in place";
  EXPECT_EQ(at100, ToVector(make(volume, 100.0)->GetOutput()));

  FillBlock(volume.GetPointer(), { { 0, 0, 0 } }, { { 5, 6, 2 } }, -1000);
  volume->Modified();
  drr->Update();
  const auto edited = ToVector(drr->GetOutput());
  EXPECT_NE(edited, at100) << "the input edited in place";
  EXPECT_EQ(edited, ToVector(make(volume, 100.0)->GetOutput()));

  auto stage = itk::DRRImageToAttenuationVolumeFilter<HUVolumeType>::New();
  stage->SetInput(volume);
  drr->SetAttenuationVolume(stage->GetOutput());
  EXPECT_TRUE(Contains(ExceptionMessage([&] { drr->Update(); }, "both"), "give one"));
  drr->SetInput(nullptr);
  drr->SetLabelChannels(true);
  EXPECT_TRUE(Contains(ExceptionMessage([&] { drr->Update(); }, "labels"), "belong to the shared"));
  drr->SetLabelChannels(false);
  EXPECT_NO_THROW(drr->Update());
  EXPECT_EQ(ToVector(drr->GetOutput()), ToVector(make(volume, 60.0)->GetOutput())) << "the stage's own 60 keV";
  drr->SetAttenuationVolume(nullptr);
  EXPECT_TRUE(Contains(ExceptionMessage([&] { drr->Update(); }, "nothing"), "no input volume"));
}

// A sampler replaced by another of the same type, made before the first render (so older than everything the filter
// made), is initialized and draws the kept points again; the image is the same as the first sampler's.
TEST(PointBasedDRRReuse, ASamplerReplacedByAnotherOfTheSameTypeIsInitializedAndDrawsAgain)
{
  const auto volume = MakePhantom<HUVolumeType>(false);
  using PointType = itk::PointBasedDRRImageFilter<HUVolumeType, ProjectionType>;
  for (const char * name : { "stratified", "level-alias" })
  {
    auto first = itk::DRRSamplerFactory::Create(name);
    auto second = itk::DRRSamplerFactory::Create(name);
    auto drr = PointType::New();
    drr->SetInput(volume);
    drr->SetGeometry(MakeGeometry(ProjectionEnum::Perspective, 8, 6, 7.0, 8.0));
    drr->SetNumberOfSamples(20000);
    drr->SetReusePoints(true);
    drr->SetSampler(first);
    drr->Update();
    const auto image = ToVector(drr->GetOutput());
    ASSERT_GT(first->GetTotalMass(), 0.0);
    drr->SetSampler(second);
    drr->Update();
    EXPECT_EQ(second->GetTotalMass(), first->GetTotalMass()) << name << ": the new sampler was initialized";
    EXPECT_EQ(drr->GetNumberOfPointCloudDraws(), 2u) << name << ": its points were drawn";
    EXPECT_EQ(ToVector(drr->GetOutput()), image) << name;
  }
}

// A sampler's own setting changed in place (the level sampler's bins of a continuous volume) makes its tables, and the
// kept points, anew: the image is that of a fresh filter whose sampler had the setting from the start.
TEST(PointBasedDRRReuse, ASamplerSettingChangedInPlaceRemakesItsTables)
{
  const auto volume = MakePhantom<MuVolumeType>(true);
  using PointType = itk::PointBasedDRRImageFilter<MuVolumeType, ProjectionType>;
  const auto make = [&](itk::DRRLevelSampler * sampler, bool reuse) {
    auto drr = PointType::New();
    drr->SetInput(volume);
    drr->GetTransferFunction()->SetMode(itk::PointBasedDRREnums::TransferFunction::Identity);
    drr->SetGeometry(MakeGeometry(ProjectionEnum::Perspective, 8, 6, 7.0, 8.0));
    drr->SetNumberOfSamples(20000);
    drr->SetReusePoints(reuse);
    drr->SetSampler(sampler);
    return drr;
  };
  for (const bool reuse : { false, true })
  {
    auto sampler = itk::DRRLevelAliasSampler::New();
    auto drr = make(sampler, reuse);
    drr->Update();
    const auto manyBins = ToVector(drr->GetOutput());
    sampler->SetNumberOfBins(3);
    drr->Update();
    auto fresh = itk::DRRLevelAliasSampler::New();
    fresh->SetNumberOfBins(3);
    auto freshFilter = make(fresh, reuse);
    freshFilter->Update();
    EXPECT_EQ(sampler->GetNumberOfLevels(), fresh->GetNumberOfLevels()) << "reuse " << reuse;
    EXPECT_EQ(ToVector(drr->GetOutput()), ToVector(freshFilter->GetOutput())) << "reuse " << reuse;
    EXPECT_NE(ToVector(drr->GetOutput()), manyBins) << "reuse " << reuse << ": 3 bins draw other points";
  }
}

/** A stand-in for a streaming reader of a CT (PointBasedDRRTestHelpers.h). */
using RegionRecordingSource = RecordingSource<HUVolumeType>;

// Streaming (issue 30): the exact filter reads the volume from its pipeline in slabs of whole z planes, each requested
// once and modelled alone, and the slabs' projections sum to the whole volume's to rounding, for any number of slabs,
// from a streaming source or an image in memory.
TEST(ExactDRRImageFilter, StreamedSlabsOfThePipelineSumToTheWholeVolumesProjection)
{
  const auto volume = MakePhantom<HUVolumeType>(false); // 6 x 7 x 5, rotated, random HU levels
  using ExactType = itk::ExactDRRImageFilter<HUVolumeType, ProjectionType>;
  const auto planes = volume->GetLargestPossibleRegion().GetSize()[2];
  for (const auto projection : { ProjectionEnum::Perspective, ProjectionEnum::Parallel })
  {
    auto geometry = MakeGeometry(projection, 9, 7, 3.0, 3.5);
    geometry->SetGantryAngleInDegrees(35.0);
    const auto render = [&](const HUVolumeType * input, unsigned int slabs) {
      auto exact = ExactType::New();
      exact->SetInput(input);
      exact->SetGeometry(geometry);
      exact->SetRaysPerPixelSide(2);
      exact->SetNumberOfStreamDivisions(slabs);
      exact->Update();
      return ToVector(exact->GetOutput());
    };
    const auto   whole = render(volume, 1);
    const double largest = *std::max_element(whole.begin(), whole.end());
    ASSERT_GT(largest, 0.1);
    for (const unsigned int slabs : { 2u, 3u, 5u, 9u })
    {
      auto source = RegionRecordingSource::New();
      source->Image = volume;
      for (const auto & streamed : { render(source->GetOutput(), slabs), render(volume, slabs) })
      {
        ASSERT_EQ(streamed.size(), whole.size());
        for (size_t p = 0; p < whole.size(); ++p)
        {
          EXPECT_NEAR(streamed[p], whole[p], 1e-6 * largest) << projection << ", " << slabs << " slabs, pixel " << p;
        }
      }
      // Every plane once, in consecutive slabs of whole planes.
      ASSERT_EQ(source->Requests.size(), std::min<size_t>(slabs, planes)) << slabs << " slabs";
      itk::IndexValueType next = 0;
      for (const auto & request : source->Requests)
      {
        EXPECT_EQ(request.GetIndex()[2], next);
        EXPECT_EQ(request.GetSize()[0], 6u);
        EXPECT_EQ(request.GetSize()[1], 7u);
        next += static_cast<itk::IndexValueType>(request.GetSize()[2]);
      }
      EXPECT_EQ(next, static_cast<itk::IndexValueType>(planes));
    }
  }
  auto tent = ExactType::New();
  tent->SetInput(volume);
  tent->SetNumberOfStreamDivisions(2);
  tent->SetReconstructionKernel(KernelEnum::Tent);
  EXPECT_TRUE(Contains(ExceptionMessage([&] { tent->Update(); }, "streamed tent"), "needs the box kernel"));
}

/** A CT-like volume several brick planes deep (19 x 17 x 45 voxels, rotated, anisotropic): an ellipsoid of random HU
 * levels in air, so that some bricks are empty and a collimated view culls others. */
HUVolumeType::Pointer
MakeDeepPhantom()
{
  HUVolumeType::SizeType    size = { { 19, 17, 45 } };
  HUVolumeType::SpacingType spacing;
  spacing[0] = 1.0;
  spacing[1] = 1.2;
  spacing[2] = 0.8;
  HUVolumeType::PointType origin;
  origin[0] = -9.0;
  origin[1] = -11.0;
  origin[2] = -17.0;
  itk::Vector<double, 3> axis;
  axis[0] = 2.0 / 3.0;
  axis[1] = 1.0 / 3.0;
  axis[2] = 2.0 / 3.0;
  auto         volume = MakeVolume<HUVolumeType>(size, spacing, origin, RotationMatrix(axis, 20.0));
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

// Streaming (issue 30): the point-based filter reads the volume from its pipeline slab by slab and draws each slab's
// share of the stratified sampler's points, the same points as the whole volume's render: the same image and standard
// error, bit for bit, for any number of slabs, with and without the control variate, dense and sparse walks, a full and
// a collimated (culled) view, from a streaming source or an image in memory.
TEST(PointBasedDRRImageFilter, StreamedSlabsDrawTheWholeVolumesPointsBitForBit)
{
  using PointType = itk::PointBasedDRRImageFilter<HUVolumeType, ProjectionType>;
  const auto volume = MakeDeepPhantom();
  const auto planes = volume->GetLargestPossibleRegion().GetSize()[2];
  for (const auto projection : { ProjectionEnum::Perspective, ProjectionEnum::Parallel })
  {
    for (const bool collimated : { false, true })
    {
      auto geometry = MakeGeometry(projection, collimated ? 9 : 34, collimated ? 7 : 30, 1.3, 1.1);
      geometry->SetSourceToIsocenterDistance(300.0);
      geometry->SetSourceToDetectorDistance(500.0);
      for (const unsigned int factor : { 0u, 2u, 16u, PointType::AutomaticControlVariateFactor })
      {
        for (const uint64_t samples : { uint64_t{ 3000 }, uint64_t{ 400000 } })
        {
          const auto render = [&](const HUVolumeType * input, unsigned int slabs) {
            auto drr = PointType::New();
            drr->SetInput(input);
            drr->SetGeometry(geometry);
            drr->SetNumberOfSamples(samples);
            drr->SetSeed(11);
            drr->SetControlVariateFactor(factor);
            drr->SetNumberOfStreamDivisions(slabs);
            drr->Update();
            return std::make_pair(ToVector(drr->GetOutput()), ToVector(drr->GetStandardErrorOutput()));
          };
          const auto whole = render(volume, 1);
          ASSERT_GT(*std::max_element(whole.first.begin(), whole.first.end()), 0.1);
          for (const unsigned int slabs : { 2u, 3u, 6u })
          {
            auto source = RegionRecordingSource::New();
            source->Image = volume;
            const std::string what = "F " + std::to_string(factor) + ", " + std::to_string(samples) + " samples, " +
                                     std::to_string(slabs) + " slabs" + (collimated ? ", collimated" : "");
            for (const auto & streamed : { render(source->GetOutput(), slabs), render(volume, slabs) })
            {
              ASSERT_EQ(streamed.first.size(), whole.first.size());
              for (size_t p = 0; p < whole.first.size(); ++p)
              {
                ASSERT_EQ(streamed.first[p], whole.first[p]) << projection << ", " << what << ", pixel " << p;
                ASSERT_EQ(streamed.second[p], whole.second[p]) << projection << ", " << what << ", pixel " << p;
              }
            }
            // Passes over consecutive slabs of whole brick planes (and coarse blocks): the first over every plane
            // (the masses along the curve), the last over the slabs in view (an `auto` control variate declined
            // makes one more first pass).
            std::ostringstream requests;
            for (const auto & request : source->Requests)
            {
              requests << request.GetIndex()[2] << "+" << request.GetSize()[2] << " ";
            }
            const size_t        alignment = factor == 16 ? 16 : 8;
            const size_t        slabsMade = std::min<size_t>(slabs, (planes + alignment - 1) / alignment);
            itk::IndexValueType next = 0;
            for (const auto & request : source->Requests)
            {
              const itk::IndexValueType first = request.GetIndex()[2];
              EXPECT_EQ(first % static_cast<itk::IndexValueType>(alignment), 0) << what << ": " << requests.str();
              EXPECT_TRUE(first == next || first == 0) << what << ": " << requests.str();
              next = first + static_cast<itk::IndexValueType>(request.GetSize()[2]);
            }
            ASSERT_GE(source->Requests.size(), slabsMade + 1) << what << ": " << requests.str();
            const auto & lastOfFirstPass = source->Requests[slabsMade - 1];
            EXPECT_EQ(lastOfFirstPass.GetIndex()[2] + static_cast<itk::IndexValueType>(lastOfFirstPass.GetSize()[2]),
                      static_cast<itk::IndexValueType>(planes))
              << what << ": " << requests.str();
          }
        }
      }
    }
  }
}

// Streaming with kept points (batches, registration): the points of the whole volume are drawn slab by slab at the
// first pose and re-projected at every later one without reading the volume again; at every pose the image is the
// unstreamed filter's, bit for bit.
TEST(PointBasedDRRImageFilter, StreamedKeptPointsAreTheWholeVolumesAtEveryPose)
{
  using PointType = itk::PointBasedDRRImageFilter<HUVolumeType, ProjectionType>;
  const auto volume = MakeDeepPhantom();
  for (const unsigned int factor : { 0u, 4u, PointType::AutomaticControlVariateFactor })
  {
    auto source = RegionRecordingSource::New();
    source->Image = volume;
    const auto make = [&](const HUVolumeType * input, unsigned int slabs, itk::DRRProjectionGeometry * geometry) {
      auto drr = PointType::New();
      drr->SetInput(input);
      drr->SetGeometry(geometry);
      drr->SetNumberOfSamples(200000);
      drr->SetSeed(5);
      drr->SetControlVariateFactor(factor);
      drr->SetReusePoints(true);
      drr->SetExpectedNumberOfPoses(3);
      drr->SetNumberOfStreamDivisions(slabs);
      return drr;
    };
    auto       wholeGeometry = MakeGeometry(ProjectionEnum::Perspective, 30, 26, 1.3, 1.1);
    auto       streamedGeometry = MakeGeometry(ProjectionEnum::Perspective, 30, 26, 1.3, 1.1);
    const auto whole = make(volume, 1, wholeGeometry);
    const auto streamed = make(source->GetOutput(), 3, streamedGeometry);
    size_t     readsAtFirstPose = 0;
    for (const double gantry : { 10.0, 55.0, 130.0 })
    {
      wholeGeometry->SetGantryAngleInDegrees(gantry);
      streamedGeometry->SetGantryAngleInDegrees(gantry);
      whole->Update();
      streamed->Update();
      const auto expected = ToVector(whole->GetOutput());
      const auto actual = ToVector(streamed->GetOutput());
      ASSERT_GT(*std::max_element(expected.begin(), expected.end()), 0.1);
      ASSERT_EQ(actual.size(), expected.size());
      for (size_t p = 0; p < expected.size(); ++p)
      {
        ASSERT_EQ(actual[p], expected[p]) << "F " << factor << ", gantry " << gantry << ", pixel " << p;
      }
      readsAtFirstPose = readsAtFirstPose == 0 ? source->Requests.size() : readsAtFirstPose;
      EXPECT_EQ(source->Requests.size(), readsAtFirstPose)
        << "F " << factor << ": the volume read again at " << gantry << " degrees";
    }
    EXPECT_GE(readsAtFirstPose, 3u);
    EXPECT_EQ(streamed->GetNumberOfPointCloudDraws(), 1u);
  }
}

// What streaming cannot share out is refused by name: samplers that draw from tables of the whole volume.
TEST(PointBasedDRRImageFilter, StreamingRefusesWhatItCannotShareOut)
{
  using PointType = itk::PointBasedDRRImageFilter<HUVolumeType, ProjectionType>;
  const auto volume = MakeDeepPhantom();
  auto       drr = PointType::New();
  drr->SetInput(volume);
  drr->SetGeometry(MakeGeometry(ProjectionEnum::Perspective, 9, 7, 1.0, 1.0));
  drr->SetNumberOfStreamDivisions(2);
  drr->SetSampler(itk::DRRSamplerFactory::Create("level-alias"));
  EXPECT_TRUE(Contains(ExceptionMessage([&] { drr->Update(); }, "level-alias"), "use the stratified sampler"));
  drr->SetSampler(itk::DRRSamplerFactory::Create("stratified"));
  EXPECT_NO_THROW(drr->Update());
}

} // namespace
