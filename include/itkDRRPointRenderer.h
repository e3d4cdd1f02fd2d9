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
#ifndef itkDRRPointRenderer_h
#define itkDRRPointRenderer_h

#include "itkDRRPointCloud.h"
#include "itkDRRPointProjection.h"
#include "itkDRRPointSampler.h"
#include "itkMultiThreaderBase.h"
#include "itkProcessObject.h"
#include "PointBasedDRRExport.h"

#include <memory>
#include <vector>

namespace itk
{
/** \class DRRPointRenderer
 * \brief The Monte Carlo core of the point-based DRR: draws N points, projects and splats them, and returns the
 * line-integral image and its standard error.
 *
 * The estimate of pixel j is L_j = M / (N a) sum_i c_ij, where c_ij is the share of point i in pixel j (its sampler
 * weight times its perspective weight times its splat fraction), M the room attenuation mass and a the pixel area.
 * Its standard error is M / (N a) sqrt(N / (N - 1) (sum c^2 - (sum c)^2 / N)), from the same sums, for samplers of
 * independent points; for dependent points (stratified, Markov chains) the N samples form R independent strata
 * (Settings::NumberOfStrata, by default the sampler's DRRSamplerTraits::PreferredNumberOfStrata: 4 for the
 * stratified sampler, 16 for the Markov chain) and the standard error comes from the spread of their R estimates.
 *
 * Reproducibility: the N samples are cut into fixed chunks; chunk k draws from the Philox streams keyed by (seed, k).
 * Every contribution is rounded once to a 64-bit fixed-point integer whose scale is chosen from N and a bound on
 * the contributions, so sums cannot overflow and integer addition makes the result independent of which thread
 * ran which chunk: the same seed gives the same bits on any number of threads.
 *
 * \sa PointBasedDRRImageFilter, DRRPointSampler, DRRPointProjection, DRRPointCloud
 * \ingroup PointBasedDRR
 */
class PointBasedDRR_EXPORT DRRPointRenderer
{
public:
  /** Box or Tent reconstruction kernel. */
  using KernelEnum = PointBasedDRREnums::ReconstructionKernel;
  /** Nearest or Bilinear splat. */
  using SplatEnum = PointBasedDRREnums::Splat;
  /** Unbiased or PaperCount point weighting. */
  using WeightingEnum = PointBasedDRREnums::PointWeighting;

  /** Samples per chunk: the unit of random-stream addressing, work distribution and progress. */
  static constexpr uint64_t SamplesPerChunk = 65536;

  /** The number of points a render draws unless told otherwise, for PointBasedDRRImageFilter and pbdrr alike: 10^7
   * points give an image of 2 to 3% NRMSE on a 256 x 256 chest view (level-alias 2.8%, stratified 2.3%; README and
   * docs/benchmark/) in about a second on 2 cores, a radiograph whose noise is below what the eye separates from
   * anatomy at that size. PointBasedDRRInterpolateImageFunction draws a fifth of it per view: a registration renders
   * hundreds of views, and with the points drawn once (frozen noise) its metric needs smoothness more than accuracy. */
  static constexpr uint64_t DefaultNumberOfSamples = 10000000;

  /** Fewest points a render draws (Settings::NumberOfSamples): the one home of that rule (renderer and filters). */
  static constexpr uint64_t MinimumNumberOfSamples = 1;

  /** Fewest samples per stratum: with fewer, a render of dependent points is one run (see Settings::NumberOfStrata).
   */
  static constexpr uint64_t MinimumSamplesPerStratum = 16;

  /** The strata a render asks for: requestedStrata (Settings::NumberOfStrata), or, for 0, the sampler's preference
   * (DRRSamplerTraits::PreferredNumberOfStrata); 1 for a sampler of independent points. */
  static uint64_t
  RequestedNumberOfStrata(const DRRSamplerTraits & traits, uint64_t requestedStrata)
  {
    if (traits.IndependentSamples)
    {
      return 1;
    }
    return requestedStrata > 0 ? requestedStrata : traits.PreferredNumberOfStrata;
  }

  /** True if numberOfSamples fill numberOfStrata strata with at least MinimumSamplesPerStratum samples each: the one
   * home of the samples-per-stratum rule (the renderer's strata, the filter's warning). */
  static bool
  HasEnoughSamplesPerStratum(uint64_t numberOfSamples, uint64_t numberOfStrata)
  {
    return numberOfSamples >= MinimumSamplesPerStratum * numberOfStrata;
  }

