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
#include "itkDRRPointRenderer.h"
#include "itkDRRCompilerBuiltins.h"
#include "itkDRRDrawAndSplatChunks.h"
#include "itkDRRPointDrawer.h"
#include "itkDRRPointSplatter.h"
#include "itkDRRPolicies.h"
#include "itkDRRRenderPlan.h"
#include "itkDRRRenderReduction.h"
#include "itkDRRRenderWorkers.h"
#include "itkDRRStreamedPointRender.h"

#include <algorithm>
#include <memory>

namespace itk
{
using namespace DRRRendering;

namespace
{
/** A render of the points of a cloud. */
template <typename TSplat>
class SplatCloudChunks : public ChunkWorkBase
{
public:
  SplatCloudChunks(const DRRPointCloud & cloud, const PointSplatter<TSplat> & splatter)
    : m_Cloud(cloud), m_Splatter(splatter)
  {}
  void
  Run(uint64_t chunk, const Strata & strata, Worker & worker) const override
  {
    this->RunChunk(chunk, strata, worker);
  }

private:
  PointBasedDRR_VECTOR_CLONES void
  RunChunk(uint64_t chunk, const Strata & strata, Worker & worker) const
  {
    if (!worker.CloudScratch)
    {
      worker.CloudScratch.reset(new CloudBatch);
    }
    CloudBatch &    batch = *worker.CloudScratch;
    const uint64_t  end = std::min((chunk + 1) * DRRPointRenderer::SamplesPerChunk, strata.GetNumberOfSamples());
    const float *   weights = m_Cloud.GetWeights();
    const uint8_t * stratum = m_Cloud.GetStrata();
    const uint8_t * channel = m_Cloud.GetChannels();
    const uint32_t  channels = m_Cloud.GetDescription().NumberOfChannels;
    // Absent weights and strata read as a batch of ones and of zeros: one loop for every cloud.
    static const std::vector<float>   ones(samplesPerBatch, 1.0f);
    static const std::vector<uint8_t> zeros(samplesPerBatch, 0);
    for (uint64_t first = chunk * DRRPointRenderer::SamplesPerChunk; first < end; first += samplesPerBatch)
    {
      const uint64_t count = std::min(samplesPerBatch, end - first);
      const auto     splat = [&](const auto * slot, uint64_t slots) {
        m_Splatter.ProjectAndSplat(count,
                                   m_Cloud.GetX() + first,
                                   m_Cloud.GetY() + first,
                                   m_Cloud.GetZ() + first,
                                   weights ? weights + first : ones.data(),
                                   slot,
                                   batch,
                                   slots,
                                   worker.Sums);
      };
      const uint8_t * ownStratum = stratum ? stratum + first : zeros.data();
      if (!channel)
      {
        splat(ownStratum, strata.GetNumberOfStrata());
        continue;
      }
      // The slot of a point: stratum * K + channel.
      for (uint64_t s = 0; s < count; ++s)
      {
        batch.Slot[s] = static_cast<uint32_t>(ownStratum[s]) * channels + channel[first + s];
      }
      splat(batch.Slot, strata.GetNumberOfStrata() * channels);
    }
  }

