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
#ifndef itkDRRStreamedPointRender_h
#define itkDRRStreamedPointRender_h

#include "itkDRRCompatibility.h"
#include "itkDRRPointCloud.h"
#include "itkDRRPointRenderer.h"
#include "itkDRRStratifiedSampler.h"
#include "PointBasedDRRExport.h"

#include <array>
#include <memory>

namespace itk
{
/** \class DRRStreamedPointRender
 * \brief A point render of a volume read slab by slab: the sums of the whole volume's render, filled one slab at a
 * time, reduced once (docs/design.md section 16).
 *
 * Everything a render fixes before its first point is the whole volume's: the strata and samples of the run, the
 * fixed-point scales (from the whole volume's box and the view), the projection (the whole volume's grid) and the
 * masses the estimate is scaled by. Each slab then draws its window of the run's samples (for the stratified
 * sampler: DRRStratifiedSampler::GetSampleWindow() of its slab plan) into the same integer sums, so the image is
 * the unstreamed render's, bit for bit, whatever the slabs, and Finish() reduces them as DRRPointRenderer::Render()
 * does. A sampler of independent points has no windows: streamed, each slab is its own render (see
 * PointBasedDRRImageFilter::SetNumberOfStreamDivisions()).
 *
 * \sa DRRPointRenderer, DRRStratifiedSampler::MakeSlabViewPlan()
 * \ingroup PointBasedDRR
 */
class PointBasedDRR_EXPORT DRRStreamedPointRender
{
public:
  ITK_DISALLOW_COPY_AND_MOVE(DRRStreamedPointRender);

  /** Begins a render of settings (NumberOfChannels: the whole volume's; the slabs give their voxels' channels to
   * AddSlab()) over a volume of wholeSize voxels, seen through
   * projection (built for the whole volume's grid), by a sampler of these traits and maximum weight. */
  DRRStreamedPointRender(const DRRPointRenderer::Settings & settings,
                         const DRRPointProjection &         projection,
                         const DRRSamplerTraits &           traits,
                         double                             maximumWeight,
                         const std::array<uint64_t, 3> &    wholeSize,
                         MultiThreaderBase *                threader);
  ~DRRStreamedPointRender();

  /** The plan of a slab (DRRStratifiedSampler::MakeSlabViewPlan()) culled to the view of projection (the whole
   * volume's) with the reaches of the settings' kernel and splat. */
  static DRRPointSampler::ViewPlanConstPointer
  MakeSlabPlan(const DRRStratifiedSampler &                sampler,
               const DRRPointProjection &                  projection,
               const DRRPointRenderer::Settings &          settings,
               const DRRStratifiedSampler::SlabPlacement & placement);

  /** The run of a render of settings by a sampler of traits, whose windows the slabs draw (GetRun()). */
  static DRRPointSampler::SampleRange
  MakeRun(const DRRPointRenderer::Settings & settings, const DRRSamplerTraits & traits);

  /** The run whose windows the slabs draw: seed, strata interleaved in it and its size (First and Count 0). */
  DRRPointSampler::SampleRange
  GetRun() const;

  /** Draws the samples [window[0], window[1]) of the run from the plan of a sampler initialized on a slab, whose
   * first z plane is firstPlane of the whole volume, into the sums. signedResidual: the slab's control-variate
   * residual (its signs), or null. voxelChannels: the channel of each of the slab's voxels, numbered as the whole
   * volume's (DRRAttenuationVolume::GetVoxelChannels() of the slab's model), for more than one channel; else null. */
  void
  AddSlab(const DRRSamplerViewPlan &    plan,
          const DRRPointSampler &       sampler,
          const std::array<uint64_t, 2> window,
          uint64_t                      firstPlane,
          const DRRAttenuationVolume *  signedResidual,
          const uint8_t *               voxelChannels = nullptr);

  /** Points kept for many views (PointBasedDRRImageFilter::SetReusePoints()), drawn slab by slab: a cloud sized for
   * the whole run of settings (with a channel per point for settings' channels), described as the whole volume's
   * (wholeSize voxels, sampledMass mm^2), whose points the slabs then draw (DrawSlab()). signedPoints: a control
   * variate's residual (the cloud keeps the weights' signs). DRRPointRenderer::Draw() is the draw of one slab. */
  static DRRPointCloud::Pointer
  MakeCloud(const DRRPointRenderer::Settings & settings,
            const DRRSamplerTraits &           traits,
            double                             maximumWeight,
            const std::array<uint64_t, 3> &    wholeSize,
            double                             sampledMass,
            bool                               signedPoints);

  /** Draws the samples [window[0], window[1]) of a cloud's run (MakeCloud()) from the plan of a sampler initialized on
   * a slab whose first z plane is firstPlane of the whole volume (settings' signed residual and voxel channels are the
   * slab's): the points a draw of the whole volume puts there. Progress goes to progressFilter (may be null). */
  static void
  DrawSlab(DRRPointCloud &                    cloud,
           const DRRPointRenderer::Settings & settings,
           const DRRSamplerViewPlan &         plan,
           const DRRPointSampler &            sampler,
           const std::array<uint64_t, 2>      window,
           uint64_t                           firstPlane,
           MultiThreaderBase *                threader,
           ProcessObject *                    progressFilter);

  /** The samples the slabs have drawn so far. */
  uint64_t
  GetNumberOfSamplesDrawn() const;

  /** The render: the sums reduced as DRRPointRenderer::Render() reduces them, scaled by the whole volume's
   * attenuation mass totalMass and the part the slabs' plans sampled, sampledMass (mm^2, volume frame). */
  DRRPointRenderer::Result
  Finish(double totalMass, double sampledMass);

private:
  struct State;
  std::unique_ptr<State> m_State;
};
} // namespace itk

#endif