  /** What to render. */
  struct Settings
  {
    uint64_t      NumberOfSamples{ 0 };                 ///< N, the number of points to draw
    uint64_t      Seed{ 0 };                            ///< key of the random streams
    KernelEnum    Kernel{ KernelEnum::Box };            ///< where in its voxel a point goes
    SplatEnum     Splat{ SplatEnum::Nearest };          ///< how a point is deposited on the detector
    WeightingEnum Weighting{ WeightingEnum::Unbiased }; ///< perspective weight, or the paper's count
    /** Strata R for dependent samplers (0: the sampler's preference); used only if there are at least 16 points
     * per stratum (N >= 16 R, HasEnoughSamplesPerStratum()), otherwise, like R = 1, one stratum (standard error from
     * the points as if they were independent). */
    uint64_t NumberOfStrata{ 0 };
    /** Signed points: the residual volume of a control variate (DRRControlVariate::GetResidualVolume()), whose
     * DRRAttenuationVolume::IsNegativeResidual() says which points carry a negative weight; null: every weight is
     * positive. */
    const DRRAttenuationVolume * SignedResidual{ nullptr };
    /** Channels (docs/design.md section 13): the channel, 0 to NumberOfChannels - 1, of every voxel of the volume (x
     * fastest, DRRAttenuationVolume::GetVoxelChannels()); null: one channel. A point adds to the channel of the voxel
     * it was drawn in; the channels' fixed-point sums add up, exactly, to the sums of the render without channels. */
    const uint8_t * VoxelChannels{ nullptr };
    unsigned int    NumberOfChannels{ 1 }; ///< K, 1 to 256 (1: no channel images)
  };

  /** What a render returns. */
  struct Result
  {
    std::vector<double> LineIntegral;              ///< the estimate, dimensionless; cols x rows, columns fastest
    std::vector<double> StandardError;             ///< its standard error, same layout
    double              RoomMass{ 0.0 };           ///< attenuation mass of the whole volume in the room, mm^2
    double              SampledRoomMass{ 0.0 };    ///< mm^2, of the part sampled (in the view, for culling samplers)
    double              MinimumDepth{ 0.0 };       ///< mm; points nearer the source were dropped (0: none)
    bool                SourceNearVolume{ false }; ///< the volume comes near enough the source to drop points
    uint64_t            PointsOnDetector{ 0 };     ///< points that landed on the detector (nearest pixel inside)
    uint64_t            NumberOfStrata{ 1 };       ///< 1: standard error from the points; more: from the strata
    uint64_t            NumberOfSamples{ 0 };      ///< drawn: N, or R ceil(N / R) for samplers that interleave R strata
    /** K channels rendered (0: none). The line integral and standard error above are then the sum of the channels,
     * the same bits as a render without channels. */
    unsigned int NumberOfChannels{ 0 };
    /** Line integral of every channel, dimensionless; pixel major: K values per pixel, columns fastest. */
    std::vector<double> ChannelLineIntegral;
    /** Covariance of the channels' estimates per pixel (dimensionless^2): K (K + 1) / 2 values per pixel, the upper
     * triangle row major, (0, 0), (0, 1), ..., (0, K - 1), (1, 1), ..., (K - 1, K - 1). */
    std::vector<double> ChannelCovariance;
  };

  /** Renders. The volume must be the one the sampler was initialized with; the points are drawn from the sampler's
   * plan for the view (DRRPointSampler::MakeViewPlan(): culled, for samplers that cull), and the sampler is not
   * changed. Progress goes to progressFilter (may be null), which is also checked for abort between chunks. */
  static Result
  Render(const DRRAttenuationVolume & volume,
         const DRRPointSampler &      sampler,
         DRRPointProjection           projection,
         const Settings &             settings,
         MultiThreaderBase *          threader,
         ProcessObject *              progressFilter);

  /** Draws the points of a render of settings.NumberOfSamples points (seed, kernel and strata from the settings)
   * over the whole volume (no culling: they serve every view) and keeps them, for Render(cloud, ...). */
  static DRRPointCloud::Pointer
  Draw(const DRRAttenuationVolume & volume,
       const DRRPointSampler &      sampler,
       const Settings &             settings,
       MultiThreaderBase *          threader,
       ProcessObject *              progressFilter);

  /** What a render of a cloud keeps for the next one: the workers' sums (left cleared) and batches. A caller that
   * renders many poses passes the same workspace to each render, which then allocates and clears nothing up front.
   * Opaque; one render at a time. */
  class Workspace;
  /** A new, empty workspace for Render(cloud, ...). */
  static std::shared_ptr<Workspace>
  MakeWorkspace();

  /** Renders the points of a cloud for a projection (built from the volume the cloud was drawn from, with any
   * transform and geometry); only the splat and weighting of the settings are used. Cheaper than a render that
   * draws: no sampling, the points are read from memory. The same cloud and projection give the same bits on any
   * number of threads, with or without a workspace (may be null). */
  static Result
  Render(const DRRPointCloud & cloud,
         DRRPointProjection    projection,
         const Settings &      settings,
         MultiThreaderBase *   threader,
         ProcessObject *       progressFilter,
         Workspace *           workspace = nullptr);

  /** Continuous-index box [lower, upper] that the kernel's points can reach. */
  static void
  ComputeKernelSupport(const DRRAttenuationVolume & volume,
                       KernelEnum                   kernel,
                       std::array<double, 3> &      lower,
                       std::array<double, 3> &      upper);
};
} // namespace itk

#endif