  const DRRPointCloud &         m_Cloud;
  const PointSplatter<TSplat> & m_Splatter;
};
} // namespace

void
DRRPointRenderer::ComputeKernelSupport(const DRRAttenuationVolume & volume,
                                       KernelEnum                   kernel,
                                       std::array<double, 3> &      lower,
                                       std::array<double, 3> &      upper)
{
  KernelSupport(kernel, { { volume.GetSize()[0], volume.GetSize()[1], volume.GetSize()[2] } }, lower, upper);
}

DRRPointRenderer::Result
DRRPointRenderer::Render(const DRRAttenuationVolume & volume,
                         const DRRPointSampler &      sampler,
                         DRRPointProjection           projection,
                         const Settings &             settings,
                         MultiThreaderBase *          threader,
                         ProcessObject *              progressFilter)
{
  VerifyNumberOfSamples(settings);
  VerifyChannels(settings);
  Result result = ZeroResult(projection, settings.NumberOfChannels);
  result.RoomMass = sampler.GetTotalMass() * projection.GetRoomMassScale();
  if (!(result.RoomMass > 0.0))
  {
    return result; // all air: the exact answer is a zero image
  }
  // Sample only what can reach the detector (for samplers that cull).
  const DRRPointSampler::ViewPlanConstPointer plan =
    sampler.MakeViewPlan(volume, &projection, KernelReach(settings.Kernel), SplatReach(settings.Splat));
  result.SampledRoomMass = plan->GetSampledMass() * projection.GetRoomMassScale();
  if (!(result.SampledRoomMass > 0.0))
  {
    return result; // nothing in view: the exact answer is a zero image
  }

  const DRRSamplerTraits traits = sampler.GetTraits();
  const Strata           strata = MakeStrata(traits, settings);
  std::array<double, 3>  lower, upper;
  ComputeKernelSupport(volume, settings.Kernel, lower, upper);
  const FixedPoint fixedPoint = PlanFixedPoint(static_cast<double>(strata.GetNumberOfSamples()),
                                               sampler.GetMaximumWeight(),
                                               lower,
                                               upper,
                                               settings.Weighting == WeightingEnum::Unbiased,
                                               projection,
                                               result);
  Workspace        workspace;
  PrepareWorkers(workspace, strata, settings.NumberOfChannels, result.LineIntegral.size(), threader);
  DRRPolicies::Kernels::Visit(settings.Kernel, [&](auto kernel) {
    return DRRPolicies::Splats::Visit(settings.Splat, [&](auto splat) {
      const PointDrawer<decltype(kernel)>  drawer(sampler, *plan, traits, settings.Seed, settings.SignedResidual);
      const PointSplatter<decltype(splat)> splatter(
        projection, fixedPoint, settings.Weighting == WeightingEnum::Unbiased);
      const DrawAndSplatChunks<decltype(kernel), decltype(splat)> work(
        drawer, splatter, settings.VoxelChannels, settings.NumberOfChannels);
      RunChunks(work, strata, workspace, threader, progressFilter);
      return 0;
    });
  });
  Reduce(workspace, strata, settings.NumberOfChannels, fixedPoint, projection.GetPixelArea(), threader, result);
  return result;
}

std::shared_ptr<DRRPointRenderer::Workspace>
DRRPointRenderer::MakeWorkspace()
{
  return std::make_shared<Workspace>();
}

DRRPointCloud::Pointer
DRRPointRenderer::Draw(const DRRAttenuationVolume & volume,
                       const DRRPointSampler &      sampler,
                       const Settings &             settings,
                       MultiThreaderBase *          threader,
                       ProcessObject *              progressFilter)
{
  VerifyNumberOfSamples(settings);
  VerifyChannels(settings);
  // Every pose: the whole volume, drawn as the one slab of a streamed draw.
  const DRRPointSampler::ViewPlanConstPointer plan = sampler.MakeViewPlan(volume, nullptr, 0.0, 0.0);
  const auto                                  cloud =
    DRRStreamedPointRender::MakeCloud(settings,
                                      sampler.GetTraits(),
                                      sampler.GetMaximumWeight(),
                                      { { volume.GetSize()[0], volume.GetSize()[1], volume.GetSize()[2] } },
                                      plan->GetSampledMass(),
                                      settings.SignedResidual != nullptr);
  if (cloud->GetNumberOfPoints() > 0) // none for all air
  {
    DRRStreamedPointRender::DrawSlab(
      *cloud, settings, *plan, sampler, { { 0, cloud->GetNumberOfPoints() } }, 0, threader, progressFilter);
  }
  return cloud;
}

DRRPointRenderer::Result
DRRPointRenderer::Render(const DRRPointCloud & cloud,
                         DRRPointProjection    projection,
                         const Settings &      settings,
                         MultiThreaderBase *   threader,
                         ProcessObject *       progressFilter,
                         Workspace *           workspace)
{
  const DRRPointCloud::Description & description = cloud.GetDescription();
  Result                             result = ZeroResult(projection, description.NumberOfChannels);
  result.RoomMass = description.SampledMass * projection.GetRoomMassScale();
  result.SampledRoomMass = result.RoomMass;
  if (!(result.RoomMass > 0.0) || cloud.GetNumberOfPoints() == 0)
  {
    return result; // all air: the exact answer is a zero image
  }
  const Strata strata(description.NumberOfRequestedSamples, description.NumberOfStrata, description.InterleavedStrata);
  if (strata.GetNumberOfSamples() != cloud.GetNumberOfPoints())
  {
    itkGenericExceptionMacro("DRRPointRenderer: the point cloud's description does not match its points");
  }
  const bool       unbiased = settings.Weighting == WeightingEnum::Unbiased;
  const FixedPoint fixedPoint = PlanFixedPoint(static_cast<double>(strata.GetNumberOfSamples()),
                                               description.MaximumWeight,
                                               description.SupportLower,
                                               description.SupportUpper,
                                               unbiased,
                                               projection,
                                               result);
  Workspace        ownWorkspace;
  Workspace &      kept = workspace ? *workspace : ownWorkspace;
  PrepareWorkers(kept, strata, description.NumberOfChannels, result.LineIntegral.size(), threader);
  DRRPolicies::Splats::Visit(settings.Splat, [&](auto splat) {
    const PointSplatter<decltype(splat)>    splatter(projection, fixedPoint, unbiased);
    const SplatCloudChunks<decltype(splat)> work(cloud, splatter);
    RunChunks(work, strata, kept, threader, progressFilter);
    return 0;
  });
  Reduce(kept, strata, description.NumberOfChannels, fixedPoint, projection.GetPixelArea(), threader, result);
  return result;
}
} // namespace itk
